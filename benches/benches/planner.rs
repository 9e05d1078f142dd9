//! Chapter-2 planner benchmarks (issues 4 and 10), each beside the `polyanya` crate (Cui, Harabor
//! and Grastien's optimal any-angle search on navigation meshes) on identical input, in one run:
//! - **first SHP** (the classic single query, start at the top of the strip, goal at the bottom)
//!   on the generated 1,000- and 10,000-obstacle crater strips
//!   (`CraterStripOptions::new(n, 1)`); polyanya's mesh is built from the BTM's free triangles;
//! - **a ~60 m query** (`spt`: the class with its sleeve, crossings and H-signature;
//!   `spt_taut_path`: the path and its length only, polyanya's answer) in the middle of the 1,000-, 10,000- and 100,000-obstacle strips (the
//!   per-query cost must follow the part of the map the search touches, not the map's size);
//! - **polyanya's arena benchmark**: its published map (`benches/data/polyanya/arena.mesh`,
//!   turned into a rappel map by chaining the mesh's boundary edges) and the 160 queries of
//!   `arena.scen`, all 160 per iteration;
//! - the first 10 classes on the 10,000-obstacle strip (no peer: polyanya has no classes), and
//!   memory for 100 classes, printed before the timings: the search's own peak bytes and the
//!   process's peak resident set growth (`VmHWM` in `/proc/self/status`, Linux only).
//!
//! The first SHP on the 100,000-obstacle strip takes seconds per query, so it runs only when the
//! environment variable `RAPPEL_BENCH_100K` is set: once per side, timed, with its memory (the
//! search's peak bytes and the process's peak resident set growth, the peak reset before each
//! run), printed in the set-up; then the criterion group `planner_first_shp_100k` (skipped when
//! the variable is `once`: the single timed runs only).
//!
//! Polyanya works in `f32`; the set-up asserts that its lengths agree with ours (1e-4 relative on
//! the strips' long queries, 1e-3 on the short ones, 1e-3 absolute on the arena).

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use nalgebra::Point2;
use polyanya::Mesh;
use rappel_benches::{map_from_polyanya_v2, polyanya_mesh, scenario_pairs, short_query, to_vec2};
use rappel_geometry::btm::Btm;
use rappel_geometry::generate::{CraterStripOptions, GeneratedMap, crater_strip};
use rappel_homotopy::h_signature::HSignature;
use rappel_planners::spt::{SearchOptions, SptPlanner};
use std::hint::black_box;
use std::time::Duration;

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

/// Current resident set size of this process, kB (`None` off Linux).
fn rss_kb() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    status
        .lines()
        .find(|l| l.starts_with("VmRSS:"))?
        .split_whitespace()
        .nth(1)?
        .parse()
        .ok()
}

/// Runs `f` once and returns its result, its wall time and how far the process's peak resident
/// set rose above the resident set before the call, MB: the peak is reset first (writing `5` to
/// `/proc/self/clear_refs`, Linux), so earlier peaks of the set-up do not hide the growth
/// (`None` when the kernel does not allow it).
fn measure_once<T>(f: impl FnOnce() -> T) -> (T, Duration, Option<f64>) {
    let reset = std::fs::write("/proc/self/clear_refs", "5").is_ok();
    let before = rss_kb();
    let t = std::time::Instant::now();
    let out = f();
    let elapsed = t.elapsed();
    let growth = match (reset, before, peak_rss_kb()) {
        (true, Some(b), Some(a)) => Some(a.saturating_sub(b) as f64 / 1e3),
        _ => None,
    };
    (out, elapsed, growth)
}

/// One generated strip with its BTM, planner, polyanya mesh and queries.
struct Strip {
    n: usize,
    generated: GeneratedMap,
    btm: Btm,
    /// Polyanya's mesh, or `None` when polyanya cannot build it (its `f32` angle sort panics on
    /// the 100,000-obstacle strip).
    mesh: Option<Mesh>,
    /// Where polyanya's coordinates are centred.
    origin: Point2<f64>,
    /// A ~60 m query in the middle of the strip.
    short: (Point2<f64>, Point2<f64>),
}

