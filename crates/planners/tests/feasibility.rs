//! Ascent feasibility (thesis Alg. 5, eq. 2.7) and path pairs (Alg. 6): verdicts flip exactly where
//! the closed-form friction cone says, each condition of §2.4.2 is named when it fails, waypoints lie
//! on their visibility lines, and path pairs are free, homotopic and clear of the anchors
//! (checked with the homotopy crate's own functions).

mod common;

use common::random_map;
use nalgebra::Point2;
use rappel_geometry::btm::Btm;
use rappel_geometry::map::Map;
use rappel_geometry::polygon::Polygon;
use rappel_homotopy::crossing::CrossingSequence;
use rappel_homotopy::path::Path;
use rappel_mechanics::friction_cone::TetherFrictionCone;
use rappel_planners::feasibility::{
    FeasibilityContext, Impassability, Passability, check_feasibility, distance_to_segment,
    fill_reachable_areas,
};
use rappel_planners::path_pair::{path_pair, plan_path_pair};
use rappel_planners::spt::{SearchOptions, SptPlanner};
use rappel_planners::terrain::PlaneSeries;
use rappel_terrain::plane_series::TerrainPlane;

/// Alg. 5 on `taut` with the point-robot friction cone on `planes` and a 0.5 m clearance.
fn check_on_planes(
    btm: &Btm,
    planes: &[TerrainPlane],
    taut: &rappel_homotopy::funnel::TautPath,
) -> rappel_planners::feasibility::FeasibilityReport {
    let terrain = PlaneSeries::new(planes, &TetherFrictionCone).unwrap();
    let ctx = FeasibilityContext {
        btm,
        terrain: &terrain,
        clearance: 0.5,
        tether_length: None,
    };
    check_feasibility(&ctx, taut)
}

fn p(x: f64, y: f64) -> Point2<f64> {
    Point2::new(x, y)
}

/// The shortest-infeasible fixture's geometry: round the west corner (40, 85) the first tether
/// segment is at atan(10 / 15) from the fall line.
fn triangle_map() -> Map {
    Map::new(
        Polygon::new(vec![p(0., -10.), p(100., -10.), p(100., 110.), p(0., 110.)]),
        vec![Polygon::new(vec![p(40., 85.), p(65., 40.), p(45., 40.)])],
    )
}

#[test]
fn the_verdict_flips_where_the_friction_cone_says() {
    let btm = Btm::build(&triangle_map()).unwrap();
    let planner = SptPlanner::new(&btm);
    let best = planner
        .shortest_path(p(50., 100.), p(50., 0.))
        .unwrap()
        .unwrap();
    let psi = 10f64.atan2(15.0);
    // theta_max = asin(mu cot 45) = asin(mu): feasible exactly when mu > sin(psi).
    for (mu, feasible) in [(psi.sin() - 1e-6, false), (psi.sin() + 1e-6, true)] {
        let r = check_on_planes(
            &btm,
            &[TerrainPlane::new(110., -10., 45., mu)],
            &best.shp.taut,
        );
        assert_eq!(r.feasible(), feasible, "mu {mu}: {}", r.describe());
        assert!((r.anchors[0].psi - psi).abs() < 1e-12);
        if !feasible {
            let b = r.blockage.unwrap();
            assert_eq!(b.anchor, Some(1));
            assert!(matches!(b.reason, Impassability::NoVisibilityEdge { .. }));
        }
    }
}

#[test]
fn condition_two_uses_the_previous_anchors_plane() {
    // A concave series: steep above (narrow cone at the start), shallow below (wide cone at the
    // anchor). psi_1 = 33.69 degrees fits the lower cone but not the upper one.
    let btm = Btm::build(&triangle_map()).unwrap();
    let best = SptPlanner::new(&btm)
        .shortest_path(p(50., 100.), p(50., 0.))
        .unwrap()
        .unwrap();
    let planes = [
        TerrainPlane::new(110., 90., 60., 0.4),
        TerrainPlane::new(90., -10., 30., 0.4),
    ];
    let terrain = PlaneSeries::new(&planes, &TetherFrictionCone).unwrap();
    assert_eq!(terrain.concave_edges(), vec![0]);
    let ctx = FeasibilityContext {
        btm: &btm,
        terrain: &terrain,
        clearance: 0.5,
        tether_length: None,
    };
    let r = check_feasibility(&ctx, &best.shp.taut);
    let b = r.blockage.expect("infeasible");
    assert_eq!(b.anchor, Some(1));
    assert!(
        matches!(b.reason, Impassability::OutsidePreviousReachableSet { .. }),
        "{:?}",
        b.reason
    );
}

