//! The tethers of a stability map come from one shortest path map from the start: on the
//! generated 100-obstacle crater strip every assessed pose's tether length and last anchor agree
//! with an independent SPT search from the start to that pose (length to 1e-9, the same last
//! anchor up to ties), and poses behind obstacles are numerous enough for that to mean something.

use rappel::scenario::Scenario;
use rappel::stability::{StabilityOptions, stability_over_scenario};
use rappel_geometry::btm::Btm;
use rappel_planners::spt::SptPlanner;
use rappel_planners::visibility_graph::segment_is_free;

/// Relative tolerance of the length comparison (the 1e-9).
const TOLERANCE: f64 = 1e-9;

#[test]
fn every_pose_has_the_tether_of_its_own_spt_search() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../fixtures/generated/crater-strip-100.ron"
    );
    let s = Scenario::load(std::path::Path::new(path)).expect("fixture loads");
    let options = StabilityOptions {
        grid_step: 5.0,
        tension_limit: None,
        ..Default::default()
    };
    let r = stability_over_scenario(s.validate().expect("valid scenario"), &options).expect("map");
    let btm = Btm::from_map(&s.map).unwrap();
    let planner = SptPlanner::new(&btm);
    let (mut behind, mut ties) = (0, 0);
    for d in &r.dots {
        let shp = planner
            .shortest_taut_path(s.start, d.point)
            .expect("search runs")
            .expect("the strip is connected");
        if shp.points.len() < 2 {
            // The start itself: no tether pulls.
            assert!(d.point == s.start && d.last_anchor.is_none(), "{d:?}");
            continue;
        }
        let (Some(length), Some(anchor)) = (d.tether_length_m, d.last_anchor) else {
            panic!("pose {:?} has no tether", d.point);
        };
        assert!(
            (length - shp.length).abs() <= TOLERANCE * shp.length.max(1.0),
            "pose {:?}: map {length} vs search {}",
            d.point,
            shp.length
        );
        let expected = shp.points[shp.points.len() - 2];
        if anchor != expected {
            // A tie: the map's anchor sees the pose and a shortest path through it is as short.
            let via = planner
                .shortest_taut_path(s.start, anchor)
                .unwrap()
                .unwrap();
            assert!(
                segment_is_free(&s.map, &anchor, &d.point)
                    && ((via.length + (d.point - anchor).norm()) - shp.length).abs()
                        <= TOLERANCE * shp.length,
                "pose {:?}: anchor {anchor:?}, search's {expected:?}",
                d.point
            );
            ties += 1;
        }
        behind += usize::from(anchor != s.start);
    }
    assert!(r.dots.len() >= 1_500, "only {} poses", r.dots.len());
    assert!(behind >= 200, "only {behind} poses behind obstacles");
    assert!(ties <= r.dots.len() / 20, "{ties} ties");
}
