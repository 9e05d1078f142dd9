//! Online planning (thesis §3.5): a descent planned on a prior map, driven over the true one where
//! an obstacle appears (`cargo run -p rappel --example online`).
use rappel::online::run;
use rappel::planners::online::SimulationOptions;
use rappel::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures");
    let prior = Scenario::load(format!("{dir}/online-example.ron"))?;
    let truth = Scenario::load(format!("{dir}/online-example-discovered.ron"))?;
    let result = run(
        &prior,
        &truth,
        &SimulationOptions::default(),
        &mut |_, _| {},
    )?;
    for event in &result.report.timeline {
        println!("{event:?}");
    }
    println!("reached the goal: {}", result.report.ending.reached());
    Ok(())
}
