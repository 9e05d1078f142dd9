//! Polyanya's 160 arena queries in a plain loop, for profilers and for same-run ratios (issue 10):
//! `arena_queries [class|path|polyanya|all] [ROUNDS]` runs the published arena map's 160 queries
//! ROUNDS times (default 200, at most 100,000) with one answer: rappel's class answer
//! ([`SptPlanner::shortest_path`]), its path alone ([`SptPlanner::shortest_taut_path`]) or
//! polyanya's `Mesh::path`, and prints the wall time per query and the sum of the lengths (a
//! digest: the same for every build that gives the same answers). The timed loop is
//! `run_rounds`, so `valgrind --tool=callgrind --toggle-collect='*run_rounds*'` counts the queries
//! alone, without the set-up.
//!
//! `all` interleaves the three: ROUNDS rounds, each timing 20 passes over the 160 queries with
//! every answer in turn (the order rotating from round to round), and prints each answer's median
//! time per query over the rounds and its ratio to polyanya's. On a machine whose load drifts
//! within a minute this keeps the ratios meaningful where criterion's consecutive groups
//! (`planner_arena_160_queries`, the benchmark of record) do not.

use rappel_benches::{map_from_polyanya_v2, median_by, scenario_pairs, to_vec2};
use rappel_geometry::btm::Btm;
use rappel_planners::spt::SptPlanner;
use std::hint::black_box;
use std::time::Instant;

/// Rounds accepted on the command line (a loop bound for user input).
const MAX_ROUNDS: usize = 100_000;

/// The answer timed.
#[derive(Clone, Copy)]
enum Answer {
    Class,
    Path,
    Polyanya,
}

/// A query: start and goal.
type Pair = (nalgebra::Point2<f64>, nalgebra::Point2<f64>);

/// Runs every pair `rounds` times with `answer` and returns the sum of the lengths of one round.
#[inline(never)]
fn run_rounds(
    answer: Answer,
    rounds: usize,
    pairs: &[Pair],
    spt: &SptPlanner<'_>,
    mesh: &polyanya::Mesh,
) -> f64 {
    let origin = nalgebra::Point2::new(0.0, 0.0);
    let mut sum = 0.0;
    for _ in 0..rounds {
        sum = pairs
            .iter()
            .map(|&(a, b)| match answer {
                Answer::Class => spt
                    .shortest_path(black_box(a), black_box(b))
                    .ok()
                    .flatten()
                    .map_or(0.0, |s| s.length()),
                Answer::Path => spt
                    .shortest_taut_path(black_box(a), black_box(b))
                    .ok()
                    .flatten()
                    .map_or(0.0, |s| s.length),
                Answer::Polyanya => mesh
                    .path(black_box(to_vec2(a, origin)), black_box(to_vec2(b, origin)))
                    .map_or(0.0, |p| f64::from(p.length)),
            })
            .sum::<f64>();
    }
    sum
}

/// The ROUNDS argument (`default` when absent); exits with status 2 when it is not an integer in
/// `1..=MAX_ROUNDS`.
fn rounds_arg(arg: Option<&String>, default: usize) -> usize {
    match arg.map(|r| r.parse::<usize>()) {
        None => default,
        Some(Ok(r)) if (1..=MAX_ROUNDS).contains(&r) => r,
        Some(_) => {
            eprintln!("error: ROUNDS must be an integer in 1..={MAX_ROUNDS}");
            std::process::exit(2);
        }
    }
}

/// The three answers interleaved (module docs): medians per query and ratios to polyanya.
fn interleaved(rounds: usize, pairs: &[Pair], spt: &SptPlanner<'_>, mesh: &polyanya::Mesh) {
    const PASSES: usize = 20;
    let answers = [Answer::Class, Answer::Path, Answer::Polyanya];
    let mut times: [Vec<f64>; 3] = Default::default();
    let mut sums = [0.0; 3];
    for round in 0..rounds {
        for k in 0..answers.len() {
            let i = (round + k) % answers.len();
            let t = Instant::now();
            sums[i] = run_rounds(answers[i], PASSES, pairs, spt, mesh);
            times[i].push(t.elapsed().as_secs_f64() / (PASSES * pairs.len()) as f64);
        }
    }
    let medians = times
        .each_mut()
        .map(|v| median_by(v, f64::total_cmp).unwrap_or(f64::NAN));
    for (i, name) in ["class answer", "path alone", "polyanya"]
        .iter()
        .enumerate()
    {
        println!(
            "{name:>12}: median {:.3} us per query over {rounds} rounds, ratio to polyanya {:.3}, length sum {:.6}",
            medians[i] * 1e6,
            medians[i] / medians[2],
            sums[i]
        );
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let data = concat!(env!("CARGO_MANIFEST_DIR"), "/data/polyanya/");
    let read = |name: &str| {
        std::fs::read_to_string(format!("{data}{name}"))
            .unwrap_or_else(|e| panic!("benchmark data {data}{name}: {e}"))
    };
    let text = read("arena.mesh");
    let mesh: polyanya::Mesh = polyanya::PolyanyaFile::from_bytes(text.as_bytes())
        .try_into()
        .expect("polyanya reads its own mesh");
    let map = map_from_polyanya_v2(&text);
    let btm = Btm::from_map(&map).expect("the arena is a valid map");
    let spt = SptPlanner::new(&btm);
    let pairs = scenario_pairs(&read("arena.scen"));
    let answer = match args.first().map(String::as_str) {
        None | Some("class") => Answer::Class,
        Some("path") => Answer::Path,
        Some("polyanya") => Answer::Polyanya,
        Some("all") => {
            interleaved(rounds_arg(args.get(1), 30), &pairs, &spt, &mesh);
            return;
        }
        Some(other) => {
            eprintln!("error: answer `{other}`: expected class, path, polyanya or all");
            std::process::exit(2);
        }
    };
    let rounds = rounds_arg(args.get(1), 200);
    let t = Instant::now();
    let sum = run_rounds(answer, rounds, &pairs, &spt, &mesh);
    let per_query = t.elapsed().as_secs_f64() / (rounds * pairs.len()) as f64;
    println!(
        "{} queries x {rounds}: {:.3} us per query, length sum {sum:.6}",
        pairs.len(),
        per_query * 1e6
    );
}
