//! A digital elevation model turned into a planning scenario (fall line, planes, obstacles), then
//! planned (`cargo run -p rappel --example dem`).
use rappel::prelude::*;
use rappel::terrain::ingest::IngestOptions;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/terrain");
    let path = format!("{dir}/mars_hirise_dteec_010228_1490_crop.asc");
    let dem = dem_scenario(path.as_ref(), &IngestOptions::default())?;
    let s = &dem.scenario;
    println!(
        "{} planes, {} obstacles",
        s.terrain.planes.len(),
        s.map.obstacles.len()
    );
    let report = plan(s, &PlanOptions::default())?;
    println!("{}", report.outcome.verdict);
    Ok(())
}
