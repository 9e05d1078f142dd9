//! Mesh-terrain benchmarks (issue 14, Paton §IV): building the dense distance field of Paton's
//! ledge (settling one pose through it and the other distance sources is `benches/settle.rs`). The
//! build is timed at 20 cm only: measured once at 1.9 s (20 cm) and 26 s (10 cm, 15 M grid
//! points, the Dijkstra propagation dominates), 5 cm would take minutes per sample; the fast
//! field (`terrain::sparse_sdf`, the 5 cm target) is benchmarked beside it in `benches/sdf.rs`.
//!
//! Anchor prediction (Paton Alg. 1) of one motion step across the ledge's lip under the test-1
//! root anchor, through the same 10 cm field, on the exact mesh by brute force and through the
//! parry3d BVH adapter (target < 100 us), and the
//! stability of one settled pose with its predicted anchor (place + QP, boom inline, by the dense
//! active-set solver and by clarabel; and both boom configurations as `rappel settle-map` does;
//! target < 100 us).
//!
//! The boom swept against the mesh (`rappel_mechanics::boom_contact`, exact section sweep over
//! the ledge's triangles) for a pose just past the lip (its shaft rests on the lip), with the
//! in-contact and the mesh-checked inline placements + QP; the sweep on a 318 402-triangle DEM
//! mesh over every triangle and over parry's BVH candidates.

use criterion::{Criterion, criterion_group, criterion_main};
use nalgebra::{Point3, Vector3};
use rappel::planners::rover::stability_map::{pose_stability, tether_end};
use rappel_mechanics::axel::{Axel, AxelParams, BoomMode};
use rappel_mechanics::settle::{SettleParams, settle_axel};
use rappel_mechanics::stability_qp::StabilityQp;
use rappel_planners::anchor_prediction::{AnchorHistory, PredictParams, predict};
use rappel_terrain::paton_scene::PatonScene;
use rappel_terrain::sdf::{Sdf, SdfParams};
use std::hint::black_box;

