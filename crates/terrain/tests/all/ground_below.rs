//! `SignedDistance::ground_below`, the settlers' vertical drop, on Paton's ledge scene against its
//! closed-form heights: the brute-force mesh and parry's BVH (the same exact vertical ray) give
//! the scene's height bit for bit, and the sparse 10 cm field's ground point is within its error
//! bound of the mesh. The verticals include those the earlier sphere tracing could not finish in
//! its 200 steps: 1 cm beside the ledge's vertical side wall (exact distances: each step moved
//! 1 cm along 4 m of wall) and inside the side wall's plane below the slope's edge (through the
//! field: the interpolant creeps to zero at a slope of about 0.04 there).

use nalgebra::Point3;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rappel_terrain::parry_mesh::ParryMesh;
use rappel_terrain::paton_scene::PatonScene;
use rappel_terrain::sparse_sdf::{SparseSdf, SparseSdfParams};
use rappel_terrain::surface::SignedDistance;

/// The paper's ledge (crates/terrain/src/paton_scene.rs): top at 4 m over x in [-5, 0] and
/// |y| <= 5, the 55° slope down to x = 4 / tan 55°, the ground at 0 elsewhere; the first ground
/// from above on a vertical through an edge is the higher side.
fn height(scene: &PatonScene, x: f64, y: f64) -> f64 {
    let foot = scene.slope_foot_x();
    if y.abs() > 0.5 * scene.length || x < -scene.width || x > foot {
        0.0
    } else if x <= 0.0 {
        scene.height
    } else {
        (foot - x) * scene.slope_deg.to_radians().tan()
    }
}

#[test]
fn the_vertical_drop_finds_the_ledge_s_closed_form_heights() {
    let scene = PatonScene::paper(false);
    let mesh = scene.mesh().unwrap();
    let parry = ParryMesh::new(&mesh).unwrap();
    let mut p = SparseSdfParams::new(0.1);
    p.margin = 2.0;
    let field = SparseSdf::from_mesh(&mesh, &p).unwrap();
    let bound = field.error_bound();
    let mut rng = ChaCha8Rng::seed_from_u64(140);
    let mut verticals: Vec<(f64, f64)> = (0..400)
        .map(|_| (rng.random_range(-8.0..6.0), rng.random_range(-7.0..7.0)))
        .collect();
    // Beside the side and back walls (1 cm and 1 mm off), in the side wall's plane below the
    // slope's edge (the whole-ledge map's corner cells' footprint), on the lip and the foot.
    verticals.extend([
        (-2.0, 5.01),
        (-2.0, -5.001),
        (-5.01, 0.0),
        (1.5, 5.01),
        (2.55, 5.0),
        (2.55, -5.0),
        (1.0, 5.0),
        (0.0, 0.0),
        (scene.slope_foot_x(), 1.0),
    ]);
    for (x, y) in verticals {
        let top = Point3::new(x, y, 5.0);
        let want = height(&scene, x, y);
        let brute = mesh.ground_below(&top, 1e-6).expect("ground below");
        let bvh = parry.ground_below(&top, 1e-6).expect("ground below");
        assert_eq!(brute, bvh, "({x}, {y})");
        assert!(
            (brute.z - want).abs() < 1e-9,
            "({x}, {y}): {} vs {want}",
            brute.z
        );
        // From below the ground (inside the ledge, not on a wall) the search goes up to the same
        // surface.
        if want > 0.5 && y.abs() < 4.9 && x > -4.9 {
            let under = Point3::new(x, y, want - 0.3);
            let up = mesh.ground_below(&under, 1e-6).expect("ground above");
            assert!(
                (up.z - want).abs() < 1e-9,
                "({x}, {y}) from below: {}",
                up.z
            );
            assert_eq!(up, parry.ground_below(&under, 1e-6).unwrap());
        }
        // The field's ground point is a zero of its interpolant, so within the field's error
        // bound of the mesh.
        let g = field.ground_below(&top, 1e-6).expect("field ground below");
        assert_eq!((g.x, g.y), (x, y));
        assert!(field.distance(&g).unwrap().abs() < 1e-9, "({x}, {y})");
        let exact = mesh.signed_distance(&g);
        assert!(
            exact.abs() <= bound,
            "({x}, {y}): field ground {g:?} is {exact} m off"
        );
    }
    // Off the grid: no answer, typed.
    assert!(
        field
            .ground_below(&Point3::new(100.0, 0.0, 5.0), 1e-6)
            .is_err()
    );
}
