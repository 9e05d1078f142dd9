//! Ascent feasibility (thesis Alg. 5, eq. 2.7) and path pairs (Alg. 6): verdicts flip exactly where
//! the closed-form friction cone says, each condition of §2.4.2 is named when it fails, waypoints lie
//! on their visibility lines, and path pairs are free, homotopic and clear of the anchors
//! (checked with the homotopy crate's own functions).

use crate::common;

use common::random_map;
use nalgebra::Point2;
use rappel_geometry::btm::Btm;
use rappel_geometry::map::Map;
use rappel_geometry::polygon::Polygon;
use rappel_homotopy::crossing::CrossingSequence;
use rappel_homotopy::path::Path;
use rappel_mechanics::anchor_traversability::TetherLimit;
use rappel_mechanics::friction_cone::TetherFrictionCone;
use rappel_planners::feasibility::{
    FeasibilityContext, Impassability, Passability, admits_direction, check_feasibility,
    distance_to_segment, fill_reachable_areas, in_wedge, wedge_edges,
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
    let btm = Btm::from_map(&triangle_map()).unwrap();
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
    let btm = Btm::from_map(&triangle_map()).unwrap();
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
    let btm = Btm::from_map(&map).unwrap();
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

/// The random-map tests' terrain: one 40° plane with friction 0.6 over the maps.
fn random_map_terrain() -> PlaneSeries {
    PlaneSeries::new(
        &[TerrainPlane::new(30., -30., 40., 0.6)],
        &TetherFrictionCone,
    )
    .unwrap()
}

/// A random map's start and goal, the higher first (the descent starts uphill).
fn top_and_bottom(start: Point2<f64>, goal: Point2<f64>) -> (Point2<f64>, Point2<f64>) {
    if start.y > goal.y {
        (start, goal)
    } else {
        (goal, start)
    }
}

/// The pipelined Alg. 6 (the search on its own thread, ahead of the checks) answers exactly as a
/// plain loop over the classes does: the same classes with the same feasibility and pair
/// failures, the same pair, termination, stop reason and counters, when listing every class and
/// when stopping at the first pair (where the search thread has run ahead and is stopped).
#[test]
fn the_pipelined_plan_equals_a_sequential_loop() {
    use rappel_planners::path_pair::{ClassOutcome, PairPlan};
    use rappel_planners::spt::Termination;
    let terrain = random_map_terrain();
    let mut compared = 0;
    let mut stopped_early = 0;
    for seed in 0..12u64 {
        let Some(m) = random_map(5_000 + seed, 7) else {
            continue;
        };
        let btm = Btm::from_map(&m.map).unwrap();
        let ctx = FeasibilityContext {
            btm: &btm,
            terrain: &terrain,
            clearance: 0.3,
            tether_length: None,
        };
        let (top, bottom) = top_and_bottom(m.start, m.goal);
        let planner = SptPlanner::new(&btm);
        for (classes, stop_at_first) in [(1, false), (6, false), (6, true)] {
            let options = SearchOptions::default()
                .with_max_classes(Some(classes))
                .unwrap();
            // The reference: one loop on this thread.
            let mut search = planner.search(top, bottom, &options).unwrap();
            let mut reference = PairPlan {
                classes: Vec::new(),
                pair: None,
                termination: Termination::ClassCount,
                stop_reason: None,
                stats: Default::default(),
            };
            while let Some(class) = search.next_best().unwrap() {
                let feasibility = check_feasibility(&ctx, &class.shp.taut);
                let mut pair_failure = None;
                if reference.pair.is_none() && feasibility.feasible() {
                    match path_pair(&ctx, &class, &feasibility) {
                        Ok(p) => reference.pair = Some(p),
                        Err(e) => pair_failure = Some(e),
                    }
                }
                reference.classes.push(ClassOutcome {
                    class,
                    feasibility,
                    pair_failure,
                });
                if stop_at_first && reference.pair.is_some() {
                    break;
                }
            }
            reference.termination = search.termination().unwrap_or(Termination::ClassCount);
            reference.stop_reason = search.stop_reason();
            reference.stats = search.stats();
            let plan =
                plan_path_pair(&planner, top, bottom, &options, &ctx, stop_at_first).unwrap();
            assert_eq!(
                plan, reference,
                "seed {seed}, {classes} classes, {stop_at_first}"
            );
            compared += 1;
            stopped_early += usize::from(stop_at_first && plan.classes.len() < classes);
        }
    }
    assert!(compared >= 12, "only {compared} plans compared");
    assert!(
        stopped_early >= 1,
        "no plan stopped at its first pair early"
    );
}

#[test]
fn waypoints_and_pairs_on_random_maps() {
    let terrain = random_map_terrain();
    let clearance = 0.3;
    let mut pairs = 0;
    let mut no_pair = Vec::new();
    for seed in 0..40u64 {
        let Some(m) = random_map(5_000 + seed, 7) else {
            continue;
        };
        let btm = Btm::from_map(&m.map).unwrap();
        let ctx = FeasibilityContext {
            btm: &btm,
            terrain: &terrain,
            clearance,
            tether_length: None,
        };
        let options = SearchOptions::default().with_max_classes(Some(4)).unwrap();
        let (top, bottom) = top_and_bottom(m.start, m.goal);
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
    let btm = Btm::from_map(&map).unwrap();
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
        let (top, bottom) = top_and_bottom(m.start, m.goal);
        // Per class: the anchor count, the verdict, and per anchor examined whether it was
        // passed and the length of its reachable part (computed exactly: it may move by
        // rounding, never jump).
        type Verdict = (usize, bool, Vec<(bool, f64)>);
        let verdicts = |map: &Map| -> Option<Vec<Verdict>> {
            let btm = Btm::from_map(map).ok()?;
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
                    .map(|c| {
                        let anchors = c
                            .feasibility
                            .anchors
                            .iter()
                            .filter(|a| !matches!(a.passability, Passability::NotReached))
                            .map(|a| {
                                (
                                    matches!(a.passability, Passability::Passable { .. }),
                                    a.reachable_part.iter().map(|[u, v]| (v - u).norm()).sum(),
                                )
                            })
                            .collect();
                        (
                            c.class.shp.taut.anchors.len(),
                            c.feasibility.feasible(),
                            anchors,
                        )
                    })
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
                assert_eq!(x.2.len(), y.2.len(), "seed {seed}: {a:?} vs {b:?}");
                for (p, q) in x.2.iter().zip(&y.2) {
                    assert_eq!(p.0, q.0, "seed {seed}: {a:?} vs {b:?}");
                    assert!((p.1 - q.1).abs() <= 1e-6, "seed {seed}: {a:?} vs {b:?}");
                }
                compared += 1;
            } else {
                ties += 1;
            }
        }
    }
    assert!(compared >= 30, "only {compared} classes compared");
    assert!(ties * 10 <= compared, "{ties} ties for {compared} classes");
}

