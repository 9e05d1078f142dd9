//! The first SHP beside polyanya, interleaved (issues 10, 35): `first_shp_interleaved [ROUNDS]
//! [N...] [--side=SIDE] [--tsv]` builds the N-obstacle crater strip (seed 1; default 1,000 and
//! 10,000 obstacles), then runs the first SHP from the strip's start to its goal ROUNDS times on
//! each side (default 5, at most 1,000), round by round in alternating order, and prints one row
//! per side: its set-up time, the median wall and CPU time of a query (this process's user +
//! system time from `/proc/self/stat`), rappel's time over the side's (below 1: rappel is
//! faster), the peak memory of a query, the
//! length found and rappel's search counters.
//!
//! The sides:
//! - `rappel`: [`SptPlanner::shortest_path`] (the class answer: SHP, sleeve, crossings,
//!   H-signature); its set-up is the BTM and the planner (kite table);
//! - `rappel-astar`: the same search in the A* order ([`QueueOrder::AStar`]) instead of the
//!   one-class search's wave order (`rappel_planners::spt` module docs, "The wave order"), on the
//!   same planner: what the order gains, in the same run;
//! - `polyanya`: polyanya's `Mesh::path` on the BTM's free triangles (the raw CDT), set-up the
//!   mesh built from the BTM and baked;
//! - `polyanya-merged`: the same on polyanya's own merged convex polygons (`merge_polygons`, then
//!   baked: its point-location BVH and islands), polyanya's best configuration for long queries;
//!   its set-up adds the merge.
//!
//! **Answers.** A timing counts only when every side found a path and all lengths agree within
//! 1e-4 relative (polyanya works in `f32`); otherwise the program exits 2 naming the sides.
//!
//! **Memory.** With `--side=SIDE` only that side runs (its structures are the only ones built
//! beyond the strip), so each side's memory is measured in its own process: before each query the
//! process's peak resident set is reset (`/proc/self/clear_refs`), and after it the growth of the
//! peak over the resident set before is that query's peak memory (the largest over the rounds).
//! Without `--side` all sides share one process and the memory column is indicative only.
//!
//! **Short queries.** `--short` answers the strip's short query instead (about 64 m across the
//! strip's middle, [`rappel_benches::short_query`]; the same as the criterion bench's) and the
//! memory column becomes the side's **resident memory**: the growth of the peak resident set over
//! its set-up and its queries together (rappel: the BTM, the planner and the queries; polyanya:
//! its mesh and the queries, its input BTM standing for a mesh file read beforehand), for a
//! process that answers short queries. Measure it with `--side`, one side per process.
//!
//! `--band-bits=B` runs the `rappel` side in the wave order with bands of `B` bits of mantissa
//! ([`QueueOrder::Wave`]) instead of the default's
//! [`WAVE_BAND_BITS`](rappel_planners::spt::WAVE_BAND_BITS), for tuning.
//!
//! `--tsv` prints the rows tab-separated with plain numbers (seconds, MB), for `cargo xtask
//! growth`. The 100,000-obstacle strip takes seconds per query and side: give it explicitly
//! (`first_shp_interleaved 1 100000`).

use nalgebra::Point2;
use polyanya::Mesh;
use rappel_benches::proc_stats::{cpu_time, peak_growth_mb, reset_peak};
use rappel_benches::{median_by, polyanya_mesh, polyanya_mesh_merged, short_query, to_vec2};
use rappel_geometry::btm::Btm;
use rappel_geometry::generate::{CraterStripOptions, crater_strip};
use rappel_planners::spt::{QueueOrder, SearchOptions, SearchStats, SptPlanner};
use std::hint::black_box;
use std::time::{Duration, Instant};

/// The median of `v` (zero when empty).
fn median(mut v: Vec<Duration>) -> Duration {
    median_by(&mut v, Ord::cmp).unwrap_or_default()
}

fn fail(message: String) -> ! {
    eprintln!("error: {message}");
    std::process::exit(2);
}

/// The sides, in the order of the rows.
const SIDES: [&str; 4] = ["rappel", "polyanya", "polyanya-merged", "rappel-astar"];

