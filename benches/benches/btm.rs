//! BTM benchmarks (issues 2 and 10): building the constrained Delaunay BTM of the generated
//! 1,000- and 10,000-obstacle crater strips (and of the 100,000-obstacle strip when the environment variable
//! `RAPPEL_BENCH_100K` is set), side by side in one run with spade's constrained Delaunay bulk
//! load of the same vertices and edges; and a local update (insert or remove one obstacle) versus
//! a full rebuild.
//!
//! What each side does: `rappel/build` validates the map exactly (ring simplicity, containment,
//! overlaps), triangulates, inserts the map edges, labels free/obstacle/exterior faces and builds
//! the point-location index; `rappel/validate` is the validation alone; `spade/bulk_load_cdt`
//! triangulates and inserts the edges (no validation, no face labels).

use criterion::{BatchSize, Criterion, criterion_group, criterion_main};
use rappel_benches::spade_input;
use rappel_geometry::btm::Btm;
use rappel_geometry::generate::{CraterStripOptions, crater_strip};
use rappel_geometry::map::Map;
use spade::{ConstrainedDelaunayTriangulation, Point2 as SpadePoint, Triangulation};
use std::hint::black_box;

fn big_map() -> Map {
    strip(10_000)
}

/// The generated crater strip with `n` obstacles (seed 1).
fn strip(n: usize) -> Map {
    crater_strip(&CraterStripOptions::new(n, 1))
        .expect("valid options")
        .map
}

fn build(c: &mut Criterion) {
    build_group(c, 1_000, 50);
    build_group(c, 10_000, 30);
    if std::env::var_os("RAPPEL_BENCH_100K").is_some() {
        build_group(c, 100_000, 10);
    }
}

/// `btm_build_{n}_obstacles`: rappel's build, its validation alone and spade's bulk load.
fn build_group(c: &mut Criterion, n: usize, samples: usize) {
    let map = strip(n);
    let (pts, edges) = spade_input(&map);
    let mut g = c.benchmark_group(format!("btm_build_{n}_obstacles"));
    g.sample_size(samples);
    g.bench_function("rappel/build", |b| {
        b.iter(|| Btm::from_map(black_box(&map)).map(|btm| btm.triangle_count()))
    });
    g.bench_function("rappel/validate", |b| {
        b.iter(|| black_box(&map).validate().is_ok())
    });
    g.bench_function("spade/bulk_load_cdt", |b| {
        b.iter_batched(
            || (pts.clone(), edges.clone()),
            |(p, e)| {
                ConstrainedDelaunayTriangulation::<SpadePoint<f64>>::bulk_load_cdt(p, e)
                    .map(|t| t.num_inner_faces())
            },
            BatchSize::LargeInput,
        )
    });
    g.finish();
}

fn update(c: &mut Criterion) {
    let mut map = big_map();
    // Take one obstacle out of the middle of the strip: it is the one inserted and removed.
    let obstacle = map.obstacles.remove(5_000);
    let mut btm = Btm::from_map(&map).expect("valid map");
    let mut g = c.benchmark_group("btm_update_10000_obstacles");
    // Each iteration inserts the obstacle and removes it again, timing one half: the BTM returns
    // to the same triangulation (new ids) so every iteration does the same work, and no clone or
    // drop of the big structure is timed.
    g.bench_function("insert_one_obstacle", |b| {
        b.iter_custom(|iters| {
            let mut total = std::time::Duration::ZERO;
            for _ in 0..iters {
                let t = std::time::Instant::now();
                let id = btm.insert_obstacle(black_box(&obstacle)).map(|r| r.0);
                total += t.elapsed();
                if let Ok(id) = id {
                    let _ = btm.remove_obstacle(id);
                }
            }
            total
        })
    });
    g.bench_function("remove_one_obstacle", |b| {
        b.iter_custom(|iters| {
            let mut total = std::time::Duration::ZERO;
            for _ in 0..iters {
                if let Ok((id, _)) = btm.insert_obstacle(&obstacle) {
                    let t = std::time::Instant::now();
                    let _ = black_box(btm.remove_obstacle(black_box(id)));
                    total += t.elapsed();
                }
            }
            total
        })
    });
    g.sample_size(20);
    map.obstacles.push(obstacle.clone());
    let full = map;
    g.bench_function("rebuild", |b| {
        b.iter(|| Btm::from_map(black_box(&full)).map(|btm| btm.triangle_count()))
    });
    g.finish();
}

fn locate(c: &mut Criterion) {
    let g = crater_strip(&CraterStripOptions::new(10_000, 1)).expect("valid options");
    let btm = Btm::from_map(&g.map).expect("valid map");
    let b = g.map.aabb();
    let queries: Vec<_> = (0..1000)
        .map(|i| {
            let u = (i as f64 * 0.618_033_988_75).fract();
            let v = (i as f64 * 0.754_877_666_25).fract();
            nalgebra::Point2::new(
                b.min.x + u * (b.max.x - b.min.x),
                b.min.y + v * (b.max.y - b.min.y),
            )
        })
        .collect();
    c.bench_function("btm_locate_1000_cold_queries_10000_obstacles", |bench| {
        bench.iter(|| {
            queries
                .iter()
                .map(|q| btm.locate(black_box(q)))
                .filter(|l| matches!(l, rappel_geometry::btm::Location::Triangle(_)))
                .count()
        })
    });
}

criterion_group!(benches, build, update, locate);
criterion_main!(benches);
