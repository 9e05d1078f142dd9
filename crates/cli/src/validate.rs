//! `rappel validate FILE [--json]`: loads and checks a scenario and prints a one-line summary (or
//! its JSON form).

use crate::output::{CliError, print_report};
use rappel::scenario::Scenario;
use std::path::PathBuf;

/// Arguments of `rappel validate`.
#[derive(clap::Args)]
pub struct Args {
    /// The scenario file (.ron or .json).
    file: PathBuf,
    /// Print the summary as JSON.
    #[arg(long)]
    json: bool,
}

/// Runs `rappel validate`.
pub fn run(args: &Args) -> Result<(), CliError> {
    let s = Scenario::load(&args.file)?;
    if args.json {
        return print_report(&rappel::report::ValidateReport {
            file: args.file.display().to_string(),
            valid: true,
            obstacles: s.map.obstacles.len(),
            vertices: s.map.vertex_count(),
            terrain_planes: s.terrain.planes.len(),
            free_area_m2: s.map.free_area(),
            ptfos: s.friction.as_ref().map_or(0, |f| f.ptfos.len()),
            georeferenced: s.georeference.is_some(),
        });
    }
    crate::output::outln!(
        "{}: valid: {} obstacles, {} vertices, {} terrain planes, free area {} m²",
        args.file.display(),
        s.map.obstacles.len(),
        s.map.vertex_count(),
        s.terrain.planes.len(),
        crate::output::quantity(s.map.free_area())
    );
    Ok(())
}
