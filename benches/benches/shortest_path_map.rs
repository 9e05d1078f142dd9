//! The shortest path map from one start (issue 10, stability maps) on the generated
//! 1,000-obstacle crater strip (`crater_strip_scenario(1000, 1, 200.0)`, the fixture
//! `fixtures/generated/crater-strip-1000.ron`), beside its peers on identical input in one run:
//! - `build`: the map from the strip's start, computed once;
//! - `queries`: the geodesic length and last anchor of every free point of a 5 m grid over the
//!   strip (about 5,900 points, one thread), from the built map;
//! - `polyanya_each`: polyanya answering the same points one by one from the start;
//! - `spt_each`: rappel's own SPT search (`SptPlanner::shortest_taut_path`) likewise.
//!
//! The set-up checks that all three agree on every point (1e-4 relative: polyanya works in
//! `f32`) and prints the map's counters and size.

use criterion::{Criterion, criterion_group, criterion_main};
use nalgebra::Point2;
use rappel_benches::{polyanya_mesh, to_vec2};
use rappel_geometry::btm::{Btm, Location};
use rappel_planners::shortest_path_map::ShortestPathMap;
use rappel_planners::spt::SptPlanner;
use std::hint::black_box;
use std::time::Duration;

/// The grid's step, m.
const STEP: f64 = 5.0;

fn shortest_path_map(c: &mut Criterion) {
    let s = rappel::generated::crater_strip_scenario(1_000, 1, 200.0).expect("valid options");
    let btm = Btm::from_map(&s.map).expect("valid map");
    let b = s.map.aabb();
    let points: Vec<Point2<f64>> = (0..=((b.max.x - b.min.x) / STEP) as usize)
        .flat_map(|i| {
            (0..=((b.max.y - b.min.y) / STEP) as usize)
                .map(move |j| Point2::new(b.min.x + STEP * i as f64, b.min.y + STEP * j as f64))
        })
        .filter(|p| matches!(btm.locate(p), Location::Triangle(_) | Location::Edge(_)))
        .collect();
    let origin = Point2::new(0.5 * (b.min.x + b.max.x), 0.5 * (b.min.y + b.max.y));
    let mesh = polyanya_mesh(&btm, origin);
    let spt = SptPlanner::new(&btm);
    let spm = ShortestPathMap::build(&btm, s.start).expect("map builds");
    for p in &points {
        let ours = spm.query(*p).expect("free point").expect("connected");
        let theirs = mesh
            .path(to_vec2(s.start, origin), to_vec2(*p, origin))
            .expect("polyanya finds the path");
        let search = spt.shortest_taut_path(s.start, *p).unwrap().unwrap();
        assert!((ours.length - search.length).abs() <= 1e-9 * search.length.max(1.0));
        assert!((ours.length - f64::from(theirs.length)).abs() <= 1e-4 * ours.length.max(1.0));
    }
    let st = spm.stats();
    eprintln!(
        "1,000-obstacle strip: {} points; map: {} expansions, {} pruned, {} tree nodes, queue peak {}, {:.1} MB",
        points.len(),
        st.expansions,
        st.pruned_dominated,
        st.tree_nodes,
        st.queue_peak,
        spm.held_bytes() as f64 / 1e6
    );
    let mut g = c.benchmark_group("shortest_path_map/strip-1000");
    g.sample_size(10);
    g.bench_function("build", |bench| {
        bench.iter(|| ShortestPathMap::build(black_box(&btm), black_box(s.start)).unwrap())
    });
    g.bench_function("queries", |bench| {
        bench.iter(|| {
            points
                .iter()
                .map(|p| spm.query(*p).unwrap().unwrap().length)
                .sum::<f64>()
        })
    });
    g.bench_function("polyanya_each", |bench| {
        let start = to_vec2(s.start, origin);
        bench.iter(|| {
            points
                .iter()
                .map(|p| mesh.path(start, to_vec2(*p, origin)).unwrap().length)
                .sum::<f32>()
        })
    });
    g.bench_function("spt_each", |bench| {
        bench.iter(|| {
            points
                .iter()
                .map(|p| spt.shortest_taut_path(s.start, *p).unwrap().unwrap().length)
                .sum::<f64>()
        })
    });
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().measurement_time(Duration::from_secs(5));
    targets = shortest_path_map
}
criterion_main!(benches);
