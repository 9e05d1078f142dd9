//! `cargo xtask gen-fixtures`: regenerates the generated fixtures (random crater-strip maps) from
//! their seeds, so that anyone can check they are exactly what the seeds produce, and rewrites the
//! terrain golden counts after a deliberate change. The regression suite compares the committed
//! files with a fresh generation.

use crate::regress::case::workspace_root;
use std::path::PathBuf;
use std::process::ExitCode;

/// The generated fixtures: obstacle count and seed.
pub const GENERATED: &[(usize, u64)] = &[(100, 1), (1_000, 1), (10_000, 1)];

/// Path of the generated fixture with `n` obstacles.
pub fn generated_path(n: usize) -> PathBuf {
    workspace_root()
        .join("fixtures")
        .join("generated")
        .join(format!("crater-strip-{n}.ron"))
}

/// Regenerates every generated fixture.
pub fn generate() -> Result<ExitCode, String> {
    for &(n, seed) in GENERATED {
        let s =
            rappel::generated::crater_strip_scenario(n, seed, 200.0).map_err(|e| e.to_string())?;
        let path = generated_path(n);
        s.save(&path).map_err(|e| e.to_string())?;
        println!(
            "wrote {} ({} obstacles, seed {seed})",
            path.display(),
            s.map.obstacles.len()
        );
    }
    let golden = crate::regress::terrain::write_golden()?;
    println!(
        "wrote {} (terrain ingestion golden counts)",
        golden.display()
    );
    Ok(ExitCode::SUCCESS)
}
