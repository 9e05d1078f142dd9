//! Axel settling (Paton §IV-A) against closed forms: planes of any slope and aspect, a step under
//! one wheel, a box ridge under the axle (body collision exactly where it meets the axle body).

use nalgebra::Point3;
use rappel_mechanics::axel::AxelParams;
use rappel_mechanics::settle::{SettleError, SettleParams, settle_axel};
use rappel_terrain::mesh::TriMesh;

/// A mesh extruded along x over `[-20, 20]` from a `(y, z)` profile (vertical steps allowed).
fn profile(points: &[(f64, f64)]) -> TriMesh {
    profile_over(points, 20.0)
}

/// A mesh extruded along x over `[-half_x, half_x]` from a `(y, z)` profile.
fn profile_over(points: &[(f64, f64)], half_x: f64) -> TriMesh {
    let mut v = Vec::new();
    for &(y, z) in points {
        v.push(Point3::new(-half_x, y, z));
        v.push(Point3::new(half_x, y, z));
    }
    let mut t = Vec::new();
    for i in 0..points.len() - 1 {
        let (a, b, c, d) = (2 * i, 2 * i + 1, 2 * i + 3, 2 * i + 2);
        t.push([a, b, c]);
        t.push([a, c, d]);
    }
    TriMesh::new(v, t).unwrap()
}

fn plane(a: f64, b: f64) -> TriMesh {
    let z = |x: f64, y: f64| a * x + b * y;
    let c = [(-20.0, -20.0), (20.0, -20.0), (20.0, 20.0), (-20.0, 20.0)];
    let v = c.iter().map(|&(x, y)| Point3::new(x, y, z(x, y))).collect();
    TriMesh::new(v, vec![[0, 1, 2], [0, 2, 3]]).unwrap()
}

#[test]
fn plane_of_any_slope_and_aspect() {
    let axel = AxelParams::default();
    let p = SettleParams::default();
    for slope_deg in [0.0, 10.0, 30.0, 55.0] {
        for aspect_deg in [0.0f64, 40.0, 135.0, 250.0] {
            let g = f64::tan(f64::to_radians(slope_deg));
            let (a, b) = (
                g * aspect_deg.to_radians().cos(),
                g * aspect_deg.to_radians().sin(),
            );
            let m = plane(a, b);
            for yaw_deg in [0.0, 70.0, 200.0] {
                let yaw: f64 = f64::to_radians(yaw_deg);
                let (x, y) = (1.3, -0.7);
                let pose = settle_axel(&m, &axel, x, y, 30.0, yaw, &p).unwrap();
                // Closed forms for the plane z = a x + b y.
                let (c, s) = (yaw.cos(), yaw.sin());
                let pitch = (a * c + b * s).atan();
                let nn = (1.0 + a * a + b * b).sqrt();
                let mm = (1.0 + (a * c + b * s).powi(2)).sqrt();
                let roll = ((b * c - a * s) / (nn * mm)).asin();
                let ctx = format!("slope {slope_deg} aspect {aspect_deg} yaw {yaw_deg}");
                assert!(
                    (pose.origin.z - (a * x + b * y)).abs() < 1e-3,
                    "height {ctx}"
                );
                assert!(
                    (pose.pitch() - pitch).abs() < 1e-3,
                    "pitch {} vs {pitch} {ctx}",
                    pose.pitch()
                );
                assert!(
                    (pose.roll() - roll).abs() < 1e-3,
                    "roll {} vs {roll} {ctx}",
                    pose.roll()
                );
                for q in pose.contacts {
                    assert!((q.z - (a * q.x + b * q.y)).abs() < 1e-3, "contact {ctx}");
                }
            }
        }
    }
}

#[test]
fn step_under_one_wheel_rolls_the_body() {
    let axel = AxelParams::default();
    let h = 0.1;
    // Ground z = 0 for y < 0, z = h for y > 0 (a vertical step along x).
    let m = profile(&[(-20.0, 0.0), (0.0, 0.0), (0.0, h), (20.0, h)]);
    let pose = settle_axel(&m, &axel, 0.0, -0.01, 5.0, 0.0, &SettleParams::default()).unwrap();
    // Heading +x: the left wheel (y > 0) on the upper level.
    let roll = (h / axel.track).asin();
    assert!(
        (pose.roll() - roll).abs() < 1e-3,
        "{} vs {roll}",
        pose.roll()
    );
    let [right, left] = pose.contacts;
    assert!(right.z.abs() < 1e-3 && right.y < 0.0, "{right}");
    assert!((left.z - h).abs() < 1e-3 && left.y > 0.0, "{left}");
    assert!((left - right).norm() - axel.track < 1e-3);
}

