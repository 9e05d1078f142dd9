//! Many start/goal pairs on one map, the BTM built once: each pair's shortest tether length
//! (`cargo run -p rappel --example query`).
use rappel::prelude::*;
use rappel::query::{QueryOptions, QueryPair, answer};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures");
    let scenario = Scenario::load(format!("{dir}/thesis-fig-2-7.ron"))?;
    let pairs = [
        (scenario.start, scenario.goal),
        (scenario.goal, scenario.start),
    ]
    .map(|(start, goal)| QueryPair { start, goal });
    for (pair, a) in pairs.iter().zip(answer(
        scenario.map.validate()?,
        &pairs,
        &QueryOptions::default(),
    )?) {
        println!("{:?} -> {:?}: {:?} m", pair.start, pair.goal, a.lengths_m);
    }
    Ok(())
}
