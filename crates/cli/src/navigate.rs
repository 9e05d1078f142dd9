//! `rappel navigate SCENE --seed S [--test N] [--iterations N] [--time T] [--time-limit SECONDS]
//! [--held] [--shadow]
//! [--field RES] [--json] [--svg OUT] [--html OUT]`: plans the tethered rover's path on a Paton scene with ABIT*
//! ([`rappel::navigate`]): the start on the ledge, the goal on the ground beyond the slope, the
//! root anchor of the scene's test N. Prints the path, its anchor history, the stability margin
//! along it and the search statistics. `--field RES`: the planner's motion checks settle and
//! predict anchors through the sparse distance field ([`crate::field_arg`]); the reported path is
//! re-validated on the exact mesh either way. Exit 0 when a re-validated path was found, 1 when none
//! was found within the budget (or the planner's path failed re-validation), 2 on errors.
//! `--time T` is the sampler's own wall-time budget (default 120 s; `stopped by time`);
//! `--time-limit SECONDS` is the stop condition every long command takes ([`crate::stop`];
//! `stopped by time_limit`), and Ctrl-C stops the search too (`stopped by cancelled`): the
//! tighter limit holds, and a path found before the stop is still reported.

use crate::field_arg::FieldArg;
use crate::output::{Answer, CliError, PictureArgs, print_report, refuse_clashing_outputs};
use rappel::navigate::StoppedBy;
use rappel::navigate::{DEFAULT_TIME, PATON_ITERATIONS, RoverProblem, navigate};
use rappel::planners::sampler::Termination;
use rappel::settle::load_scene;
use rappel_render::navigate::navigate_svg;
use std::path::PathBuf;
use std::time::Duration;

/// Arguments of `rappel navigate`.
#[derive(clap::Args)]
pub struct Args {
    /// The scene: a Paton scene (.ron, fixtures/paton/).
    file: PathBuf,
    /// The planner's seed (same seed, same iterations: same path).
    #[arg(long, allow_negative_numbers = true)]
    seed: u64,
    /// The root anchor of the scene's test N: 1 behind the start, 2 in front (the pole scene's
    /// test 3 uses anchor 2).
    #[arg(
        long,
        value_name = "N",
        default_value_t = 1,
        allow_negative_numbers = true
    )]
    test: usize,
    /// Iteration budget (one iteration processes one edge; Paton ran 750).
    #[arg(long, default_value_t = PATON_ITERATIONS, allow_negative_numbers = true)]
    iterations: u64,
    /// The sampler's wall-time budget, seconds (default 120): a run it ends is `stopped by
    /// time`.
    #[arg(long, value_parser = crate::numbers::finite, value_name = "T", allow_negative_numbers = true)]
    time: Option<f64>,
    /// The command's time limit (as every long command's; Ctrl-C stops it too): a run it ends
    /// is `stopped by time_limit`. With `--time` the tighter holds.
    #[command(flatten)]
    time_limit: crate::stop::TimeLimitArg,
    /// Count poses whose last anchor is within the boom's reach as held by the boom (see
    /// `RoverProblem::held_within_boom_reach`; off: the faithful model).
    #[arg(long)]
    held: bool,
    /// Draw a fifth of the samples from the root anchor's shadow, where the tether must wrap
    /// (`rappel::planners::rover::shadow`; off: Paton's uniform sampling).
    #[arg(long)]
    shadow: bool,
    #[command(flatten)]
    field: FieldArg,
    #[command(flatten)]
    picture: PictureArgs,
    /// Print the report as JSON.
    #[arg(long)]
    json: bool,
}

