//! The stability map of Paton's ledge at 10 cm (Fig. 8's whole-ledge view, as
//! `rappel settle-map fixtures/paton/ledge.ron --test N --step 0.1`: x from the ledge's back to
//! 1 m past the slope's foot, y along the whole ledge, 89 x 101 = 8 989 cells, every pose
//! heading down the slope), under the root anchors of Paton's tests 1 and 2 (issue 14's goal:
//! < 5 s on 2 cores). Each map settles every cell, predicts the anchor histories ring by ring
//! from the start and runs the stability QP for both boom configurations (rayon), through
//! parry's exact BVH distances and through the sparse 10 cm distance field (its build included,
//! as the CLI's `--field 0.1` does), on identical input in one run.

use criterion::{Criterion, criterion_group, criterion_main};
use rappel::planners::rover::ground::{DistanceSource, GroundDistances};
use rappel::planners::rover::stability_map::{MapSpec, stability_map_with};
use rappel_planners::anchor_prediction::AnchorHistory;
use rappel_terrain::paton_scene::PatonScene;
use std::hint::black_box;

fn stability_map(c: &mut Criterion) {
    let scene = PatonScene::paper(false);
    let ground = scene.mesh().expect("the paper's scene meshes");
    let s = scene.start();
    // The CLI's default view of a scene (crates/cli/src/settle_map.rs).
    let spec = MapSpec {
        x: (-scene.width, scene.slope_foot_x() + 1.0),
        y: (-0.5 * scene.length, 0.5 * scene.length),
        step: 0.1,
        yaw_deg: 0.0,
        start: [s.x, s.y],
    };
    let mut g = c.benchmark_group("stability_map");
    g.sample_size(10);
    for (test, root) in scene.anchor_points().into_iter().take(2).enumerate() {
        let root = AnchorHistory::new(root).expect("a finite root");
        for (name, source) in [
            ("exact", DistanceSource::Exact),
            ("field_10cm", DistanceSource::Field { resolution_m: 0.1 }),
        ] {
            g.bench_function(format!("ledge_10cm_test{}_{name}", test + 1), |b| {
                b.iter(|| {
                    let d = GroundDistances::new(black_box(&ground), source).expect("builds");
                    let map = stability_map_with(&ground, &d, &root, &spec).expect("maps");
                    assert_eq!(map.cells.len(), 8_989);
                    map.stable
                })
            });
        }
    }
    g.finish();
}

criterion_group!(benches, stability_map);
criterion_main!(benches);