#[test]
fn box_ridge_meets_the_axle_body_exactly() {
    let axel = AxelParams::default();
    let p = SettleParams::default();
    let ridge = |h: f64| {
        profile(&[
            (-20.0, 0.0),
            (-0.1, 0.0),
            (-0.1, h),
            (0.1, h),
            (0.1, 0.0),
            (20.0, 0.0),
        ])
    };
    // The axle is wheel_radius above the ground; the body reaches body_radius below it: the
    // clearance over a ridge of height h is wheel_radius - body_radius - h.
    let free = axel.wheel_radius - p.body_radius;
    let ok = settle_axel(&ridge(free + 0.01), &axel, 0.0, 0.8, 5.0, 0.0, &p);
    // Beside the ridge (the wheels at y = 0.8 +- 0.45 on the flat) no collision.
    let ok = ok.unwrap();
    assert!(ok.origin.z.abs() < 1e-6);
    let on = settle_axel(&ridge(free - 0.01), &axel, 0.0, 0.0, 5.0, 0.0, &p).unwrap();
    assert!(
        (on.body_clearance - 0.01).abs() < 1e-6,
        "{}",
        on.body_clearance
    );
    match settle_axel(&ridge(free + 0.01), &axel, 0.0, 0.0, 5.0, 0.0, &p) {
        Err(SettleError::BodyCollision {
            index, clearance, ..
        }) => {
            assert_eq!(index, p.body_points / 2);
            assert!((clearance + 0.01).abs() < 1e-6, "{clearance}");
        }
        other => panic!("expected a body collision, got {other:?}"),
    }
}

#[test]
fn typed_failures() {
    let axel = AxelParams::default();
    let p = SettleParams::default();
    let m = plane(0.0, 0.0);
    assert!(matches!(
        settle_axel(&m, &axel, f64::NAN, 0.0, 5.0, 0.0, &p),
        Err(SettleError::Parameter(_))
    ));
    // A wall-like slope beyond max_slope.
    let steep = plane(8.0, 0.0);
    assert!(matches!(
        settle_axel(&steep, &axel, 0.0, 0.0, 200.0, 0.0, &p),
        Err(SettleError::SlopeBeyondModel(_))
    ));
    // Off a distance field's grid: no ground.
    let f =
        rappel_terrain::sdf::Sdf::from_mesh(&m, &rappel_terrain::sdf::SdfParams::new(0.5)).unwrap();
    assert!(matches!(
        settle_axel(&f, &axel, 100.0, 0.0, 1.0, 0.0, &p),
        Err(SettleError::NoGround { .. })
    ));
}

#[test]
fn paton_ledge_start_and_slope() {
    use rappel_terrain::paton_scene::PatonScene;
    use rappel_terrain::sdf::{Sdf, SdfParams};
    let scene = PatonScene::paper(false);
    let m = scene.mesh().unwrap();
    let axel = AxelParams::default();
    let p = SettleParams::default();
    let s = scene.start();
    // On the top, through the distance field (planar there: trilinear is exact in the band).
    let mut sp = SdfParams::new(0.25);
    sp.margin = 2.0; // room for the wheels `delta` above the top
    let f = Sdf::from_mesh(&m, &sp).unwrap();
    let top = settle_axel(&f, &axel, s.x, s.y, 5.9, 0.0, &p).unwrap();
    assert!(
        (top.origin.z - 4.0).abs() < 1e-3 && top.pitch().abs() < 1e-3,
        "{top:?}"
    );
    // Mid-slope facing down it (exact mesh): pitch -55 degrees, roll 0.
    let x = 0.5 * scene.slope_foot_x();
    let down = settle_axel(&m, &axel, x, 0.0, 8.0, 0.0, &p).unwrap();
    assert!(
        (down.pitch() + 55f64.to_radians()).abs() < 1e-3,
        "{}",
        down.pitch()
    );
    assert!(down.roll().abs() < 1e-3);
    assert!((down.origin.z - 2.0).abs() < 1e-3, "{}", down.origin);
}

