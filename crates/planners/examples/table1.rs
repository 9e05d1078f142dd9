//! Paton's Table I, one test over many seeds, the direct way (without the whole regress suite):
//! each seed planned as [`RoverProblem::solve`] plans it for a number of iterations, every solution
//! re-validated ([`RoverProblem::revalidate`]), then the found share, the iterations and time to
//! the first solution (mean and sd over the found seeds) and where the iterations went
//! ([`AbitCounters`], summed over the seeds).
//!
//! `cargo run --release -p rappel-planners --example table1 -- TEST ITERATIONS SEEDS [shadow]`
//! (defaults: test 3, 750 iterations, seeds 0-99, Paton's uniform sampling; `shadow` uses our
//! shadow sampling, `SHADOW_SAMPLE_FRACTION`); rayon across seeds (`RAYON_NUM_THREADS`).
//! `VERBOSE` prints a line per seed; `KF` and `BATCH` override `rgg_k_factor` and `batch_size`;
//! `POLE_R` sets test 3's pole radius, metres (Paton does not state it; ours is 0.3 m), for a
//! sensitivity study of the scene; `START_BACK` the start's distance behind the lip (1 m; the
//! root anchors stay where Paton puts them, relative to the start), `GOAL_DX` the goal's distance
//! beyond the slope's foot (2 m), `BOX_X0`, `BOX_X1` and `BOX_Y` the sampled box's near and far
//! `x` and its half-width in `y` (-4.5, 5.8 and 3 m): the other positions Paton does not state;
//! `CHECKS` also counts the seeds whose first solution came within that many motion checks
//! (the other reading of Paton's 750-iteration budget: OMPL logs both its iterations and its
//! "collision checked" edges); `SURFACE` draws the uniform samples over the ground's surface
//! area ([`RoverProblem::sample_surface_area`]) instead of its footprint.
use rappel_planners::rover::problem::{RoverProblem, SHADOW_SAMPLE_FRACTION};
use rappel_planners::sampler::{AbitCounters, Termination};
use rappel_planners::stop::StopCondition;
use rappel_terrain::paton_scene::PatonScene;
use rayon::prelude::*;

/// One seed's outcome: found (re-validated), first-solution iteration, seconds and motion checks,
/// counters, iterations, batches, wall seconds.
type Run = (bool, Option<(u64, f64, u64)>, AbitCounters, u64, u64, f64);

