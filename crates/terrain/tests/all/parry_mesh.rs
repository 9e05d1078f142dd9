//! The parry3d adapter against the brute-force exact mesh distance on Paton's scenes (seeded
//! random points over the ledge and around the pole) and ray casts against closed forms.

use nalgebra::{Point3, Vector3};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rappel_terrain::parry_mesh::ParryMesh;
use rappel_terrain::paton_scene::PatonScene;
use rappel_terrain::surface::SignedDistance;

#[test]
fn parry_distances_agree_with_the_exact_mesh() {
    for pole in [false, true] {
        let scene = PatonScene::paper(pole);
        let mesh = scene.mesh().unwrap();
        let parry = ParryMesh::new(&mesh).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(14);
        for _ in 0..2000 {
            // Over the ledge and the ground in front, away from the mesh's outer boundary.
            let q = Point3::new(
                rng.random_range(-8.0..6.0),
                rng.random_range(-7.0..7.0),
                rng.random_range(-1.0..8.0),
            );
            let want = mesh.signed_distance(&q);
            let got = parry.signed_distance(&q).unwrap();
            assert!(
                (got - want).abs() < 1e-9,
                "pole {pole}, {q:?}: parry {got}, mesh {want}"
            );
            if want.abs() > 1e-6 {
                let g = parry.distance_gradient(&q).unwrap();
                // The gradient points from the closest point toward q (outside).
                let (p, _) = parry.project(&q);
                assert!(((q - p).normalize() * want.signum() - g).norm() < 1e-9);
            }
        }
    }
}

#[test]
fn rays_hit_the_ledge_where_geometry_says() {
    let scene = PatonScene::paper(false);
    let parry = ParryMesh::new(&scene.mesh().unwrap()).unwrap();
    // Straight down onto the top (z = 4) from z = 10.
    let t = parry
        .cast_ray(&Point3::new(-1.0, 0.0, 10.0), &-Vector3::z(), 100.0)
        .unwrap();
    assert!((t - 6.0).abs() < 1e-9, "{t}");
    // Down onto the slope at x = 1: z = 4 - tan 55°.
    let t = parry
        .cast_ray(&Point3::new(1.0, 0.0, 10.0), &-Vector3::z(), 100.0)
        .unwrap();
    assert!((t - (6.0 + 55f64.to_radians().tan())).abs() < 1e-9, "{t}");
    // Up into the sky: no hit.
    assert!(
        parry
            .cast_ray(&Point3::new(1.0, 0.0, 10.0), &Vector3::z(), 100.0)
            .is_none()
    );
    assert!(
        parry
            .signed_distance(&Point3::new(f64::NAN, 0.0, 0.0))
            .is_none()
    );
}
