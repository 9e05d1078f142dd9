//! The shortest path map from one start: for many seeded random maps and points, the geodesic
//! length agrees with the independent visibility-graph oracle to 1e-9 and the last anchor is the
//! oracle's (or, on a tie, one through which a path of the same length runs); it agrees with the
//! per-point SPT search; bad points and budgets give typed errors.

use crate::common;

use common::{one_box, random_map};
use nalgebra::Point2;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rappel_geometry::btm::Btm;
use rappel_geometry::map::Map;
use rappel_planners::shortest_path_map::ShortestPathMap;
use rappel_planners::spt::{SearchError, SptPlanner};
use rappel_planners::visibility_graph;

/// Relative tolerance of length comparisons (the 1e-9).
const TOLERANCE: f64 = 1e-9;

/// Seeded free points of `map` (and now and then one of its vertices; with `on_edges`, also
/// midpoints of obstacle edges).
fn free_points(map: &Map, seed: u64, n: usize, on_edges: bool) -> Vec<Point2<f64>> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x5eed);
    let mut out = Vec::new();
    let mut tries = 0;
    while out.len() < n && tries < 100 * n {
        tries += 1;
        let p = Point2::new(rng.random_range(-16.0..16.0), rng.random_range(-16.0..16.0));
        if map.validate_point("point", &p).is_ok() {
            out.push(p);
        }
    }
    // Map vertices: the path ends on a vertex, its anchor is the one before. Points on obstacle
    // edges (their midpoints, when rounding leaves them in the closed free space): the query's
    // triangle is chosen by the canonical-endpoint rule. (The visibility-graph oracle is not
    // asked about those: on seed 9 it routes to such a midpoint past the edge's far end and
    // back, 2.56 m longer than the straight run along the edge that the map and the SPT search
    // agree on.)
    for o in map.obstacles.iter().take(3) {
        out.push(o.vertices[1]);
        let m = nalgebra::center(&o.vertices[0], &o.vertices[1]);
        if on_edges && map.validate_point("point", &m).is_ok() {
            out.push(m);
        }
    }
    out
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= TOLERANCE * b.max(1.0)
}

#[test]
fn lengths_and_last_anchors_match_the_visibility_graph_oracle_on_random_maps() {
    let (mut maps, mut points, mut bent, mut ties) = (0, 0, 0, 0);
    for seed in 0..60u64 {
        let Some(m) = random_map(seed, 5 + (seed % 9) as usize) else {
            continue;
        };
        let btm = Btm::from_map(&m.map).unwrap();
        let spm = ShortestPathMap::build(&btm, m.start).unwrap();
        for q in free_points(&m.map, seed, 25, false) {
            let oracle = visibility_graph::shortest_path(&m.map, m.start, q).expect("reachable");
            let got = spm.query(q).unwrap().expect("connected");
            assert!(
                close(got.length, oracle.length),
                "seed {seed} point {q:?}: map {} vs oracle {} ({:?})",
                got.length,
                oracle.length,
                oracle.points
            );
            let expected = oracle.points[oracle.points.len() - 2];
            if got.last_anchor != expected {
                // A tie: another shortest path ends through the map's anchor. It must see the
                // point, and the oracle's distance to it plus the last leg must be the length.
                let to_anchor = visibility_graph::shortest_path(&m.map, m.start, got.last_anchor)
                    .expect("the anchor is reachable");
                assert!(
                    visibility_graph::segment_is_free(&m.map, &got.last_anchor, &q)
                        && close(
                            to_anchor.length + (q - got.last_anchor).norm(),
                            oracle.length
                        ),
                    "seed {seed} point {q:?}: anchor {:?}, oracle's {:?} (path {:?})",
                    got.last_anchor,
                    expected,
                    oracle.points
                );
                ties += 1;
            }
            bent += usize::from(got.anchor_vertex.is_some());
            points += 1;
        }
        maps += 1;
    }
    assert!(maps >= 40, "only {maps} valid random maps");
    assert!(points >= 1_000, "only {points} points");
    assert!(bent >= 300, "only {bent} points behind obstacles");
    assert!(ties <= points / 20, "{ties} ties of {points}: too many");
}

#[test]
fn the_map_agrees_with_one_spt_search_per_point() {
    let mut compared = 0;
    for seed in (0..15u64).chain(100..130) {
        // The oracle test's maps for the first seeds (seed 9 holds the edge midpoint the oracle
        // gets wrong), 12 obstacles for the others.
        let obstacles = if seed < 100 {
            5 + (seed % 9) as usize
        } else {
            12
        };
        let Some(m) = random_map(seed, obstacles) else {
            continue;
        };
        let btm = Btm::from_map(&m.map).unwrap();
        let spm = ShortestPathMap::build(&btm, m.start).unwrap();
        let planner = SptPlanner::new(&btm);
        for q in free_points(&m.map, seed, 40, true) {
            let got = spm.query(q).unwrap().expect("connected");
            let taut = planner
                .shortest_taut_path(m.start, q)
                .unwrap()
                .expect("connected");
            assert!(
                close(got.length, taut.length),
                "seed {seed} point {q:?}: map {} vs search {}",
                got.length,
                taut.length
            );
            compared += 1;
        }
    }
    assert!(compared >= 800, "only {compared} points");
}

#[test]
fn the_start_sees_its_own_triangle_and_the_open_ground() {
    let btm = Btm::from_map(&one_box(4.0, 6.0, 4.0, 6.0)).unwrap();
    let start = Point2::new(5.0, 9.0);
    let spm = ShortestPathMap::build(&btm, start).unwrap();
    let here = spm.query(start).unwrap().unwrap();
    assert_eq!((here.length, here.last_anchor), (0.0, start));
    let side = spm.query(Point2::new(9.0, 5.0)).unwrap().unwrap();
    assert_eq!(side.last_anchor, start);
    assert!(close(side.length, (16.0f64 + 16.0).sqrt()));
    // Straight below the box: around a top corner then a bottom corner, the bottom one last.
    let below = spm.query(Point2::new(5.0, 1.0)).unwrap().unwrap();
    assert!(below.last_anchor.y == 4.0 && below.anchor_vertex.is_some());
    assert!(close(below.length, 2.0 * 10f64.sqrt() + 2.0));
}

#[test]
fn bad_points_and_small_budgets_are_typed_errors() {
    let btm = Btm::from_map(&one_box(4.0, 6.0, 4.0, 6.0)).unwrap();
    let start = Point2::new(5.0, 9.0);
    assert!(matches!(
        ShortestPathMap::build(&btm, Point2::new(5.0, 5.0)),
        Err(SearchError::Endpoint { which: "start", .. })
    ));
    assert!(matches!(
        ShortestPathMap::build_with_budget(&btm, start, 3),
        Err(SearchError::BudgetExhausted { expansions: 3 })
    ));
    assert!(matches!(
        ShortestPathMap::build_with_budget(&btm, start, 0),
        Err(SearchError::Option(_))
    ));
    let spm = ShortestPathMap::build(&btm, start).unwrap();
    for bad in [
        Point2::new(5.0, 5.0),
        Point2::new(11.0, 5.0),
        Point2::new(f64::NAN, 1.0),
    ] {
        assert!(matches!(
            spm.query(bad),
            Err(SearchError::Endpoint { which: "query", .. })
        ));
    }
}
