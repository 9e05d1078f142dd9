//! Frictional planning (Alg. 7, 8, 10, 14) against independent references: the SHP after a slip
//! equals the frictionless SHP on the clipped map built from scratch; capstan classes follow
//! `e^{μθ}`; the capstan along the tether multiplies.

use nalgebra::Point2;
use rappel_geometry::btm::Btm;
use rappel_geometry::map::Map;
use rappel_geometry::polygon::Polygon;
use rappel_homotopy::path::Path;
use rappel_homotopy::shp::shortest_homotopic_path;
use rappel_mechanics::friction::FrictionInterval;
use rappel_mechanics::friction_cone::TetherFrictionCone;
use rappel_mechanics::ptfo::{PtfoClass, TensionAssumptions};
use rappel_mechanics::ptfo_surface::PtfoSurface;
use rappel_planners::frictional::anchor_check::AnchorVerdict;
use rappel_planners::frictional::search::{FrictionalQuery, plan_frictional};
use rappel_planners::frictional::{FrictionModel, Ptfo};
use rappel_planners::spt::{SearchOptions, SptPlanner};
use rappel_planners::terrain::PlaneSeries;
use rappel_terrain::plane_series::TerrainPlane;

fn p(x: f64, y: f64) -> Point2<f64> {
    Point2::new(x, y)
}

/// A pillar PTFO of `radius` about `center`: its footprint must hold the anchors (the diamond's
/// side corners lie 8 m from its centre, the square's corners `5 sqrt 2`).
fn pillar_model(obstacle: usize, center: Point2<f64>, radius: f64, mu: f64) -> FrictionModel {
    FrictionModel {
        ptfos: vec![Ptfo {
            obstacle,
            surface: PtfoSurface::Cylinder { center, radius },
            friction: FrictionInterval::exact(mu).unwrap(),
        }],
        tensions: TensionAssumptions::new(100.0, 400.0, 200.0, 20.0).unwrap(),
        geometric_friction: 0.0,
    }
}

fn query<'a>(
    t: &'a PlaneSeries,
    options: &'a SearchOptions,
    start: Point2<f64>,
    goal: Point2<f64>,
    holding_limit: Option<f64>,
) -> FrictionalQuery<'a> {
    FrictionalQuery {
        terrain: t,
        clearance: 0.5,
        start,
        goal,
        options,
        holding_limit,
        tether_length: None,
    }
}

fn terrain() -> PlaneSeries {
    let plane = TerrainPlane {
        y_top: 100.0,
        y_bottom: 0.0,
        slope_deg: 45.0,
        friction: 0.9,
    };
    PlaneSeries::new(&[plane], &TetherFrictionCone).unwrap()
}

/// A diamond PTFO and a geometric block to its right: once the diamond's right vertex slips, the
/// tether wraps the block instead (Alg. 14 finds a new anchor on another obstacle).
fn two_obstacle_map() -> (Map, Polygon, Polygon) {
    let diamond = Polygon::new(vec![
        p(12.0, 50.0),
        p(20.0, 44.0),
        p(28.0, 50.0),
        p(20.0, 56.0),
    ]);
    let block = Polygon::new(vec![
        p(24.0, 30.0),
        p(27.0, 30.0),
        p(27.0, 33.0),
        p(24.0, 33.0),
    ]);
    let map = Map::new(
        Polygon::rectangle(0.0, 0.0, 40.0, 100.0),
        vec![diamond.clone(), block.clone()],
    );
    (map, diamond, block)
}

#[test]
fn slip_path_equals_the_frictionless_shp_on_the_clipped_map() {
    let (map, diamond, block) = two_obstacle_map();
    let btm = Btm::from_map(&map).unwrap();
    let (start, goal) = (p(30.0, 95.0), p(22.0, 5.0));
    let options = SearchOptions::default().with_max_classes(Some(4)).unwrap();
    let t = terrain();
    let query = query(&t, &options, start, goal, None);
    // Almost no friction: every wrap of the diamond slides.
    let model = pillar_model(0, p(20.0, 50.0), 8.0, 0.01);
    let plan = plan_frictional(&btm, &map, &model, &query).unwrap();
    let first = &plan.classes[0];
    assert!(!first.check.slips.is_empty(), "the diamond must slip");
    let slip = &first.check.slips[0];
    assert_eq!(slip.obstacle, 0);
    // Independent reference: clip the vertex by hand, rebuild from scratch, frictionless search.
    let clipped: Vec<_> = diamond
        .vertices
        .iter()
        .copied()
        .filter(|v| *v != slip.vertex)
        .collect();
    let reference_map = Map::new(
        map.boundary.clone(),
        vec![Polygon::new(clipped), block.clone()],
    );
    let reference_btm = Btm::from_map(&reference_map).unwrap();
    let search = SptPlanner::new(&reference_btm)
        .search(start, goal, &options)
        .unwrap()
        .run()
        .unwrap();
    if first.check.slips.len() == 1 {
        assert!(
            search
                .classes
                .iter()
                .any(|c| c.shp.taut.points == first.check.taut.points),
            "slipped SHP {:?} is no frictionless class of the clipped map",
            first.check.taut.points
        );
    }
    // The SHP only gets shorter when an obstacle shrinks.
    assert!(slip.length_after_m <= slip.length_before_m);
}

