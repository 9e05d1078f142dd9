//! The wheel/tether stability QP (Paton §IV-C) against closed forms (sliding and tipping limits,
//! the re-derived Axel tension eq. 3.32) and the physical sanity checks of issue 5.

use nalgebra::{Point3, Vector3};
use rappel_mechanics::axel::{Axel, AxelParams, BoomMode, tether_tension_estimate};
use rappel_mechanics::conic::SolverSettings;
use rappel_mechanics::four_wheel::FourWheelRover;
use rappel_mechanics::robot::{
    PlacedRobot, PlanarPose, RobotModel, STANDARD_GRAVITY, SlopePlane, TetherSpec, place,
};
use rappel_mechanics::stability_error::StabilityError;
use rappel_mechanics::stability_qp::{QpReport, StabilityQp};
use rappel_mechanics::traversability::StabilitySettings;
use std::f64::consts::PI;

fn placed(model: &dyn RobotModel, deg: f64, mu: f64, tether: Option<&TetherSpec>) -> PlacedRobot {
    let plane = SlopePlane::new(deg.to_radians(), mu).unwrap();
    place(model, &PlanarPose::new(0.0, 0.0, PI), &plane, tether).unwrap()
}

fn qp(robot: &PlacedRobot) -> QpReport {
    StabilityQp::default().check(robot).unwrap()
}

const UP: TetherSpec = TetherSpec {
    anchor: Point3::new(0.0, 30.0, 0.0),
    max_tension: None,
};

#[test]
fn untethered_rover_slides_exactly_at_the_friction_angle() {
    // μ = 0.5: slides past atan 0.5 = 26.57°, well before tipping (tan η = 0.3/0.25).
    let rover = FourWheelRover::default();
    assert!(qp(&placed(&rover, 26.0, 0.5, None)).stable);
    assert!(!qp(&placed(&rover, 27.0, 0.5, None)).stable);
    // The least-squares distribution of tangential load gives a utilisation between the average
    // demand tan η / μ and 1 (module docs of `stability_qp`).
    let r = qp(&placed(&rover, 20.0, 0.5, None));
    let demand = 20f64.to_radians().tan() / 0.5;
    assert!(
        r.utilization >= demand - 1e-6 && r.utilization <= 1.0 + 1e-6,
        "{}",
        r.utilization
    );
}

#[test]
fn untethered_rover_tips_at_the_tipping_angle() {
    // Enough friction to hold, the centre of mass 0.25 m high, 0.3 m from the downhill axle:
    // tips past atan(0.3 / 0.25) = 50.19°.
    let rover = FourWheelRover::default();
    assert!(qp(&placed(&rover, 49.5, 2.0, None)).stable);
    assert!(!qp(&placed(&rover, 51.0, 2.0, None)).stable);
}

#[test]
fn axel_sanity_flat_slope_and_tether() {
    let axel = Axel::default();
    let flat = qp(&placed(&axel, 0.0, 0.8, None));
    assert!(flat.stable && flat.utilization < 1e-6);
    assert!(!qp(&placed(&axel, 55.0, 0.8, None)).stable);
    let held = qp(&placed(&axel, 55.0, 0.8, Some(&UP)));
    assert!(held.stable);
    // Moments about the wheel contact line: the inline tether passes through the axle, and the
    // boom's weight, resting uphill of the contact line, helps to hold the rover, so the tether
    // carries less than the along-slope weight (the rest by wheel friction and grouser moments).
    let t = held.tether_tension.unwrap();
    let along = 55.0 * STANDARD_GRAVITY * 55f64.to_radians().sin();
    assert!(t < along && t > 0.7 * along, "{t} vs {along}");
    // From 10°: on flat ground an inline boom hangs off the axle and the grouser moments cannot hold
    // it (Paton's in-contact configuration is the stable one there).
    let margins: Vec<f64> = (1..=6)
        .map(|k| qp(&placed(&axel, 10.0 * k as f64, 0.8, Some(&UP))).margin)
        .collect();
    assert!(margins.windows(2).all(|w| w[1] < w[0]), "{margins:?}");
}

