//! The BTM build beside spade's CDT bulk load, interleaved (issue 10): `btm_interleaved [ROUNDS]
//! [N...]` builds the N-obstacle crater strip (seed 1; default 1,000, 10,000 and 100,000
//! obstacles) ROUNDS times each way (default 11, at most 1,000), alternating rappel and spade
//! round by round so that a change in the machine's load hits both sides alike, and prints each
//! side's median and the ratio. The criterion benchmark (`benches/btm.rs`) runs each side's
//! samples one after the other; on a shared machine whose load changes within a minute its
//! ratios move by tens of percent between runs, which this pairing avoids. `--tsv` prints the rows
//! tab-separated with plain numbers (seconds), for `cargo xtask growth`.
//!
//! **Memory.** With `--side=rappel` or `--side=spade` only that side is built, in its own process:
//! each build's peak resident set over the resident set before it (`/proc/self/clear_refs`; the
//! map and spade's input are resident before) and what the finished structure keeps resident
//! while it is held (the resident set after the build over the one before), the largest over the
//! rounds.
//!
//! rappel's side is `Btm::build` (exact validation, triangulation, map edges, face labels, point
//! location index); spade's is `bulk_load_cdt` on the same vertices and edges (no validation, no
//! labels), its input copied outside the timed part.

use rappel_benches::proc_stats::{peak_growth_mb, reset_peak, status_kb};
use rappel_benches::{median_by, spade_input};
use rappel_geometry::btm::Btm;
use rappel_geometry::generate::{CraterStripOptions, crater_strip};
use spade::{ConstrainedDelaunayTriangulation, Point2 as SpadePoint, Triangulation};
use std::hint::black_box;
use std::time::{Duration, Instant};

/// The median of `v` (zero when empty).
fn median(mut v: Vec<Duration>) -> Duration {
    median_by(&mut v, Ord::cmp).unwrap_or_default()
}

fn main() {
    let mut args = std::env::args().skip(1);
    let rounds: usize = args
        .next()
        .and_then(|s| s.parse().ok())
        .unwrap_or(11)
        .clamp(1, 1000);
    let rest: Vec<String> = args.collect();
    let tsv = rest.iter().any(|a| a == "--tsv");
    let only = rest
        .iter()
        .find_map(|a| a.strip_prefix("--side="))
        .map(|side| match side {
            "rappel" => 0,
            "spade" => 1,
            _ => {
                eprintln!("error: --side={side}: the sides are rappel and spade");
                std::process::exit(2);
            }
        });
    if let Some(a) = rest
        .iter()
        .find(|a| a.starts_with("--") && *a != "--tsv" && !a.starts_with("--side="))
    {
        eprintln!("error: unknown option {a}");
        std::process::exit(2);
    }
    let mut sizes: Vec<usize> = rest.iter().filter_map(|s| s.parse().ok()).collect();
    if sizes.is_empty() {
        sizes = vec![1_000, 10_000, 100_000];
    }
    if let Some(side) = only {
        let name = ["rappel", "spade"][side];
        if tsv {
            println!("obstacles\tside\tbuild_s\tpeak_mb\tretained_mb\trounds");
        } else {
            println!(
                "obstacles  side    build (median)  peak MB  retained MB  rounds  ({name} alone)"
            );
        }
    } else if tsv {
        println!("obstacles\trappel_s\tspade_s\tratio\trounds\ttriangles");
    } else {
        println!("obstacles  rappel build (median)  spade bulk_load_cdt (median)  ratio  rounds");
    }
    for n in sizes {
        let map = match crater_strip(&CraterStripOptions::new(n, 1)) {
            Ok(g) => g.map,
            Err(e) => {
                eprintln!("error: {n} obstacles: {e}");
                std::process::exit(2);
            }
        };
        let (pts, edges) = spade_input(&map);
        let (mut ours, mut theirs) = (Vec::new(), Vec::new());
        let mut triangles = 0;
        // The largest peak growth and retained size over the rounds, MB (with `--side`).
        let (mut peak, mut retained) = (0.0f64, 0.0f64);
        let mut measure = |before: Option<u64>| {
            let after = status_kb("VmRSS").zip(before);
            retained =
                retained.max(after.map_or(0.0, |(a, b)| a.saturating_sub(b) as f64 / 1024.0));
            peak = peak.max(peak_growth_mb(before).unwrap_or(0.0));
        };
        for round in 0..rounds {
            // Alternate which side goes first, so neither always follows the other's frees.
            for side in [round % 2, 1 - round % 2] {
                if only.is_some_and(|o| o != side) {
                    continue;
                }
                if side == 0 {
                    let before = reset_peak();
                    let t = Instant::now();
                    let r = Btm::from_map(black_box(&map));
                    ours.push(t.elapsed());
                    match r {
                        Ok(btm) => {
                            triangles = btm.triangle_count();
                            measure(before);
                        }
                        Err(e) => {
                            eprintln!("error: rappel: {e}");
                            std::process::exit(2);
                        }
                    }
                } else {
                    let (p, e) = (pts.clone(), edges.clone());
                    let before = reset_peak();
                    let t = Instant::now();
                    let r =
                        ConstrainedDelaunayTriangulation::<SpadePoint<f64>>::bulk_load_cdt(p, e);
                    theirs.push(t.elapsed());
                    match r {
                        Ok(cdt) => {
                            black_box(cdt.num_inner_faces());
                            measure(before);
                        }
                        Err(_) => {
                            eprintln!("error: spade refused the strip");
                            std::process::exit(2);
                        }
                    }
                }
            }
        }
        if let Some(side) = only {
            let (name, t) = (["rappel", "spade"][side], median([ours, theirs].concat()));
            if tsv {
                println!(
                    "{n}\t{name}\t{:.6}\t{peak:.1}\t{retained:.1}\t{rounds}",
                    t.as_secs_f64()
                );
            } else {
                println!(
                    "{n:>9}  {name:<6}  {:>14.2?}  {peak:>7.0}  {retained:>11.0}  {rounds:>6}",
                    t
                );
            }
            continue;
        }
        let (a, b) = (median(ours), median(theirs));
        if tsv {
            println!(
                "{n}\t{:.6}\t{:.6}\t{:.4}\t{rounds}\t{triangles}",
                a.as_secs_f64(),
                b.as_secs_f64(),
                a.as_secs_f64() / b.as_secs_f64()
            );
            continue;
        }
        println!(
            "{n:>9}  {:>21.2?}  {:>28.2?}  {:>5.2}  {rounds:>6}",
            a,
            b,
            a.as_secs_f64() / b.as_secs_f64()
        );
    }
}
