//! The dense active-set stability QP (`StabilityQp::check`, Goldfarb-Idnani, `dense_qp`) against
//! clarabel (`StabilityQp::check_clarabel`, the independent interior-point oracle) on seeded
//! random placed robots and on settled Axel poses on Paton's ledge (both boom configurations,
//! planar and mesh boom placements): the verdicts agree, the optimal values agree within
//! [`OBJECTIVE_TOL`], and every dense solution satisfies the statics (force and moment balance,
//! friction pyramids, moment bounds, tether bounds) within [`RESIDUAL_TOL`] checked here from
//! its wrenches, independently of both solvers.

use nalgebra::{Point3, Rotation3, Unit, Vector3};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rappel_mechanics::axel::{Axel, AxelParams, BoomMode};
use rappel_mechanics::boom_contact::{place_boom_in_contact, place_boom_inline};
use rappel_mechanics::robot::{ContactFrame, PlacedRobot, PointMass, STANDARD_GRAVITY, TetherLine};
use rappel_mechanics::settle::{SettleParams, settle_axel};
use rappel_mechanics::stability_qp::{QpReport, StabilityQp};
use rappel_terrain::paton_scene::PatonScene;

/// Optimal values (weight-normalised, O(1)) agree within this, absolute plus relative: clarabel's
/// gap tolerances are 1e-8, the dense solver's regularisation moves the value by about 1e-9.
const OBJECTIVE_TOL: f64 = 1e-6;
/// Balance and cone residuals of a dense solution, in units of the weight (or weight x metre).
const RESIDUAL_TOL: f64 = 1e-7;

/// `Σ (λx² + λy²)/μ² + |M|²/μ_m²` of a stable report, weight-normalised (the QP's objective).
fn objective(robot: &PlacedRobot, r: &QpReport) -> f64 {
    let w = weight(robot);
    r.wrenches
        .iter()
        .enumerate()
        .map(|(i, c)| {
            let (f, m) = (c.force / w, c.moment / w);
            let mu = robot.contact_friction(i).max(1e-9);
            let mut v = (f.x * f.x + f.y * f.y) / (mu * mu);
            if robot.moment_coefficient > 0.0 {
                v += m.norm_squared() / robot.moment_coefficient.powi(2);
            }
            v
        })
        .sum()
}

fn weight(robot: &PlacedRobot) -> f64 {
    robot.masses.iter().map(|m| m.mass).sum::<f64>() * STANDARD_GRAVITY
}

/// The statics of a stable report's solution, checked from its wrenches and tension.
fn assert_statics(robot: &PlacedRobot, r: &QpReport, what: &str) {
    let w = weight(robot);
    let o = robot.reference;
    let g = Vector3::new(0.0, 0.0, -STANDARD_GRAVITY);
    let mut force = Vector3::zeros();
    let mut moment = Vector3::zeros();
    for m in &robot.masses {
        force += g * m.mass;
        moment += (m.position - o).cross(&(g * m.mass));
    }
    for (i, (c, wr)) in robot.contacts.iter().zip(&r.wrenches).enumerate() {
        let f = c.rotation * wr.force;
        force += f;
        moment += (c.position - o).cross(&f) + c.rotation * wr.moment;
        let (fl, ml) = (wr.force / w, wr.moment / w);
        let mu = robot.contact_friction(i);
        assert!(fl.z >= -RESIDUAL_TOL, "{what}: normal force {}", fl.z);
        assert!(
            fl.x.abs().max(fl.y.abs()) <= mu * fl.z + RESIDUAL_TOL,
            "{what}: outside the pyramid {fl:?}"
        );
        assert!(
            ml.amax() <= robot.moment_coefficient * fl.z + RESIDUAL_TOL,
            "{what}: moment bound {ml:?}"
        );
    }
    if let Some(t) = &robot.tether {
        let tension = r.tether_tension.expect("tethered");
        let f = t.direction.into_inner() * tension;
        force += f;
        moment += (t.exit - o).cross(&f);
        if let Some(max) = t.max_tension {
            assert!(tension <= max + RESIDUAL_TOL * w, "{what}: tension limit");
        }
    }
    assert!(
        force.norm() <= RESIDUAL_TOL * w && moment.norm() <= RESIDUAL_TOL * w,
        "{what}: balance residual {force:?} {moment:?}"
    );
}

/// Compares the two solvers on `robot`; whether it was stable, `None` when clarabel gave no
/// verdict (its `InsufficientProgress` on a few ill-conditioned random instances; counted).
fn cross_check(robot: &PlacedRobot, what: &str) -> Option<bool> {
    let qp = StabilityQp::default();
    let dense = qp.check(robot).expect("the dense solver answers");
    let oracle = qp.check_clarabel(robot).ok()?;
    assert_eq!(dense.stable, oracle.stable, "{what}: verdicts differ");
    if dense.stable {
        assert_statics(robot, &dense, what);
        let (a, b) = (objective(robot, &dense), objective(robot, &oracle));
        assert!(
            (a - b).abs() <= OBJECTIVE_TOL * (1.0 + b.abs()),
            "{what}: optimal values {a} (dense) vs {b} (clarabel)"
        );
    }
    Some(dense.stable)
}