#[test]
fn axel_tension_matches_re_derived_eq_3_32() {
    for (deg, boom_deg) in [(25.0f64, 10.0f64), (40.0, 30.0), (60.0, 45.0)] {
        let params = AxelParams {
            boom_mass: 0.0,
            body_mass: 55.0,
            moment_coefficient: 0.0,
            boom: BoomMode::Fixed(boom_deg.to_radians()),
            ..AxelParams::default()
        };
        let axel = Axel::new(params).unwrap();
        let robot = placed(&axel, deg, 2.0, Some(&UP));
        let t = qp(&robot).tether_tension.unwrap();
        let normal = SlopePlane::new(deg.to_radians(), 2.0).unwrap().normal();
        let tether_angle = robot.tether.unwrap().direction.dot(&normal).asin();
        let estimate = tether_tension_estimate(
            55.0,
            STANDARD_GRAVITY,
            params.wheel_radius,
            params.boom_length,
            deg.to_radians(),
            boom_deg.to_radians(),
            tether_angle,
        )
        .unwrap();
        assert!(
            ((t - estimate) / estimate).abs() < 1e-5,
            "{deg}: {t} vs {estimate}"
        );
    }
}

#[test]
fn solution_satisfies_balance_and_cones() {
    let axel = Axel::default();
    let robot = placed(
        &axel,
        35.0,
        0.8,
        Some(&TetherSpec {
            anchor: Point3::new(6.0, 25.0, 0.0),
            max_tension: None,
        }),
    );
    let r = qp(&robot);
    assert!(r.stable);
    let mut force = Vector3::new(0.0, 0.0, -55.0 * STANDARD_GRAVITY);
    for (c, w) in robot.contacts.iter().zip(&r.wrenches) {
        force += c.rotation * w.force;
        let tol = 1e-6 * 55.0 * STANDARD_GRAVITY;
        assert!(w.force.z >= -tol);
        assert!(
            w.force.x.abs() <= 0.8 * w.force.z + tol && w.force.y.abs() <= 0.8 * w.force.z + tol
        );
        assert!(w.moment.amax() <= 0.05 * w.force.z + tol);
    }
    let t = robot.tether.unwrap();
    force += t.direction.into_inner() * r.tether_tension.unwrap();
    assert!(force.norm() < 1e-5 * 55.0 * STANDARD_GRAVITY, "{force:?}");
    assert!(r.utilization <= 1.0 + 1e-6);
}

#[test]
fn solver_trouble_is_a_typed_error() {
    let robot = placed(&Axel::default(), 30.0, 0.8, Some(&UP));
    let settings = StabilitySettings::default()
        .with_solver(SolverSettings::default().with_max_iter(1).unwrap());
    // clarabel's iteration limit (the dense solver's own bound is tested in `dense_qp`).
    assert!(matches!(
        StabilityQp::new(settings).check_clarabel(&robot),
        Err(StabilityError::Trouble(_))
    ));
    let mut bad = robot.clone();
    bad.friction = f64::NAN;
    assert!(matches!(
        StabilityQp::default().check(&bad),
        Err(StabilityError::Input(_))
    ));
}

#[test]
fn a_point_contact_carries_no_moment() {
    use nalgebra::Rotation3;
    use rappel_mechanics::robot::{ContactFrame, PointMass};
    // One horizontal contact at the origin, a 10 kg mass `d` beside it: a contact patch
    // (`μ_m` = 0.1 m) holds it by a moment `W d` iff `W d <= μ_m W`, i.e. d <= 0.1 m (statics by
    // hand); a point contact never holds it off-centre, and holds it exactly above.
    let robot = |d: f64, point: bool| PlacedRobot {
        masses: vec![PointMass {
            mass: 10.0,
            position: Point3::new(d, 0.0, 0.3),
        }],
        contacts: vec![ContactFrame {
            position: Point3::origin(),
            rotation: Rotation3::identity(),
            friction: None,
            point,
        }],
        tether: None,
        friction: 0.6,
        moment_coefficient: 0.1,
        reference: Point3::origin(),
    };
    let both = |r: &PlacedRobot| {
        let dense = StabilityQp::default().check(r).unwrap();
        let clarabel = StabilityQp::default().check_clarabel(r).unwrap();
        assert_eq!(dense.stable, clarabel.stable, "dense vs clarabel");
        dense
    };
    assert!(both(&robot(0.09, false)).stable);
    assert!(!both(&robot(0.11, false)).stable);
    assert!(!both(&robot(0.01, true)).stable);
    let centred = both(&robot(0.0, true));
    assert!(centred.stable);
    assert_eq!(centred.wrenches[0].moment, Vector3::zeros());
}
