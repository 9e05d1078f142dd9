//! `rappel validate FILE`: loads and checks a scenario and prints a one-line summary.

use crate::output::CliError;
use rappel::scenario::Scenario;
use std::path::PathBuf;

/// Arguments of `rappel validate`.
#[derive(clap::Args)]
pub struct Args {
    /// The scenario file (.ron or .json).
    file: PathBuf,
}

/// Runs `rappel validate`.
pub fn run(args: &Args) -> Result<(), CliError> {
    let s = Scenario::load(&args.file)?;
    crate::outln!(
        "{}: valid: {} obstacles, {} vertices, {} terrain planes, free area {} m²",
        args.file.display(),
        s.map.obstacles.len(),
        s.map.vertex_count(),
        s.terrain.planes.len(),
        crate::output::quantity(s.map.free_area())
    );
    Ok(())
}