/// `u(phi)`: the unit vector at `phi` degrees from the fall line (`-y`), positive towards `+x`.
fn fall(phi: f64) -> nalgebra::Vector2<f64> {
    let r = phi.to_radians();
    nalgebra::Vector2::new(r.sin(), -r.cos())
}

/// The sliver map: the taut tether from `S` wraps the tip `A = (50, 50)` of a long wedge `O1`
/// coming in at 20° from the fall line and leaves for the goal `G` at -10°; a second wedge `B`
/// points up at `A`, its tip `p` 35 mm below `A` on the bisector (5°) of the tether to the goal and
/// the visibility line. Returns the map, start, goal and `p`.
fn sliver_map(h: f64) -> (Map, Point2<f64>, Point2<f64>, Point2<f64>) {
    let a = p(50., 50.);
    let start = a - fall(20.) * 40.;
    let goal = a + fall(-10.) * 40.;
    let tip = a + fall(5.) * h;
    let map = Map::new(
        Polygon::new(vec![p(0., 0.), p(100., 0.), p(100., 100.), p(0., 100.)]),
        vec![
            Polygon::new(vec![a, p(10., 40.), p(10., 60.)]),
            Polygon::new(vec![tip, a + fall(3.) * 20., a + fall(7.) * 20.]),
        ],
    );
    (map, start, goal, tip)
}

