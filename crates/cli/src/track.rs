//! `rappel track SCENARIO --robot1 P1.json --robot2 P2.json [--json] [--svg OUT] [--html OUT] [--svg3d OUT]`: two robots on
//! one tether on multi-slope terrain (Kumar Problem 1). With `--robot1` a single point, Robot 1 is
//! a fixed anchor (the one-robot form). Exit 0 when Robot 2 is stable at every waypoint, 1 at the
//! first unstable one (named), 2 on an error.

use crate::output::{CliError, PictureArgs, print_report, refuse_clashing_outputs, write_file};
use rappel::track::{load_path, load_terrain, track};
use rappel_render::track::{track_picture, track_picture_3d};
use std::path::{Path, PathBuf};

/// Arguments of `rappel track`.
#[derive(clap::Args)]
pub struct Args {
    /// The track scenario (.json or .ron): surfaces, obstacles, holding robot.
    scenario: PathBuf,
    /// Robot 1's path: a JSON array of [x, y] frame points (one point: a fixed anchor).
    #[arg(long, value_name = "P1.json")]
    robot1: PathBuf,
    /// Robot 2's path: a JSON array of [x, y] frame points.
    #[arg(long, value_name = "P2.json")]
    robot2: PathBuf,
    /// Print the report as JSON.
    #[arg(long)]
    json: bool,
    /// The picture: the unfolded frame, paths, final tether and waypoint verdicts.
    #[command(flatten)]
    picture: PictureArgs,
    /// Draw an axonometric 3D view (surfaces, obstacle prisms, paths, tether) to this SVG file.
    #[arg(long, value_name = "OUT")]
    svg3d: Option<PathBuf>,
}

/// Runs `rappel track`; `Ok(false)` when Robot 2 is unstable somewhere.
pub fn run(args: &Args) -> Result<bool, CliError> {
    let mut outputs: Vec<(&str, &Path)> = args.picture.outputs();
    if let Some(p) = &args.svg3d {
        outputs.push(("--svg3d", p.as_path()));
    }
    refuse_clashing_outputs(&outputs, &[&args.scenario, &args.robot1, &args.robot2])?;
    let err = |e: rappel::track::TrackRunError| CliError(e.to_string());
    let (scenario, terrain) = load_terrain(&args.scenario).map_err(err)?;
    let p1 = load_path(&args.robot1).map_err(err)?;
    let p2 = load_path(&args.robot2).map_err(err)?;
    let report = track(&scenario, &terrain, &p1, &p2).map_err(err)?;
    if args.picture.wanted() {
        args.picture.write(
            &track_picture(&terrain, &p1, &p2, &report),
            &format!("rappel track {}", args.scenario.display()),
        )?;
    }
    if let Some(out) = &args.svg3d {
        write_file(out, &track_picture_3d(&terrain, &p1, &p2, &report))?;
    }
    let stable = report.first_unstable.is_none();
    if args.json {
        print_report(&report)?;
        return Ok(stable);
    }
    crate::output::outln!("scenario      {}", args.scenario.display());
    crate::output::outln!("waypoint  surface  T2max(N)  winding(deg)  ground  stable  required(N)");
    for w in &report.waypoints {
        crate::output::outln!(
            "{:>8}  {:>7}  {:>8.1}  {:>12.1}  {:>6}  {:>6}  {}",
            w.waypoint,
            w.surface,
            w.t2max_n,
            w.total_winding.to_degrees(),
            if w.ground_anchored { "yes" } else { "no" },
            if w.stable { "yes" } else { "no" },
            w.required_tension_n
                .map_or("-".to_string(), |t| format!("{t:.1}"))
        );
    }
    crate::output::outln!("verdict       {}", report.verdict);
    Ok(stable)
}
