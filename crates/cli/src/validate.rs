//! `rappel validate FILE [--kind KIND] [--json]`: checks any input file rappel reads (a
//! scenario, a Paton scene, a tracking terrain, a path or pairs file, a mesh, an elevation model,
//! a lidar point cloud)
//! with the loader of the commands that read it, says which kind it checked, and prints a
//! one-line summary (or its JSON form). The kind is detected from the extension and the file's
//! top-level shape ([`rappel::input_kind::detect`]) unless `--kind` names it.

use crate::output::{CliError, print_report};
use rappel::input_kind::{InputKind, check, detect};
use std::path::PathBuf;

/// Arguments of `rappel validate`.
#[derive(clap::Args)]
pub struct Args {
    /// The file: a scenario (.ron, .json), a Paton scene (.ron), a tracking terrain (.json), a
    /// path or pairs file (.json), a mesh (.obj, .ply, .stl), an elevation model (.asc, .tif) or
    /// a lidar point cloud (.las, .laz).
    file: PathBuf,
    /// Check the file as this kind instead of the detected one: scenario, paton-scene,
    /// tracking-terrain, path, pairs, mesh, dem or point-cloud.
    #[arg(long, value_name = "KIND", value_parser = kind)]
    kind: Option<InputKind>,
    /// Print the summary as JSON.
    #[arg(long)]
    json: bool,
}

/// `--kind NAME`.
fn kind(name: &str) -> Result<InputKind, String> {
    InputKind::parse(name).ok_or_else(|| {
        let names: Vec<&str> = InputKind::ALL.iter().map(|k| k.name()).collect();
        format!("expected one of {}", names.join(", "))
    })
}

/// Runs `rappel validate`.
pub fn run(args: &Args) -> Result<(), CliError> {
    let kind = args.kind.unwrap_or_else(|| detect(&args.file));
    let found = check(&args.file, kind).map_err(|e| CliError(e.to_string()))?;
    let s = found.scenario.as_deref();
    if args.json {
        return print_report(&rappel::input_kind::ValidateReport {
            file: args.file.display().to_string(),
            kind,
            valid: true,
            summary: found.summary,
            obstacles: s.map(|s| s.map.obstacles.len()),
            vertices: s.map(|s| s.map.vertex_count()),
            terrain_planes: s.map(|s| s.terrain.planes.len()),
            free_area_m2: s.map(|s| s.map.free_area()),
            ptfos: s.map(|s| s.friction.as_ref().map_or(0, |f| f.ptfos.len())),
            georeferenced: s.map(|s| s.georeference.is_some()),
        });
    }
    match s {
        Some(s) => crate::output::outln!(
            "{}: valid scenario: {} obstacles, {} vertices, {} terrain planes, free area {} m²",
            args.file.display(),
            s.map.obstacles.len(),
            s.map.vertex_count(),
            s.terrain.planes.len(),
            crate::output::quantity(s.map.free_area())
        ),
        None => crate::output::outln!(
            "{}: valid {}: {}",
            args.file.display(),
            kind.name(),
            found.summary
        ),
    }
    Ok(())
}