/// Cross-check of two implementations: the QP verdict of a pose settled on a plane mesh equals
/// that of the closed-form placement `robot::place` on the same `SlopePlane`, both boom modes.
#[test]
fn settled_stability_matches_planar_placement() {
    use nalgebra::{Point3, Rotation3, Vector3};
    use rappel_mechanics::axel::{Axel, BoomMode};
    use rappel_mechanics::robot::{PlanarPose, SlopePlane, TetherSpec, place};
    use rappel_mechanics::stability_qp::StabilityQp;
    let qp = StabilityQp::default();
    for boom in [BoomMode::Inline, BoomMode::InContact] {
        let params = AxelParams {
            boom,
            ..AxelParams::default()
        };
        let axel = Axel::new(params).unwrap();
        for slope_deg in [20.0f64, 40.0, 55.0] {
            let eta = slope_deg.to_radians();
            let plane = SlopePlane::new(eta, 0.6).unwrap();
            // World plane z = y tan(eta): the plane frame rotated by eta about x.
            let m = plane_mesh_b(eta.tan());
            let rot = Rotation3::from_axis_angle(&Vector3::x_axis(), eta);
            for (heading, anchor_plane) in [
                (std::f64::consts::PI, Point3::new(0.0, 6.0, 1.0)),
                (std::f64::consts::PI, Point3::new(0.0, -6.0, 1.0)),
                (2.0, Point3::new(3.0, 5.0, 2.0)),
            ] {
                let pose = PlanarPose::new(0.0, 0.0, heading);
                let spec = TetherSpec {
                    anchor: anchor_plane,
                    max_tension: None,
                };
                let reference = qp
                    .check(&place(&axel, &pose, &plane, Some(&spec)).unwrap())
                    .unwrap();
                // The heading is an in-plane angle from up-slope; the settler's yaw is the
                // azimuth of the forward axis seen from above.
                let f = rot * Vector3::new(-heading.sin(), heading.cos(), 0.0);
                let yaw = f.y.atan2(f.x);
                let settled =
                    settle_axel(&m, &params, 0.0, 0.0, 10.0, yaw, &SettleParams::default())
                        .unwrap();
                let anchor_world = rot * anchor_plane;
                let placed = settled
                    .place(&axel, &m, 0.6, Some((&anchor_world, None)))
                    .unwrap();
                let got = qp.check(&placed).unwrap();
                assert_eq!(
                    got.stable, reference.stable,
                    "{boom:?} {slope_deg} {heading}"
                );
                // Same contacts, masses and tether up to the settler's 1e-6 m tolerance.
                let tol = 1e-5 * reference.margin.abs().max(1e-3);
                assert!(
                    (got.margin - reference.margin).abs() < tol,
                    "{boom:?} {slope_deg} {heading}: {} vs {}",
                    got.margin,
                    reference.margin
                );
            }
        }
    }
}

fn plane_mesh_b(b: f64) -> TriMesh {
    plane(0.0, b)
}

/// A horizontal cylinder of radius `r` along the world x axis (axis at the origin): the exact
/// signed distance `|(y, z)| - r`.
struct Cylinder(f64);

impl rappel_terrain::surface::SignedDistance for Cylinder {
    fn signed_distance(&self, q: &Point3<f64>) -> Option<f64> {
        Some((q.y * q.y + q.z * q.z).sqrt() - self.0)
    }
    fn distance_gradient(&self, q: &Point3<f64>) -> Option<nalgebra::Vector3<f64>> {
        nalgebra::Vector3::new(0.0, q.y, q.z).try_normalize(0.0)
    }
}

/// Axel driving along the top of a large cylinder (a log or a rounded ridge crest, along the
/// heading): each wheel circle, in a plane `y = ±track/2`, rests on the cylinder's line there at
/// height `sqrt(R² - (track/2)²)` under its lowest point; the body stays level.
#[test]
fn on_a_cylinder_the_wheels_touch_where_geometry_puts_them() {
    let axel = AxelParams::default();
    let p = SettleParams::default();
    for r in [2.0, 5.0, 20.0] {
        let ground = Cylinder(r);
        let pose = settle_axel(&ground, &axel, 0.3, 0.0, r + 3.0, 0.0, &p).expect("settles");
        let h = (r * r - 0.25 * axel.track * axel.track).sqrt();
        for (c, side) in pose.contacts.iter().zip([-1.0, 1.0]) {
            assert!((c.y - side * 0.5 * axel.track).abs() < 1e-6, "R {r}: {c:?}");
            assert!((c.z - h).abs() < 1e-6, "R {r}: {c:?} vs {h}");
            assert!((c.x - 0.3).abs() < 1e-6, "R {r}: {c:?}");
        }
        assert!(pose.roll().abs() < 1e-9 && pose.pitch().abs() < 1e-9);
        assert!((pose.origin.z - h).abs() < 1e-6);
    }
}

/// Ground `z = 0` for `y < w` and a wall at `y = w` rising to `height` (its top flat beyond):
/// extruded along x.
fn wall_beside(w: f64, height: f64) -> TriMesh {
    profile(&[(-20.0, 0.0), (w, 0.0), (w, height), (20.0, height)])
}

