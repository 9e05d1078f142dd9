//! The Chapter-2 planner around one long obstacle (issue 10): a 2,000-vertex star
//! (`rappel::generated::star_scenario`) against closed forms of the circle its even vertices lie
//! on. The first two classes pass either side of the star, touching its hull from the tangent
//! point of the start to that of the goal; the third winds once more round the hull; the angles
//! `psi` of the anchors follow the tangent's direction, and the planes' limits (eq. 2.7) decide
//! which class the goal holds. Every expected value is computed here from the scenario's
//! numbers (radius, centre, start, goal, slopes, friction), not by the planner.

use crate::common;

use common::Prepared;
use rappel::generated::{STAR_CENTRE, STAR_INNER_RADIUS, STAR_OUTER_RADIUS, star_scenario};
use rappel::plan::{PlanOptions, plan};
use std::f64::consts::TAU;

/// Vertices of the star.
const VERTICES: usize = 2_000;

/// The polar angle of a point around the star's centre, radians in `(-pi, pi]`.
fn polar(x: f64, y: f64) -> f64 {
    (y - STAR_CENTRE[1]).atan2(x - STAR_CENTRE[0])
}

/// Distance from the star's centre.
fn radius(x: f64, y: f64) -> f64 {
    (x - STAR_CENTRE[0]).hypot(y - STAR_CENTRE[1])
}

/// The tangent points of a point at polar angle `phi` and distance `d` from the centre on the
/// circle of radius `r`: at `phi -+ acos(r / d)` (right, left).
fn tangents(phi: f64, d: f64, r: f64) -> (f64, f64) {
    let half = (r / d).acos();
    (phi - half, phi + half)
}

#[test]
fn a_long_star_plans_as_its_circle_says() {
    let scenario = star_scenario(VERTICES).expect("star");
    let report = plan(
        &scenario,
        &PlanOptions {
            classes: 3,
            ..Default::default()
        },
    )
    .expect("plan");
    let r = STAR_OUTER_RADIUS;
    let (s, g) = (scenario.start, scenario.goal);
    let (ds, dg) = (radius(s.x, s.y), radius(g.x, g.y));
    let (ts_right, ts_left) = tangents(polar(s.x, s.y), ds, r);
    let (tg_left, tg_right) = tangents(polar(g.x, g.y), dg, r);
    // Right of the star: from the start's right tangent point clockwise down to the goal's.
    let arc_right = ts_right - tg_right;
    // Left: from the start's left tangent point anticlockwise to the goal's.
    let arc_left = tg_left + TAU - ts_left;
    let legs = (ds * ds - r * r).sqrt() + (dg * dg - r * r).sqrt();
    // The hull is the regular polygon of the even vertices, inscribed in the circle: its
    // perimeter, and its arcs shorter than the circle's by less than a vertex step's sagitta.
    let step = TAU / (VERTICES / 2) as f64;
    let perimeter = VERTICES as f64 * r * (step / 2.0).sin();
    let tolerance = r * step * step;
    assert_eq!(report.classes.len(), 3);
    let [first, second, third] = [&report.classes[0], &report.classes[1], &report.classes[2]];
    for (class, arc) in [(first, arc_right), (second, arc_left)] {
        assert!(
            (class.length_m - (legs + r * arc)).abs() < tolerance,
            "class {}: {} m, circle {} m",
            class.rank,
            class.length_m,
            legs + r * arc
        );
        // The anchors: consecutive hull vertices (radius 20) spanning the arc, one per step.
        let expected = arc / step;
        assert!(
            (class.anchors.len() as f64 - expected).abs() <= 2.0,
            "class {}: {} anchors, {expected:.1} hull vertices on its arc",
            class.rank,
            class.anchors.len()
        );
        for a in &class.anchors {
            assert!(
                (radius(a.point.x, a.point.y) - STAR_OUTER_RADIUS).abs() < 1e-9,
                "class {}: anchor {} not on the hull",
                class.rank,
                a.index
            );
            assert!(
                (radius(a.point.x, a.point.y) - STAR_INNER_RADIUS).abs() > 1.0,
                "class {}: anchor {} on an inner vertex",
                class.rank,
                a.index
            );
        }
    }
    // Once more round the hull: the first class plus the hull's perimeter.
    assert!(
        (third.length_m - (first.length_m + perimeter)).abs() < tolerance,
        "class 3: {} m, class 1 + perimeter {} m",
        third.length_m,
        first.length_m + perimeter
    );
    assert!(!third.simple);
    // psi of an anchor on the right side, tether running clockwise: the tangent's direction
    // (sin phi, -cos phi), at |phi| from the fall line, within a vertex step (the tether runs
    // along chords).
    for a in &first.anchors {
        let phi = polar(a.point.x, a.point.y);
        assert!(
            (a.psi_deg - phi.abs().to_degrees()).abs() <= step.to_degrees(),
            "anchor {}: psi {}°, tangent {}°",
            a.index,
            a.psi_deg,
            phi.abs().to_degrees()
        );
    }
    // Eq. 2.7: theta_max = asin(mu cot eta); 43.85° above y = 60, 19.61° below.
    let limit = |slope: f64| (0.4 / slope.to_radians().tan()).asin().to_degrees();
    let (upper, lower) = (limit(30.0), limit(50.0));
    // The first class: every psi below its plane's limit, and the goal held (the last segment
    // leaves the goal's tangent point at |phi| from the fall line, below the lower limit): the
    // ascent is decided by the crossings, and it is feasible.
    // The last segment runs from the goal's tangent point to the goal.
    let psi_from = |theta: f64| {
        let (tx, ty) = (
            STAR_CENTRE[0] + r * theta.cos(),
            STAR_CENTRE[1] + r * theta.sin(),
        );
        (g.x - tx).abs().atan2(ty - g.y).to_degrees()
    };
    let goal_psi = psi_from(tg_right);
    assert!(goal_psi < lower && ts_right.to_degrees() < upper);
    assert!((first.goal_psi_deg - goal_psi).abs() < step.to_degrees());
    assert!(first.feasible, "class 1: {}", first.verdict);
    assert_eq!(first.waypoints.len(), first.anchors.len());
    // The second class: the goal's left tangent point sees the goal at more than the lower
    // plane's limit, so the taut tether cannot hold the robot there.
    let goal_psi_left = psi_from(tg_left);
    assert!(goal_psi_left > lower, "{goal_psi_left}° vs {lower}°");
    assert!((second.goal_psi_deg - goal_psi_left).abs() < step.to_degrees());
    assert!(!second.feasible);
    assert!(
        second
            .verdict
            .to_string()
            .contains("cannot hold the robot at the goal"),
        "{}",
        second.verdict
    );
}

