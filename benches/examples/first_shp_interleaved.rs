//! The first SHP beside polyanya, interleaved (issue 10): `first_shp_interleaved [ROUNDS] [N...]`
//! builds the N-obstacle crater strip (seed 1; default 1,000 and 10,000 obstacles), then runs the
//! first SHP from the strip's start to its goal ROUNDS times each way (default 5, at most 1,000),
//! alternating rappel's [`SptPlanner::shortest_path`] (the class answer) and polyanya's
//! `Mesh::path` round by round, the order of the pair alternating too, and prints each side's
//! median wall time and CPU time (this process's, `getrusage`-free: `/proc/self/stat`), the
//! ratio, the search's counters and a digest of the answer (the length's bits and the class's
//! crossing count) so that two builds can be checked for identical answers.
//!
//! On a shared machine whose load changes within a minute the pairing keeps the ratio meaningful
//! where criterion's consecutive groups do not. The 100,000-obstacle strip takes tens of seconds
//! per query and side: give it explicitly (`first_shp_interleaved 1 100000`).
//!
//! Memory: before each query the process's peak resident set is reset (`/proc/self/clear_refs`),
//! and after it the growth of the peak over the resident set before is that query's peak memory
//! (the largest over the rounds is printed, with the search's own count `peak_bytes` and the
//! planner's kite table, which is built before the rounds and so not in rappel's figure). With
//! `--side=rappel` or `--side=polyanya` only that side runs (for `/usr/bin/time -v` on separate
//! processes); its ratio columns are then meaningless.

use nalgebra::Point2;
use rappel_benches::{median_by, polyanya_mesh, to_vec2};
use rappel_geometry::btm::Btm;
use rappel_geometry::generate::{CraterStripOptions, crater_strip};
use rappel_homotopy::kite::KiteTable;
use rappel_planners::spt::{SearchOptions, SptPlanner};
use std::hint::black_box;
use std::time::{Duration, Instant};

/// The median of `v` (zero when empty).
fn median(mut v: Vec<Duration>) -> Duration {
    median_by(&mut v, Ord::cmp).unwrap_or_default()
}

/// This process's user + system CPU time (`/proc/self/stat` fields 14 and 15, in clock ticks of
/// 1/100 s; `None` off Linux).
fn cpu_time() -> Option<Duration> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // The command name (field 2) is parenthesised and may hold spaces: count after its `)`.
    let rest = &stat[stat.rfind(')')? + 2..];
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let ticks: u64 = fields.get(11)?.parse::<u64>().ok()? + fields.get(12)?.parse::<u64>().ok()?;
    Some(Duration::from_millis(ticks * 10))
}

/// A field of `/proc/self/status` in kB (`VmRSS`, `VmHWM`; `None` off Linux).
fn status_kb(field: &str) -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with(field))?;
    line[field.len()..]
        .trim_start_matches(':')
        .split_whitespace()
        .next()?
        .parse()
        .ok()
}

/// Resets the peak resident set to the current one and returns the current one, kB (`None` when
/// the kernel does not allow it).
fn reset_peak() -> Option<u64> {
    std::fs::write("/proc/self/clear_refs", "5").ok()?;
    status_kb("VmRSS")
}

/// Growth of the peak resident set since `before` (from [`reset_peak`]), MB.
fn peak_growth_mb(before: Option<u64>) -> Option<f64> {
    let (before, peak) = (before?, status_kb("VmHWM")?);
    Some(peak.saturating_sub(before) as f64 / 1024.0)
}

fn fail(message: String) -> ! {
    eprintln!("error: {message}");
    std::process::exit(2);
}