/// What one side measured on one strip.
#[derive(Default)]
struct Measured {
    setup: Duration,
    wall: Vec<Duration>,
    cpu: Vec<Duration>,
    peak_mb: Option<f64>,
    length: Option<f64>,
}

fn main() {
    let mut args = std::env::args().skip(1);
    let rounds: usize = args
        .next()
        .and_then(|s| s.parse().ok())
        .unwrap_or(5)
        .clamp(1, 1000);
    let rest: Vec<String> = args.collect();
    let tsv = rest.iter().any(|a| a == "--tsv");
    let short = rest.iter().any(|a| a == "--short");
    // `--band-bits=B`: the `rappel` side's wave order with bands of B bits (module docs).
    let band_bits = rest
        .iter()
        .find_map(|a| a.strip_prefix("--band-bits="))
        .map(|b| {
            b.parse::<u32>()
                .ok()
                .filter(|&b| b <= 52)
                .unwrap_or_else(|| fail(format!("--band-bits={b}: expected 0 to 52")))
        });
    // `--side=SIDE`: run one side only (module docs).
    let only = rest
        .iter()
        .find_map(|a| a.strip_prefix("--side="))
        .map(|side| {
            SIDES.iter().position(|s| *s == side).unwrap_or_else(|| {
                fail(format!(
                    "--side={side}: expected rappel, polyanya, polyanya-merged or rappel-astar"
                ))
            })
        });
    if let Some(a) = rest.iter().find(|a| {
        a.starts_with("--")
            && *a != "--tsv"
            && *a != "--short"
            && !a.starts_with("--side=")
            && !a.starts_with("--band-bits=")
    }) {
        fail(format!("unknown option {a}"));
    }
    let mut sizes: Vec<usize> = rest.iter().filter_map(|s| s.parse().ok()).collect();
    if sizes.is_empty() {
        sizes = vec![1_000, 10_000];
    }
    if tsv {
        println!(
            "obstacles\tside\tsetup_s\twall_s\tcpu_s\trappel_over_side\tpeak_mb\tlength_m\texpansions\trounds"
        );
    } else {
        println!(
            "obstacles  side              set-up      query wall / cpu (median)   rappel/side  peak MB  length m          expansions  rounds"
        );
    }
    for n in sizes {
        let strip = crater_strip(&CraterStripOptions::new(n, 1))
            .unwrap_or_else(|e| fail(format!("{n} obstacles: {e}")));
        let mid = Point2::new(
            0.5 * (strip.start.x + strip.goal.x),
            0.5 * (strip.start.y + strip.goal.y),
        );
        let runs = |side: usize| only.is_none_or(|o| o == side);
        let mut m: [Measured; 4] = Default::default();
        // Set-up. rappel's BTM is also the input polyanya's meshes are built from (outside
        // their set-up time: it stands for reading a mesh file). With `--short` the peak is
        // reset before each side's set-up and read after its queries (module docs).
        let ours = runs(0) || runs(3);
        let mut resident_from = ours.then(reset_peak).flatten();
        let t = Instant::now();
        let btm = Btm::from_map(&strip.map).unwrap_or_else(|e| fail(format!("{n} obstacles: {e}")));
        let planner = ours.then(|| SptPlanner::new(&btm));
        m[0].setup = t.elapsed();
        m[3].setup = m[0].setup;
        let (a, b) = if short {
            short_query(&btm, strip.start, strip.goal)
                .unwrap_or_else(|| fail(format!("{n} obstacles: no free short query")))
        } else {
            (strip.start, strip.goal)
        };
        let (pa, pb) = (to_vec2(a, mid), to_vec2(b, mid));
        let mut meshes: [Option<Mesh>; 2] = [None, None];
        for (k, mesh) in meshes.iter_mut().enumerate() {
            if runs(k + 1) {
                if !ours {
                    resident_from = reset_peak();
                }
                let t = Instant::now();
                *mesh = Some(if k == 0 {
                    polyanya_mesh(&btm, mid)
                } else {
                    polyanya_mesh_merged(&btm, mid)
                });
                m[k + 1].setup = t.elapsed();
            }
        }
        // The 100k first SHP needs millions of expansions: above the default budget.
        let options = SearchOptions::default()
            .with_max_classes(Some(1))
            .and_then(|o| o.with_max_expansions(1_000_000_000))
            .unwrap_or_else(|e| fail(e.to_string()));
        let astar = options.clone().with_queue_order(QueueOrder::AStar);
        let options = match band_bits {
            Some(band_bits) => options.with_queue_order(QueueOrder::Wave { band_bits }),
            None => options,
        };
        let mut stats = [SearchStats::default(), SearchStats::default()];
        for round in 0..rounds {
            let order: Vec<usize> = (0..SIDES.len())
                .map(|i| (i + round) % SIDES.len())
                .collect();
            for side in order {
                if !runs(side) {
                    continue;
                }
                let rss = if short { resident_from } else { reset_peak() };
                let (t, c) = (Instant::now(), cpu_time());
                let length = match side {
                    0 | 3 => {
                        let Some(planner) = planner.as_ref() else {
                            continue;
                        };
                        let options = if side == 0 { &options } else { &astar };
                        let outcome = planner
                            .search(black_box(a), black_box(b), options)
                            .and_then(|s| s.run())
                            .unwrap_or_else(|e| fail(format!("{}: {e}", SIDES[side])));
                        stats[side / 3] = outcome.stats;
                        outcome.classes.first().map(|c| c.length())
                    }
                    k => meshes[k - 1]
                        .as_ref()
                        .and_then(|mesh| mesh.path(black_box(pa), black_box(pb)))
                        .map(|p| f64::from(p.length)),
                };
                let wall = t.elapsed();
                let cpu = cpu_time().zip(c).map(|(after, before)| after - before);
                let Some(length) = length else {
                    fail(format!("{}: no path ({n} obstacles)", SIDES[side]));
                };
                let s = &mut m[side];
                s.wall.push(wall);
                s.cpu.extend(cpu);
                s.length = Some(black_box(length));
                if let Some(mb) = peak_growth_mb(rss) {
                    s.peak_mb = Some(s.peak_mb.map_or(mb, |p: f64| p.max(mb)));
                }
            }
        }
        // A timing is a figure only when every side answered the same (module docs).
        let lengths: Vec<(usize, f64)> = (0..SIDES.len())
            .filter_map(|k| m[k].length.map(|l| (k, l)))
            .collect();
        for &(k, l) in &lengths {
            let (k0, l0) = lengths[0];
            if (l - l0).abs() > 1e-4 * l0 {
                fail(format!(
                    "{n} obstacles: {} found {l0} m, {} found {l} m",
                    SIDES[k0], SIDES[k]
                ));
            }
        }
        let ours = median(m[0].wall.clone());
        for (k, s) in m.iter().enumerate() {
            if !runs(k) {
                continue;
            }
            let (wall, cpu) = (median(s.wall.clone()), median(s.cpu.clone()));
            // rappel's time over this side's (below 1: rappel is faster).
            let ratio = if k == 0 || only.is_some() {
                f64::NAN
            } else {
                ours.as_secs_f64() / wall.as_secs_f64()
            };
            let expansions = match k {
                0 => stats[0].expansions.to_string(),
                3 => stats[1].expansions.to_string(),
                _ => "-".into(),
            };
            let peak = s.peak_mb.map_or(f64::NAN, |p| p);
            let length = s.length.unwrap_or(f64::NAN);
            if tsv {
                println!(
                    "{n}\t{}\t{:.6}\t{:.6}\t{:.6}\t{ratio:.4}\t{peak:.1}\t{length:.6}\t{expansions}\t{rounds}",
                    SIDES[k],
                    s.setup.as_secs_f64(),
                    wall.as_secs_f64(),
                    cpu.as_secs_f64(),
                );
            } else {
                println!(
                    "{n:>9}  {:<16}  {:>9.2?}  {:>12.2?} / {:>10.2?}  {ratio:>11.3}  {peak:>7.0}  {length:>16.6}  {expansions:>10}  {rounds:>6}",
                    SIDES[k], s.setup, wall, cpu
                );
            }
        }
    }
}