#[test]
fn a_route_hugging_the_star_fails_its_pair_at_the_closest_waypoint() {
    use rappel::planners::feasibility::check_feasibility;
    use rappel::planners::path_pair::{PairFailure, path_pair};
    // The route's waypoints lie on the hull's tangent lines, which pass within a sagitta of the
    // next hull vertices: every ascent through them passes closer than the clearance to one of
    // them. The pair must fail naming the anchor closest to a waypoint, at that distance, found
    // here by comparing every waypoint with every anchor.
    let prepared = Prepared::new(&star_scenario(VERTICES).expect("star"), 3);
    let (ctx, classes) = (prepared.ctx(), &prepared.classes);
    let mut failed = 0;
    for class in classes {
        let report = check_feasibility(&ctx, &class.shp.taut);
        if !report.feasible() {
            continue;
        }
        let anchors = &class.shp.taut.anchors;
        // (distance, waypoint, anchor from 1) of the closest pair; ties to the first waypoint,
        // then the lowest anchor.
        let mut closest = (f64::INFINITY, 0, 0);
        for (i, w) in report.route.iter().enumerate() {
            for (k, a) in anchors.iter().enumerate() {
                let d = (w.point - a.point).norm();
                if d < closest.0 {
                    closest = (d, i, k + 1);
                }
            }
        }
        assert!(
            closest.0 < ctx.clearance,
            "class {}: the route keeps {} m from every anchor",
            class.rank,
            closest.0
        );
        match path_pair(&ctx, class, &report) {
            Err(PairFailure::TooClose {
                which,
                anchor,
                distance,
                clearance,
            }) => {
                assert_eq!(which, "ascent");
                assert_eq!(clearance, ctx.clearance);
                assert_eq!(
                    (distance, anchor),
                    (closest.0, closest.2),
                    "class {}",
                    class.rank
                );
            }
            other => panic!("class {}: {other:?}", class.rank),
        }
        failed += 1;
    }
    assert!(failed >= 1, "no class of the star was feasible");
}
