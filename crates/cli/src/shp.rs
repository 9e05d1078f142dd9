//! `rappel shp FILE --path PATH.json [--json] [--svg OUT] [--html OUT]`: the shortest homotopic path (taut
//! tether) of a path, with its length, anchors, reduced crossing sequence and H-signature; and
//! `rappel homotopic FILE --path A.json --path B.json [--json]`: `homotopic` (exit code 0) or `not
//! homotopic` (exit code 1). A path file is a JSON array of `[x, y]` points; a path that leaves free space is
//! bad input (exit 2, the segment named).

use crate::output::{Answer, CliError, PictureArgs, print_report, refuse_clashing_outputs};
use rappel::geometry::btm::Btm;
use rappel::homotopy::crossing::CrossingSequence;
use rappel::homotopy::funnel::Side;
use rappel::homotopy::homotopy::are_homotopic;
use rappel::scenario::Scenario;
use rappel::tether::{load_path, shp_report};
use rappel_render::Picture;
use std::path::PathBuf;

/// Arguments of `rappel shp`.
#[derive(clap::Args)]
pub struct Args {
    /// The scenario file (.ron or .json); its map is used.
    file: PathBuf,
    /// The path file: a JSON array of [x, y] points.
    #[arg(long, value_name = "PATH.json")]
    path: PathBuf,
    /// Print the result as JSON.
    #[arg(long)]
    json: bool,
    /// The picture: the BTM, the path, its sleeve, the SHP and its anchors.
    #[command(flatten)]
    picture: PictureArgs,
    /// The picture's crop.
    #[command(flatten)]
    window: crate::window::WindowArg,
}

/// Arguments of `rappel homotopic`.
#[derive(clap::Args)]
pub struct HomotopicArgs {
    /// The scenario file (.ron or .json); its map is used.
    file: PathBuf,
    /// The two path files (JSON arrays of [x, y] points), with the same endpoints.
    #[arg(long, value_name = "PATH.json", num_args = 1, required = true)]
    path: Vec<PathBuf>,
    /// Print the answer as JSON.
    #[arg(long)]
    json: bool,
}

fn load_btm(file: &std::path::Path) -> Result<(Scenario, Btm), CliError> {
    // Read, then validated once: the proof carries the valid map to the BTM build.
    let s = Scenario::read(file)?;
    let btm = Btm::build(s.validate_at(file)?.map())
        .map_err(|e| CliError(format!("{}: {e}", file.display())))?;
    Ok((s, btm))
}

/// Runs `rappel shp`.
pub fn run(args: &Args) -> Result<(), CliError> {
    refuse_clashing_outputs(&args.picture.outputs(), &[&args.file, &args.path])?;
    let (s, btm) = load_btm(&args.file)?;
    let path = load_path(&args.path, &btm)?;
    let (shp, report) =
        shp_report(&btm, &path).map_err(|e| CliError(format!("{}: {e}", args.path.display())))?;
    if args.picture.wanted() {
        let mut pic = Picture::of_map_in(&s.map, args.window.aabb()?.as_ref());
        pic.sleeve(&btm, &shp.sleeve);
        pic.btm(&btm);
        pic.map(&s.map);
        pic.path(path.points());
        pic.taut_path(&shp.taut);
        pic.start_goal(path.start(), path.end());
        let title = format!("SHP of {}", args.path.display());
        args.picture.write(&pic.finish(&title), &title)?;
    }
    if args.json {
        return print_report(&report);
    }
    crate::output::outln!("scenario             {}", args.file.display());
    crate::output::outln!(
        "path                 {} ({} points, {:.3} m)",
        args.path.display(),
        report.path_points,
        report.path_length_m
    );
    crate::output::outln!("SHP length           {:.3} m", report.length_m);
    crate::output::outln!(
        "crossing sequence    {} crossings, {} after reduction",
        report.crossings,
        report.reduced_crossings
    );
    crate::output::outln!(
        "H-signature          {} ({} obstacles with non-zero winding)",
        report.h_signature.digest,
        report.h_signature.windings.len()
    );
    crate::output::outln!("SHP                  {} points", report.points.len());
    for (i, q) in report.points.iter().enumerate() {
        crate::output::outln!("  {i:>4}  ({:.3}, {:.3})", q.x, q.y);
    }
    crate::output::outln!("anchors              {}", report.anchors.len());
    if !report.anchors.is_empty() {
        crate::output::outln!("     #  vertex  obstacle  side   turning   position");
        for (i, a) in report.anchors.iter().enumerate() {
            let obstacle = a
                .obstacle
                .map_or_else(|| "boundary".to_string(), |o| o.to_string());
            let side = match a.side {
                Side::Left => "left",
                Side::Right => "right",
            };
            crate::output::outln!(
                "  {:>4}  {:>6}  {:>8}  {:<5}  {:>6.2}°   ({:.3}, {:.3})",
                i + 1,
                a.vertex,
                obstacle,
                side,
                a.turning_angle_deg,
                a.point.x,
                a.point.y
            );
        }
    }
    for (_, out) in args.picture.outputs() {
        crate::output::outln!("picture              {}", out.display());
    }
    Ok(())
}

/// Runs `rappel homotopic`: [`Answer::Yes`] when the two paths are homotopic.
pub fn run_homotopic(args: &HomotopicArgs) -> Result<Answer, CliError> {
    let [a, b] = args.path.as_slice() else {
        return Err(CliError(format!(
            "give exactly two --path files, not {}",
            args.path.len()
        )));
    };
    let (_, btm) = load_btm(&args.file)?;
    let (pa, pb) = (load_path(a, &btm)?, load_path(b, &btm)?);
    let same = are_homotopic(&btm, &pa, &pb)
        .map_err(|e| CliError(format!("{} and {}: {e}", a.display(), b.display())))?;
    if args.json {
        let reduced = |p: &rappel::homotopy::path::Path, f: &std::path::Path| {
            CrossingSequence::reduced_of_path(&btm, p)
                .map(|c| c.len())
                .map_err(|e| CliError(format!("{}: {e}", f.display())))
        };
        print_report(&rappel::report::HomotopicReport {
            homotopic: same,
            paths: [a.display().to_string(), b.display().to_string()],
            reduced_crossings: [reduced(&pa, a)?, reduced(&pb, b)?],
        })?;
        return Ok(if same { Answer::Yes } else { Answer::No });
    }
    crate::output::outln!("{}", if same { "homotopic" } else { "not homotopic" });
    Ok(if same { Answer::Yes } else { Answer::No })
}
