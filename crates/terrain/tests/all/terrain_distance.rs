//! The `Terrain` trait's analytic signed distance against an independent oracle: the exact
//! brute-force distance to a triangle mesh of the same surfaces (`mesh::TriMesh`).

use nalgebra::{Point2, Point3};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rappel_terrain::mesh::TriMesh;
use rappel_terrain::plane_series::TerrainPlane;
use rappel_terrain::plane_series_terrain::PlaneSeriesTerrain;
use rappel_terrain::surface::{SignedDistance, Terrain};

fn check(slopes: [f64; 2]) {
    let t = PlaneSeriesTerrain::new(
        &[
            TerrainPlane::new(20.0, 10.0, slopes[0], 0.4),
            TerrainPlane::new(10.0, 0.0, slopes[1], 0.4),
        ],
        (0.0, 10.0),
        vec![],
    )
    .unwrap();
    // The same two quads as a mesh, corners folded from the frame.
    let mut vertices = Vec::new();
    for (s, (top, bottom)) in [(0, (20.0, 10.0)), (1, (10.0, 0.0))] {
        for p in [(0.0, bottom), (10.0, bottom), (10.0, top), (0.0, top)] {
            vertices.push(t.fold(s, &Point2::new(p.0, p.1)));
        }
    }
    // Share the crest vertices: surface 1's top corners are surface 0's bottom corners.
    vertices[6] = vertices[1];
    vertices[7] = vertices[0];
    let mut triangles = vec![[0, 1, 2], [0, 2, 3], [4, 5, 1], [4, 1, 0]];
    let m0 = TriMesh::new(vertices.clone(), triangles.clone()).unwrap();
    if m0.face_normal(0).z < 0.0 {
        for tri in &mut triangles {
            tri.swap(1, 2);
        }
    }
    let m = TriMesh::new(vertices, triangles).unwrap();
    assert!(m.face_normal(0).z > 0.0 && m.face_normal(2).z > 0.0);
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let mut n = 0;
    for _ in 0..400 {
        let fx = rng.random_range(2.0..8.0);
        let fy = rng.random_range(2.0..18.0);
        let ground = t.world(&Point2::new(fx, fy)).unwrap();
        let q = ground + nalgebra::Vector3::new(0.0, 0.0, rng.random_range(-1.5..1.5));
        let oracle = m.closest(&q);
        // Only points whose nearest ground is away from the terrain's outer boundary.
        let c = oracle.point;
        let fc = (0..2)
            .map(|s| t.unfold(s, &c))
            .find(|p| t.surface_at(p).is_some());
        let Some(fc) = fc else { continue };
        if fc.x < 0.5 || fc.x > 9.5 || fc.y < 0.5 || fc.y > 19.5 {
            continue;
        }
        let d = t.signed_distance(&q).expect("a distance over the terrain");
        assert!(
            (d - oracle.signed_distance).abs() < 1e-9,
            "{q}: {d} vs {}",
            oracle.signed_distance
        );
        let g = t.distance_gradient(&q).unwrap();
        assert!((g.norm() - 1.0).abs() < 1e-9);
        if oracle.signed_distance.abs() > 1e-6 {
            let dir = (q - c) / oracle.signed_distance;
            assert!((g - dir).norm() < 1e-6, "{q}: gradient {g} vs {dir}");
        }
        n += 1;
    }
    assert!(n > 300, "only {n} points checked");
}

#[test]
fn crest_distance_matches_mesh_oracle() {
    check([0.0, 30.0]);
}

#[test]
fn steep_crest_distance_matches_mesh_oracle() {
    check([10.0, 55.0]);
}

#[test]
fn off_terrain_is_none() {
    let t = PlaneSeriesTerrain::new(
        &[TerrainPlane::new(20.0, 10.0, 0.0, 0.4)],
        (0.0, 10.0),
        vec![],
    )
    .unwrap();
    assert_eq!(t.signed_distance(&Point3::new(50.0, 50.0, 1.0)), None);
    let above = t.world(&Point2::new(5.0, 15.0)).unwrap() + nalgebra::Vector3::z() * 2.0;
    assert!((t.signed_distance(&above).unwrap() - 2.0).abs() < 1e-12);
}