/// Runs `rappel navigate`.
pub fn run(args: &Args) -> Result<Answer, CliError> {
    refuse_clashing_outputs(&args.picture.outputs(), &[&args.file])?;
    let at = |why: String| CliError(format!("{}: {why}", args.file.display()));
    let scene = load_scene(&args.file).map_err(|e| CliError(e.to_string()))?;
    let anchor = args.test.checked_sub(1).ok_or_else(|| {
        CliError(format!(
            "--test {}: the scene has tests 1 to {}",
            args.test,
            scene.anchors.len()
        ))
    })?;
    if anchor >= scene.anchors.len() {
        return Err(CliError(format!(
            "--test {}: the scene has tests 1 to {}",
            args.test,
            scene.anchors.len()
        )));
    }
    if args.iterations == 0 {
        return Err(CliError("--iterations must be at least 1".into()));
    }
    let time = match args.time {
        None => DEFAULT_TIME,
        Some(t) if t.is_finite() && t > 0.0 && t <= 86_400.0 => Duration::from_secs_f64(t),
        Some(t) => {
            return Err(CliError(format!(
                "--time {t}: must be a positive number of seconds up to 86400"
            )));
        }
    };
    let stop = crate::stop::condition(
        rappel::planners::budget::ExpansionBudget::Auto,
        &args.time_limit,
    )?;
    let mut problem = RoverProblem::paton(&scene, anchor).map_err(at)?;
    if args.field.field.is_some() {
        problem
            .use_distances(args.field.source())
            .map_err(|e| args.field.error(e))?;
    }
    problem.held_within_boom_reach = args.held;
    if args.shadow {
        problem.shadow_sample_fraction = rappel::navigate::SHADOW_SAMPLE_FRACTION;
    }
    let term = Termination::iterations(args.iterations).or_time(time);
    // A search checks motions for seconds to minutes: say so on a terminal.
    let progress = crate::progress::Progress::spinner("navigate");
    progress.message("sampling and checking motions");
    let report = navigate(&problem, args.seed, term, &stop).map_err(at);
    progress.finish();
    let report = report?;
    if args.picture.wanted() {
        args.picture
            .write(&navigate_svg(&problem, &report), "rappel navigate")?;
    }
    crate::stop::say(report.stop_reason);
    let budget_out = report.stopped_by != StoppedBy::CostThreshold;
    let stopped = report.stopped_by.by_condition();
    if args.json {
        print_report(&report)?;
    } else {
        if report.found {
            crate::output::outln!(
                "path found: cost {:.3}, {} states, first solution after {} iterations ({:.2} s)",
                report.cost.unwrap_or(f64::NAN),
                report.path.len(),
                report.first_solution_iteration.unwrap_or(0),
                report.first_solution_s.unwrap_or(0.0)
            );
            for (p, y) in report.path.iter().zip(&report.yaw_deg) {
                crate::output::outln!(
                    "  state ({:.3}, {:.3}, {:.3}) yaw {y:.1}°",
                    p[0],
                    p[1],
                    p[2]
                );
            }
            for (k, a) in report.anchors.iter().enumerate() {
                crate::output::outln!("  anchor {k} ({:.3}, {:.3}, {:.3})", a[0], a[1], a[2]);
            }
            crate::output::outln!(
                "  stability margin along the path: min {:.2} N over {} poses; max roll {:.1}°",
                report.min_margin_n.unwrap_or(f64::NAN),
                report.poses.len(),
                report.max_roll_deg.unwrap_or(f64::NAN)
            );
        } else if let Some(why) = &report.unsafe_reason {
            crate::output::outln!("the planner's path failed re-validation: {why}");
        } else {
            crate::output::outln!(
                "no path within the budget{}",
                if let (true, Some(r)) = (stopped, report.stop_reason) {
                    format!(" (the search stopped at {r})")
                } else if budget_out {
                    format!(" (the {} budget ran out)", report.stopped_by)
                } else {
                    String::new()
                }
            );
        }
        crate::output::outln!(
            "search: {} iterations, {} batches, {} states, {} motions checked, {:.2} s, stopped by {}",
            report.iterations,
            report.batches,
            report.states,
            report.motions_checked,
            report.elapsed_s,
            report.stopped_by
        );
    }
    Ok(if report.found {
        Answer::Yes
    } else {
        Answer::No
    })
}