#[test]
fn a_reachable_sliver_narrower_than_any_ladder_is_found() {
    // Zero clearance, so the visibility edge starts at the anchor itself. The tether's sweep from
    // the goal (directly, or in along the tether first) meets B's tip as soon as the waypoint is
    // h / cos(15°) from A: the reachable part is (0, 36.2 mm), narrower than the first rung of
    // the sampled version's ladder (MIN_WAYPOINT_STEP_FRACTION of the 100 m extent: 50 mm), which
    // therefore found nothing and called A impassable. The reference end is the closed form of
    // the isosceles sweep triangle (A, A + t e, A + t d) reaching the tip on its axis.
    let h = 0.035;
    let (map, start, goal, tip) = sliver_map(h);
    let btm = Btm::from_map(&map).unwrap();
    let best = SptPlanner::new(&btm)
        .shortest_path(start, goal)
        .unwrap()
        .unwrap();
    let taut = &best.shp.taut;
    assert_eq!(taut.anchors.len(), 1, "{:?}", taut.points);
    assert_eq!(taut.anchors[0].point, p(50., 50.));
    let terrain = PlaneSeries::new(
        &[TerrainPlane::new(100., 0., 45., 0.6)],
        &TetherFrictionCone,
    )
    .unwrap();
    let ctx = FeasibilityContext {
        btm: &btm,
        terrain: &terrain,
        clearance: 0.0,
        tether_length: None,
    };
    let r = check_feasibility(&ctx, taut);
    assert!(r.feasible(), "{}", r.describe());
    let a = &r.anchors[0];
    assert_eq!(a.reachable_part.len(), 1, "{:?}", a.reachable_part);
    let [u, v] = a.reachable_part[0];
    let apex = p(50., 50.);
    let half = ((1.0 + fall(20.).dot(&fall(-10.))) / 2.0).sqrt();
    let expected = (tip - apex).norm() / half;
    assert_eq!(u, apex);
    // The clear sweep's end is located to within the tie width (1e-10 of the 100 m extent).
    let end_tol = 2.0 * rappel_planners::feasibility::TIE_WIDTH_FRACTION * 100.0;
    assert!(
        ((v - apex).norm() - expected).abs() < end_tol,
        "reachable to {} m, closed form {expected} m",
        (v - apex).norm()
    );
    let ladder = rappel_planners::feasibility::MIN_WAYPOINT_STEP_FRACTION * 100.0;
    assert!((v - apex).norm() < ladder);
    let Passability::Passable { waypoint, .. } = a.passability else {
        panic!("{:?}", a.passability);
    };
    assert!((waypoint - apex).norm() > 0.0 && (waypoint - apex).norm() < expected);
    // One ulp on every coordinate of B, either way: the same verdict and the same sliver.
    for sign in [1.0, -1.0] {
        let nudge = |x: f64, k: usize| {
            if k.is_multiple_of(2) == (sign > 0.0) {
                x.next_up()
            } else {
                x.next_down()
            }
        };
        let b = &map.obstacles[1];
        let moved = Polygon::new(
            b.vertices
                .iter()
                .enumerate()
                .map(|(k, v)| p(nudge(v.x, k), nudge(v.y, k + 1)))
                .collect(),
        );
        let nudged = Map::new(map.boundary.clone(), vec![map.obstacles[0].clone(), moved]);
        let btm = Btm::from_map(&nudged).unwrap();
        let ctx = FeasibilityContext {
            btm: &btm,
            terrain: &terrain,
            clearance: 0.0,
            tether_length: None,
        };
        let again = SptPlanner::new(&btm)
            .shortest_path(start, goal)
            .unwrap()
            .unwrap();
        assert_eq!(again.shp.taut.points, taut.points);
        let r = check_feasibility(&ctx, &again.shp.taut);
        assert!(r.feasible(), "nudged {sign}: {}", r.describe());
        let [_, v] = r.anchors[0].reachable_part[0];
        assert!(((v - apex).norm() - expected).abs() < end_tol);
    }
    // Widening the gap past the ladder's first rung keeps it passable; closing it (B's tip on the
    // tether's own line is a tie, so just short of it) leaves a reachable part that shrinks in
    // proportion: the verdict follows the geometry, not a sample spacing.
    for h in [0.001, 0.01, 0.2] {
        let (map, start, goal, tip) = sliver_map(h);
        let btm = Btm::from_map(&map).unwrap();
        let best = SptPlanner::new(&btm)
            .shortest_path(start, goal)
            .unwrap()
            .unwrap();
        let ctx = FeasibilityContext {
            btm: &btm,
            terrain: &terrain,
            clearance: 0.0,
            tether_length: None,
        };
        let r = check_feasibility(&ctx, &best.shp.taut);
        assert!(r.feasible(), "h {h}: {}", r.describe());
        let [_, v] = r.anchors[0].reachable_part[0];
        let expected = (tip - apex).norm() / half;
        assert!(((v - apex).norm() - expected).abs() < end_tol);
    }
}

