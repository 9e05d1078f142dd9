//! Two robots on one tether on Kumar's multi-slope terrain (Problem 1): the tension Robot 2 needs
//! at each waypoint against what Robot 1 holds (`cargo run -p rappel --example track`).
use rappel::prelude::*;
use rappel::track::{load_path, load_terrain};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/tracking");
    let (scenario, terrain) = load_terrain(format!("{dir}/kumar.json").as_ref())?;
    let robot1 = load_path(format!("{dir}/robot1-partial.json").as_ref())?;
    let robot2 = load_path(format!("{dir}/robot2-descent.json").as_ref())?;
    let report: TrackReport = track(&scenario, &terrain, &robot1, &robot2)?;
    println!("{} waypoints: {}", report.waypoints.len(), report.verdict);
    Ok(())
}
