//! The BTM build beside spade's CDT bulk load, interleaved (issue 10): `btm_interleaved [ROUNDS]
//! [N...]` builds the N-obstacle crater strip (seed 1; default 1,000, 10,000 and 100,000
//! obstacles) ROUNDS times each way (default 11, at most 1,000), alternating rappel and spade
//! round by round so that a change in the machine's load hits both sides alike, and prints each
//! side's median and the ratio. The criterion benchmark (`benches/btm.rs`) runs each side's
//! samples one after the other; on a shared machine whose load changes within a minute its
//! ratios move by tens of percent between runs, which this pairing avoids. `--tsv` prints the rows
//! tab-separated with plain numbers (seconds), for `cargo xtask growth`.
//!
//! rappel's side is `Btm::build` (exact validation, triangulation, map edges, face labels, point
//! location index); spade's is `bulk_load_cdt` on the same vertices and edges (no validation, no
//! labels), its input copied outside the timed part.

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
    if let Some(a) = rest.iter().find(|a| a.starts_with("--") && *a != "--tsv") {
        eprintln!("error: unknown option {a}");
        std::process::exit(2);
    }
    let mut sizes: Vec<usize> = rest.iter().filter_map(|s| s.parse().ok()).collect();
    if sizes.is_empty() {
        sizes = vec![1_000, 10_000, 100_000];
    }
    if tsv {
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
        for round in 0..rounds {
            // Alternate which side goes first, so neither always follows the other's frees.
            for side in [round % 2, 1 - round % 2] {
                if side == 0 {
                    let t = Instant::now();
                    let r = Btm::from_map(black_box(&map)).map(|b| b.triangle_count());
                    ours.push(t.elapsed());
                    match r {
                        Ok(count) => triangles = count,
                        Err(e) => {
                            eprintln!("error: rappel: {e}");
                            std::process::exit(2);
                        }
                    }
                } else {
                    let (p, e) = (pts.clone(), edges.clone());
                    let t = Instant::now();
                    let r =
                        ConstrainedDelaunayTriangulation::<SpadePoint<f64>>::bulk_load_cdt(p, e)
                            .map(|t| t.num_inner_faces());
                    theirs.push(t.elapsed());
                    if r.is_err() {
                        eprintln!("error: spade refused the strip");
                        std::process::exit(2);
                    }
                }
            }
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