/// Independent reference for one move of the crossing model (`feasibility::crossing` docs): the
/// straight move `from -> w` lies in the wedge of `apex` (checked at the move's ends, where it
/// crosses each band edge, against both bands there, and at 64 points between) and the swept
/// triangle `(apex, from, w)` is free: no map vertex inside it (farther than `tol` from its sides)
/// and no map edge properly crossing `from -> w`. Plain floating point, written apart from the
/// code under test (which traces the loop through the BTM).
fn brute_move(
    map: &Map,
    terrain: &PlaneSeries,
    apex: Point2<f64>,
    from: Point2<f64>,
    w: Point2<f64>,
    tol: f64,
) -> bool {
    let admits = |x: Point2<f64>, limit: rappel_mechanics::anchor_traversability::TetherLimit| {
        let d = x - apex;
        x == apex || limit.admits(d.x.abs().atan2(-d.y))
    };
    let mut wedge = admits(from, terrain.limit_at(&from)) && admits(w, terrain.limit_at(&w));
    for k in 0..=64 {
        let x = from + (w - from) * (k as f64 / 64.0);
        wedge &= admits(x, terrain.limit_at(&x));
    }
    let planes = terrain.planes();
    for (k, plane) in planes.iter().enumerate().skip(1) {
        let yb = plane.y_top;
        if (from.y - yb) * (w.y - yb) < 0.0 {
            let x = from + (w - from) * ((yb - from.y) / (w.y - from.y));
            wedge &= admits(x, terrain.limits()[k - 1]) && admits(x, terrain.limits()[k]);
        }
    }
    if !wedge {
        return false;
    }
    let cross = |o: Point2<f64>, a: Point2<f64>, b: Point2<f64>| {
        (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x)
    };
    let rings: Vec<&Polygon> = std::iter::once(&map.boundary)
        .chain(map.obstacles.iter())
        .collect();
    let corners = [apex, from, w];
    let area = cross(apex, from, w);
    for ring in &rings {
        let n = ring.vertices.len();
        for i in 0..n {
            let (a, b) = (ring.vertices[i], ring.vertices[(i + 1) % n]);
            // A vertex strictly inside the triangle.
            let inside = (0..3).all(|k| {
                let (s, e) = (corners[k], corners[(k + 1) % 3]);
                let side = cross(s, e, a) * area.signum();
                side > tol * (e - s).norm()
            });
            if inside {
                return false;
            }
            // A map edge properly crossing the move.
            // (Ends within `tol` of the other segment's line touch, as the via point on a
            // tether running along an obstacle edge does.)
            let (lm, le) = ((w - from).norm(), (b - a).norm());
            let (d1, d2) = (cross(from, w, a), cross(from, w, b));
            let (d3, d4) = (cross(a, b, from), cross(a, b, w));
            let apart = |x: f64, y: f64, len: f64| x * y < 0.0 && x.abs().min(y.abs()) > tol * len;
            if apart(d1, d2, lm) && apart(d3, d4, le) {
                return false;
            }
        }
    }
    true
}

/// The reference verdict for `w(t)`: the direct move from `q`, or in along the tether to
/// `max(t, c)` from `apex` (while nearer than `q`) and across.
#[allow(clippy::too_many_arguments)]
fn brute_reached(
    map: &Map,
    terrain: &PlaneSeries,
    apex: Point2<f64>,
    q: Point2<f64>,
    dir: nalgebra::Vector2<f64>,
    c: f64,
    t: f64,
    tol: f64,
) -> bool {
    let w = apex + dir * t;
    let r = (q - apex).norm();
    let s = t.max(c);
    let mut starts = vec![q];
    if s < r {
        starts.push(apex + (q - apex) * (s / r));
    }
    starts
        .into_iter()
        .any(|from| brute_move(map, terrain, apex, from, w, tol))
}

