//! `SignedDistance::ground_along`, the settlers' drop along a footprint normal (Paton §IV-A):
//! on planes of several slopes and aspects against the closed form of a line meeting a plane
//! (the brute-force mesh and parry's BVH exactly, the sparse field within its error bound and
//! on a zero of its interpolant); on Paton's ledge the BVH's answer equals the brute force's bit
//! for bit, agrees with parry's own floating-point ray cast (an independent implementation), and
//! the field's hit points lie within its error bound of the mesh; lines running 1 cm and 1 mm
//! beside the ledge's vertical walls reach the ground below.

use nalgebra::{Point3, Unit, Vector3};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rappel_terrain::mesh::TriMesh;
use rappel_terrain::parry_mesh::ParryMesh;
use rappel_terrain::paton_scene::PatonScene;
use rappel_terrain::sparse_sdf::{SparseSdf, SparseSdfParams};
use rappel_terrain::surface::SignedDistance;

/// The plane `z = a x + b y` over `[-7, 7]^2` (the lines below stay more than 1 m inside).
fn plane(a: f64, b: f64) -> TriMesh {
    let c = [(-7.0, -7.0), (7.0, -7.0), (7.0, 7.0), (-7.0, 7.0)];
    let v = c
        .iter()
        .map(|&(x, y)| Point3::new(x, y, a * x + b * y))
        .collect();
    TriMesh::new(v, vec![[0, 1, 2], [0, 2, 3]]).unwrap()
}

/// Whether the segment from `q` to `end` lies in the field's box (outside it the field has no
/// value: `DropError::Undefined`).
fn in_box(field: &SparseSdf, q: &Point3<f64>, end: &Point3<f64>) -> bool {
    let (lo, hi) = field.bounds();
    [q, end]
        .iter()
        .all(|p| (0..3).all(|a| p[a] > lo[a] && p[a] < hi[a]))
}

/// A seeded unit vector, uniform on the sphere.
fn unit(rng: &mut ChaCha8Rng) -> Unit<Vector3<f64>> {
    loop {
        let v = Vector3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        );
        let n = v.norm();
        if n > 0.1 && n <= 1.0 {
            return Unit::new_normalize(v);
        }
    }
}

#[test]
fn on_planes_the_drop_is_the_line_plane_closed_form() {
    let mut rng = ChaCha8Rng::seed_from_u64(1414);
    for slope_deg in [0.0f64, 10.0, 30.0, 55.0] {
        for aspect_deg in [0.0f64, 40.0, 135.0, 250.0] {
            let g = slope_deg.to_radians().tan();
            let (a, b) = (
                g * aspect_deg.to_radians().cos(),
                g * aspect_deg.to_radians().sin(),
            );
            let mesh = plane(a, b);
            let bvh = ParryMesh::new(&mesh).unwrap();
            let mut p = SparseSdfParams::new(0.1);
            p.margin = 2.0;
            let field = SparseSdf::from_mesh(&mesh, &p).unwrap();
            let bound = field.error_bound();
            let mut hits = 0;
            for _ in 0..60 {
                let q = Point3::new(
                    rng.random_range(-3.0..3.0),
                    rng.random_range(-3.0..3.0),
                    0.0,
                );
                let q = Point3::new(q.x, q.y, a * q.x + b * q.y + rng.random_range(-0.8..0.8));
                let dir = unit(&mut rng);
                let reach = rng.random_range(0.2..2.0);
                // Closed form: the height above the plane is linear along the line.
                let height = q.z - a * q.x - b * q.y;
                let rate = dir.z - a * dir.x - b * dir.y;
                let t = -height / rate;
                let want = (t.abs() <= reach && t * height.signum() >= 0.0).then_some(t);
                let ctx = format!("slope {slope_deg} aspect {aspect_deg} q {q} dir {dir:?}");
                let brute = mesh.ground_along(&q, &dir, reach, 1e-9).unwrap();
                assert_eq!(
                    brute,
                    bvh.ground_along(&q, &dir, reach, 1e-9).unwrap(),
                    "{ctx}"
                );
                match (brute, want) {
                    (Some(got), Some(t)) => {
                        assert!(
                            (got - t).abs() <= 1e-9 * (1.0 + t.abs()),
                            "{ctx}: {got} vs {t}"
                        );
                        hits += 1;
                    }
                    (None, None) => {}
                    (got, want) => panic!("{ctx}: {got:?} vs {want:?}"),
                }
                // The field: a zero of its interpolant, within the field's bound of the plane;
                // only lines that clear the plane by more than the bound at the reach's end can
                // miss.
                let end = q + dir.as_ref() * (reach * height.signum());
                if !in_box(&field, &q, &end) {
                    continue;
                }
                match field.ground_along(&q, &dir, reach, 1e-9).unwrap() {
                    Some(t) => {
                        let hit = q + dir.as_ref() * t;
                        assert!(field.distance(&hit).unwrap().abs() < 1e-9, "{ctx}");
                        let exact = (hit.z - a * hit.x - b * hit.y) / (1.0 + a * a + b * b).sqrt();
                        assert!(exact.abs() <= bound, "{ctx}: {exact} off the plane");
                        assert!(t * height.signum() >= -1e-12, "{ctx}: wrong way {t}");
                    }
                    None => {
                        let end_height =
                            (end.z - a * end.x - b * end.y) / (1.0 + a * a + b * b).sqrt();
                        assert!(
                            end_height * height.signum() > -bound,
                            "{ctx}: the field missed a crossing ({end_height} at the end)"
                        );
                    }
                }
            }
            assert!(
                hits >= 5,
                "slope {slope_deg} aspect {aspect_deg}: {hits} hits"
            );
        }
    }
}