#[test]
fn the_goal_must_be_held_by_the_last_anchor() {
    // No obstacle: the straight tether at atan(30 / 60) = 26.6 degrees > 23.58.
    let map = Map::new(
        Polygon::new(vec![p(0., 0.), p(100., 0.), p(100., 100.), p(0., 100.)]),
        vec![],
    );
    let btm = Btm::build(&map).unwrap();
    let best = SptPlanner::new(&btm)
        .shortest_path(p(20., 90.), p(50., 30.))
        .unwrap()
        .unwrap();
    let r = check_on_planes(
        &btm,
        &[TerrainPlane::new(100., 0., 45., 0.4)],
        &best.shp.taut,
    );
    let b = r.blockage.expect("infeasible");
    assert_eq!(b.anchor, None);
    assert!(matches!(
        b.reason,
        Impassability::GoalOutsideReachableSet { .. }
    ));
    // Flat ground: tether-free, any class will do.
    let flat = PlaneSeries::flat();
    let ctx = FeasibilityContext {
        btm: &btm,
        terrain: &flat,
        clearance: 0.5,
        tether_length: None,
    };
    assert!(check_feasibility(&ctx, &best.shp.taut).feasible());
}

#[test]
fn waypoints_and_pairs_on_random_maps() {
    let terrain = PlaneSeries::new(
        &[TerrainPlane::new(30., -30., 40., 0.6)],
        &TetherFrictionCone,
    )
    .unwrap();
    let clearance = 0.3;
    let mut pairs = 0;
    let mut no_pair = Vec::new();
    for seed in 0..40u64 {
        let Some(m) = random_map(5_000 + seed, 7) else {
            continue;
        };
        let btm = Btm::build(&m.map).unwrap();
        let ctx = FeasibilityContext {
            btm: &btm,
            terrain: &terrain,
            clearance,
            tether_length: None,
        };
        let options = SearchOptions::default().with_max_classes(Some(4)).unwrap();
        let (top, bottom) = if m.start.y > m.goal.y {
            (m.start, m.goal)
        } else {
            (m.goal, m.start)
        };
        let plan =
            plan_path_pair(&SptPlanner::new(&btm), top, bottom, &options, &ctx, false).unwrap();
        for c in &plan.classes {
            let r = &c.feasibility;
            let taut = &c.class.shp.taut;
            // Every passed anchor's waypoint lies on its visibility line, beyond the anchor.
            for a in &r.anchors {
                if let Passability::Passable { waypoint, .. } = a.passability {
                    let j = a.index;
                    let prev = if j == 1 {
                        taut.start()
                    } else {
                        taut.anchors[j - 2].point
                    };
                    let (d, w) = (a.anchor.point - prev, waypoint - a.anchor.point);
                    assert!((d.x * w.y - d.y * w.x).abs() <= 1e-9 * d.norm() * w.norm());
                    assert!(d.dot(&w) > 0.0);
                    assert!(w.norm() >= clearance.min(w.norm()) - 1e-12);
                }
            }
            assert_eq!(
                r.feasible(),
                r.waypoints.len() == taut.anchors.len() && r.blockage.is_none()
            );
        }
        no_pair.extend(plan.classes.iter().filter_map(|c| c.pair_failure.clone()));
        if let Some(pair) = &plan.pair {
            pairs += 1;
            let class = &plan.classes[pair.rank - 1].class;
            let word = &class.shp.crossings;
            let descent = Path::new(pair.descent.clone()).unwrap();
            let ascent_forward = Path::new(pair.ascent.iter().rev().copied().collect()).unwrap();
            for path in [&descent, &ascent_forward] {
                path.validate(&btm).expect("in free space");
                assert_eq!(
                    &CrossingSequence::reduced_of_path(&btm, path).unwrap(),
                    word
                );
                for a in &class.shp.taut.anchors {
                    for w in path.points().windows(2) {
                        assert!(
                            distance_to_segment(&a.point, &w[0], &w[1]) >= clearance * (1.0 - 1e-9)
                        );
                    }
                }
            }
            assert_eq!(pair.ascent[0], bottom);
            assert_eq!(*pair.ascent.last().unwrap(), top);
            // The pair is what path_pair builds for that class.
            let again = path_pair(&ctx, class, &plan.classes[pair.rank - 1].feasibility).unwrap();
            assert_eq!(&again, pair);
            // Earlier classes were infeasible or had no pair: Alg. 6 takes the first that works.
            for c in &plan.classes[..pair.rank - 1] {
                assert!(!c.feasibility.feasible() || c.pair_failure.is_some());
            }
        }
    }
    assert!(pairs >= 10, "only {pairs} pairs");
    // A feasible class nearly always gets its pair.
    assert!(no_pair.len() <= 2, "{no_pair:?}");
}

