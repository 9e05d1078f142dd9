//! Four-wheel settling against closed forms: planes of any slope and aspect (all four wheels
//! down, pitch the slope along the heading, sin²(pitch) + sin²(roll) = sin²(slope)), a step under
//! the front axle (pitch asin(h / wheelbase)), a bump under one wheel (three wheels down, the
//! opposite one hanging by the bump's height), and the untethered stability QP on a plane (the
//! friction angle decides).

use nalgebra::{Point3, Vector3};
use rappel_mechanics::four_wheel::{FourWheelParams, FourWheelRover};
use rappel_mechanics::four_wheel_settle::settle_four_wheel;
use rappel_mechanics::settle::SettleParams;
use rappel_mechanics::stability_qp::StabilityQp;
use rappel_terrain::mesh::TriMesh;
use rappel_terrain::surface::SignedDistance;

fn plane(a: f64, b: f64) -> TriMesh {
    let z = |x: f64, y: f64| a * x + b * y;
    let c = [(-20.0, -20.0), (20.0, -20.0), (20.0, 20.0), (-20.0, 20.0)];
    let v = c.iter().map(|&(x, y)| Point3::new(x, y, z(x, y))).collect();
    TriMesh::new(v, vec![[0, 1, 2], [0, 2, 3]]).unwrap()
}

/// Ground made of axis-aligned boxes (their union): exact signed distance outside.
struct Boxes(Vec<([f64; 3], [f64; 3])>);

impl Boxes {
    fn one(lo: &[f64; 3], hi: &[f64; 3], q: &Point3<f64>) -> f64 {
        let mut outside = Vector3::zeros();
        let mut inside = f64::NEG_INFINITY;
        for a in 0..3 {
            let d = (lo[a] - q[a]).max(q[a] - hi[a]);
            outside[a] = d.max(0.0);
            inside = inside.max(d);
        }
        outside.norm() + inside.min(0.0)
    }
}

impl SignedDistance for Boxes {
    fn signed_distance(&self, q: &Point3<f64>) -> Option<f64> {
        self.0
            .iter()
            .map(|(lo, hi)| Boxes::one(lo, hi, q))
            .min_by(f64::total_cmp)
    }
    fn distance_gradient(&self, q: &Point3<f64>) -> Option<Vector3<f64>> {
        let e = 1e-6;
        let f = |d: Vector3<f64>| self.signed_distance(&(q + d)).unwrap_or(0.0);
        Some(
            Vector3::new(
                f(Vector3::x() * e) - f(-Vector3::x() * e),
                f(Vector3::y() * e) - f(-Vector3::y() * e),
                f(Vector3::z() * e) - f(-Vector3::z() * e),
            ) / (2.0 * e),
        )
    }
}

const FLOOR: ([f64; 3], [f64; 3]) = ([-50.0, -50.0, -10.0], [50.0, 50.0, 0.0]);

#[test]
fn plane_of_any_slope_and_aspect_all_four_wheels_down() {
    let r = FourWheelParams::default();
    let p = SettleParams::default();
    for slope_deg in [0.0f64, 8.0, 20.0, 35.0] {
        for aspect_deg in [0.0f64, 40.0, 135.0, 250.0] {
            for yaw_deg in [0.0f64, 70.0, 200.0] {
                let g = slope_deg.to_radians().tan();
                let (a, b) = (
                    g * aspect_deg.to_radians().cos(),
                    g * aspect_deg.to_radians().sin(),
                );
                let ground = plane(a, b);
                let (x, y, yaw) = (1.0, -2.0, yaw_deg.to_radians());
                let pose = settle_four_wheel(&ground, &r, x, y, 30.0, yaw, &p)
                    .unwrap_or_else(|e| panic!("{slope_deg} {aspect_deg} {yaw_deg}: {e}"));
                assert_eq!(pose.support, vec![0, 1, 2, 3]);
                // The origin on the plane under the start.
                let z = a * x + b * y;
                assert!(
                    (pose.origin - Point3::new(x, y, z)).norm() < 1e-6,
                    "{pose:?}"
                );
                // Pitch: the plane's slope along the heading.
                let along = a * yaw.cos() + b * yaw.sin();
                assert!((pose.pitch() - along.atan()).abs() < 1e-9);
                let s = |v: f64| v.sin().powi(2);
                assert!(
                    (s(pose.pitch()) + s(pose.roll()) - s(slope_deg.to_radians())).abs() < 1e-9
                );
                assert!(pose.wheel_clearance.iter().all(|c| c.abs() < 1e-5));
            }
        }
    }
}

