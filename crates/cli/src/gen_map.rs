//! `rappel gen-map --obstacles N --seed S --out FILE [--json]`: writes a random crater-strip scenario
//! (non-overlapping convex obstacles of varied size), reproducible from the seed.

use crate::output::CliError;
use rappel::scenario::Format;
use std::path::PathBuf;

/// Arguments of `rappel gen-map`.
#[derive(clap::Args)]
pub struct Args {
    /// Number of obstacles.
    #[arg(long, allow_negative_numbers = true)]
    obstacles: usize,
    /// Random seed.
    #[arg(long, default_value_t = 1, allow_negative_numbers = true)]
    seed: u64,
    /// Strip width across the slope, metres.
    #[arg(long, value_parser = crate::numbers::finite, default_value_t = 200.0, allow_negative_numbers = true)]
    width: f64,
    /// Output scenario (.ron or .json).
    #[arg(long)]
    out: PathBuf,
    /// Print what was written as JSON.
    #[arg(long)]
    json: bool,
}

/// Runs `rappel gen-map`.
pub fn run(args: &Args) -> Result<(), CliError> {
    if Format::of_path(&args.out).is_none() {
        return Err(CliError(format!(
            "{}: unknown scenario format; use a .ron or .json file",
            args.out.display()
        )));
    }
    let s = rappel::generated::crater_strip_scenario(args.obstacles, args.seed, args.width)?;
    s.save(&args.out)?;
    let report = rappel::report::GenMapReport {
        file: args.out.display().to_string(),
        obstacles: s.map.obstacles.len(),
        vertices: s.map.vertex_count(),
        seed: args.seed,
        width_m: args.width,
    };
    if args.json {
        return crate::output::print_report(&report);
    }
    crate::output::outln!(
        "{}: {} obstacles, {} vertices, seed {}",
        report.file,
        report.obstacles,
        report.vertices,
        report.seed
    );
    Ok(())
}