/// Every examined anchor's reachable part against the brute-force reference, sampled densely
/// along the usable visibility edge, and just inside and just outside each end of the part.
/// Returns (samples reachable, samples not, parts ending strictly inside the usable edge).
fn check_parts_against_brute_force(
    map: &Map,
    terrain: &PlaneSeries,
    c: f64,
    taut: &rappel_homotopy::funnel::TautPath,
    r: &rappel_planners::feasibility::FeasibilityReport,
    label: &str,
) -> (usize, usize, usize) {
    let (mut yes, mut no, mut interior_ends) = (0, 0, 0);
    let b = map.boundary.aabb();
    let extent = (b.max.x - b.min.x).max(b.max.y - b.min.y);
    let (delta, tol) = (1e-6 * extent, 1e-9 * extent);
    let n = taut.anchors.len();
    for a in &r.anchors {
        let j = a.index;
        if a.visibility_edge.is_none() || matches!(a.passability, Passability::NotReached) {
            continue;
        }
        let q = if j == n {
            taut.goal()
        } else {
            match r.anchors[j].passability {
                Passability::Passable { waypoint, .. } => waypoint,
                _ => continue,
            }
        };
        let apex = a.anchor.point;
        let prev = if j == 1 {
            taut.start()
        } else {
            taut.anchors[j - 2].point
        };
        let dir = (apex - prev).normalize();
        let set = r.reachable_sets.iter().find(|s| s.anchor == j).unwrap();
        let [_, end] = set.visibility_line.unwrap();
        let pieces: Vec<(f64, f64)> = terrain
            .pieces(apex, end)
            .into_iter()
            .filter(|(_, _, l)| l.admits(a.psi))
            .map(|(x, y, _)| ((x - apex).norm(), (y - apex).norm()))
            .filter(|(t0, t1)| t1 > t0)
            .map(|(t0, t1)| {
                let m = c.min((t1 - t0) / 4.0);
                (t0 + m, t1 - m)
            })
            .collect();
        let part: Vec<(f64, f64)> = a
            .reachable_part
            .iter()
            .map(|[u, v]| ((u - apex).dot(&dir), (v - apex).dot(&dir)))
            .collect();
        let inside = |t: f64| part.iter().any(|&(u, v)| u < t && t < v);
        let near_end = |t: f64| {
            part.iter()
                .chain(pieces.iter())
                .any(|&(u, v)| (t - u).abs() < 2.0 * delta || (t - v).abs() < 2.0 * delta)
        };
        let mut ts = Vec::new();
        for &(lo, hi) in &pieces {
            ts.extend((1..200).map(|k| lo + (hi - lo) * k as f64 / 200.0));
        }
        for &(u, v) in &part {
            for e in [u, v] {
                if pieces
                    .iter()
                    .any(|&(lo, hi)| lo + 3.0 * delta < e && e < hi - 3.0 * delta)
                {
                    interior_ends += 1;
                    // Just inside and just outside the end: the reference must agree.
                    ts.extend([e - 3.0 * delta, e + 3.0 * delta]);
                }
            }
        }
        for t in ts {
            if t <= 0.0 || near_end(t) || !pieces.iter().any(|&(lo, hi)| lo < t && t < hi) {
                continue;
            }
            let expected = brute_reached(map, terrain, apex, q, dir, c, t, tol);
            if inside(t) != expected && std::env::var("H10B_DEBUG").is_ok() {
                let w = apex + dir * t;
                let rr = (q - apex).norm();
                let via = apex + (q - apex) * (t.max(c) / rr);
                eprintln!(
                    "apex {apex:?} q {q:?} w {w:?} via {via:?} r {rr} released {:?}",
                    r.anchors.get(j).map(|x| x.anchor.point)
                );
                for from in [q, via] {
                    eprintln!(
                        "  from {from:?}: move {}",
                        brute_move(map, terrain, apex, from, w, tol)
                    );
                }
                eprintln!("{:?}", map);
            }
            assert_eq!(
                inside(t),
                expected,
                "{label}: anchor {j}, t = {t}: reachable part {part:?} of usable {pieces:?}"
            );
            if expected {
                yes += 1;
            } else {
                no += 1;
            }
        }
        // The verdict and the waypoint follow the part.
        match a.passability {
            Passability::Passable { waypoint, .. } => {
                assert!(inside((waypoint - apex).dot(&dir)), "{label}: anchor {j}");
            }
            _ => assert!(part.is_empty(), "{label}: anchor {j}: {part:?}"),
        }
    }
    (yes, no, interior_ends)
}