/// A wheel 1 cm and 1 mm beside a wall (Axel heading along it, the wall `gap` left of the left
/// wheel's plane), on the exact mesh and behind parry's BVH: the drop along the normal reaches
/// the ground (the old sphere tracing stepped by the wall's distance and ran out of steps at
/// 1 mm), and the pose is what geometry makes it. A tall wall: the axle's left end (body point
/// `body_points - 1`, `wheel_radius` above the ground in the left wheel's plane) is `gap` from
/// the wall, a body collision of clearance `gap - body_radius`. A low curb of height `c`: the
/// pose settles level on the ground, its clearance the distance from the axle's end to the
/// curb's top edge, `sqrt(gap² + (wheel_radius - c)²) - body_radius`.
#[test]
fn a_wheel_beside_a_wall_settles_or_collides_where_geometry_puts_it() {
    use rappel_terrain::parry_mesh::ParryMesh;
    let axel = AxelParams::default();
    let p = SettleParams::default();
    let half = 0.5 * axel.track;
    for gap in [0.01, 0.001] {
        let tall = wall_beside(half + gap, 1.0);
        let tall_bvh = ParryMesh::new(&tall).unwrap();
        for (name, r) in [
            ("mesh", settle_axel(&tall, &axel, 0.0, 0.0, 5.0, 0.0, &p)),
            ("bvh", settle_axel(&tall_bvh, &axel, 0.0, 0.0, 5.0, 0.0, &p)),
        ] {
            match r {
                Err(SettleError::BodyCollision {
                    index,
                    x,
                    y,
                    z,
                    clearance,
                }) => {
                    assert_eq!(index, p.body_points - 1, "{name} gap {gap}");
                    assert!(
                        (Point3::new(x, y, z) - Point3::new(0.0, half, axel.wheel_radius)).norm()
                            < 1e-9,
                        "{name} gap {gap}: ({x}, {y}, {z})"
                    );
                    assert!(
                        (clearance - (gap - p.body_radius)).abs() < 1e-9,
                        "{name} gap {gap}: {clearance}"
                    );
                }
                other => panic!("{name} gap {gap}: expected a body collision, got {other:?}"),
            }
        }
        let c = 0.05;
        let curb = wall_beside(half + gap, c);
        let curb_bvh = ParryMesh::new(&curb).unwrap();
        for (name, r) in [
            ("mesh", settle_axel(&curb, &axel, 0.0, 0.0, 5.0, 0.0, &p)),
            ("bvh", settle_axel(&curb_bvh, &axel, 0.0, 0.0, 5.0, 0.0, &p)),
        ] {
            let pose = r.unwrap_or_else(|e| panic!("{name} gap {gap}: {e}"));
            assert!(
                pose.origin.coords.norm() < 1e-9,
                "{name} gap {gap}: {pose:?}"
            );
            assert!(pose.roll().abs() < 1e-9 && pose.pitch().abs() < 1e-9);
            for (q, side) in pose.contacts.iter().zip([-1.0, 1.0]) {
                assert!(
                    (q - Point3::new(0.0, side * half, 0.0)).norm() < 1e-9,
                    "{name} gap {gap}: {q}"
                );
            }
            let want = (gap * gap + (axel.wheel_radius - c).powi(2)).sqrt() - p.body_radius;
            assert!(
                (pose.body_clearance - want).abs() < 1e-9,
                "{name} gap {gap}: {} vs {want}",
                pose.body_clearance
            );
        }
    }
}

/// The same walls through the sparse 5 cm field: the field smears the wall over a cell, so the
/// verdict is the field's (within its error bound of the wall), but the drop never fails to
/// find the ground: a settled pose or a body collision, never `NoContact`.
#[test]
fn beside_a_wall_the_field_s_drop_never_fails_to_find_the_ground() {
    use rappel_terrain::sparse_sdf::{SparseSdf, SparseSdfParams};
    let axel = AxelParams::default();
    let p = SettleParams::default();
    let half = 0.5 * axel.track;
    for gap in [0.01, 0.001] {
        for height in [1.0, 0.05] {
            // A 4 m x 4 m patch: the field stays small.
            let m = profile_over(
                &[
                    (-2.0, 0.0),
                    (half + gap, 0.0),
                    (half + gap, height),
                    (2.0, height),
                ],
                2.0,
            );
            let mut fp = SparseSdfParams::new(0.05);
            fp.margin = 2.0;
            let f = SparseSdf::from_mesh(&m, &fp).unwrap();
            match settle_axel(&f, &axel, 0.0, 0.0, 2.0, 0.0, &p) {
                Ok(pose) => assert!(pose.origin.z.abs() <= f.error_bound(), "{pose:?}"),
                Err(SettleError::BodyCollision { index, .. }) => {
                    assert_eq!(index, p.body_points - 1, "gap {gap} height {height}")
                }
                Err(e) => panic!("gap {gap} height {height}: {e}"),
            }
        }
    }
}
