//! Plans the Golden-Queen-like fixture (thesis Fig. 2.44) with the facade: homotopy classes
//! shortest first, ascent feasibility, the chosen ascent/descent pair, and a picture.
//!
//! `cargo run -p rappel --example plan [SCENARIO] [OUT.svg]`

use rappel::plan::{PlanOptions, plan_detailed};
use rappel::scenario::Scenario;
use std::path::PathBuf;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let file = args.next().map(PathBuf::from).unwrap_or_else(|| {
        PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join("../../fixtures/plan/golden-queen-two-anchors.ron")
    });
    let scenario = Scenario::read(&file)?;
    let plan = plan_detailed(
        &scenario.validate_at(&file)?,
        &PlanOptions {
            classes: 3,
            ..Default::default()
        },
    )?;
    for c in &plan.report.classes {
        println!(
            "class {}: {:.3} m, {} anchors, {}",
            c.rank,
            c.length_m,
            c.anchors.len(),
            c.verdict
        );
    }
    println!("{}", plan.report.outcome.verdict);
    if let Some(out) = args.next() {
        rappel::io::write_atomically(
            std::path::Path::new(&out),
            rappel_render::plan::picture(&plan, &scenario, None).as_bytes(),
        )?;
        println!("picture: {out}");
    }
    Ok(())
}
