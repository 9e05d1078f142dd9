//! The README's quick start: plan a scenario with the facade in ten lines (`cargo run -p rappel
//! --example quickstart` from the workspace root). `cargo test` compiles it, so the README's code
//! stays true.

use rappel::plan::{PlanOptions, plan};
use rappel::scenario::Scenario;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let scenario = Scenario::load("fixtures/thesis-fig-2-7.ron")?;
    let report = plan(&scenario, &PlanOptions::default())?;
    for class in &report.classes {
        println!(
            "class {}: {:.1} m, feasible: {}",
            class.rank, class.length_m, class.feasible
        );
    }
    let pair = report.outcome.chosen.ok_or("no feasible class")?;
    println!(
        "descend through {} points of class {}",
        pair.descent.len(),
        pair.rank
    );
    Ok(())
}