#[test]
fn every_slip_matches_a_scratch_rebuild() {
    // Both diamond vertices the tether can wrap slip in turn; each intermediate SHP is checked
    // against a from-scratch frictionless search on the map with the same clips.
    let (map, diamond, block) = two_obstacle_map();
    let btm = Btm::from_map(&map).unwrap();
    let options = SearchOptions::default().with_max_classes(Some(6)).unwrap();
    let t = terrain();
    let mut local = 0;
    for (start, goal) in [(p(30.0, 95.0), p(22.0, 5.0)), (p(10.0, 95.0), p(30.0, 5.0))] {
        let query = query(&t, &options, start, goal, None);
        let model = pillar_model(0, p(20.0, 50.0), 8.0, 0.01);
        let plan = plan_frictional(&btm, &map, &model, &query).unwrap();
        for class in &plan.classes {
            let mut ring = diamond.vertices.clone();
            for slip in &class.check.slips {
                ring.retain(|v| *v != slip.vertex);
            }
            let mut obstacles = vec![block.clone()];
            if ring.len() >= 3 {
                obstacles.push(Polygon::new(ring));
            }
            let reference_map = Map::new(map.boundary.clone(), obstacles);
            let reference_btm = Btm::from_map(&reference_map).unwrap();
            let search = SptPlanner::new(&reference_btm)
                .search(
                    start,
                    goal,
                    &SearchOptions::default().with_max_classes(Some(12)).unwrap(),
                )
                .unwrap()
                .run()
                .unwrap();
            assert!(
                search
                    .classes
                    .iter()
                    .any(|c| c.shp.taut.points == class.check.taut.points),
                "class {}: {:?} not found",
                class.rank,
                class.check.taut.points
            );
            // The thesis' local form of Alg. 14 (funnel only between the slipped vertex's
            // neighbours, splice the ends back) gives the same SHP as our whole-sleeve funnel.
            if let [slip] = class.check.slips.as_slice() {
                let before: Vec<_> = std::iter::once(start)
                    .chain(slip.anchors_before.iter().copied())
                    .chain(std::iter::once(goal))
                    .collect();
                let i = before.iter().position(|p| *p == slip.vertex).unwrap();
                let sub = Path::new(before[i - 1..=i + 1].to_vec()).unwrap();
                let part = shortest_homotopic_path(&reference_btm, &sub).unwrap().taut;
                let spliced: Vec<_> = before[..i - 1]
                    .iter()
                    .chain(&part.points)
                    .chain(&before[i + 2..])
                    .copied()
                    .collect();
                assert_eq!(spliced, class.check.taut.points, "class {}", class.rank);
                local += 1;
            }
            // No friction anchor on the diamond survives with μ = 0.01.
            assert!(class.check.anchors.iter().all(|d| d.obstacle != Some(0)));
        }
    }
    assert!(local > 0, "no single-slip class to compare");
}

#[test]
fn capstan_anchor_classes_follow_exp_mu_theta() {
    // A square PTFO wrapped by a right-angle turn; the pillar model gives I = μθ.
    let square = Polygon::new(vec![
        p(15.0, 45.0),
        p(25.0, 45.0),
        p(25.0, 55.0),
        p(15.0, 55.0),
    ]);
    let map = Map::new(Polygon::rectangle(0.0, 0.0, 40.0, 100.0), vec![square]);
    let btm = Btm::from_map(&map).unwrap();
    let (start, goal) = (p(26.0, 56.0), p(14.0, 44.0));
    let options = SearchOptions::default().with_max_classes(Some(1)).unwrap();
    let t = terrain();
    let query = query(&t, &options, start, goal, Some(100.0));
    let tensions = TensionAssumptions::new(100.0, 400.0, 200.0, 20.0).unwrap();
    let mut seen = std::collections::HashSet::new();
    for mu in [0.05, 0.3, 0.6, 0.9, 1.2, 2.0] {
        let model = pillar_model(0, p(20.0, 50.0), 50f64.sqrt(), mu);
        let plan = plan_frictional(&btm, &map, &model, &query).unwrap();
        let class = &plan.classes[0];
        if let Some(d) = class.check.anchors.iter().find(|d| d.obstacle == Some(0)) {
            let i = mu * d.anchor.turning_angle;
            assert!((d.omega_integral_hold - i).abs() < 1e-9);
            let expected = if tensions.t_max() < tensions.t_min() * i.exp() {
                PtfoClass::Solid
            } else if tensions.t_d() + tensions.epsilon() > tensions.t_d() * i.exp() {
                PtfoClass::Slides
            } else {
                PtfoClass::Volatile
            };
            assert_eq!(d.verdict, AnchorVerdict::Friction(expected), "mu {mu}");
            seen.insert(format!("{expected:?}"));
            if let Some(h) = &class.holding {
                let total: f64 = h.exponents.iter().sum();
                assert!((h.holding_force_at_start_n - 400.0 * (-total).exp()).abs() < 1e-9);
                assert!((h.tension_limit_n.unwrap() - 100.0 * total.exp()).abs() < 1e-9);
            }
        } else {
            assert!(
                !class.check.slips.is_empty(),
                "mu {mu}: no anchor and no slip"
            );
            // Each slipped wrap was below the sliding bound ln((T_d + ε)/T_d) = ln 1.1.
            assert!(mu * std::f64::consts::PI < 1.1f64.ln() * 4.0);
            seen.insert("Slides".to_string());
        }
    }
    // The sweep of μ reaches every class.
    assert_eq!(seen.len(), 3, "{seen:?}");
}