impl Strip {
    fn new(n: usize) -> Strip {
        let generated = crater_strip(&CraterStripOptions::new(n, 1)).expect("valid options");
        let btm = Btm::from_map(&generated.map).expect("valid map");
        let mid = Point2::new(
            0.5 * (generated.start.x + generated.goal.x),
            0.5 * (generated.start.y + generated.goal.y),
        );
        let mesh =
            std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| polyanya_mesh(&btm, mid)))
                .ok();
        if mesh.is_none() {
            eprintln!("{n} obstacles: polyanya could not build its mesh; no peer on this strip");
        }
        let (a, b) = short_query(&btm, generated.start, generated.goal)
            .expect("free space within 100 m of the short query's ends");
        Strip {
            n,
            generated,
            btm,
            mesh,
            origin: mid,
            short: (a, b),
        }
    }

    /// Checks that both planners answer `(a, b)` with the same length (relative tolerance `rel`)
    /// and prints it.
    fn check(&self, what: &str, (a, b): (Point2<f64>, Point2<f64>), rel: f64) {
        let t = std::time::Instant::now();
        let spt = SptPlanner::new(&self.btm);
        eprintln!(
            "{} obstacles: planner prepared in {:.1} ms, cut index {}",
            self.n,
            t.elapsed().as_secs_f64() * 1e3,
            spt.cut_index().map_or("none".into(), |c| format!(
                "{} entries, {:.1} MB",
                c.len(),
                c.bytes() as f64 / 1e6
            )),
        );
        let ours = spt
            .shortest_path(a, b)
            .expect("search runs")
            .expect("connected");
        let Some(mesh) = &self.mesh else {
            eprintln!("{} obstacles, {what}: SPT {:.4} m", self.n, ours.length());
            return;
        };
        let theirs = mesh
            .path(to_vec2(a, self.origin), to_vec2(b, self.origin))
            .expect("polyanya finds the path");
        eprintln!(
            "{} obstacles, {what}: SPT {:.4} m ({} anchors, {} expansions), polyanya {:.4} m",
            self.n,
            ours.length(),
            ours.shp.taut.anchors.len(),
            ours.expansions,
            theirs.length,
        );
        assert!((ours.length() - f64::from(theirs.length)).abs() < rel * ours.length());
    }
}

/// The arena's coordinates are small: no shift for polyanya.
const O: Point2<f64> = Point2::new(0.0, 0.0);

