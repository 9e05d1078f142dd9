//! The online session follows Alg. 6's pair and survives what it senses (issue 29 §5):
//! - on the prior map the session's initial class, descent and ascent are those of
//!   `plan_path_pair` (Alg. 6), also when the shortest class has no pair and Alg. 6 moves on;
//! - a descent the session replans keeps the clearance from its class's anchors, or the
//!   session says why it cannot (a typed `ClearanceShortfall`);
//! - the simulator never fails on valid prior/true maps: staggered walls whose shifts
//!   interleave, and random truths made from generated crater strips with obstacles removed,
//!   added, shifted and walls laid across them.

use crate::common::random_map;
use nalgebra::{Point2, Vector2};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rappel_geometry::btm::Btm;
use rappel_geometry::generate::{CraterStripOptions, crater_strip};
use rappel_geometry::map::Map;
use rappel_geometry::polygon::Polygon;
use rappel_mechanics::friction_cone::TetherFrictionCone;
use rappel_planners::feasibility::{CLEARANCE_TOLERANCE, FeasibilityContext, distance_to_segment};
use rappel_planners::online::simulate::{Ending, simulate_with};
use rappel_planners::online::{
    ClearanceShortfall, Decision, OnlineOptions, OnlineSession, SimulationOptions,
};
use rappel_planners::path_pair::plan_path_pair;
use rappel_planners::spt::SptPlanner;
use rappel_planners::terrain::PlaneSeries;
use rappel_terrain::plane_series::TerrainPlane;

fn p(x: f64, y: f64) -> Point2<f64> {
    Point2::new(x, y)
}

/// One tether-demand plane over the whole map (so ascents follow Alg. 5's routes), or flat.
fn terrain(map: &Map, steep: bool) -> PlaneSeries {
    if !steep {
        return PlaneSeries::flat();
    }
    let b = map.aabb();
    let plane = TerrainPlane {
        y_top: b.max.y,
        y_bottom: b.min.y,
        slope_deg: 45.0,
        friction: 0.4,
    };
    PlaneSeries::new(&[plane], &TetherFrictionCone).expect("a valid plane")
}

/// The session's initial plan against Alg. 6 on the same map; `true` when a pair was compared.
fn check_initial_plan(
    map: &Map,
    start: Point2<f64>,
    goal: Point2<f64>,
    steep: bool,
    what: &str,
) -> bool {
    let options = OnlineOptions::default();
    let Ok(session) = OnlineSession::new(map, start, goal, terrain(map, steep), options.clone())
    else {
        return false;
    };
    let btm = Btm::from_map(map).expect("the session built it");
    let plane_series = terrain(map, steep);
    let ctx = FeasibilityContext {
        btm: &btm,
        terrain: &plane_series,
        clearance: options.clearance,
        tether_length: options.tether_length,
    };
    let plan = plan_path_pair(
        &SptPlanner::new(&btm),
        start,
        goal,
        &options.search,
        &ctx,
        true,
    )
    .expect("Alg. 6 runs");
    let Some(pair) = plan.pair else {
        // No class has a pair: the session follows a feasible class with the reason, or none.
        if let Some(c) = session.class() {
            assert!(
                c.pair_failure.is_some(),
                "{what}: a pair Alg. 6 did not find"
            );
            assert!(
                matches!(
                    session.clearance_shortfall(),
                    Some(ClearanceShortfall::NoPair { .. })
                ),
                "{what}"
            );
        }
        return false;
    };
    let c = session.class().expect("Alg. 6 found a class");
    assert_eq!(c.shp.crossings, pair.crossings, "{what}: another class");
    assert_eq!(c.descent, pair.descent, "{what}: another descent");
    assert_eq!(c.ascent, pair.ascent, "{what}: another ascent");
    assert_eq!(c.pair_failure, None, "{what}");
    assert_eq!(session.clearance_shortfall(), None, "{what}");
    if start != goal {
        assert_eq!(
            session.route(),
            &pair.descent[..],
            "{what}: the robot's route"
        );
    }
    true
}

