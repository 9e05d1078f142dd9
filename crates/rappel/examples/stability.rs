//! A stability map over a scenario's terrain planes (Kumar Fig. 5): how many poses on a 1 m grid
//! the robot holds (`cargo run -p rappel --example stability`).
use rappel::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures");
    let scenario = Scenario::load(format!("{dir}/plan/multi-plane.ron"))?;
    let options = StabilityOptions {
        grid_step: 1.0,
        ..Default::default()
    };
    let report = stability_over_scenario(scenario.validate()?, &options)?;
    let stable = report.dots.iter().filter(|d| d.stable).count();
    println!("{stable} of {} poses stable", report.dots.len());
    Ok(())
}
