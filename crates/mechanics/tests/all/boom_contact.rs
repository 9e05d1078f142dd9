//! Axel's boom swept into contact with a mesh (Paton §IV-A, in-contact configuration) against
//! closed forms: on a plane the tip touches at elevation `-asin(r_w / L_c)` (the planar model's
//! answer); past a convex lip the shaft rests on the lip at `-atan(r_w / s)` (`s` the distance
//! along the slope from the lip) while the lip is within reach, the tip on the slope beyond; a
//! raised step's edge at `atan((H - r_w) / d)` while within reach, else the tip on the wall at
//! `acos(d / L_c)`; and on Paton's ledge a settled pose just past the lip rests its boom on the
//! lip.

use nalgebra::{Point3, Unit, Vector3};
use rappel_mechanics::axel::{Axel, AxelParams, BoomMode};
use rappel_mechanics::boom_contact::{
    BoomContactError, place_boom_in_contact, place_boom_inline, sweep_boom,
};
use rappel_mechanics::settle::{SettleParams, settle_axel};
use rappel_terrain::mesh::TriMesh;
use rappel_terrain::paton_scene::PatonScene;

/// A mesh extruded along y over `[-20, 20]` from an `(x, z)` profile in increasing x (vertical
/// steps allowed), the air above.
fn profile(points: &[(f64, f64)]) -> TriMesh {
    let mut v = Vec::new();
    for &(x, z) in points {
        v.push(Point3::new(x, -20.0, z));
        v.push(Point3::new(x, 20.0, z));
    }
    let mut t = Vec::new();
    for i in 0..points.len() - 1 {
        let (a, b, c, d) = (2 * i, 2 * i + 2, 2 * i + 3, 2 * i + 1);
        t.push([a, b, c]);
        t.push([a, c, d]);
    }
    TriMesh::new(v, t).unwrap()
}

const R: f64 = 0.35;
const L: f64 = 1.0;

#[test]
fn plane_tip_contact_matches_the_planar_model() {
    for slope_deg in [0.0f64, 20.0, 55.0] {
        let t = slope_deg.to_radians().tan();
        // z = -t x: descending toward +x.
        let m = profile(&[(-20.0, 20.0 * t), (20.0, -20.0 * t)]);
        let n = Unit::new_normalize(Vector3::new(t, 0.0, 1.0));
        let down = Unit::new_normalize(Vector3::new(1.0, 0.0, -t));
        let origin = Point3::new(0.3, 0.2, -0.3 * t);
        let pivot = origin + n.into_inner() * R;
        // The boom toward up-slope (-down).
        let back = Unit::new_unchecked(-down.into_inner());
        let c = sweep_boom(&m, &pivot, &back, &n, L).unwrap();
        let want = -(R / L).asin();
        assert!((c.elevation - want).abs() < 1e-9, "{slope_deg}: {c:?}");
        assert!(c.at_tip && (c.along - L).abs() < 1e-9);
        assert!((c.point - c.tip).norm() < 1e-9);
        assert!((c.normal.into_inner() - n.into_inner()).norm() < 1e-9);
        // The tip on the plane.
        assert!(m.signed_distance(&c.tip).abs() < 1e-9);
    }
}

