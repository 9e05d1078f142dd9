//! Settling benchmarks (issue 14, Paton §IV-A; target < 50 us per Axel pose): one Axel pose on
//! Paton's ledge through each distance source a caller can hand the settler: the dense 10 cm
//! field (`terrain::sdf`), parry's exact BVH distances (`terrain::parry_mesh`) and the sparse
//! 10 cm field (`terrain::sparse_sdf`, the source `rappel settle` uses with `--field`), on the
//! top, mid-slope and with the left wheel 1 cm beside the ledge's side wall (heading +x on the
//! ground at y = 5.46); and the four-wheel settler (`rappel_mechanics::four_wheel_settle`)
//! mid-slope through the dense field and the exact mesh. Kept apart from `benches/mesh.rs` so
//! that its set-up (three fields of one small scene) takes seconds, not a minute.

use criterion::{Criterion, criterion_group, criterion_main};
use rappel_mechanics::axel::AxelParams;
use rappel_mechanics::four_wheel::FourWheelParams;
use rappel_mechanics::four_wheel_settle::settle_four_wheel;
use rappel_mechanics::settle::{SettleParams, settle_axel};
use rappel_terrain::parry_mesh::ParryMesh;
use rappel_terrain::paton_scene::PatonScene;
use rappel_terrain::sdf::{Sdf, SdfParams};
use rappel_terrain::sparse_sdf::{SparseSdf, SparseSdfParams};
use rappel_terrain::surface::SignedDistance;
use std::hint::black_box;

fn settle(c: &mut Criterion) {
    let scene = PatonScene::paper(false);
    let m = scene.mesh().expect("the paper's scene meshes");
    let mut dp = SdfParams::new(0.1);
    dp.margin = 2.0;
    let dense = Sdf::from_mesh(&m, &dp).expect("the field fits the cap");
    let bvh = ParryMesh::new(&m).expect("parry builds");
    let mut sp = SparseSdfParams::new(0.1);
    sp.margin = 2.0;
    let sparse = SparseSdf::from_mesh(&m, &sp).expect("field builds");
    let axel = AxelParams::default();
    let p = SettleParams::default();
    let s = scene.start();
    let mid_slope = 0.5 * scene.slope_foot_x();
    let wall_y = 0.5 * scene.length + 0.5 * axel.track + 0.01;

    let mut g = c.benchmark_group("settle");
    g.sample_size(10);
    let sources: [(&str, &dyn SignedDistance); 3] = [
        ("sdf_10cm", &dense),
        ("parry_bvh", &bvh),
        ("sparse_sdf_10cm", &sparse),
    ];
    for (name, ground) in sources {
        for (place, px, py) in [
            ("top", s.x, s.y),
            ("slope", mid_slope, 0.0),
            ("beside_wall", -2.0, -wall_y),
        ] {
            g.bench_function(format!("axel_{place}_{name}"), |b| {
                b.iter(|| {
                    let _ = black_box(settle_axel(ground, &axel, black_box(px), py, 5.9, 0.0, &p));
                })
            });
        }
    }
    let rover = FourWheelParams::default();
    let four: [(&str, &dyn SignedDistance); 3] = [
        ("four_wheel_slope_sdf_10cm", &dense),
        ("four_wheel_slope_sparse_sdf_10cm", &sparse),
        ("four_wheel_slope_exact_mesh", &m),
    ];
    for (name, ground) in four {
        g.bench_function(name, |b| {
            b.iter(|| {
                settle_four_wheel(ground, &rover, black_box(mid_slope), 0.0, 5.9, 0.0, &p)
                    .expect("settles")
            })
        });
    }
    g.finish();
}

criterion_group!(benches, settle);
criterion_main!(benches);
