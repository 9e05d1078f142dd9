//! The tethered rover on Paton's ledge (Table I, test 1) planned by ABIT* with one seed
//! (`cargo run --release -p rappel --example navigate`).
use rappel::planners::sampler::Termination;
use rappel::prelude::*;
use rappel::terrain::paton_scene::PatonScene;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let problem = RoverProblem::paton(&PatonScene::paper(false), 0)?;
    let stop = StopCondition::time(Duration::from_secs(60));
    let report = navigate(&problem, 3, Termination::iterations(750), &stop)?;
    println!(
        "found {} after {} iterations: {} anchors",
        report.found,
        report.iterations,
        report.anchors.len()
    );
    Ok(())
}
