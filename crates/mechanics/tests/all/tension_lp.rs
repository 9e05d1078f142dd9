//! Kumar's tension-limited stability LP (Kumar §III-B) against closed forms, and its monotonicity
//! in the tension limit.

use nalgebra::Point3;
use rappel_mechanics::four_wheel::FourWheelRover;
use rappel_mechanics::robot::{PlanarPose, STANDARD_GRAVITY, SlopePlane, TetherSpec, place};
use rappel_mechanics::stability_error::StabilityError;
use rappel_mechanics::tension_lp::{LpReport, TensionLimitedLp};
use std::f64::consts::PI;

/// The four-wheel rover facing downhill at the origin of a slope `deg` with friction `mu`, its
/// tether running to `anchor` (plane frame) with limit `limit`.
fn check(deg: f64, mu: f64, heading: f64, anchor: Point3<f64>, limit: f64) -> LpReport {
    let slope = SlopePlane::new(deg.to_radians(), mu).unwrap();
    let tether = TetherSpec {
        anchor,
        max_tension: Some(limit),
    };
    let robot = place(
        &FourWheelRover::default(),
        &PlanarPose::new(0.0, 0.0, heading),
        &slope,
        Some(&tether),
    )
    .unwrap();
    TensionLimitedLp::default().check(&robot).unwrap()
}

#[test]
fn least_tension_up_the_fall_line_matches_closed_form() {
    // Tether parallel to the slope (anchor at the exit height): T = m g (sin η - μ cos η).
    let w = 35.0 * STANDARD_GRAVITY;
    for (deg, mu) in [(55.0f64, 0.4), (65.0, 0.4), (40.0, 0.6), (30.0, 0.2)] {
        let r = check(deg, mu, PI, Point3::new(0.0, 30.0, 0.35), 1000.0);
        let exact = w * (deg.to_radians().sin() - mu * deg.to_radians().cos());
        let t = r.required_tension.unwrap();
        assert!(
            r.stable && ((t - exact) / exact).abs() < 1e-6,
            "{deg} deg: {t} vs {exact}"
        );
        assert!((r.headroom - (1.0 - exact / 1000.0)).abs() < 1e-6);
    }
    // A tether pulling into the slope at angle α needs m g (sin η - μ cos η)/(cos α + μ sin α).
    let (deg, mu, alpha) = (55.0f64, 0.4, 0.2f64);
    let anchor = Point3::new(0.0, 10.0, 0.35 - (10.0 - 0.3) * alpha.tan());
    let t = check(deg, mu, PI, anchor, 1000.0).required_tension.unwrap();
    let exact = w * (deg.to_radians().sin() - mu * deg.to_radians().cos())
        / (alpha.cos() + mu * alpha.sin());
    assert!(((t - exact) / exact).abs() < 1e-6, "{t} vs {exact}");
}

#[test]
fn gentle_slope_needs_no_tension_and_limits_are_nested() {
    let r = check(15.0, 0.4, PI, Point3::new(0.0, 30.0, 0.35), 50.0);
    assert!(r.stable && r.required_tension.unwrap() < 1e-6 && (r.headroom - 1.0).abs() < 1e-6);
    // Stable sets grow with the tension limit (Kumar Fig. 5): check on a fan of anchor offsets.
    for dx in [-20.0, -8.0, -3.0, 0.0, 5.0, 12.0] {
        let mut was_stable = false;
        for limit in [150.0, 200.0, 250.0, 300.0, 400.0, 600.0] {
            let stable = check(60.0, 0.4, PI, Point3::new(dx, 15.0, 0.35), limit).stable;
            assert!(
                stable || !was_stable,
                "offset {dx}: stable at a lower limit but not at {limit}"
            );
            was_stable = stable;
        }
    }
}

#[test]
fn a_tethered_lp_needs_a_limit() {
    let slope = SlopePlane::new(0.5, 0.4).unwrap();
    let tether = TetherSpec {
        anchor: Point3::new(0.0, 30.0, 0.35),
        max_tension: None,
    };
    let robot = place(
        &FourWheelRover::default(),
        &PlanarPose::new(0.0, 0.0, PI),
        &slope,
        Some(&tether),
    )
    .unwrap();
    assert!(matches!(
        TensionLimitedLp::default().check(&robot),
        Err(StabilityError::Input(_))
    ));
}

