//! `rappel btm FILE [--json] [--svg OUT]`: builds the BTM of a scenario's map, checks its
//! invariants, prints a summary (or JSON) and optionally draws it.

use crate::output::{CliError, print_json, refuse_overwriting_inputs, write_file};
use rappel::btm_summary::summarize_btm;
use rappel::scenario::Scenario;
use rappel::svg::Picture;
use std::path::PathBuf;

/// Arguments of `rappel btm`.
#[derive(clap::Args)]
pub struct Args {
    /// The scenario file (.ron or .json).
    file: PathBuf,
    /// Print the summary as JSON.
    #[arg(long)]
    json: bool,
    /// Draw the map and its BTM to this SVG file.
    #[arg(long, value_name = "OUT")]
    svg: Option<PathBuf>,
}

/// Runs `rappel btm`.
pub fn run(args: &Args) -> Result<(), CliError> {
    if let Some(out) = &args.svg {
        refuse_overwriting_inputs(out, &[&args.file])?;
    }
    let s = Scenario::load(&args.file)?;
    let (btm, summary) =
        summarize_btm(&s.map).map_err(|e| CliError(format!("{}: {e}", args.file.display())))?;
    if let Some(out) = &args.svg {
        let mut pic = Picture::of_map(&s.map);
        pic.btm(&btm);
        pic.map(&s.map);
        pic.start_goal(s.start, s.goal);
        let title = if s.name.is_empty() {
            args.file.display().to_string()
        } else {
            s.name.clone()
        };
        write_file(out, &pic.finish(&format!("BTM of {title}")))?;
    }
    if args.json {
        print_json(&summary)?;
    } else {
        crate::outln!("scenario              {}", args.file.display());
        crate::outln!("vertices              {}", summary.vertices);
        crate::outln!("holes                 {}", summary.holes);
        crate::outln!(
            "triangles             {} (n + 2h - 2 = {})",
            summary.triangles,
            summary.expected_triangles
        );
        crate::outln!(
            "constrained Delaunay  {}",
            if summary.constrained_delaunay {
                "yes (checked)"
            } else {
                "NO"
            }
        );
        crate::outln!(
            "invariants            {}",
            summary.invariant_violation.as_deref().unwrap_or("all hold")
        );
        crate::outln!(
            "free area             {} m²",
            crate::output::quantity(summary.free_area)
        );
        crate::outln!("build time            {:.2} ms", summary.build_ms);
        if let Some(out) = &args.svg {
            crate::outln!("picture               {}", out.display());
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
