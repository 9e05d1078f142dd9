//! `rappel settle GROUND --at X,Y --yaw DEG [--robot axel|four-wheel] [--anchor X,Y,Z]
//! [--field RES] [--json] [--svg OUT]`: settles Axel (or the four-wheel rover) on 3D ground
//! (Paton §IV-A; a Paton scene `.ron`, an elevation model `.asc` / `.tif` or a mesh `.obj` /
//! `.ply` / `.stl`) and prints the pose; with `--anchor`, the stability QP's verdict (Axel: both
//! boom configurations; the four-wheel rover: the tether to its body; exit 1 when none is
//! stable); with `--field`, settling reads the sparse distance field ([`crate::field_arg`]);
//! with `--svg`, an axonometric picture of the settled pose (Axel only).

use crate::field_arg::FieldArg;
use crate::output::{Answer, CliError, print_report, refuse_clashing_outputs, write_file};
use rappel::settle::{SettleRobot, four_wheel_report_with, load_ground, settle_report_with};
use std::path::PathBuf;

/// `--robot NAME` as given: `axel` or `four-wheel`; anything else is an error naming the flag.
pub(crate) fn robot(name: &str) -> Result<SettleRobot, CliError> {
    match name {
        "axel" => Ok(SettleRobot::Axel),
        "four-wheel" => Ok(SettleRobot::FourWheel),
        other => Err(CliError(format!(
            "--robot {other}: expected axel or four-wheel"
        ))),
    }
}

/// Arguments of `rappel settle`.
#[derive(clap::Args)]
pub struct Args {
    /// The ground: a Paton scene (.ron, fixtures/paton/), an elevation model (.asc, .tif) or a
    /// mesh (.obj, .ply, .stl).
    file: PathBuf,
    /// Ground point under the axle centre, `X,Y` metres.
    #[arg(long, value_name = "X,Y", allow_hyphen_values = true)]
    at: String,
    /// Heading: the forward axis' azimuth, degrees counter-clockwise from +x.
    #[arg(long, value_parser = crate::numbers::finite, value_name = "DEG", allow_negative_numbers = true)]
    yaw: f64,
    /// The robot: `axel` (two wheels of 12 contact points, body along the axle, boom) or
    /// `four-wheel` (the rigid four-wheel rover: point wheels, no body geometry, the tether fixed
    /// to its body; `--svg` draws Axel only).
    #[arg(long, value_name = "NAME", default_value = "axel")]
    robot: String,
    /// The tether's last anchor `X,Y,Z` (world): adds the stability verdict.
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true)]
    anchor: Option<String>,
    #[command(flatten)]
    field: FieldArg,
    /// Print the report as JSON.
    #[arg(long)]
    json: bool,
    /// Write an axonometric SVG of the settled pose (the ground around it, wheels, body, and with
    /// `--anchor` the boom and the tether).
    #[arg(long, value_name = "OUT")]
    svg: Option<PathBuf>,
}

/// Runs `rappel settle`: `Yes` when settled (and stable in some boom configuration when an
/// anchor is given), `No` otherwise; bad input is an error.
pub fn run(args: &Args) -> Result<Answer, CliError> {
    let robot = robot(&args.robot)?;
    if let Some(out) = &args.svg {
        if robot != SettleRobot::Axel {
            return Err(CliError(
                "--svg with --robot four-wheel: the settled-pose picture draws Axel only".into(),
            ));
        }
        refuse_clashing_outputs(&[("--svg", out.as_path())], &[&args.file])?;
    }
    let ground = load_ground(&args.file).map_err(|e| CliError(e.to_string()))?;
    let at = crate::numbers::numbers("--at", &args.at, 2)?;
    rappel::settle::within_ground(&ground, at[0], at[1])
        .map_err(|why| CliError(format!("--at {}: {why}", args.at)))?;
    let anchor = match &args.anchor {
        Some(a) => {
            let a = crate::numbers::numbers("--anchor", a, 3)?;
            Some([a[0], a[1], a[2]])
        }
        None => None,
    };
    let distances = args.field.distances(&ground)?;
    let settled = match robot {
        SettleRobot::Axel => {
            settle_report_with(&ground, &distances, at[0], at[1], args.yaw, anchor)
                .map(|(pose, report)| (Some(pose), report))
        }
        SettleRobot::FourWheel => {
            four_wheel_report_with(&distances, at[0], at[1], args.yaw, anchor)
                .map(|(_, report)| (None, report))
        }
    };
    let (pose, report) = match settled {
        Ok(r) => r,
        Err(e) if matches!(e, rappel::mechanics::settle::SettleError::Parameter(_)) => {
            return Err(CliError(e.to_string()));
        }
        Err(e) if args.json => {
            print_report(&rappel::settle::NotSettledReport {
                robot,
                at: [at[0], at[1]],
                yaw_deg: args.yaw,
                reason: e.to_string(),
            })?;
            return Ok(Answer::No);
        }
        Err(e) => {
            crate::output::outln!("not settled: {e}");
            return Ok(Answer::No);
        }
    };
    if let (Some(out), Some(pose)) = (&args.svg, &pose) {
        let title = format!(
            "rappel settle {} at {:.2},{:.2} yaw {:.1}°",
            args.file.display(),
            at[0],
            at[1],
            args.yaw
        );
        let svg = rappel_render::settle::settled_pose_picture(
            &ground,
            pose,
            &Default::default(),
            anchor,
            &report.stability,
            &title,
        );
        write_file(out, &svg)?;
    }
    if args.json {
        print_report(&report)?;
    } else {
        let o = report.origin;
        let clearance = report
            .body_clearance_m
            .map(|c| format!(", body clearance {c:.3} m"))
            .unwrap_or_default();
        crate::output::outln!(
            "settled      origin ({:.3}, {:.3}, {:.3}), roll {:.2}°, pitch {:.2}°{clearance}",
            o[0],
            o[1],
            o[2],
            report.roll_deg,
            report.pitch_deg,
        );
        const WHEELS: [&str; 4] = ["front-left", "front-right", "rear-left", "rear-right"];
        let names: Vec<&str> = match &report.support {
            None => vec!["right", "left"],
            Some(support) => support
                .iter()
                .map(|&w| WHEELS.get(w).copied().unwrap_or("wheel"))
                .collect(),
        };
        for (name, c) in names.iter().zip(&report.contacts) {
            crate::output::outln!(
                "  {name:<11} contact ({:.3}, {:.3}, {:.3})",
                c[0],
                c[1],
                c[2]
            );
        }
        for v in &report.stability {
            match (v.stable, &v.error) {
                (Some(s), _) => crate::output::outln!(
                    "  boom {:<10} {} (margin {:.3})",
                    v.boom,
                    if s { "stable" } else { "not stable" },
                    v.margin
                ),
                (None, e) => crate::output::outln!(
                    "  boom {:<10} not checked: {}",
                    v.boom,
                    e.as_deref().unwrap_or("unknown")
                ),
            }
        }
    }
    let stable =
        report.stability.is_empty() || report.stability.iter().any(|v| v.stable == Some(true));
    Ok(if stable { Answer::Yes } else { Answer::No })
}
