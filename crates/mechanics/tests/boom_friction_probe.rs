//! temporary search
use nalgebra::Point3;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rappel_mechanics::axel::AxelParams;
use rappel_mechanics::boom_contact::place_boom_in_contact;
use rappel_mechanics::settle::{SettleParams, settle_axel};
use rappel_mechanics::stability_qp::StabilityQp;
use rappel_terrain::paton_scene::PatonScene;
#[test]
fn search() {
    let scene = PatonScene::paper(false);
    let mesh = scene.mesh().unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    let mut found = 0;
    let mut tried = 0;
    for _ in 0..3000 {
        let x = rng.random_range(-1.5..3.5);
        let y = rng.random_range(-4.0..4.0);
        let yaw = rng.random_range(-3.14..3.14);
        let anchor = Point3::new(rng.random_range(-6.0..9.0), rng.random_range(-5.0..5.0), rng.random_range(0.0..8.0));
        let Ok(pose) = settle_axel(&mesh, &AxelParams::default(), x, y, 10.0, yaw, &SettleParams::default()) else { continue };
        let v = |bf: f64| -> Option<bool> {
            let a = AxelParams { boom_friction: bf, ..AxelParams::default() };
            let (placed, _) = place_boom_in_contact(&pose, &a, &mesh, 0.6, (&anchor, None)).ok()?;
            StabilityQp::default().check(&placed).ok().map(|r| r.stable)
        };
        let (Some(a), Some(b)) = (v(0.0), v(0.6)) else { continue };
        tried += 1;
        if !a && b {
            found += 1;
            if found < 10 { eprintln!("flip x {x:.3} y {y:.3} yaw {yaw:.3} anchor {anchor:?}"); }
        }
    }
    eprintln!("tried {tried} found {found}");
}