/// A friction class gets an ascent/descent pair (thesis §3.4.2 with Alg. 6): both paths drive
/// over the solid friction anchor, keep the clearance from the geometric anchor, and are
/// homotopic to the class's taut tether: the homotopy crate's SHP of each path (computed from
/// the path alone) has the taut tether's length.
#[test]
fn a_friction_class_gets_a_pair_driving_over_its_solid_anchor() {
    let square = Polygon::new(vec![
        p(15.0, 45.0),
        p(25.0, 45.0),
        p(25.0, 55.0),
        p(15.0, 55.0),
    ]);
    // A geometric block below the square's lower edge line, in the way of the tether to the goal.
    let block = Polygon::new(vec![
        p(17.0, 33.0),
        p(19.0, 33.0),
        p(19.0, 37.0),
        p(17.0, 37.0),
    ]);
    let map = Map::new(
        Polygon::rectangle(0.0, 0.0, 40.0, 100.0),
        vec![square, block],
    );
    let btm = Btm::from_map(&map).unwrap();
    let (start, goal) = (p(26.0, 56.0), p(8.0, 20.0));
    let options = SearchOptions::default().with_max_classes(Some(5)).unwrap();
    let t = terrain();
    let clearance = 0.5;
    let mut q = query(&t, &options, start, goal, None);
    q.clearance = clearance;
    let model = pillar_model(0, p(20.0, 50.0), 50f64.sqrt(), 4.0);
    let plan = plan_frictional(&btm, &map, &model, &q).unwrap();
    let chosen = &plan.classes[plan.chosen.expect("a feasible friction class")];
    let pair = chosen
        .pair
        .as_ref()
        .expect("feasible classes carry their pair");
    let kinds: Vec<AnchorVerdict> = chosen.check.anchors.iter().map(|d| d.verdict).collect();
    assert!(
        kinds.contains(&AnchorVerdict::Friction(PtfoClass::Solid))
            && kinds.contains(&AnchorVerdict::Geometric),
        "the case needs both kinds of anchor: {kinds:?}"
    );
    let dist = |a: &Point2<f64>, path: &[Point2<f64>]| {
        path.windows(2)
            .map(|w| {
                let (u, v) = (w[1] - w[0], a - w[0]);
                let t = (v.dot(&u) / u.norm_squared()).clamp(0.0, 1.0);
                (v - u * t).norm()
            })
            .fold(f64::INFINITY, f64::min)
    };
    for d in &chosen.check.anchors {
        for path in [&pair.ascent, &pair.descent] {
            let gap = dist(&d.anchor.point, path);
            match d.verdict {
                AnchorVerdict::Friction(PtfoClass::Solid) => {
                    assert!(gap < 1e-9, "solid anchor driven over: {gap}");
                }
                _ => assert!(gap >= clearance * (1.0 - 1e-6), "geometric anchor: {gap}"),
            }
        }
    }
    let shp_length = |points: Vec<Point2<f64>>| {
        let path = Path::new(points).unwrap();
        shortest_homotopic_path(&btm, &path).unwrap().taut.length
    };
    let taut = chosen.check.taut.length;
    assert!((shp_length(pair.descent.clone()) - taut).abs() < 1e-9 * taut);
    let up: Vec<Point2<f64>> = pair.ascent.iter().rev().copied().collect();
    assert!((shp_length(up) - taut).abs() < 1e-9 * taut);
    assert!(pair.min_anchor_distance >= clearance * (1.0 - 1e-6));
}