#[test]
fn circumscribed_pyramid_is_optimistic_off_axis_and_inscribed_is_not() {
    use rappel_mechanics::tension_lp::FrictionPyramid;
    // 55°, μ = 0.4, 35 kg: G = m g sin η, μN = μ m g cos η. Facing away from an anchor at θ off
    // the fall line, eq. 3c needs G cos θ - μN (while G sin θ <= μN).
    let w = 35.0 * STANDARD_GRAVITY;
    let (g_along, mu_n) = (
        w * 55f64.to_radians().sin(),
        0.4 * w * 55f64.to_radians().cos(),
    );
    // 10°: small enough that the yaw moment of the saturated longitudinal friction (unequal left
    // and right wheel loads) can still be balanced; beyond ~13° that coupling binds first.
    let theta = 10f64.to_radians();
    // The robot's back (and tether exit, 0.3 m behind centre) points up the line at θ.
    let anchor = Point3::new(20.3 * theta.sin(), 20.3 * theta.cos(), 0.35);
    let heading = PI - theta;
    let slope = SlopePlane::new(55f64.to_radians(), 0.4).unwrap();
    let tether = TetherSpec {
        anchor,
        max_tension: Some(400.0),
    };
    let robot = place(
        &FourWheelRover::default(),
        &PlanarPose::new(0.0, 0.0, heading),
        &slope,
        Some(&tether),
    )
    .unwrap();
    let t = TensionLimitedLp::default()
        .check(&robot)
        .unwrap()
        .required_tension
        .unwrap();
    let exact = g_along * theta.cos() - mu_n;
    assert!(((t - exact) / exact).abs() < 1e-4, "{t} vs {exact}");
    assert!(
        t < g_along - mu_n,
        "off-axis needs less than on-axis with the circumscribed pyramid"
    );
    let inscribed = TensionLimitedLp::default()
        .with_pyramid(FrictionPyramid::Inscribed)
        .check(&robot)
        .unwrap();
    assert!(
        inscribed.required_tension.unwrap() > g_along - mu_n,
        "inscribed pyramid is at least as strict as the cone"
    );
}

/// The dense simplex (`check`) against clarabel (`check_clarabel`, the independent
/// interior-point oracle) on 2,000 seeded random set-ups: slopes 0-80°, friction 0.05-1.2, any
/// heading, anchors all around (above, into and away from the slope), limits 0-1,500 N. The
/// verdicts agree wherever clarabel's least tension is not within `BOUNDARY` of the limit, and
/// the least tensions agree within `TENSION_TOL`.
#[test]
fn the_dense_simplex_agrees_with_clarabel() {
    use rand::{RngExt, SeedableRng};
    /// Least tensions agree within this, relative to the weight (clarabel's gap tolerance 1e-8).
    const TENSION_TOL: f64 = 1e-6;
    /// A least tension this close to the limit (relative to the weight) is on the boundary,
    /// where the two solvers' tolerances may disagree about the verdict.
    const BOUNDARY: f64 = 1e-6;
    let w = 35.0 * STANDARD_GRAVITY;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(30);
    let (mut stable, mut unstable) = (0, 0);
    for case in 0..2000 {
        let deg = rng.random_range(0.0..80.0);
        let mu = rng.random_range(0.05..1.2);
        let heading = rng.random_range(-PI..PI);
        let anchor = Point3::new(
            rng.random_range(-30.0..30.0),
            rng.random_range(-30.0..30.0),
            rng.random_range(-3.0..6.0),
        );
        let limit = rng.random_range(0.0..1500.0);
        let slope = SlopePlane::new(f64::to_radians(deg), mu).unwrap();
        let tether = TetherSpec {
            anchor,
            max_tension: Some(limit),
        };
        let Ok(robot) = place(
            &FourWheelRover::default(),
            &PlanarPose::new(0.0, 0.0, heading),
            &slope,
            Some(&tether),
        ) else {
            continue;
        };
        let lp = TensionLimitedLp::default();
        let (dense, oracle) = (
            lp.check(&robot).unwrap(),
            lp.check_clarabel(&robot).unwrap(),
        );
        let what = format!("case {case}: {deg:.1} deg, mu {mu:.2}, {anchor:?}, limit {limit:.0}");
        match (oracle.required_tension, dense.required_tension) {
            (Some(a), Some(b)) => {
                assert!(
                    (a - b).abs() <= TENSION_TOL * w,
                    "{what}: {b} vs clarabel {a}"
                );
            }
            (Some(a), None) | (None, Some(a)) => {
                assert!(
                    (a - limit).abs() <= BOUNDARY * w,
                    "{what}: verdicts differ ({dense:?} vs {oracle:?}) away from the boundary"
                );
            }
            (None, None) => assert_eq!(dense.stable, oracle.stable, "{what}"),
        }
        if oracle.stable {
            stable += 1;
        } else {
            unstable += 1;
        }
    }
    // Both verdicts are well represented.
    assert!(
        stable > 300 && unstable > 300,
        "{stable} stable, {unstable} unstable"
    );
}

