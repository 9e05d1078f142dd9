//! The ten lines of `docs/embedding.md`: a scenario built in code, planned under a 100 ms time
//! limit (`cargo run -p rappel --example embed`).
use rappel::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let scenario = Scenario::builder()
        .boundary([(0.0, 0.0), (40.0, 0.0), (40.0, 100.0), (0.0, 100.0)])
        .obstacle([(15.0, 45.0), (25.0, 45.0), (20.0, 55.0)])
        .start(20.0, 95.0)
        .goal(20.0, 5.0)
        .plane(100.0, 0.0, 50.0, 0.4)
        .build()?;
    let options = PlanOptions {
        stop: StopCondition::time(Duration::from_millis(100)),
        ..Default::default()
    };
    let report = plan(&scenario, &options)?;
    println!("{}", report.outcome.verdict);
    Ok(())
}