fn main() {
    let mut args = std::env::args().skip(1);
    let rounds: usize = args
        .next()
        .and_then(|s| s.parse().ok())
        .unwrap_or(5)
        .clamp(1, 1000);
    let rest: Vec<String> = args.collect();
    // `--side=rappel` or `--side=polyanya`: run one side only (module docs).
    let only = rest
        .iter()
        .find_map(|a| a.strip_prefix("--side="))
        .map(|side| match side {
            "rappel" => 0,
            "polyanya" => 1,
            other => fail(format!("--side={other}: expected rappel or polyanya")),
        });
    let mut sizes: Vec<usize> = rest.iter().filter_map(|s| s.parse().ok()).collect();
    if sizes.is_empty() {
        sizes = vec![1_000, 10_000];
    }
    println!(
        "obstacles  rappel (median wall / cpu)  polyanya (median wall / cpu)  ratio wall / cpu  rounds  expansions  pruned dominated  queue peak  length bits  crossings  peak MB rappel / polyanya  search MB  kite table MB"
    );
    for n in sizes {
        let strip = crater_strip(&CraterStripOptions::new(n, 1))
            .unwrap_or_else(|e| fail(format!("{n} obstacles: {e}")));
        let btm = Btm::from_map(&strip.map).unwrap_or_else(|e| fail(format!("{n} obstacles: {e}")));
        let (a, b) = (strip.start, strip.goal);
        let mid = Point2::new(0.5 * (a.x + b.x), 0.5 * (a.y + b.y));
        let mesh = polyanya_mesh(&btm, mid);
        let (pa, pb) = (to_vec2(a, mid), to_vec2(b, mid));
        let planner = SptPlanner::new(&btm);
        // The 100k first SHP needs 16.5 million expansions: above the default budget.
        let options = SearchOptions::default()
            .with_max_classes(Some(1))
            .and_then(|o| o.with_max_expansions(100_000_000))
            .unwrap_or_else(|e| fail(e.to_string()));
        let (mut ours, mut theirs) = (Vec::new(), Vec::new());
        let (mut ours_cpu, mut theirs_cpu) = (Vec::new(), Vec::new());
        let kite_mb = KiteTable::new(&btm).held_bytes() as f64 / 1e6;
        let mut digest = None;
        let mut their_length: Option<f64> = None;
        let mut peaks: [Option<f64>; 2] = [None, None];
        for round in 0..rounds {
            for side in [round % 2, 1 - round % 2] {
                if only.is_some_and(|o| o != side) {
                    continue;
                }
                let rss = reset_peak();
                let (t, c) = (Instant::now(), cpu_time());
                if side == 0 {
                    let outcome = planner
                        .search(black_box(a), black_box(b), &options)
                        .and_then(|s| s.run())
                        .unwrap_or_else(|e| fail(format!("rappel: {e}")));
                    ours.push(t.elapsed());
                    ours_cpu.extend(cpu_time().zip(c).map(|(after, before)| after - before));
                    let first = outcome
                        .classes
                        .first()
                        .unwrap_or_else(|| fail(format!("rappel: no path ({n} obstacles)")));
                    digest = Some((outcome.stats, first.length(), first.shp.crossings.len()));
                } else {
                    let length = mesh
                        .path(black_box(pa), black_box(pb))
                        .map(|p| p.length)
                        .unwrap_or_else(|| fail(format!("polyanya: no path ({n} obstacles)")));
                    theirs.push(t.elapsed());
                    theirs_cpu.extend(cpu_time().zip(c).map(|(after, before)| after - before));
                    their_length = Some(f64::from(black_box(length)));
                }
                if let Some(mb) = peak_growth_mb(rss) {
                    peaks[side] = Some(peaks[side].map_or(mb, |p: f64| p.max(mb)));
                }
            }
        }
        // A timing is a figure only when both answered the same: polyanya works in f32, so its
        // length agrees with ours to about 1e-7 relative (1e-4 allowed, as the criterion bench).
        if let (Some((_, ours_length, _)), Some(theirs_length)) = (&digest, their_length)
            && (ours_length - theirs_length).abs() > 1e-4 * ours_length
        {
            fail(format!(
                "{n} obstacles: rappel's first SHP is {ours_length} m, polyanya's {theirs_length} m"
            ));
        }
        let (stats, length, crossings) = match digest {
            Some(d) => d,
            // Polyanya alone: no rappel answer to digest.
            None => (Default::default(), 0.0, 0),
        };
        let mb = |p: Option<f64>| p.map_or("-".to_string(), |p| format!("{p:.0}"));
        let (w0, w1) = (median(ours), median(theirs));
        let (c0, c1) = (median(ours_cpu), median(theirs_cpu));
        println!(
            "{n:>9}  {w0:>12.2?} / {c0:>10.2?}  {w1:>14.2?} / {c1:>10.2?}  {:>6.3} / {:>5.3}  {rounds:>6}  {:>10}  {:>16}  {:>10}  {:016x}  {crossings:>9}  {:>12} / {:>8}  {:>9.0}  {kite_mb:>13.1}",
            w0.as_secs_f64() / w1.as_secs_f64(),
            c0.as_secs_f64() / c1.as_secs_f64().max(1e-9),
            stats.expansions,
            stats.pruned_dominated,
            stats.queue_peak,
            length.to_bits(),
            mb(peaks[0]),
            mb(peaks[1]),
            stats.peak_bytes as f64 / 1e6,
        );
    }
}