#[test]
fn reachable_parts_agree_with_brute_force_sampling() {
    // Two bands (the wedge narrows across y = 0), a 0.3 m clearance, up to six classes on each
    // seeded map; plus the sliver map with zero clearance.
    let terrain = PlaneSeries::new(
        &[
            TerrainPlane::new(25.0, 0.0, 35.0, 0.5),
            TerrainPlane::new(0.0, -25.0, 50.0, 0.5),
        ],
        &TetherFrictionCone,
    )
    .unwrap();
    let c = 0.3;
    let options = SearchOptions::default().with_max_classes(Some(6)).unwrap();
    let (mut yes, mut no, mut ends) = (0, 0, 0);
    for seed in 0..60u64 {
        let Some(m) = random_map(7_000 + seed, 7) else {
            continue;
        };
        let btm = Btm::from_map(&m.map).unwrap();
        let ctx = FeasibilityContext {
            btm: &btm,
            terrain: &terrain,
            clearance: c,
            tether_length: None,
        };
        let (top, bottom) = top_and_bottom(m.start, m.goal);
        let classes = SptPlanner::new(&btm)
            .search(top, bottom, &options)
            .unwrap()
            .run()
            .unwrap()
            .classes;
        for (k, class) in classes.iter().enumerate() {
            let r = check_feasibility(&ctx, &class.shp.taut);
            let (y, n, e) = check_parts_against_brute_force(
                &m.map,
                &terrain,
                c,
                &class.shp.taut,
                &r,
                &format!("seed {seed} class {k}"),
            );
            yes += y;
            no += n;
            ends += e;
        }
    }
    let (map, start, goal, _) = sliver_map(0.035);
    let btm = Btm::from_map(&map).unwrap();
    let flat_cone = PlaneSeries::new(
        &[TerrainPlane::new(100., 0., 45., 0.6)],
        &TetherFrictionCone,
    )
    .unwrap();
    let ctx = FeasibilityContext {
        btm: &btm,
        terrain: &flat_cone,
        clearance: 0.0,
        tether_length: None,
    };
    let best = SptPlanner::new(&btm)
        .shortest_path(start, goal)
        .unwrap()
        .unwrap();
    let r = check_feasibility(&ctx, &best.shp.taut);
    let (_, _, e) =
        check_parts_against_brute_force(&map, &flat_cone, 0.0, &best.shp.taut, &r, "sliver");
    assert!(e >= 1, "the sliver's end is checked");
    // Both verdicts occur, and parts end inside the usable edge often enough to matter.
    assert!(yes >= 1_000 && no >= 200, "{yes} reachable, {no} not");
    assert!(
        ends >= 6,
        "only {ends} interior ends ({yes} reachable, {no} not)"
    );
}

