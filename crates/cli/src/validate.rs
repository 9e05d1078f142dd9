//! `rappel validate FILE [--json]`: loads and checks a scenario and prints a one-line summary (or
//! its JSON form).

use crate::output::{CliError, print_json};
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

/// The JSON form of a valid scenario's summary.
#[derive(serde::Serialize)]
struct Summary {
    file: String,
    valid: bool,
    obstacles: usize,
    vertices: usize,
    terrain_planes: usize,
    free_area_m2: f64,
    ptfos: usize,
    georeferenced: bool,
}

/// Runs `rappel validate`.
pub fn run(args: &Args) -> Result<(), CliError> {
    let s = Scenario::load(&args.file)?;
    if args.json {
        return print_json(&Summary {
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
