//! Settling through the sparse distance field (`rappel::planners::rover::ground`, `--field RES`) against
//! parry's exact distances on seeded poses over both ledge scenes, and the poses the vertical drop
//! used to lose: the whole-ledge map's corner cells at the side walls (x = 2.9, y = ±5: "no ground
//! within 6 m" through the field) and a pose whose footprint probe runs 1 cm beside the side wall
//! (the same failure on exact distances).

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rappel::planners::rover::ground::{DistanceSource, GroundDistances};
use rappel::terrain::paton_scene::PatonScene;

fn field(h: f64) -> DistanceSource {
    DistanceSource::Field { resolution_m: h }
}

#[test]
fn the_corner_cells_and_the_wall_side_pose_settle() {
    let scene = PatonScene::paper(false);
    let mesh = scene.mesh().unwrap();
    let exact = GroundDistances::new(&mesh, DistanceSource::Exact).unwrap();
    let through = GroundDistances::new(&mesh, field(0.1)).unwrap();
    let bound = through.report().error_bound_m.unwrap();
    for y in [5.0, -5.0] {
        let e = exact.settle(2.9, y, 0.0).expect("exact settles");
        let f = through.settle(2.9, y, 0.0).expect("the field settles");
        assert!((e.origin - f.origin).norm() <= bound, "{e:?} vs {f:?}");
    }
    // Heading +y beside the side wall: the footprint's probes run 1 cm off the wall, the wheels
    // stand on the ground (z = 0) clear of it.
    for d in [&exact, &through] {
        let p = d.settle(-2.0, 5.36, 90.0).expect("settles beside the wall");
        assert!(p.origin.z.abs() <= bound, "{:?}", p.origin);
    }
}

/// Seeded poses over the ledge and the pole scene: settled through the 10 cm field in the same
/// cases as on exact distances (apart from poses within the field's error of a settling limit),
/// every field contact within the field's error bound of the exact surface, and the origins
/// within two bounds of each other.
#[test]
fn field_settling_agrees_with_exact_settling_on_seeded_poses() {
    for pole in [false, true] {
        let scene = PatonScene::paper(pole);
        let mesh = scene.mesh().unwrap();
        let exact = GroundDistances::new(&mesh, DistanceSource::Exact).unwrap();
        let through = GroundDistances::new(&mesh, field(0.1)).unwrap();
        let bound = through.report().error_bound_m.unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(14 + pole as u64);
        let (mut both, mut one) = (0, 0);
        for _ in 0..300 {
            let (x, y, yaw) = (
                rng.random_range(-4.5..4.0),
                rng.random_range(-4.5..4.5),
                rng.random_range(0.0..360.0),
            );
            match (exact.settle(x, y, yaw), through.settle(x, y, yaw)) {
                (Ok(e), Ok(f)) => {
                    both += 1;
                    for c in &f.contacts {
                        let d = mesh.signed_distance(c);
                        assert!(d.abs() <= bound, "({x}, {y}, {yaw}): contact {c:?} {d}");
                    }
                    let gap = (e.origin - f.origin).norm();
                    assert!(gap <= 2.0 * bound, "({x}, {y}, {yaw}): {gap}");
                }
                (Err(_), Err(_)) => {}
                _ => one += 1,
            }
        }
        assert!(both >= 200, "pole {pole}: {both} settled both ways");
        assert!(one <= 6, "pole {pole}: {one} settled one way only");
    }
}