/// The failure of the Monte Carlo: the shortest class's pair cannot be built (the goal lies
/// 0.36 m from the corner the tether turns at, inside the 0.5 m clearance), Alg. 6 takes rank 2;
/// the session used to descend rank 1's bare taut tether, 0 m from that corner.
#[test]
fn online_starts_on_alg6_class_when_rank_1_has_no_pair() {
    let map = Map::new(
        Polygon::new(vec![p(0., 0.), p(40., 0.), p(40., 100.), p(0., 100.)]),
        vec![Polygon::new(vec![
            p(18., 50.),
            p(22., 50.),
            p(22., 54.),
            p(18., 54.),
        ])],
    );
    let (start, goal) = (p(10., 95.), p(18.3, 49.8));
    assert!(check_initial_plan(&map, start, goal, false, "box"));
    // On the steep plane no class is feasible: the session agrees there is none.
    assert!(!check_initial_plan(&map, start, goal, true, "box, steep"));
    let session = OnlineSession::new(
        &map,
        start,
        goal,
        PlaneSeries::flat(),
        OnlineOptions::default(),
    )
    .unwrap();
    let c = session.class().unwrap();
    // Rank 2 goes east of the box: its tether turns at (22, 54) and (22, 50).
    assert!(c.shp.taut.anchors.iter().any(|a| a.point == p(22., 50.)));
    // The bare rank-1 tether turned at (18, 50), 0.36 m from the goal; the descent followed now
    // keeps the clearance from every corner its tether turns at.
    assert!(!c.shp.taut.anchors.iter().any(|a| a.point == p(18., 50.)));
    for a in &c.shp.taut.anchors {
        let closest = session
            .route()
            .windows(2)
            .map(|w| distance_to_segment(&a.point, &w[0], &w[1]))
            .fold(f64::INFINITY, f64::min);
        assert!(
            closest >= 0.5,
            "the route passes {closest} m from {:?}",
            a.point
        );
    }
}

/// Random maps, crater strips, flat and steep: the initial plan is Alg. 6's.
#[test]
fn online_initial_plan_is_alg6_pair_on_generated_maps() {
    let mut compared = 0;
    for seed in 0..24u64 {
        if let Some(m) = random_map(seed, 6) {
            for steep in [false, true] {
                let what = format!("random map {seed}, steep {steep}");
                compared += usize::from(check_initial_plan(&m.map, m.start, m.goal, steep, &what));
            }
        }
    }
    for seed in 1..=6u64 {
        let mut o = CraterStripOptions::new(30, seed);
        o.width = 40.0;
        let g = crater_strip(&o).unwrap();
        for steep in [false, true] {
            let what = format!("crater strip {seed}, steep {steep}");
            compared += usize::from(check_initial_plan(&g.map, g.start, g.goal, steep, &what));
        }
    }
    assert!(compared >= 30, "only {compared} pairs compared");
}

/// `count` walls 2 m thick across a 100 m strip, `gap` apart from `y0` down, alternately on the
/// west (`x` 1-70) and the east (30-99) side, the first on the west when `west_first`.
fn staggered(count: usize, y0: f64, gap: f64, west_first: bool) -> Vec<Polygon> {
    (0..count)
        .map(|k| {
            let y = y0 - gap * k as f64;
            let west = (k % 2 == 0) == west_first;
            let (x0, x1) = if west { (1.0, 70.0) } else { (30.0, 99.0) };
            Polygon::new(vec![p(x0, y), p(x1, y), p(x1, y + 2.0), p(x0, y + 2.0)])
        })
        .collect()
}