#[test]
fn a_step_under_the_front_axle_pitches_the_rover_by_asin_h_over_the_wheelbase() {
    let r = FourWheelParams::default();
    let h = 0.1;
    let ground = Boxes(vec![FLOOR, ([0.0, -50.0, -10.0], [50.0, 50.0, h])]);
    let pose = settle_four_wheel(&ground, &r, 0.0, 0.0, 5.0, 0.0, &SettleParams::default())
        .expect("settles");
    assert_eq!(pose.support, vec![0, 1, 2, 3]);
    assert!(
        (pose.pitch() - (h / r.wheelbase).asin()).abs() < 1e-6,
        "{}",
        pose.pitch()
    );
    assert!(pose.roll().abs() < 1e-9);
    assert!(
        pose.ground_points[..2]
            .iter()
            .all(|g| (g.z - h).abs() < 1e-5)
    );
    assert!(pose.ground_points[2..].iter().all(|g| g.z.abs() < 1e-5));
}

#[test]
fn a_bump_under_one_wheel_leaves_the_opposite_wheel_hanging() {
    let r = FourWheelParams::default();
    let h = 0.08;
    // Under the front-left wheel (0.3, 0.275).
    let bump = ([0.2, 0.175, -10.0], [0.4, 0.375, h]);
    let ground = Boxes(vec![FLOOR, bump]);
    let pose = settle_four_wheel(&ground, &r, 0.0, 0.0, 5.0, 0.0, &SettleParams::default())
        .expect("settles");
    assert_eq!(pose.support.len(), 3, "{pose:?}");
    assert!(
        pose.support.contains(&0) && pose.support.contains(&3),
        "{pose:?}"
    );
    let hanging = (0..4)
        .find(|k| !pose.support.contains(k))
        .expect("one hangs");
    assert!(hanging == 1 || hanging == 2);
    // The wheels form a parallelogram on the chassis plane and the three supporting ones stand
    // on the ground (heights h, 0, 0 around it), so the hanging one is h above the floor,
    // vertically: h / n_z along the chassis normal.
    let n = pose.rotation * Vector3::z();
    assert!(
        (pose.wheel_clearance[hanging] - h / n.z).abs() < 1e-6,
        "{} vs {}",
        pose.wheel_clearance[hanging],
        h / n.z
    );
    for k in &pose.support {
        assert!(pose.wheel_clearance[*k].abs() < 1e-5);
    }
}

#[test]
fn untethered_on_a_plane_the_friction_angle_decides() {
    let rover = FourWheelRover::new(FourWheelParams::default()).expect("rover");
    let mu: f64 = 0.4;
    for slope_deg in [5.0f64, 15.0, 20.0, 24.0, 30.0] {
        let ground = plane(slope_deg.to_radians().tan(), 0.0);
        let pose = settle_four_wheel(
            &ground,
            rover.params(),
            0.0,
            0.0,
            30.0,
            0.3,
            &SettleParams::default(),
        )
        .expect("settles");
        let placed = pose.place(&rover, &ground, mu, None).expect("placed");
        let r = StabilityQp::default().check(&placed).expect("solved");
        assert_eq!(
            r.stable,
            slope_deg.to_radians().tan() <= mu,
            "slope {slope_deg}: {r:?}"
        );
    }
}

#[test]
fn bad_input_is_a_typed_error() {
    use rappel_mechanics::settle::SettleError;
    let ground = plane(0.1, 0.0);
    let p = SettleParams::default();
    let r = FourWheelParams::default();
    for (x, params) in [
        (f64::NAN, r),
        (
            0.0,
            FourWheelParams {
                wheelbase: 0.0,
                ..r
            },
        ),
        (
            0.0,
            FourWheelParams {
                track: f64::INFINITY,
                ..r
            },
        ),
    ] {
        assert!(matches!(
            settle_four_wheel(&ground, &params, x, 0.0, 5.0, 0.0, &p),
            Err(SettleError::Parameter(_))
        ));
    }
    // Steeper than the model accepts.
    let steep = plane(10.0, 0.0);
    assert!(matches!(
        settle_four_wheel(&steep, &r, 0.0, 0.0, 80.0, 0.0, &p),
        Err(SettleError::SlopeBeyondModel(_))
    ));
}