/// Kumar's point body (Fig. 4, eq. 3c: one ground force in one pyramid aligned with the tether)
/// against the four-wheel rover at 14° off the tether's line on 55°, μ = 0.4, 35 kg, limit
/// 199 N. The body needs the closed form `G cos θ - μN` = 194.1 N (lateral `G sin θ` = 68.1 N <=
/// μN = 78.8 N), so eq. 3c holds it; the rover's saturated longitudinal friction leaves a yaw
/// moment its wheels cannot balance at 14°, so it is refused; the exact cone needs
/// `G cos θ - sqrt((μN)² - (G sin θ)²)` = 233.5 N and the inscribed pyramid more still.
#[test]
fn kumar_point_body_admits_what_the_rover_and_the_inscribed_pyramid_refuse() {
    use rappel_mechanics::point_body::PointBody;
    use rappel_mechanics::tension_lp::FrictionPyramid;
    let w = 35.0 * STANDARD_GRAVITY;
    let eta = 55f64.to_radians();
    let (g_along, mu_n) = (w * eta.sin(), 0.4 * w * eta.cos());
    let theta = 14f64.to_radians();
    let slope = SlopePlane::new(eta, 0.4).unwrap();
    let limit = 199.0;
    let body = PointBody::new(35.0).unwrap();
    // The body's tether leaves at its point, parallel to the plane.
    let tether = TetherSpec {
        anchor: Point3::new(20.0 * theta.sin(), 20.0 * theta.cos(), 0.0),
        max_tension: Some(limit),
    };
    let placed = place(
        &body,
        &PlanarPose::new(0.0, 0.0, PI - theta),
        &slope,
        Some(&tether),
    )
    .unwrap();
    let r = TensionLimitedLp::default().check(&placed).unwrap();
    let pyramid = g_along * theta.cos() - mu_n;
    assert!(r.stable, "eq. 3c holds the body at 14 degrees");
    let t = r.required_tension.unwrap();
    assert!(((t - pyramid) / pyramid).abs() < 1e-6, "{t} vs {pyramid}");
    // The same body with the exact cone's requirement is beyond the limit, and so is the
    // inscribed pyramid (contained in the cone).
    let cone = g_along * theta.cos() - (mu_n.powi(2) - (g_along * theta.sin()).powi(2)).sqrt();
    assert!(cone > limit);
    let inscribed = TensionLimitedLp::default()
        .with_pyramid(FrictionPyramid::Inscribed)
        .check(&placed)
        .unwrap();
    assert!(!inscribed.stable, "the inscribed pyramid refuses 199 N");
    // The four-wheel rover, its tether exit 0.35 m high and 0.3 m behind centre, on the same
    // line: refused at 199 N.
    let rover_tether = TetherSpec {
        anchor: Point3::new(20.3 * theta.sin(), 20.3 * theta.cos(), 0.35),
        max_tension: Some(limit),
    };
    let rover = place(
        &FourWheelRover::default(),
        &PlanarPose::new(0.0, 0.0, PI - theta),
        &slope,
        Some(&rover_tether),
    )
    .unwrap();
    assert!(!TensionLimitedLp::default().check(&rover).unwrap().stable);
    // The clarabel oracle agrees on the body.
    let oracle = TensionLimitedLp::default().check_clarabel(&placed).unwrap();
    assert!(oracle.stable);
    assert!((oracle.required_tension.unwrap() - t).abs() < 1e-3 * w);
}