#[test]
fn on_the_ledge_the_bvh_is_the_brute_force_and_agrees_with_parry_s_ray_cast() {
    let scene = PatonScene::paper(false);
    let mesh = scene.mesh().unwrap();
    let bvh = ParryMesh::new(&mesh).unwrap();
    let mut p = SparseSdfParams::new(0.1);
    p.margin = 2.0;
    let field = SparseSdf::from_mesh(&mesh, &p).unwrap();
    let bound = field.error_bound();
    let mut rng = ChaCha8Rng::seed_from_u64(14);
    let (mut hits, mut field_hits) = (0, 0);
    for _ in 0..1500 {
        let q = Point3::new(
            rng.random_range(-7.0..5.0),
            rng.random_range(-6.5..6.5),
            rng.random_range(-0.5..5.5),
        );
        let d = mesh.signed_distance(&q);
        if d.abs() < 1e-6 {
            continue;
        }
        let dir = unit(&mut rng);
        let reach = rng.random_range(0.5..6.0);
        let brute = mesh.ground_along(&q, &dir, reach, 1e-9).unwrap();
        assert_eq!(
            brute,
            bvh.ground_along(&q, &dir, reach, 1e-9).unwrap(),
            "{q} {dir:?}"
        );
        if d > 0.0 {
            // Parry's own ray cast (floating point, its BVH traversal) from the air.
            let parry = bvh.cast_ray(&q, dir.as_ref(), reach);
            match (brute, parry) {
                (Some(t), Some(u)) => {
                    assert!((t - u).abs() < 1e-9, "{q} {dir:?}: {t} vs parry {u}");
                    hits += 1;
                }
                (None, None) => {}
                (t, u) => panic!("{q} {dir:?}: {t:?} vs parry {u:?}"),
            }
            let end = q + dir.as_ref() * reach;
            if !in_box(&field, &q, &end) {
                continue;
            }
            if let Some(t) = field.ground_along(&q, &dir, reach, 1e-9).unwrap() {
                let hit = q + dir.as_ref() * t;
                let exact = mesh.signed_distance(&hit);
                assert!(exact.abs() <= bound, "{q} {dir:?}: field hit {exact} off");
                field_hits += 1;
            }
        } else {
            // From below the ground the line is searched backward.
            assert!(brute.is_none_or(|t| t <= 0.0), "{q} {dir:?}: {brute:?}");
        }
    }
    assert!(hits > 100 && field_hits > 100, "{hits} {field_hits}");
}

#[test]
fn beside_the_ledge_s_walls_the_drop_reaches_the_ground_below() {
    let scene = PatonScene::paper(false);
    let mesh = scene.mesh().unwrap();
    let bvh = ParryMesh::new(&mesh).unwrap();
    let mut p = SparseSdfParams::new(0.05);
    p.margin = 2.0;
    let field = SparseSdf::from_mesh(&mesh, &p).unwrap();
    let bound = field.error_bound();
    let half = 0.5 * scene.length;
    let down = -Vector3::z_axis();
    // Straight down, and tilted 20° along the wall (the line stays beside it).
    let tilted = Unit::new_normalize(Vector3::new(20f64.to_radians().tan(), 0.0, -1.0));
    for gap in [0.01, 0.001] {
        for (q, dir) in [
            (Point3::new(-2.0, half + gap, 3.5), down),
            (Point3::new(-2.0, -half - gap, 3.5), down),
            (Point3::new(-scene.width - gap, 1.0, 3.5), down),
            (Point3::new(-3.0, half + gap, 3.5), tilted),
        ] {
            let t = mesh
                .ground_along(&q, &dir, 6.0, 1e-9)
                .unwrap()
                .expect("ground");
            let hit = q + dir.as_ref() * t;
            assert!(hit.z.abs() < 1e-12, "{q}: {hit}");
            assert_eq!(Some(t), bvh.ground_along(&q, &dir, 6.0, 1e-9).unwrap());
            // The field smears the wall over a cell: its zero is within its bound of the mesh.
            let tf = field
                .ground_along(&q, &dir, 6.0, 1e-9)
                .unwrap()
                .expect("field ground");
            let hit = q + dir.as_ref() * tf;
            assert!(
                mesh.signed_distance(&hit).abs() <= bound,
                "{q}: field {hit}"
            );
        }
    }
}