/// Staggered walls, each truly one row lower than the prior says: a wall's true outline lies
/// where the prior has the next wall (on the other side), so every addition needs the room of
/// a removal that is sensed only through it, and those chain down the whole slope. This failed
/// with "obstacles overlap" (the simulator pulled in one level of removals only).
#[test]
fn online_survives_staggered_walls_shifted_a_row() {
    let boundary = Polygon::new(vec![p(0., 0.), p(100., 0.), p(100., 200.), p(0., 200.)]);
    let prior = Map::new(boundary.clone(), staggered(8, 150.0, 10.0, true));
    let truth = Map::new(boundary, staggered(8, 140.0, 10.0, true));
    prior.validate().unwrap();
    truth.validate().unwrap();
    for steep in [false, true] {
        let (report, session) = simulate_with(
            &prior,
            &truth,
            p(50., 195.),
            p(50., 5.),
            terrain(&prior, steep),
            &SimulationOptions::default(),
            &mut |_, _| {},
        )
        .unwrap_or_else(|e| panic!("steep {steep}: {e}"));
        if steep {
            // Zigzags across a 45 degree, mu 0.4 slope: a clean "no", no error.
            assert!(!report.ending.reached());
            continue;
        }
        assert_eq!(report.ending, Ending::Goal);
        assert!(report.homotopic);
        // The first wall's true row lies beyond the sensor's reach of the descent: at most that
        // difference stays unsensed.
        assert!(report.unsensed <= 1, "{}", report.unsensed);
        assert_eq!(session.btm().map().obstacles.len(), 8);
    }
}

/// A random convex polygon around `c` of radius about `r`.
fn rock(rng: &mut ChaCha8Rng, c: Point2<f64>, r: f64) -> Polygon {
    let n = rng.random_range(3..8usize);
    let offset = rng.random_range(0.0..1.0);
    Polygon::new(
        (0..n)
            .map(|i| {
                let a = (i as f64 + offset) * std::f64::consts::TAU / n as f64;
                c + Vector2::new(a.cos(), a.sin()) * r
            })
            .collect(),
    )
}

/// A wall `length` long and 1.5 m thick at `c`, turned by `angle`.
fn wall(c: Point2<f64>, length: f64, angle: f64) -> Polygon {
    let u = Vector2::new(angle.cos(), angle.sin()) * (length / 2.0);
    let v = Vector2::new(-angle.sin(), angle.cos()) * 0.75;
    Polygon::new(vec![c - u - v, c + u - v, c + u + v, c - u + v])
}

/// Adds `polygon` to `obstacles`, first dropping every obstacle whose box it comes within 0.3 m
/// of; keeps the change when the map stays valid with `start` and `goal` free.
fn lay(obstacles: &mut Vec<Polygon>, boundary: &Polygon, polygon: Polygon, ends: [Point2<f64>; 2]) {
    let b = polygon.aabb();
    let near = |o: &Polygon| {
        let a = o.aabb();
        a.min.x <= b.max.x + 0.3
            && b.min.x <= a.max.x + 0.3
            && a.min.y <= b.max.y + 0.3
            && b.min.y <= a.max.y + 0.3
    };
    let mut next: Vec<Polygon> = obstacles.iter().filter(|o| !near(o)).cloned().collect();
    next.push(polygon);
    let map = Map::new(boundary.clone(), next);
    if map.validate().is_ok() && ends.iter().all(|e| map.validate_point("end", e).is_ok()) {
        *obstacles = map.obstacles;
    }
}

/// A random truth (or prior) from `obstacles`: some removed, some shifted, new rocks and walls
/// laid over what was there.
fn perturb(
    rng: &mut ChaCha8Rng,
    boundary: &Polygon,
    obstacles: &[Polygon],
    ends: [Point2<f64>; 2],
) -> Vec<Polygon> {
    let b = boundary.aabb();
    let mut out: Vec<Polygon> = Vec::new();
    for o in obstacles {
        match rng.random_range(0..10) {
            0 | 1 => {} // a phantom
            2 | 3 => {
                let d = Vector2::new(rng.random_range(-4.0..4.0), rng.random_range(-4.0..4.0));
                let moved = Polygon::new(o.vertices.iter().map(|q| q + d).collect());
                out.push(moved);
                let map = Map::new(boundary.clone(), out.clone());
                if map.validate().is_err()
                    || ends.iter().any(|e| map.validate_point("e", e).is_err())
                {
                    out.pop();
                    out.push(o.clone());
                }
            }
            _ => out.push(o.clone()),
        }
    }
    // Kept obstacles may now overlap shifted ones laid before them: lay them one by one.
    let mut valid = Vec::new();
    for o in out {
        let mut trial = valid.clone();
        trial.push(o);
        if Map::new(boundary.clone(), trial.clone()).validate().is_ok() {
            valid = trial;
        }
    }
    let rand_point = |rng: &mut ChaCha8Rng| {
        p(
            rng.random_range(b.min.x + 3.0..b.max.x - 3.0),
            rng.random_range(b.min.y + 12.0..b.max.y - 12.0),
        )
    };
    for _ in 0..rng.random_range(1..4) {
        let c = rand_point(rng);
        let r = rng.random_range(0.5..3.0);
        let polygon = rock(rng, c, r);
        lay(&mut valid, boundary, polygon, ends);
    }
    for _ in 0..rng.random_range(1..4) {
        let c = rand_point(rng);
        let length = rng.random_range(6.0..(b.max.x - b.min.x) * 0.6);
        let angle = rng.random_range(-0.4..0.4);
        lay(&mut valid, boundary, wall(c, length, angle), ends);
    }
    valid
}