#[test]
fn convex_lip_holds_the_shaft_then_the_tip_reaches_the_slope() {
    // A ledge top z = 0 for x < 0, a 55° slope down for x > 0 (the lip at x = 0).
    let a = 55f64.to_radians();
    let m = profile(&[(-20.0, 0.0), (0.0, 0.0), (5.0, -5.0 * a.tan())]);
    let n = Unit::new_normalize(Vector3::new(a.sin(), 0.0, a.cos()));
    let up_slope = Unit::new_normalize(Vector3::new(-a.cos(), 0.0, a.sin()));
    let mut seen = Vec::new();
    for s in [0.1, 0.3, 0.5, 0.7, 0.9, 0.95, 1.2] {
        let origin = Point3::origin() - up_slope.into_inner() * s;
        let pivot = origin + n.into_inner() * R;
        let c = sweep_boom(&m, &pivot, &up_slope, &n, L).unwrap();
        // Closed form: the largest elevation among the contacts the geometry allows: the lip
        // (while within reach), the tip on the top (where the reach circle meets z = 0 behind
        // the lip; elevation from the up-slope direction, which rises at 55°), the tip on the
        // slope (when the lip is out of reach).
        let mut want = Vec::new();
        if s.hypot(R) <= L {
            want.push(("lip", -(R / s).atan()));
        } else {
            want.push(("slope", -(R / L).asin()));
        }
        let phi = -(pivot.z / L).asin();
        if pivot.z.abs() <= L && pivot.x - L * phi.cos() < 0.0 {
            want.push(("top", phi - a));
        }
        let (kind, e) =
            want.into_iter().fold(
                ("", f64::NEG_INFINITY),
                |b, w| if w.1 > b.1 { w } else { b },
            );
        assert!((c.elevation - e).abs() < 1e-9, "{s} {kind}: {c:?}");
        seen.push(kind);
        match kind {
            "lip" => {
                assert!(!c.at_tip && (c.along - s.hypot(R)).abs() < 1e-9);
                assert!(c.point.x.abs() < 1e-9 && c.point.z.abs() < 1e-9);
                // Edge-on-line normal: perpendicular to the boom and to the lip (y).
                let boom = (c.tip - pivot).normalize();
                assert!(c.normal.dot(&boom).abs() < 1e-9 && c.normal.y.abs() < 1e-9);
                assert!(c.normal.z > 0.0);
            }
            "top" => {
                assert!(c.at_tip && c.point.z.abs() < 1e-9 && c.point.x < 0.0);
                assert!((c.normal.into_inner() - Vector3::z()).norm() < 1e-9);
            }
            _ => {
                assert!(c.at_tip && (c.normal.into_inner() - n.into_inner()).norm() < 1e-9);
            }
        }
    }
    // All three contacts occur over the range above.
    for k in ["top", "lip", "slope"] {
        assert!(seen.contains(&k), "{k} never occurs: {seen:?}");
    }
}

#[test]
fn raised_step_edge_then_wall() {
    // Ground z = 0 for x > -d, a block of height h for x < -d (its wall at x = -d).
    let h = 0.6;
    let up = Unit::new_unchecked(Vector3::z());
    let back = Unit::new_unchecked(-Vector3::x());
    let pivot = Point3::new(0.0, 0.0, R);
    for d in [0.3, 0.6, 0.9] {
        let m = profile(&[(-20.0, h), (-d, h), (-d, 0.0), (20.0, 0.0)]);
        let c = sweep_boom(&m, &pivot, &back, &up, L).unwrap();
        let edge = d.hypot(h - R);
        if edge <= L {
            assert!((c.elevation - (h - R).atan2(d)).abs() < 1e-9, "{d}: {c:?}");
            assert!((c.point - Point3::new(-d, 0.0, h)).norm() < 1e-9);
            assert!(!c.at_tip || (edge - L).abs() < 1e-9);
        } else {
            // The tip on the wall (the wall's normal +x).
            assert!((c.elevation - (d / L).acos()).abs() < 1e-9, "{d}: {c:?}");
            assert!(c.at_tip && (c.point.x + d).abs() < 1e-9);
            assert!((c.normal.into_inner() - Vector3::x()).norm() < 1e-9);
        }
    }
    // Over a drop deeper than the boom reaches: no ground.
    let cliff = profile(&[(-20.0, -5.0), (-0.2, -5.0), (-0.2, 0.0), (20.0, 0.0)]);
    let hang = Point3::new(0.0, 0.0, 0.2);
    assert!(matches!(
        sweep_boom(&cliff, &hang, &back, &up, 0.1),
        Err(BoomContactError::NoGround(_))
    ));
    assert!(sweep_boom(&cliff, &pivot, &back, &back, L).is_err());
    assert!(sweep_boom(&cliff, &Point3::new(f64::NAN, 0.0, 0.0), &back, &up, L).is_err());
}