fn planner(c: &mut Criterion) {
    let strips: Vec<Strip> = [1_000, 10_000, 100_000].map(Strip::new).into();
    for s in &strips {
        if s.n <= 10_000 {
            s.check("first SHP", (s.generated.start, s.generated.goal), 1e-4);
        }
        s.check("~60 m query", s.short, 1e-3);
    }
    let ten_k = &strips[1];
    let (start, goal) = (ten_k.generated.start, ten_k.generated.goal);

    // Memory for 100 classes.
    let spt = SptPlanner::new(&ten_k.btm);
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

    // Polyanya's arena: its own mesh for polyanya, the same free space as a rappel map.
    let data = concat!(env!("CARGO_MANIFEST_DIR"), "/data/polyanya/");
    let arena_text = std::fs::read_to_string(format!("{data}arena.mesh")).expect("arena mesh");
    let arena_mesh: Mesh = polyanya::PolyanyaFile::from_bytes(arena_text.as_bytes())
        .try_into()
        .expect("polyanya reads its own mesh");
    let arena_map = map_from_polyanya_v2(&arena_text);
    let arena_btm = Btm::from_map(&arena_map).expect("the arena is a valid map");
    let arena_spt = SptPlanner::new(&arena_btm);
    let pairs =
        scenario_pairs(&std::fs::read_to_string(format!("{data}arena.scen")).expect("scenario"));
    for &(a, b) in &pairs {
        let ours = arena_spt.shortest_path(a, b).expect("search runs");
        let theirs = arena_mesh.path(to_vec2(a, O), to_vec2(b, O));
        match (ours, theirs) {
            (Some(o), Some(t)) => assert!(
                (o.length() - f64::from(t.length)).abs() < 1e-3,
                "arena {a} -> {b}: ours {} polyanya {}",
                o.length(),
                t.length
            ),
            (o, t) => panic!(
                "arena {a} -> {b}: ours {:?} polyanya {:?}",
                o.map(|o| o.length()),
                t.map(|t| t.length)
            ),
        }
    }
    eprintln!(
        "arena: {} queries agree with polyanya ({} obstacles)",
        pairs.len(),
        arena_map.obstacles.len()
    );

    let mut g = c.benchmark_group("planner_first_shp");
    g.sample_size(10);
    g.measurement_time(Duration::from_secs(5));
    for s in &strips[..2] {
        let spt = SptPlanner::new(&s.btm);
        let (a, b) = (s.generated.start, s.generated.goal);
        g.bench_with_input(BenchmarkId::new("spt", s.n), &(a, b), |bch, &(a, b)| {
            bch.iter(|| {
                spt.shortest_path(black_box(a), black_box(b))
                    .map(|s| s.map(|s| s.length()))
            })
        });
        if let Some(mesh) = &s.mesh {
            let (a, b) = (to_vec2(a, s.origin), to_vec2(b, s.origin));
            g.bench_with_input(
                BenchmarkId::new("polyanya", s.n),
                &(a, b),
                |bch, &(a, b)| bch.iter(|| mesh.path(black_box(a), black_box(b)).map(|p| p.length)),
            );
        }
    }
    g.finish();

    let mut g = c.benchmark_group("planner_short_query");
    for s in &strips {
        let spt = SptPlanner::new(&s.btm);
        g.bench_with_input(BenchmarkId::new("spt", s.n), &s.short, |bch, &(a, b)| {
            bch.iter(|| {
                spt.shortest_path(black_box(a), black_box(b))
                    .map(|s| s.map(|s| s.length()))
            })
        });
        g.bench_with_input(
            BenchmarkId::new("spt_taut_path", s.n),
            &s.short,
            |bch, &(a, b)| {
                bch.iter(|| {
                    spt.shortest_taut_path(black_box(a), black_box(b))
                        .map(|s| s.map(|s| s.length))
                })
            },
        );
        if let Some(mesh) = &s.mesh {
            let (a, b) = (to_vec2(s.short.0, s.origin), to_vec2(s.short.1, s.origin));
            g.bench_with_input(
                BenchmarkId::new("polyanya", s.n),
                &(a, b),
                |bch, &(a, b)| bch.iter(|| mesh.path(black_box(a), black_box(b)).map(|p| p.length)),
            );
        }
    }
    g.finish();

    // The class's H-signature both ways on the same class: the winding form over the SHP's
    // polyline and the sleeve read through the cut index.
    let mut g = c.benchmark_group("planner_h_signature");
    for s in &strips {
        let spt = SptPlanner::new(&s.btm);
        let Some(index) = spt.cut_index() else {
            continue;
        };
        let mut queries = vec![("short", s.short)];
        if s.n <= 10_000 {
            queries.push(("first", (s.generated.start, s.generated.goal)));
        }
        for (what, (a, b)) in queries {
            let class = spt
                .shortest_path(a, b)
                .expect("search runs")
                .expect("connected");
            let (taut, sleeve) = (&class.shp.taut, &class.shp.sleeve);
            eprintln!(
                "{} obstacles, {what}: {} windings, sleeve of {} triangles, {} poles tested in winding form",
                s.n,
                class.h_signature.windings().len(),
                sleeve.len(),
                spt.poles().band_work(&taut.points),
            );
            let id = format!("{}/{what}", s.n);
            g.bench_function(BenchmarkId::new("winding", &id), |bch| {
                bch.iter(|| HSignature::of_taut_path(spt.poles(), black_box(taut)))
            });
            g.bench_function(BenchmarkId::new("sleeve", &id), |bch| {
                bch.iter(|| HSignature::of_sleeve(&s.btm, index, a, b, black_box(sleeve)))
            });
        }
    }
    g.finish();

    let mut g = c.benchmark_group("planner_arena_160_queries");
    g.bench_function("spt", |bch| {
        bch.iter(|| {
            pairs
                .iter()
                .map(|&(a, b)| {
                    arena_spt
                        .shortest_path(black_box(a), black_box(b))
                        .ok()
                        .flatten()
                        .map_or(0.0, |s| s.length())
                })
                .sum::<f64>()
        })
    });
    g.bench_function("spt_taut_path", |bch| {
        bch.iter(|| {
            pairs
                .iter()
                .map(|&(a, b)| {
                    arena_spt
                        .shortest_taut_path(black_box(a), black_box(b))
                        .ok()
                        .flatten()
                        .map_or(0.0, |s| s.length)
                })
                .sum::<f64>()
        })
    });
    g.bench_function("polyanya", |bch| {
        bch.iter(|| {
            pairs
                .iter()
                .map(|&(a, b)| {
                    arena_mesh
                        .path(black_box(to_vec2(a, O)), black_box(to_vec2(b, O)))
                        .map_or(0.0, |p| p.length)
                })
                .sum::<f32>()
        })
    });
    g.finish();

    let ten = SearchOptions::default()
        .with_max_classes(Some(10))
        .expect("valid option");
    let mut g = c.benchmark_group("planner_10000_obstacles");
    g.sample_size(10);
    g.bench_function("spt_first_10_shps", |b| {
        b.iter(|| {
            spt.search(black_box(start), black_box(goal), &ten)
                .and_then(|s| s.run())
                .map(|o| o.classes.len())
        })
    });
    g.finish();

    if std::env::var_os("RAPPEL_BENCH_100K").is_some() {
        let s = &strips[2];
        let spt = SptPlanner::new(&s.btm);
        let (a, b) = (s.generated.start, s.generated.goal);
        // One timed run of each side first, with its memory: the criterion group below takes
        // ten or more runs of each.
        // The first SHP here takes millions of expansions: above the default budget.
        let options = SearchOptions::default()
            .with_max_classes(Some(1))
            .and_then(|o| o.with_max_expansions(100_000_000))
            .expect("valid option");
        let (ours, time, growth) = measure_once(|| {
            spt.search(a, b, &options)
                .and_then(|s| s.run())
                .expect("search runs")
        });
        let first = ours
            .classes
            .first()
            .unwrap_or_else(|| panic!("no first SHP: {:?}", ours.termination));
        eprintln!(
            "100000 obstacles, first SHP once: SPT {:.4} m in {:.2} s, {} expansions ({} tree nodes, queue peak {}, pruned: {} dominated, {} incumbent), search peak {:.1} MB, process peak RSS growth {}",
            first.length(),
            time.as_secs_f64(),
            ours.stats.expansions,
            ours.stats.tree_nodes,
            ours.stats.queue_peak,
            ours.stats.pruned_dominated,
            ours.stats.pruned_incumbent,
            ours.stats.peak_bytes as f64 / 1e6,
            growth.map_or("n/a".into(), |g| format!("{g:.1} MB")),
        );
        if let Some(mesh) = &s.mesh {
            let (theirs, time, growth) = measure_once(|| {
                mesh.path(to_vec2(a, s.origin), to_vec2(b, s.origin))
                    .expect("polyanya finds the path")
            });
            eprintln!(
                "100000 obstacles, first SHP once: polyanya {:.4} m in {:.2} s, process peak RSS growth {}",
                theirs.length,
                time.as_secs_f64(),
                growth.map_or("n/a".into(), |g| format!("{g:.1} MB")),
            );
            assert!(
                (first.length() - f64::from(theirs.length)).abs() < 1e-4 * first.length(),
                "polyanya and SPT disagree on the 100k first SHP"
            );
        }
        drop(ours);
        if std::env::var_os("RAPPEL_BENCH_100K").is_some_and(|v| v == "once") {
            return;
        }
        let mut g = c.benchmark_group("planner_first_shp_100k");
        g.sample_size(10);
        g.bench_function("spt", |bch| {
            bch.iter(|| {
                spt.search(black_box(a), black_box(b), &options)
                    .and_then(|s| s.run())
                    .map(|o| o.classes.first().map(|c| c.length()))
            })
        });
        if let Some(mesh) = &s.mesh {
            let (a, b) = (to_vec2(a, s.origin), to_vec2(b, s.origin));
            g.bench_function("polyanya", |bch| {
                bch.iter(|| mesh.path(black_box(a), black_box(b)).map(|p| p.length))
            });
        }
        g.finish();
    }
}

criterion_group!(benches, planner);
criterion_main!(benches);