/// `mean (sd)` of `v`, or `-` when empty.
fn mean_sd(v: &[f64]) -> String {
    if v.is_empty() {
        return "-".into();
    }
    let n = v.len() as f64;
    let m = v.iter().sum::<f64>() / n;
    let sd = (v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / n).sqrt();
    format!("{m:.2} ({sd:.2})")
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let arg = |i: usize, d: u64| args.get(i).and_then(|s| s.parse().ok()).unwrap_or(d);
    let (test, iters, seeds) = (arg(1, 3), arg(2, 750), arg(3, 100));
    let shadow = args.get(4).is_some_and(|s| s == "shadow");
    let env = |k: &str| std::env::var(k).ok().and_then(|v| v.parse::<f64>().ok());
    let mut scene = PatonScene::paper(test == 3);
    if let (Some(pole), Some(r)) = (scene.pole.as_mut(), env("POLE_R")) {
        pole.radius = r;
    }
    if let Some(b) = env("START_BACK") {
        scene.start_back = b;
    }
    let mut p = match RoverProblem::paton(&scene, if test == 1 { 0 } else { 1 }) {
        Ok(p) => p,
        Err(e) => {
            eprintln!("the scene: {e}");
            std::process::exit(2);
        }
    };
    if let Some(d) = env("GOAL_DX") {
        p.goal.x = scene.slope_foot_x() + d;
    }
    if let Some(x) = env("BOX_X0") {
        p.space.lo[0] = x;
    }
    if let Some(x) = env("BOX_X1") {
        p.space.hi[0] = x;
    }
    if let Some(y) = env("BOX_Y") {
        (p.space.lo[1], p.space.hi[1]) = (-y, y);
    }
    if shadow {
        p.shadow_sample_fraction = SHADOW_SAMPLE_FRACTION;
    }
    if let Err(e) = p.sample_surface_area(std::env::var("SURFACE").is_ok()) {
        eprintln!("SURFACE: {e}");
        std::process::exit(2);
    }
    let verbose = std::env::var("VERBOSE").is_ok();
    let began = std::time::Instant::now();
    let runs: Vec<Run> = (0..seeds)
        .into_par_iter()
        .map(|seed| {
            let t = std::time::Instant::now();
            let settings = p.settings(seed).and_then(|s| {
                let s = match env("KF") {
                    Some(f) => s.with_rgg_k_factor(f).map_err(|e| e.to_string())?,
                    None => s,
                };
                match env("BATCH") {
                    Some(n) => s.with_batch_size(n as usize).map_err(|e| e.to_string()),
                    None => Ok(s),
                }
            });
            let st = match settings.and_then(|s| {
                p.solve_with(s, Termination::iterations(iters), &StopCondition::none())
            }) {
                Ok(st) => st,
                Err(e) => {
                    eprintln!("seed {seed}: {e}");
                    return (false, None, AbitCounters::default(), 0, 0, 0.0);
                }
            };
            let found = st
                .solution
                .as_ref()
                .is_some_and(|s| p.revalidate(&s.path).is_ok());
            let first = st
                .events
                .first()
                .map(|e| (e.iteration, e.elapsed.as_secs_f64(), e.motions_checked));
            if verbose {
                println!(
                    "seed {seed}: found {found} first {first:?} batches {} {:?}",
                    st.batches, st.counters
                );
            }
            let wall = t.elapsed().as_secs_f64();
            (found, first, st.counters, st.iterations, st.batches, wall)
        })
        .collect();
    let found: Vec<&Run> = runs.iter().filter(|r| r.0).collect();
    let its: Vec<f64> = found
        .iter()
        .filter_map(|r| r.1.map(|f| f.0 as f64))
        .collect();
    let secs: Vec<f64> = found.iter().filter_map(|r| r.1.map(|f| f.1)).collect();
    let checks: Vec<f64> = found
        .iter()
        .filter_map(|r| r.1.map(|f| f.2 as f64))
        .collect();
    let walls: Vec<f64> = runs.iter().map(|r| r.5).collect();
    println!(
        "test {test}{}: found {}/{} within {iters} iterations; first solution {} iterations, {} motion checks, {} s; run {} s; {:.1} s wall",
        if shadow { " shadow" } else { "" },
        found.len(),
        runs.len(),
        mean_sd(&its),
        mean_sd(&checks),
        mean_sd(&secs),
        mean_sd(&walls),
        began.elapsed().as_secs_f64()
    );
    // The other reading of Paton's budget: a first solution within `CHECKS` motion checks (run
    // enough iterations for every seed to spend them).
    if let Some(budget) = env("CHECKS") {
        let within: Vec<&Run> = found
            .iter()
            .copied()
            .filter(|r| r.1.is_some_and(|f| f.2 as f64 <= budget))
            .collect();
        let pick = |i: usize| -> Vec<f64> {
            within
                .iter()
                .filter_map(|r| r.1.map(|f| [f.0 as f64, f.2 as f64][i]))
                .collect()
        };
        let spent = runs
            .iter()
            .filter(|r| {
                (r.2.checks_valid + r.2.checks_invalid) as f64 >= budget
                    || r.1.is_some_and(|f| f.2 as f64 <= budget)
            })
            .count();
        println!(
            "within {budget} motion checks: found {}/{} ({spent} seeds spent the budget or found within it); first solution {} iterations, {} motion checks",
            within.len(),
            runs.len(),
            mean_sd(&pick(0)),
            mean_sd(&pick(1)),
        );
    }
    let mut sum = AbitCounters::default();
    for r in &runs {
        sum += r.2;
    }
    let batches: u64 = runs.iter().map(|r| r.4).sum();
    let n = runs.len().max(1) as f64;
    let per = |x: u64| x as f64 / n;
    println!(
        "per seed: batches {:.2} searches {:.2} expansions {:.1} tree edges {:.1} truncated {:.1} covered {:.1} checks new valid {:.1} invalid {:.1} cached {:.1} no improvement {:.1} history refused {:.1} edges added {:.1} rewiring edges queued {:.1}",
        per(batches),
        per(sum.searches),
        per(sum.expansions),
        per(sum.tree_edges),
        per(sum.truncated),
        per(sum.covered),
        per(sum.checks_valid),
        per(sum.checks_invalid),
        per(sum.checks_cached),
        per(sum.no_improvement),
        per(sum.history_refused),
        per(sum.edges_added),
        per(sum.rewiring_edges_queued)
    );
}