#[test]
fn settled_pose_past_the_ledge_lip_rests_its_boom_on_the_lip() {
    let scene = PatonScene::paper(false);
    let mesh = scene.mesh().unwrap();
    let axel = AxelParams::default();
    let anchor = Point3::new(-6.0, 0.0, 10.0);
    for x in [0.2, 0.4] {
        let pose = settle_axel(&mesh, &axel, x, 0.0, 10.0, 0.0, &SettleParams::default()).unwrap();
        let (placed, c) = place_boom_in_contact(&pose, &axel, &mesh, 0.6, (&anchor, None)).unwrap();
        // The footprint straddles the lip, so the pose is not on the slope's plane: the closed
        // form is that the boom passes through the lip, below the pose's plane.
        assert!(
            c.point.x.abs() < 1e-6 && (c.point.z - scene.height).abs() < 1e-6,
            "{x}: {c:?}"
        );
        let pivot = pose.origin + pose.rotation * Vector3::z() * axel.wheel_radius;
        let (boom, to_lip) = ((c.tip - pivot).normalize(), (c.point - pivot).normalize());
        assert!((boom - to_lip).norm() < 1e-6 && !c.at_tip && c.elevation < -(0.35f64).asin());
        assert_eq!(placed.contacts.len(), 3);
        // The tether leaves from the boom's tip toward the anchor.
        let t = placed.tether.unwrap();
        assert!((t.exit - c.tip).norm() < 1e-9);
        assert!((t.direction.into_inner() - (anchor - c.tip).normalize()).norm() < 1e-9);
    }
    // Mid-slope, the boom's tip lies on the slope: same as the planar in-contact model.
    let pose = settle_axel(&mesh, &axel, 1.4, 0.0, 10.0, 0.0, &SettleParams::default()).unwrap();
    let (placed, c) = place_boom_in_contact(&pose, &axel, &mesh, 0.6, (&anchor, None)).unwrap();
    let planar = pose
        .place(
            &Axel::new(AxelParams {
                boom: BoomMode::InContact,
                ..axel
            })
            .unwrap(),
            &mesh,
            0.6,
            Some((&anchor, None)),
        )
        .unwrap();
    assert!(c.at_tip);
    // The pose stands within the contact tolerance (1e-6 m) of the ground, so its plane and
    // the mesh differ by about that.
    let dc = (placed.contacts[2].position - planar.contacts[2].position).norm();
    let dt = (placed.tether.unwrap().exit - planar.tether.unwrap().exit).norm();
    assert!(dc < 1e-5 && dt < 1e-5, "{dc} {dt}");
}

#[test]
fn inline_boom_clears_the_real_ground_not_the_pose_plane() {
    let a = 55f64.to_radians();
    let m = profile(&[(-20.0, 0.0), (0.0, 0.0), (5.0, -5.0 * a.tan())]);
    let axel = AxelParams::default();
    let inline = Axel::new(AxelParams {
        boom: BoomMode::Inline,
        ..axel
    })
    .unwrap();
    // On the slope, beyond the boom's reach of the lip: an anchor up the slope's line of
    // sight agrees with the planar inline model.
    let pose = settle_axel(&m, &axel, 1.5, 0.0, 10.0, 0.0, &SettleParams::default()).unwrap();
    let far = Point3::new(-6.0, 0.0, 5.0);
    let mesh = place_boom_inline_ok(&pose, &axel, &m, &far);
    let planar = pose.place(&inline, &m, 0.6, Some((&far, None))).unwrap();
    let t = (mesh.tether.unwrap(), planar.tether.unwrap());
    assert!((t.0.exit - t.1.exit).norm() < 1e-9 && mesh.contacts.len() == 2);
    // Just past the lip (pose plane pitched down): an anchor behind the top, 0.5 m above it,
    // is below the pose's plane (the planar model says the boom digs) but the line from the
    // pivot clears the top, which falls away behind the lip.
    let near = settle_axel(&m, &axel, 0.1, 0.0, 10.0, 0.0, &SettleParams::default()).unwrap();
    let low = Point3::new(-6.0, 0.0, 0.5);
    assert!(near.place(&inline, &m, 0.6, Some((&low, None))).is_err());
    let placed = place_boom_inline_ok(&near, &axel, &m, &low);
    let pivot = near.origin + near.rotation * Vector3::z() * axel.wheel_radius;
    let exit = placed.tether.unwrap().exit;
    // The tip on the pivot-anchor line, one boom length out, above the ground.
    assert!(((exit - pivot).normalize() - (low - pivot).normalize()).norm() < 1e-9);
    assert!(
        ((exit - pivot).norm() - axel.boom_length).abs() < 1e-9 && m.signed_distance(&exit) > 0.0
    );
    // An anchor behind and below the top's level: the boom would pass through the top.
    let under = Point3::new(-6.0, 0.0, -1.0);
    assert!(matches!(
        place_boom_inline(&near, &axel, &m, 0.6, (&under, None)),
        Err(BoomContactError::InlineThroughGround { .. })
    ));
    // An anchor within the boom's reach.
    let close = Point3::new(-0.3, 0.0, 0.2);
    assert!(matches!(
        place_boom_inline(&near, &axel, &m, 0.6, (&close, None)),
        Err(BoomContactError::Robot(_))
    ));
}

fn place_boom_inline_ok(
    pose: &rappel_mechanics::settle::SettledPose,
    axel: &AxelParams,
    m: &TriMesh,
    anchor: &Point3<f64>,
) -> rappel_mechanics::robot::PlacedRobot {
    place_boom_inline(pose, axel, m, 0.6, (anchor, None)).unwrap()
}