/// The remaining descent after a decision keeps the clearance from the class's anchors, unless
/// the session reports why not.
fn check_route_clearance(session: &OnlineSession, decision: &Decision, what: &str) {
    let Some(c) = session.class() else {
        return;
    };
    if session.clearance_shortfall().is_some() {
        return;
    }
    let route = session.route();
    let from = match decision {
        Decision::Switched { junction, .. } => match route.iter().rposition(|q| q == junction) {
            Some(i) => i,
            None => return,
        },
        Decision::NewPaths => 0,
        _ => return,
    };
    let clearance = session.options().clearance * (1.0 - CLEARANCE_TOLERANCE);
    for a in &c.shp.taut.anchors {
        for w in route[from..].windows(2) {
            let d = distance_to_segment(&a.point, &w[0], &w[1]);
            assert!(
                d >= clearance,
                "{what}: the new descent passes {d} m from anchor ({}, {}) with no reason given \
                 ({decision:?}, route {:?} from {from}, robot {:?})",
                a.point.x,
                a.point.y,
                route,
                session.robot()
            );
        }
    }
}

/// Random priors and truths from crater strips (rocks removed, added, shifted; walls laid
/// across them, in the prior and in the truth): the simulator never fails, and every descent it
/// replans keeps the clearance or says why it cannot.
#[test]
fn online_never_fails_on_random_truths() {
    let mut endings = std::collections::BTreeMap::new();
    let mut shortfalls = 0;
    for seed in 0..24u64 {
        let mut rng = ChaCha8Rng::seed_from_u64(7000 + seed);
        let mut o = CraterStripOptions::new(rng.random_range(10..30), seed);
        o.width = 40.0;
        let g = crater_strip(&o).unwrap();
        let ends = [g.start, g.goal];
        let boundary = g.map.boundary.clone();
        let prior = Map::new(
            boundary.clone(),
            perturb(&mut rng, &boundary, &g.map.obstacles, ends),
        );
        let truth = Map::new(
            boundary.clone(),
            perturb(&mut rng, &boundary, &prior.obstacles, ends),
        );
        prior.validate().unwrap();
        truth.validate().unwrap();
        let steep = seed % 2 == 1;
        let options = SimulationOptions {
            sensor_range: rng.random_range(2.0..8.0),
            step: 1.0,
            max_steps: 2_000,
            ..SimulationOptions::default()
        };
        let what = format!("seed {seed}");
        let (report, _) = simulate_with(
            &prior,
            &truth,
            g.start,
            g.goal,
            terrain(&prior, steep),
            &options,
            &mut |e, s| {
                check_route_clearance(s, &e.outcome.decision, &what);
                shortfalls += usize::from(e.outcome.clearance_shortfall.is_some());
            },
        )
        .unwrap_or_else(|e| panic!("{what}: {e}"));
        if report.ending.reached() {
            assert!(report.homotopic, "{what}");
        }
        *endings.entry(format!("{:?}", report.ending)).or_insert(0) += 1;
    }
    assert!(
        endings.get("Goal").copied().unwrap_or(0) >= 12,
        "{endings:?}"
    );
    eprintln!("endings {endings:?}, events with a clearance shortfall: {shortfalls}");
}
