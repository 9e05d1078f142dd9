//! Distance fields of Paton's ledge scene (issue 14, target: the field at 5 cm in < 2 s): the
//! sparse field (`terrain::sparse_sdf`, propagated to its default `max_distance`, and truncated
//! at `T` without propagation) beside the dense banded field
//! (`terrain::sdf`) on the same mesh at 20 cm (the dense field at 5 cm exceeds its voxel cap; at
//! 10 cm it took 26 s), the sparse field at 10 and 5 cm; and queries on 1 000 identical points
//! near the ledge: the sparse field (5 cm), the dense field (20 cm) and the exact distance
//! through parry's BVH (`terrain::parry_mesh`).

use criterion::{Criterion, criterion_group, criterion_main};
use nalgebra::Point3;
use rappel_terrain::parry_mesh::ParryMesh;
use rappel_terrain::paton_scene::PatonScene;
use rappel_terrain::sdf::{Sdf, SdfParams};
use rappel_terrain::sparse_sdf::{SparseSdf, SparseSdfParams};
use rappel_terrain::surface::SignedDistance;
use std::hint::black_box;

/// 1 000 points on a 10 x 10 x 10 lattice over the ledge, its lip and the slope
/// (x from -3 to 3.5 m, y from -4 to 4 m, z from 0.1 to 4.6 m), offset off the grid planes.
fn query_points() -> Vec<Point3<f64>> {
    let mut q = Vec::with_capacity(1000);
    for i in 0..10 {
        for j in 0..10 {
            for k in 0..10 {
                q.push(Point3::new(
                    -3.0 + 0.65 * i as f64 + 0.013,
                    -4.0 + 0.8 * j as f64 + 0.017,
                    0.1 + 0.5 * k as f64 + 0.011,
                ));
            }
        }
    }
    q
}

fn sum<D: SignedDistance>(field: &D, q: &[Point3<f64>]) -> f64 {
    q.iter()
        .map(|p| field.signed_distance(p).expect("inside the field"))
        .sum()
}

fn sdf(c: &mut Criterion) {
    let m = PatonScene::paper(false)
        .mesh()
        .expect("the paper's scene meshes");
    let mut dense = SdfParams::new(0.2);
    dense.margin = 2.0;
    let sparse = |h: f64| {
        let mut p = SparseSdfParams::new(h);
        p.margin = 2.0;
        p
    };
    let mut g = c.benchmark_group("sdf");
    g.sample_size(10);
    g.bench_function("dense_build_ledge_20cm", |b| {
        b.iter(|| Sdf::from_mesh(black_box(&m), &dense).expect("fits"))
    });
    let truncated = |h: f64| {
        let mut p = SparseSdfParams::truncated(h);
        p.margin = 2.0;
        p
    };
    for (name, p) in [
        ("sparse_build_ledge_20cm", sparse(0.2)),
        ("sparse_build_ledge_10cm", sparse(0.1)),
        ("sparse_build_ledge_5cm", sparse(0.05)),
        ("truncated_build_ledge_10cm", truncated(0.1)),
        ("truncated_build_ledge_5cm", truncated(0.05)),
    ] {
        g.bench_function(name, |b| {
            b.iter(|| SparseSdf::from_mesh(black_box(&m), &p).expect("fits"))
        });
    }
    let q = query_points();
    let s5 = SparseSdf::from_mesh(&m, &sparse(0.05)).expect("fits");
    let d20 = Sdf::from_mesh(&m, &dense).expect("fits");
    let bvh = ParryMesh::new(&m).expect("parry takes it");
    g.bench_function("query_1000_sparse_5cm", |b| {
        b.iter(|| sum(&s5, black_box(&q)))
    });
    g.bench_function("query_1000_dense_20cm", |b| {
        b.iter(|| sum(&d20, black_box(&q)))
    });
    g.bench_function("query_1000_parry_exact", |b| {
        b.iter(|| sum(&bvh, black_box(&q)))
    });
    g.finish();
    eprintln!(
        "sparse 5 cm: {} blocks, T = {} m, D = {} m, bound {:.4} m",
        s5.block_count(),
        s5.truncation(),
        s5.max_distance(),
        s5.error_bound()
    );
}

criterion_group!(benches, sdf);
criterion_main!(benches);