#[test]
fn reachable_areas_stay_within_the_tether_left() {
    // With a tether 1 m longer than the taut path, each set's area lies in the square of
    // half-side "tether left at its anchor" around it, and is no larger than without a tether
    // length.
    let map = triangle_map();
    let btm = Btm::from_map(&map).unwrap();
    let best = SptPlanner::new(&btm)
        .shortest_path(p(50., 100.), p(50., 0.))
        .unwrap()
        .unwrap();
    let taut = &best.shp.taut;
    let terrain = PlaneSeries::new(
        &[TerrainPlane::new(110., -10., 30., 0.6)],
        &TetherFrictionCone,
    )
    .unwrap();
    let areas = |tether: Option<f64>| {
        let ctx = FeasibilityContext {
            btm: &btm,
            terrain: &terrain,
            clearance: 0.5,
            tether_length: tether,
        };
        let mut r = check_feasibility(&ctx, taut);
        fill_reachable_areas(&ctx, &mut r);
        r.reachable_sets
    };
    let unbounded = areas(None);
    let total = taut.length + 1.0;
    let bounded = areas(Some(total));
    assert_eq!(unbounded.len(), bounded.len());
    let mut used = 0.0;
    let mut at = taut.start();
    for (u, b) in unbounded.iter().zip(&bounded) {
        if b.anchor > 0 {
            used += (b.apex - at).norm();
            at = b.apex;
        }
        let left = total - used;
        let area = |s: &rappel_planners::feasibility::AnchorReachableSet| -> f64 {
            s.free_pieces.iter().map(|(reg, _)| reg.area()).sum()
        };
        assert!(area(b) <= area(u) + 1e-6, "set {}", b.anchor);
        assert!(area(b) > 0.0, "set {}", b.anchor);
        for (reg, _) in &b.free_pieces {
            for v in &reg.outer.vertices {
                assert!(
                    (v.x - b.apex.x).abs() <= left + 1e-9 && (v.y - b.apex.y).abs() <= left + 1e-9,
                    "set {}: {v:?} beyond {left} m of {:?}",
                    b.anchor,
                    b.apex
                );
            }
        }
    }
    // The last anchor's set is cut: its wedge reaches the bottom of the map (y = -10), its tether
    // (1 m more than the 85 m down to the goal at y = 0) does not.
    let (b, u) = (bounded.last().unwrap(), unbounded.last().unwrap());
    assert!(
        area_of(b) < area_of(u) - 1.0,
        "{} vs {}",
        area_of(b),
        area_of(u)
    );
}

fn area_of(s: &rappel_planners::feasibility::AnchorReachableSet) -> f64 {
    s.free_pieces.iter().map(|(reg, _)| reg.area()).sum()
}

/// Wedge membership follows the exact side of a wedge edge, to the last bit: a point exactly on an
/// edge (the apex at the origin and the edge direction scaled by 8, so the point is exact) is
/// outside (the strict inequality of §2.4.2); one ulp outward stays outside, one ulp inward is
/// inside, for either edge, nudging x or y, on several slopes. The reference side is the sign of
/// the nudge (moving a point on the right edge right or up turns it away from the fall line),
/// independent of the predicates; the float angle test this replaced got some of them wrong.
#[test]
fn wedge_verdicts_follow_the_exact_side_by_one_ulp() {
    let apex = p(0.0, 0.0);
    for (slope, mu) in [
        (30.0, 0.4),
        (45.0, 0.4),
        (50.0, 0.3),
        (63.0, 0.7),
        (72.5, 0.15),
    ] {
        let plane = TerrainPlane {
            y_top: 100.0,
            y_bottom: -100.0,
            slope_deg: slope,
            friction: mu,
        };
        let terrain = PlaneSeries::new(&[plane], &TetherFrictionCone).unwrap();
        let limit = terrain.limits()[0];
        let TetherLimit::Cone { max_angle } = limit else {
            panic!("slope {slope} mu {mu}: expected a tether-demand plane");
        };
        let deep = p(0.0, -8.0);
        for (edge, sign) in wedge_edges(max_angle).into_iter().zip([1.0, -1.0]) {
            let on = p(edge.x * 8.0, edge.y * 8.0);
            let outward_x = p(
                if sign > 0.0 {
                    on.x.next_up()
                } else {
                    on.x.next_down()
                },
                on.y,
            );
            let inward_x = p(
                if sign > 0.0 {
                    on.x.next_down()
                } else {
                    on.x.next_up()
                },
                on.y,
            );
            let cases = [
                (on, false, "on the edge"),
                (outward_x, false, "one ulp outward in x"),
                (inward_x, true, "one ulp inward in x"),
                (p(on.x, on.y.next_up()), false, "one ulp up"),
                (p(on.x, on.y.next_down()), true, "one ulp down"),
            ];
            for (x, inside, what) in cases {
                let ctx = format!("slope {slope} mu {mu}, edge {sign}, {what}: {x:?}");
                assert_eq!(admits_direction(&limit, &apex, &x), inside, "{ctx}");
                assert_eq!(in_wedge(&terrain, &apex, &x, &x), inside, "{ctx}");
                // A move from deep inside the wedge to the point: its far end decides.
                assert_eq!(in_wedge(&terrain, &apex, &deep, &x), inside, "{ctx}");
                assert_eq!(in_wedge(&terrain, &apex, &x, &deep), inside, "{ctx}");
            }
        }
    }
}