/// A rough DEM mesh: `n x n` cell centres `h` apart from the origin, heights a sum of seeded
/// bumps on a 20° ramp (a real-DEM-sized mesh, `2 (n - 1)²` triangles).
fn rough_dem(n: usize, h: f64, seed: u64) -> TriMesh {
    use rand::{RngExt, SeedableRng};
    use rappel_terrain::grid::{GridGeometry, HeightGrid};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let bumps: Vec<(f64, f64, f64, f64)> = (0..40)
        .map(|_| {
            let size = n as f64 * h;
            (
                rng.random_range(0.0..size),
                rng.random_range(-size..0.0),
                rng.random_range(-1.5..1.5),
                rng.random_range(0.5..4.0),
            )
        })
        .collect();
    let g = GridGeometry::new(n, n, h, h, 0.0, 0.0).unwrap();
    let dem = HeightGrid::from_fn(g, |_, _, p| {
        let ramp = 20f64.to_radians().tan() * p.x;
        Some(
            ramp + bumps
                .iter()
                .map(|&(x, y, a, r)| a * (-((p.x - x).powi(2) + (p.y - y).powi(2)) / (r * r)).exp())
                .sum::<f64>(),
        )
    })
    .unwrap();
    TriMesh::from_height_grid(&dem).unwrap()
}

/// The BVH's candidate triangles give exactly the brute-force sweep's contact (or the same
/// error) on seeded poses over a rough DEM and over Paton's ledge.
#[test]
fn bvh_sweep_finds_the_brute_force_contacts() {
    use rand::{RngExt, SeedableRng};
    use rappel_mechanics::boom_contact::IndexedGround;
    use rappel_terrain::parry_mesh::ParryMesh;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(140);
    let ledge = PatonScene::paper(false).mesh().unwrap();
    let dem = rough_dem(60, 0.25, 14);
    let (mut contacts, mut tips) = (0, 0);
    for mesh in [&ledge, &dem] {
        let bvh = ParryMesh::new(mesh).unwrap();
        let indexed = IndexedGround { mesh, bvh: &bvh };
        let (lo, hi) = mesh.bounds();
        for k in 0..400 {
            let (x, y) = (rng.random_range(lo.x..hi.x), rng.random_range(lo.y..hi.y));
            // The pivot above the ground by 0.2-0.6 m (some sweeps reach nothing).
            let down = mesh.signed_distance(&Point3::new(x, y, hi.z + 1.0));
            let pivot = Point3::new(x, y, hi.z + 1.0 - down + rng.random_range(0.2..0.6));
            let up = Unit::new_normalize(Vector3::new(
                rng.random_range(-0.5..0.5),
                rng.random_range(-0.5..0.5),
                1.0,
            ));
            let t = rng.random_range(0.0..std::f64::consts::TAU);
            let h = Vector3::new(t.cos(), t.sin(), 0.0);
            let azimuth = Unit::new_normalize(h - up.into_inner() * h.dot(&up));
            let brute = sweep_boom(mesh, &pivot, &azimuth, &up, 1.0);
            let fast = sweep_boom(&indexed, &pivot, &azimuth, &up, 1.0);
            assert_eq!(brute, fast, "pose {k} at ({x}, {y})");
            if let Ok(c) = brute {
                contacts += 1;
                tips += usize::from(c.at_tip);
            }
        }
    }
    // Tip and shaft contacts both occur, and most sweeps touch.
    assert!(
        contacts > 400 && tips > 0 && tips < contacts,
        "{contacts} {tips}"
    );
}

