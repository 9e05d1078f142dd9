//! The shadow row of Paton's Table I test 3 (`cargo xtask regress --suite paton`), seed by seed,
//! each planned to its first solution exactly as the row plans it ([`rappel::navigate::navigate`]
//! with shadow sampling, 750 iterations or the first solution): per seed the iterations, the
//! cost's bits, the path's states, the motions checked and the time to the first solution. The
//! profiling harness of `docs/sampler.md` ("Cost of the first solution"): one seed under
//! `valgrind --tool=callgrind`, and a drift check of every seed's result before and after a
//! change that must keep them (`diff` of two runs' outputs without the time column).
//!
//! `cargo run --release -p rappel-benches --example navigate_first -- [FIRST_SEED [SEEDS]]` (default seed
//! 0, one seed); `TEST=1` plans Paton's test 1 instead.
use rappel::navigate::{PATON_ITERATIONS, RoverProblem, SHADOW_SAMPLE_FRACTION, navigate};
use rappel::planners::sampler::Termination;
use rappel::planners::stop::StopCondition;
use rappel::terrain::paton_scene::PatonScene;

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().collect();
    let arg = |i: usize, d: u64| -> Result<u64, String> {
        args.get(i).map_or(Ok(d), |s| {
            s.parse().map_err(|e| format!("argument {i}: {e}"))
        })
    };
    let (first, count) = (arg(1, 0)?, arg(2, 1)?);
    let test_one = std::env::var("TEST").is_ok_and(|t| t == "1");
    let scene = PatonScene::paper(!test_one);
    let mut problem = RoverProblem::paton(&scene, if test_one { 0 } else { 1 })?;
    problem.shadow_sample_fraction = SHADOW_SAMPLE_FRACTION;
    let term = Termination::iterations(PATON_ITERATIONS).or_cost_at_most(f64::MAX);
    let mut times = Vec::new();
    // `count` runs, bounded by the caller's argument.
    for seed in first..first.saturating_add(count) {
        let r = navigate(&problem, seed, term, &StopCondition::none())?;
        let path: Vec<String> = r
            .path
            .iter()
            .zip(&r.yaw_deg)
            .map(|(p, y)| format!("({:.6},{:.6},{:.4})", p[0], p[1], y))
            .collect();
        println!(
            "seed {seed} found {} it {:?} cost {:?} states {} motions {} shadow {} anchors {} path {} time {:.3}",
            r.found,
            r.first_solution_iteration,
            r.cost.map(f64::to_bits),
            r.states,
            r.motions_checked,
            r.shadow_samples,
            r.anchors.len(),
            path.join(" "),
            r.first_solution_s.unwrap_or(f64::NAN)
        );
        times.extend(r.first_solution_s);
    }
    let mean = times.iter().sum::<f64>() / times.len().max(1) as f64;
    println!("mean first solution {mean:.3} s over {} seeds", times.len());
    Ok(())
}