fn unit(rng: &mut ChaCha8Rng) -> Unit<Vector3<f64>> {
    loop {
        let v = Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0));
        if (0.1..=1.0).contains(&v.norm()) {
            return Unit::new_normalize(v);
        }
    }
}

/// A random placed robot: 1-4 contacts with frames tilted up to 0.8 rad about each axis (30 %
/// with their own friction coefficient in [0, 1), 30 % point contacts without moments, like
/// Axel's boom), 1-3 masses, friction 0.05-1.2, moments on or off, a tether in a random direction (limited or
/// not) or none.
fn random_robot(rng: &mut ChaCha8Rng) -> PlacedRobot {
    let contacts = (0..rng.random_range(1..=4))
        .map(|_| ContactFrame {
            position: Point3::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-0.2..0.2),
            ),
            rotation: Rotation3::from_euler_angles(
                rng.random_range(-0.8..0.8),
                rng.random_range(-0.8..0.8),
                rng.random_range(-3.1..3.1),
            ),
            friction: rng.random_bool(0.3).then(|| rng.random_range(0.0..1.0)),
            point: rng.random_bool(0.3),
        })
        .collect();
    let masses: Vec<PointMass> = (0..rng.random_range(1..=3))
        .map(|_| PointMass {
            mass: rng.random_range(1.0..50.0),
            position: Point3::new(
                rng.random_range(-0.5..0.5),
                rng.random_range(-0.5..0.5),
                rng.random_range(0.1..0.6),
            ),
        })
        .collect();
    let w = masses.iter().map(|m| m.mass).sum::<f64>() * STANDARD_GRAVITY;
    let tether = rng.random_bool(0.85).then(|| TetherLine {
        exit: Point3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(0.0..1.0),
        ),
        direction: unit(rng),
        max_tension: rng.random_bool(0.3).then(|| rng.random_range(0.0..2.0) * w),
    });
    PlacedRobot {
        masses,
        contacts,
        tether,
        friction: rng.random_range(0.05..1.2),
        moment_coefficient: if rng.random_bool(0.5) {
            rng.random_range(0.01..0.1)
        } else {
            0.0
        },
        reference: Point3::origin(),
    }
}

#[test]
fn dense_solver_agrees_with_clarabel_on_random_robots() {
    let mut rng = ChaCha8Rng::seed_from_u64(14);
    let (mut stable, mut no_oracle) = (0, 0);
    let n = 3000;
    for k in 0..n {
        let robot = random_robot(&mut rng);
        match cross_check(&robot, &format!("random robot {k}")) {
            Some(s) => stable += usize::from(s),
            None => no_oracle += 1,
        }
    }
    println!("{n} random robots: {stable} stable, {no_oracle} without an oracle verdict");
    // Both verdicts must be exercised, and the oracle must answer nearly always.
    assert!(
        no_oracle <= n / 100,
        "clarabel gave no verdict {no_oracle} times"
    );
    assert!(
        stable > n / 10 && stable < n - n / 10,
        "{stable} of {n} stable ({no_oracle} without oracle)"
    );
}

#[test]
fn dense_solver_agrees_with_clarabel_on_settled_ledge_poses() {
    let scene = PatonScene::paper(false);
    let m = scene.mesh().unwrap();
    let params = AxelParams::default();
    let settle = SettleParams::default();
    let anchors = scene.anchor_points();
    let (mut checked, mut stable) = (0, 0);
    for i in 0..16 {
        let x = -2.0 + 0.3 * i as f64;
        for y in [-1.5, 0.0, 1.0] {
            for yaw_deg in [0.0f64, 60.0, 180.0, 250.0] {
                let Ok(pose) = settle_axel(&m, &params, x, y, 6.0, yaw_deg.to_radians(), &settle)
                else {
                    continue;
                };
                for a in &anchors {
                    let mut placed = Vec::new();
                    for boom in [BoomMode::Inline, BoomMode::InContact] {
                        let axel = Axel::new(AxelParams { boom, ..params }).unwrap();
                        placed.extend(pose.place(&axel, &m, 0.6, Some((a, None))).ok());
                    }
                    placed.extend(
                        place_boom_in_contact(&pose, &params, &m, 0.6, (a, None))
                            .ok()
                            .map(|(p, _)| p),
                    );
                    placed.extend(place_boom_inline(&pose, &params, &m, 0.6, (a, None)).ok());
                    for (k, robot) in placed.iter().enumerate() {
                        checked += 1;
                        let what =
                            format!("pose ({x}, {y}) yaw {yaw_deg} anchor {a} placement {k}");
                        stable += usize::from(cross_check(robot, &what).expect("clarabel answers"));
                    }
                    if let Ok(robot) = place_boom_inline(&pose, &params, &m, 0.6, (a, Some(900.0)))
                    {
                        checked += 1;
                        let s = cross_check(&robot, "inline, limited tether");
                        stable += usize::from(s.expect("clarabel answers"));
                    }
                }
            }
        }
    }
    println!("{checked} settled placements: {stable} stable");
    assert!(checked > 300, "{checked} placements");
    assert!(
        stable > checked / 10 && stable < checked,
        "{stable} of {checked} stable"
    );
}