/// The boom's ground contact carries `AxelParams::boom_friction`, the wheels the ground's: the
/// boom's force stays in its own pyramid and the verdicts are monotone in the coefficient (the
/// feasible set only grows with it).
#[test]
fn the_boom_contact_has_its_own_friction() {
    use rappel_mechanics::stability_qp::StabilityQp;
    let scene = PatonScene::paper(false);
    let mesh = scene.mesh().unwrap();
    // Mid-slope, the tether from the lip (its predicted anchor, `docs/mesh.md`).
    let anchor = Point3::new(0.0, 0.0, scene.height);
    let pose = settle_axel(
        &mesh,
        &AxelParams::default(),
        1.0,
        0.0,
        10.0,
        0.0,
        &SettleParams::default(),
    )
    .unwrap();
    let mut verdicts = Vec::new();
    for boom_friction in [0.0, 0.3, 0.6, 0.9] {
        let axel = AxelParams {
            boom_friction,
            ..AxelParams::default()
        };
        let (placed, _) = place_boom_in_contact(&pose, &axel, &mesh, 0.6, (&anchor, None)).unwrap();
        assert_eq!(placed.contacts[2].friction, Some(boom_friction));
        assert_eq!(placed.contact_friction(0), 0.6);
        assert_eq!(placed.contact_friction(2), boom_friction);
        let r = StabilityQp::default().check(&placed).unwrap();
        let w = 55.0 * rappel_mechanics::robot::STANDARD_GRAVITY;
        if r.stable {
            let b = r.wrenches[2].force;
            assert!(
                b.x.abs().max(b.y.abs()) <= boom_friction * b.z + 1e-7 * w,
                "{boom_friction}: {b:?}"
            );
        }
        verdicts.push(r.stable);
    }
    assert!(verdicts.windows(2).all(|v| v[1] >= v[0]), "{verdicts:?}");
    // The planar in-contact tip (the model's third contact) carries it too.
    let axel = Axel::new(AxelParams {
        boom: BoomMode::InContact,
        boom_friction: 0.25,
        ..AxelParams::default()
    })
    .unwrap();
    let planar = pose
        .place(&axel, &mesh, 0.6, Some((&anchor, None)))
        .unwrap();
    assert_eq!(planar.contact_friction(2), 0.25);
    assert_eq!(planar.contact_friction(1), 0.6);
    assert!(
        Axel::new(AxelParams {
            boom_friction: -1.0,
            ..AxelParams::default()
        })
        .is_err()
    );
}

/// Boom friction that changes verdicts: over seeded settled poses on Paton's ledge scene, each
/// with a seeded anchor in the air (at least 0.3 m above the mesh), the in-contact boom with
/// wheel friction 0.6 is checked with boom friction 0 and 0.6. The feasible set only grows with
/// the coefficient, so no pose may lose stability; some poses must be **held only by the boom's
/// friction** (unstable at 0, stable at 0.6: 25 of the 1 046 poses checked), and in each of
/// those the boom's tangential force is non-zero and inside its pyramid. Fails if the boom's
/// own coefficient is ignored (no flips) or misapplied (a flip the wrong way), and failed on a
/// real defect: a frictionless contact's tangential forces were weighted 1e18 in the objective,
/// and both solvers then called poses whose boom carried no load unstable at friction 0.
#[test]
fn boom_friction_decides_some_verdicts() {
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;
    use rappel_mechanics::stability_qp::StabilityQp;
    let scene = PatonScene::paper(false);
    let mesh = scene.mesh().unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    let (mut checked, mut flips) = (0, 0);
    for _ in 0..1500 {
        let (x, y) = (rng.random_range(-1.5..3.5), rng.random_range(-4.0..4.0));
        let yaw = rng.random_range(-std::f64::consts::PI..std::f64::consts::PI);
        let anchor = Point3::new(
            rng.random_range(-6.0..9.0),
            rng.random_range(-5.0..5.0),
            rng.random_range(0.0..8.0),
        );
        if mesh.signed_distance(&anchor) < 0.3 {
            continue;
        }
        let Ok(pose) = settle_axel(
            &mesh,
            &AxelParams::default(),
            x,
            y,
            10.0,
            yaw,
            &SettleParams::default(),
        ) else {
            continue;
        };
        let check = |boom_friction: f64| {
            let a = AxelParams {
                boom_friction,
                ..AxelParams::default()
            };
            let (placed, _) = place_boom_in_contact(&pose, &a, &mesh, 0.6, (&anchor, None)).ok()?;
            // The boom's contact is the last one (after the wheels' settled contacts).
            assert!(placed.contacts.last().is_some_and(|c| c.point));
            Some(StabilityQp::default().check(&placed).unwrap())
        };
        let (Some(without), Some(with)) = (check(0.0), check(0.6)) else {
            continue;
        };
        checked += 1;
        assert!(
            with.stable || !without.stable,
            "boom friction 0.6 lost a pose stable without it: ({x}, {y}) yaw {yaw}"
        );
        if with.stable && !without.stable {
            flips += 1;
            let boom = with.wrenches.last().unwrap();
            let b = boom.force;
            let t = b.x.abs().max(b.y.abs());
            assert!(t > 1e-6 && t <= 0.6 * b.z * (1.0 + 1e-6) + 1e-6, "{b:?}");
            assert_eq!(boom.moment, Vector3::zeros(), "point contact");
        }
    }
    // 25 of 1 046 when written.
    assert!(checked > 800, "{checked} poses checked");
    assert!(
        flips >= 10,
        "{flips} of {checked} poses held only by boom friction"
    );
}