#[test]
fn reachable_sets_cut_to_free_space_lose_exactly_the_obstacles() {
    // The triangle map's reachable sets, cut to free space: never larger than the uncut pieces,
    // and the difference is the part of the pieces covered by obstacles (computed independently
    // by sampling a grid of points inside each piece).
    let map = triangle_map();
    let btm = Btm::build(&map).unwrap();
    let best = SptPlanner::new(&btm)
        .shortest_path(p(50., 100.), p(50., 0.))
        .unwrap()
        .unwrap();
    let r = check_on_planes(
        &btm,
        &[TerrainPlane::new(110., -10., 30., 0.6)],
        &best.shp.taut,
    );
    // Areas are computed only when asked for.
    assert!(
        r.reachable_sets
            .iter()
            .all(|set| set.free_pieces.is_empty())
    );
    let mut r = r;
    let terrain = PlaneSeries::new(
        &[TerrainPlane::new(110., -10., 30., 0.6)],
        &TetherFrictionCone,
    )
    .unwrap();
    let ctx = FeasibilityContext {
        btm: &btm,
        terrain: &terrain,
        clearance: 0.5,
        tether_length: None,
    };
    fill_reachable_areas(&ctx, &mut r);
    assert!(!r.reachable_sets.is_empty());
    let area = |set: &rappel_planners::feasibility::AnchorReachableSet| {
        let raw: f64 = set.pieces.iter().map(|(poly, _)| poly.area()).sum();
        let free: f64 = set.free_pieces.iter().map(|(reg, _)| reg.area()).sum();
        (raw, free)
    };
    // The start's wedge covers the obstacle, so cutting must remove something there.
    assert!(r.reachable_sets.iter().any(|set| {
        let (raw, free) = area(set);
        free < raw - 1.0
    }));
    for set in &r.reachable_sets {
        let raw: f64 = set.pieces.iter().map(|(poly, _)| poly.area()).sum();
        let free: f64 = set.free_pieces.iter().map(|(reg, _)| reg.area()).sum();
        assert!(free <= raw + 1e-6, "free {free} > raw {raw}");
        // Monte Carlo-free estimate: a fine grid over each piece, counting points in free space.
        let mut inside = 0usize;
        let mut free_hits = 0usize;
        let step = 0.5;
        for (poly, _) in &set.pieces {
            let b = poly.aabb();
            let mut y = b.min.y + step / 2.0;
            while y < b.max.y {
                let mut x = b.min.x + step / 2.0;
                while x < b.max.x {
                    let q = p(x, y);
                    if poly.locate(&q) == rappel_geometry::polygon::PointInPolygon::Inside {
                        inside += 1;
                        if map.free_space_violation(&q).is_none() {
                            free_hits += 1;
                        }
                    }
                    x += step;
                }
                y += step;
            }
        }
        if inside > 0 {
            let estimate = raw * free_hits as f64 / inside as f64;
            assert!(
                (estimate - free).abs() <= 0.02 * raw + 1.0,
                "free area {free} vs grid estimate {estimate}"
            );
        }
    }
}

#[test]
fn one_ulp_in_the_map_does_not_flip_a_verdict() {
    // Issue 10: rounding an input in its last bits must not flip a feasibility verdict away from
    // true ties. Every obstacle corner is moved by one ulp (alternately up and down) and the
    // classes, found again on the perturbed map, must get the same verdicts. The reference is
    // the unperturbed plan.
    let terrain = PlaneSeries::new(
        &[
            TerrainPlane::new(25.0, 0.0, 35.0, 0.5),
            TerrainPlane::new(0.0, -25.0, 50.0, 0.5),
        ],
        &TetherFrictionCone,
    )
    .unwrap();
    let options = SearchOptions::default().with_max_classes(Some(4)).unwrap();
    let (mut compared, mut ties) = (0, 0);
    for seed in 0..25u64 {
        let Some(m) = random_map(9_000 + seed, 6) else {
            continue;
        };
        let (top, bottom) = if m.start.y > m.goal.y {
            (m.start, m.goal)
        } else {
            (m.goal, m.start)
        };
        let verdicts = |map: &Map| -> Option<Vec<(usize, bool)>> {
            let btm = Btm::build(map).ok()?;
            let ctx = FeasibilityContext {
                btm: &btm,
                terrain: &terrain,
                clearance: 0.3,
                tether_length: None,
            };
            let plan =
                plan_path_pair(&SptPlanner::new(&btm), top, bottom, &options, &ctx, false).ok()?;
            Some(
                plan.classes
                    .iter()
                    .map(|c| (c.class.shp.taut.anchors.len(), c.feasibility.feasible()))
                    .collect(),
            )
        };
        let mut k = 0usize;
        let nudged = Map::new(
            m.map.boundary.clone(),
            m.map
                .obstacles
                .iter()
                .map(|o| {
                    Polygon::new(
                        o.vertices
                            .iter()
                            .map(|v| {
                                k += 1;
                                if k.is_multiple_of(2) {
                                    p(v.x.next_up(), v.y.next_down())
                                } else {
                                    p(v.x.next_down(), v.y.next_up())
                                }
                            })
                            .collect(),
                    )
                })
                .collect(),
        );
        let (Some(a), Some(b)) = (verdicts(&m.map), verdicts(&nudged)) else {
            continue;
        };
        // A class whose anchors change under the nudge sits on a true tie (three corners in
        // line); only the classes found alike on both maps are compared.
        for (x, y) in a.iter().zip(&b) {
            if x.0 == y.0 {
                assert_eq!(x.1, y.1, "seed {seed}: {a:?} vs {b:?}");
                compared += 1;
            } else {
                ties += 1;
            }
        }
    }
    assert!(compared >= 30, "only {compared} classes compared");
    assert!(ties * 10 <= compared, "{ties} ties for {compared} classes");
}
