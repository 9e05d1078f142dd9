//! Chapter-2 planner benchmarks (issue 4) on the generated 10,000-obstacle crater strip
//! (`CraterStripOptions::new(10_000, 1)`, start at the top, goal 7.5 km below):
//! - the SPT A* search: time to the first SHP (the classic single query) and to the first 10
//!   classes;
//! - side by side in the same run, the `polyanya` crate (Cui, Harabor and Grastien's optimal
//!   any-angle search on navigation meshes) on the same triangulation: its mesh is built from the
//!   BTM's free triangles, and it answers the same start-goal query, the globally shortest path
//!   (target: the SPT search within 2x of polyanya's median);
//! - memory for 100 classes, printed before the timings: the search's own peak bytes (tree nodes,
//!   queue, trail, pruning lists) and the process's peak resident set growth (`VmHWM` in
//!   `/proc/self/status`, Linux only) over the search (target: under 200 MB).
//!
//! Polyanya works in `f32`; its length agrees with ours to about 1e-5 relative on this map, which
//! the set-up asserts.

use criterion::{Criterion, criterion_group, criterion_main};
use glam::Vec2;
use polyanya::{Mesh, Trimesh};
use rappel_geometry::btm::Btm;
use rappel_geometry::generate::{CraterStripOptions, crater_strip};
use rappel_planners::spt::{SearchOptions, SptPlanner};
use std::hint::black_box;

/// The polyanya navigation mesh of a BTM's free triangles (counter-clockwise, compact vertices).
fn polyanya_mesh(btm: &Btm) -> Mesh {
    let d = btm.dcel();
    let mut index = vec![usize::MAX; d.vertex_capacity()];
    let mut vertices = Vec::new();
    let mut triangles = Vec::new();
    for t in btm.triangles() {
        let tri = d.triangle_vertices(t).map(|v| {
            if index[v.index()] == usize::MAX {
                index[v.index()] = vertices.len();
                let p = d.point(v);
                vertices.push(Vec2::new(p.x as f32, p.y as f32));
            }
            index[v.index()]
        });
        triangles.push(tri);
    }
    let mut mesh = Mesh::try_from(Trimesh {
        vertices,
        triangles,
    })
    .expect("a BTM is a valid navigation mesh");
    mesh.bake();
    mesh
}

/// Peak resident set size of this process, kB (`None` off Linux).
fn peak_rss_kb() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    status
        .lines()
        .find(|l| l.starts_with("VmHWM:"))?
        .split_whitespace()
        .nth(1)?
        .parse()
        .ok()
}

fn planner(c: &mut Criterion) {
    let generated = crater_strip(&CraterStripOptions::new(10_000, 1)).expect("valid options");
    let (start, goal) = (generated.start, generated.goal);
    let btm = Btm::build(&generated.map).expect("valid map");
    let spt = SptPlanner::new(&btm);
    let mesh = polyanya_mesh(&btm);
    let to_vec2 = |p: nalgebra::Point2<f64>| Vec2::new(p.x as f32, p.y as f32);

    // Memory for 100 classes, measured before anything else grows the heap.
    let before = peak_rss_kb();
    let hundred = SearchOptions::default()
        .with_max_classes(Some(100))
        .expect("valid option");
    let out = spt
        .search(start, goal, &hundred)
        .expect("endpoints in free space")
        .run()
        .expect("search runs");
    let after = peak_rss_kb();
    eprintln!(
        "100 classes: {} found ({:?}), {} expansions, {} tree nodes, queue peak {}, search peak {:.1} MB, process peak RSS growth {}",
        out.classes.len(),
        out.termination,
        out.stats.expansions,
        out.stats.tree_nodes,
        out.stats.queue_peak,
        out.stats.peak_bytes as f64 / 1e6,
        match (before, after) {
            (Some(b), Some(a)) => format!("{:.1} MB", a.saturating_sub(b) as f64 / 1e3),
            _ => "n/a".to_string(),
        }
    );
    assert_eq!(out.classes.len(), 100);
    assert!(out.stats.peak_bytes < 200_000_000);
    drop(out);

    let first = spt
        .shortest_path(start, goal)
        .expect("search runs")
        .expect("connected");
    let theirs = mesh
        .path(to_vec2(start), to_vec2(goal))
        .expect("polyanya finds the path");
    eprintln!(
        "shortest path: SPT {:.4} m ({} anchors, {} expansions), polyanya {:.4} m ({} corners)",
        first.length(),
        first.shp.taut.anchors.len(),
        first.expansions,
        theirs.length,
        theirs.path.len()
    );
    assert!((first.length() - f64::from(theirs.length)).abs() < 1e-4 * first.length());
    let ten = SearchOptions::default()
        .with_max_classes(Some(10))
        .expect("valid option");

    let mut g = c.benchmark_group("planner_10000_obstacles");
    g.sample_size(20);
    g.bench_function("spt_first_shp", |b| {
        b.iter(|| {
            spt.shortest_path(black_box(start), black_box(goal))
                .map(|s| s.map(|s| s.length()))
        })
    });
    g.bench_function("polyanya_shortest_path", |b| {
        b.iter(|| {
            mesh.path(black_box(to_vec2(start)), black_box(to_vec2(goal)))
                .map(|p| p.length)
        })
    });
    g.bench_function("spt_first_10_shps", |b| {
        b.iter(|| {
            spt.search(black_box(start), black_box(goal), &ten)
                .and_then(|s| s.run())
                .map(|o| o.classes.len())
        })
    });
    g.finish();
}

criterion_group!(benches, planner);
criterion_main!(benches);