fn mesh(c: &mut Criterion) {
    let scene = PatonScene::paper(false);
    let m = scene.mesh().expect("the paper's scene meshes");
    let mut sp = SdfParams::new(0.1);
    sp.margin = 2.0;
    let field = Sdf::from_mesh(&m, &sp).expect("the field fits the cap");
    let axel = AxelParams::default();
    let p = SettleParams::default();

    let mut g = c.benchmark_group("mesh");
    g.sample_size(10);
    let x = 0.5 * scene.slope_foot_x();
    // One 0.5 m step of the boom pivot from the top over the lip onto the slope: one attach.
    let a = scene.slope_deg.to_radians();
    let pivot = |x: f64| {
        if x <= 0.0 {
            Point3::new(x, 0.0, scene.height + axel.wheel_radius)
        } else {
            Point3::new(x, 0.0, scene.height - x * a.tan())
                + Vector3::new(a.sin(), 0.0, a.cos()) * axel.wheel_radius
        }
    };
    let root = AnchorHistory::new(scene.anchor_points()[0]).expect("finite");
    let (from, to) = (pivot(0.0), pivot(0.5));
    let step = predict(&field, &PredictParams::new(0.1), &root, &from, &to).expect("predicts");
    assert_eq!(step.history.len(), 2, "the step attaches on the lip");
    g.bench_function("anchor_prediction_step_over_lip_sdf_10cm", |b| {
        b.iter(|| {
            predict(
                &field,
                &PredictParams::new(0.1),
                &root,
                black_box(&from),
                &to,
            )
            .expect("predicts")
        })
    });
    g.bench_function("anchor_prediction_step_over_lip_exact_mesh_5cm", |b| {
        b.iter(|| {
            predict(&m, &PredictParams::new(0.05), &root, black_box(&from), &to).expect("predicts")
        })
    });
    let bvh = rappel_terrain::parry_mesh::ParryMesh::new(&m).expect("parry builds");
    g.bench_function("anchor_prediction_step_over_lip_parry_bvh_5cm", |b| {
        b.iter(|| {
            predict(
                &bvh,
                &PredictParams::new(0.05),
                &root,
                black_box(&from),
                &to,
            )
            .expect("predicts")
        })
    });
    // Stability of a settled mid-slope pose with the lip anchor.
    let pose = settle_axel(&m, &axel, x, 0.0, 5.9, 0.0, &p).expect("settles");
    let tip = tether_end(&pose, &axel);
    let hist = rappel_planners::anchor_prediction::predict_path(
        &m,
        &PredictParams::new(0.05),
        &root,
        &[
            pivot(-1.0),
            pivot(-0.5),
            pivot(0.0),
            pivot(0.5),
            pivot(1.0),
            tip,
        ],
    )
    .expect("predicts")
    .history;
    let lip = hist.last().point;
    let inline = Axel::new(AxelParams {
        boom: BoomMode::Inline,
        ..axel
    })
    .expect("valid");
    let qp = StabilityQp::default();
    g.bench_function("stability_settled_pose_inline_lip_anchor", |b| {
        b.iter(|| {
            let placed = pose
                .place(&inline, &m, 0.6, Some((black_box(&lip), None)))
                .expect("places");
            qp.check(&placed).expect("solves")
        })
    });
    // The same placement solved by clarabel (the interior-point peer of the dense solver).
    g.bench_function("stability_settled_pose_inline_lip_anchor_clarabel", |b| {
        b.iter(|| {
            let placed = pose
                .place(&inline, &m, 0.6, Some((black_box(&lip), None)))
                .expect("places");
            qp.check_clarabel(&placed).expect("solves")
        })
    });
    g.bench_function("stability_settled_pose_both_booms_lip_anchor", |b| {
        b.iter(|| pose_stability(&m, black_box(&pose), &hist))
    });
    // The boom against the mesh, just past the lip (x = 0.4 m: the shaft rests on the lip).
    let near = settle_axel(&m, &axel, 0.4, 0.0, 5.9, 0.0, &p).expect("settles");
    let up = nalgebra::Unit::new_normalize(near.rotation * Vector3::z());
    let back = nalgebra::Unit::new_normalize(near.rotation * -Vector3::x());
    let near_pivot = tether_end(&near, &axel);
    g.bench_function("boom_sweep_ledge_near_lip", |b| {
        b.iter(|| {
            rappel_mechanics::boom_contact::sweep_boom(
                &m,
                black_box(&near_pivot),
                &back,
                &up,
                axel.boom_length,
            )
            .expect("touches")
        })
    });
    g.bench_function("stability_in_contact_mesh_near_lip", |b| {
        b.iter(|| {
            let (placed, _) = rappel_mechanics::boom_contact::place_boom_in_contact(
                black_box(&near),
                &axel,
                &m,
                0.6,
                (&lip, None),
            )
            .expect("places");
            qp.check(&placed).expect("solves")
        })
    });
    g.bench_function("stability_settled_pose_inline_mesh_lip_anchor", |b| {
        b.iter(|| {
            let placed = rappel_mechanics::boom_contact::place_boom_inline(
                black_box(&pose),
                &axel,
                &m,
                0.6,
                (&lip, None),
            )
            .expect("places");
            qp.check(&placed).expect("solves")
        })
    });
    // The boom sweep on a large DEM mesh (400 x 400 cell centres 0.25 m apart, 318 402
    // triangles, a 20° ramp with bumps): every triangle (the brute force) against the BVH's
    // candidates (`boom_contact::IndexedGround`), the same contact.
    let geometry = rappel_terrain::grid::GridGeometry::new(400, 400, 0.25, 0.25, 0.0, 0.0)
        .expect("valid grid");
    let dem = rappel_terrain::grid::HeightGrid::from_fn(geometry, |_, _, q| {
        Some(20f64.to_radians().tan() * q.x + 0.5 * (0.7 * q.x).sin() * (0.9 * q.y).cos())
    })
    .expect("finite heights");
    let big = rappel_terrain::mesh::TriMesh::from_height_grid(&dem).expect("meshes");
    let big_bvh = rappel_terrain::parry_mesh::ParryMesh::new(&big).expect("parry builds");
    let indexed = rappel_mechanics::boom_contact::IndexedGround {
        mesh: &big,
        bvh: &big_bvh,
    };
    let (lo, hi) = big.bounds();
    let (cx, cy) = (0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y));
    let big_pose = settle_axel(&big, &axel, cx, cy, hi.z + 1.0, 0.0, &p).expect("settles");
    let big_up = nalgebra::Unit::new_normalize(big_pose.rotation * Vector3::z());
    let big_back = nalgebra::Unit::new_normalize(big_pose.rotation * -Vector3::x());
    let big_pivot = tether_end(&big_pose, &axel);
    assert_eq!(
        rappel_mechanics::boom_contact::sweep_boom(&big, &big_pivot, &big_back, &big_up, 1.0),
        rappel_mechanics::boom_contact::sweep_boom(&indexed, &big_pivot, &big_back, &big_up, 1.0),
    );
    g.bench_function("boom_sweep_dem_318k_triangles_brute_force", |b| {
        b.iter(|| {
            rappel_mechanics::boom_contact::sweep_boom(
                &big,
                black_box(&big_pivot),
                &big_back,
                &big_up,
                axel.boom_length,
            )
            .expect("touches")
        })
    });
    g.bench_function("boom_sweep_dem_318k_triangles_bvh", |b| {
        b.iter(|| {
            rappel_mechanics::boom_contact::sweep_boom(
                &indexed,
                black_box(&big_pivot),
                &big_back,
                &big_up,
                axel.boom_length,
            )
            .expect("touches")
        })
    });
    let mut sp = SdfParams::new(0.2);
    sp.margin = 2.0;
    g.bench_function("sdf_ledge_20cm", |b| {
        b.iter(|| Sdf::from_mesh(black_box(&m), &sp).expect("fits"))
    });
    g.finish();
}

criterion_group!(benches, mesh);
criterion_main!(benches);
