//! `rappel btm FILE [--json] [--svg OUT] [--html OUT]`: builds the BTM of a scenario's map, checks its
//! invariants, prints a summary (or JSON) and optionally draws it.

use crate::output::{CliError, PictureArgs, print_report, refuse_clashing_outputs};
use rappel::btm_summary::summarize_btm;
use rappel::scenario::Scenario;
use rappel_render::Picture;
use std::path::PathBuf;

/// Arguments of `rappel btm`.
#[derive(clap::Args)]
pub struct Args {
    /// The scenario file (.ron or .json).
    file: PathBuf,
    /// Print the summary as JSON.
    #[arg(long)]
    json: bool,
    /// The picture of the map and its BTM.
    #[command(flatten)]
    picture: PictureArgs,
    /// The picture's crop.
    #[command(flatten)]
    window: crate::window::WindowArg,
}

/// Runs `rappel btm`.
pub fn run(args: &Args) -> Result<(), CliError> {
    refuse_clashing_outputs(&args.picture.outputs(), &[&args.file])?;
    // Read, then validated once: the proof carries the valid map to the BTM build.
    let s = Scenario::read(&args.file)?;
    let (btm, summary) = summarize_btm(s.validate_at(&args.file)?.map())
        .map_err(|e| CliError(format!("{}: {e}", args.file.display())))?;
    if args.picture.wanted() {
        let mut pic = Picture::of_map_in(&s.map, args.window.aabb()?.as_ref());
        pic.btm(&btm);
        pic.map(&s.map);
        pic.start_goal(s.start, s.goal);
        let title = if s.name.is_empty() {
            args.file.display().to_string()
        } else {
            s.name.clone()
        };
        let title = format!("BTM of {title}");
        args.picture.write(&pic.finish(&title), &title)?;
    }
    if args.json {
        print_report(&summary)?;
    } else {
        crate::output::outln!("scenario              {}", args.file.display());
        crate::output::outln!("vertices              {}", summary.vertices);
        crate::output::outln!("holes                 {}", summary.holes);
        crate::output::outln!(
            "triangles             {} (n + 2h - 2 = {})",
            summary.triangles,
            summary.expected_triangles
        );
        crate::output::outln!(
            "constrained Delaunay  {}",
            if summary.constrained_delaunay {
                "yes (checked)"
            } else {
                "NO"
            }
        );
        crate::output::outln!(
            "invariants            {}",
            summary.invariant_violation.as_deref().unwrap_or("all hold")
        );
        crate::output::outln!(
            "free area             {} m²",
            crate::output::quantity(summary.free_area_m2)
        );
        crate::output::outln!(
            "build time            {:.2} ms",
            summary.build_us as f64 / 1e3
        );
        for (_, out) in args.picture.outputs() {
            crate::output::outln!("picture               {}", out.display());
        }
    }
    if summary.invariants_hold {
        Ok(())
    } else {
        Err(CliError(format!(
            "{}: BTM invariant broken: {}",
            args.file.display(),
            summary.invariant_violation.unwrap_or_default()
        )))
    }
}
