//! Axel settled on Paton's ledge, and whether it stands with its tether from an anchor behind
//! (`cargo run -p rappel --example settle`).
use rappel::prelude::*;
use rappel::settle::load_ground;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/paton");
    let ground = load_ground(format!("{dir}/ledge.ron").as_ref())?;
    let (_pose, report) = settle_report(&ground, -2.0, 0.0, 0.0, Some([-6.0, 0.0, 4.5]))?;
    println!(
        "settled at {:?}, roll {:.1} deg",
        report.origin, report.roll_deg
    );
    for v in &report.stability {
        println!("boom {}: stable {:?}", v.boom, v.stable);
    }
    Ok(())
}
