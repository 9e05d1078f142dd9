//! `rappel online PRIOR.ron --truth TRUE.ron [--sensor-range R] [--step S] [--max-steps N]
//! [--classes K] [--switch-to-shorter] [--time-limit SECONDS] [--json] [--svg OUT] [--html OUT] [--frames DIR]
//! [--export OUT.fgb|OUT.geojson|OUT.csv]`: the online planner
//! (thesis Alg. 11-13) simulated. The robot descends by the plan made on the prior map; every
//! difference from the true map that comes within sensor range is a map change. Prints the
//! timeline (event, case, decision, distance travelled and backtracked) and the end state.
//! Exit code 0 at the goal with ascent and descent homotopic, 1 for a clean "no" (no feasible
//! class within the termination rule, the goal covered, or the step budget spent), 2 for errors.
//! `--time-limit SECONDS` bounds the whole run (every search shares its clock) and Ctrl-C stops it
//! ([`crate::stop`]): the run ends where it stands, the verdict says "the run stopped at the time
//! limit of SECONDS s" (or "... at a cancel request"), and the exit code is 1.
//! `--export` writes the path travelled, the final ascent and the timeline's events
//! ([`rappel_render::export::online_features`]) in the prior scenario's DEM coordinates and CRS
//! when it was made by `rappel dem`, else in the planning frame, and says which.

use crate::output::{Answer, CliError, PictureArgs, refuse_clashing_outputs, write_file};
use rappel::planners::online::simulate::{
    DEFAULT_MAX_STEPS, DEFAULT_SENSOR_RANGE, DEFAULT_STEP, Ending,
};
use rappel::planners::online::{
    DEFAULT_ONLINE_CLASSES, OnlineOptions, SimulationOptions, SimulationReport,
};
use rappel::planners::spt::SearchOptions;
use rappel::scenario::Scenario;
use rappel_render::online::{event_picture, picture};
use std::path::{Path, PathBuf};

/// Arguments of `rappel online`.
#[derive(clap::Args)]
pub struct Args {
    /// The prior scenario (.ron or .json): the map the plan is made on.
    prior: PathBuf,
    /// The true scenario: same start, goal, terrain and robot; the map the robot finds.
    #[arg(long, value_name = "TRUE")]
    truth: PathBuf,
    /// Differences within this distance of the robot are sensed, m (larger than the step).
    #[arg(long, value_parser = crate::numbers::finite, value_name = "R", default_value_t = DEFAULT_SENSOR_RANGE, allow_negative_numbers = true)]
    sensor_range: f64,
    /// Distance moved between two sensings, m; at least 1e-5 of the prior map's diagonal
    /// (crossing the map then takes at most 100,000 steps).
    #[arg(long, value_parser = crate::numbers::finite, value_name = "S", default_value_t = DEFAULT_STEP, allow_negative_numbers = true)]
    step: f64,
    /// The step budget, from 1 to 1,000,000 (each step senses the true map within the range
    /// and adds a point to the walked path).
    #[arg(long, value_name = "N", default_value_t = DEFAULT_MAX_STEPS, allow_negative_numbers = true)]
    max_steps: usize,
    /// Classes each (re)planning search examines beyond the rejected ones.
    #[arg(long, value_name = "K", default_value_t = DEFAULT_ONLINE_CLASSES, allow_negative_numbers = true)]
    classes: usize,
    /// Switch to a shorter class a removal opens when it saves more than the backtracking costs.
    #[arg(long)]
    switch_to_shorter: bool,
    /// The time limit of the whole run (Ctrl-C stops it too).
    #[command(flatten)]
    time_limit: crate::stop::TimeLimitArg,
    /// Print the report as JSON.
    #[arg(long)]
    json: bool,
    /// The picture of the final state.
    #[command(flatten)]
    picture: PictureArgs,
    /// Draw one SVG per event into this directory.
    #[arg(long, value_name = "DIR")]
    frames: Option<PathBuf>,
    /// Export the path travelled, the final ascent and the timeline's events (FlatGeobuf
    /// carries any CRS; GeoJSON; CSV), in the DEM's coordinates for a scenario made by
    /// `rappel dem`.
    #[arg(long, value_name = "OUT.fgb|OUT.geojson|OUT.csv")]
    export: Option<PathBuf>,
}

/// Runs `rappel online`: yes when the goal is reached with ascent and descent homotopic, a clean no
/// when no feasible class is left, the goal is covered or the step budget is spent.
pub fn run(args: &Args) -> Result<Answer, CliError> {
    let mut outputs = args.picture.outputs();
    if let Some(out) = &args.export {
        outputs.push(("--export", out.as_path()));
    }
    refuse_clashing_outputs(&outputs, &[&args.prior, &args.truth])?;
    let export = match &args.export {
        None => None,
        Some(out) => Some((out, crate::gis_out::export_format(out)?)),
    };
    if args.classes == 0 {
        return Err(CliError("--classes 0: examine at least one class".into()));
    }
    let stop = crate::stop::condition(
        rappel::planners::budget::ExpansionBudget::Auto,
        &args.time_limit,
    )?;
    let prior = Scenario::load(&args.prior)?;
    let truth = Scenario::load(&args.truth)?;
    let options = SimulationOptions {
        sensor_range: args.sensor_range,
        step: args.step,
        max_steps: args.max_steps,
        session: OnlineOptions {
            search: SearchOptions::default()
                .with_max_classes(Some(args.classes))?
                .with_stop(stop)?,
            switch_to_shorter: args.switch_to_shorter,
            ..Default::default()
        },
    };
    let mut frames = Vec::new();
    let mut observe = |e: &rappel::planners::online::simulate::TimelineEvent,
                       s: &rappel::planners::online::OnlineSession| {
        if args.frames.is_some() {
            frames.push(event_picture(e, s));
        }
    };
    // A mismatch between the two files is about the truth (the prior is the plan's map).
    let result = rappel::online::run(&prior, &truth, &options, &mut observe).map_err(|e| {
        let file = match e {
            rappel::online::OnlineRunError::Mismatch { .. }
            | rappel::online::OnlineRunError::BoundaryMismatch => &args.truth,
            _ => &args.prior,
        };
        CliError(format!("{}: {e}", file.display()))
    })?;
    if let Some(dir) = &args.frames {
        for (i, svg) in frames.iter().enumerate() {
            write_file(&dir.join(format!("event-{:03}.svg", i + 1)), svg)?;
        }
    }
    let r = &result.report;
    crate::stop::say(r.stopped_by);
    if args.picture.wanted() {
        let title = format!("{}: {}", truth.name, verdict(r));
        args.picture
            .write(&picture(&result.session, &title), &title)?;
    }
    if let Some((out, format)) = export {
        let geo = prior.georeference.as_ref();
        let bytes = rappel_render::export::export_online(r, prior.start, prior.goal, geo, format)
            .map_err(|e| CliError(format!("--export {}: {e}", out.display())))?;
        crate::gis_out::write_export(out, &bytes, geo, format, "the online run")?;
    }
    if args.json {
        crate::output::print_report(r)?;
    } else {
        print_text(&args.prior, &args.truth, r);
        for (_, out) in args.picture.outputs() {
            crate::output::outln!("picture      {}", out.display());
        }
        if let Some(dir) = &args.frames {
            crate::output::outln!("frames       {} in {}", frames.len(), dir.display());
        }
    }
    if r.ending.reached() && !r.homotopic {
        // Reaching the goal with a descent not homotopic to the ascent would be a bug.
        return Err(CliError(
            "internal error: the goal was reached with a descent not homotopic to the ascent"
                .into(),
        ));
    }
    Ok(if r.ending.reached() {
        Answer::Yes
    } else {
        Answer::No
    })
}

fn verdict(r: &SimulationReport) -> String {
    if let Some(reason) = r.stopped_by {
        return match &r.ending {
            Ending::NoFeasibleClass { .. } => {
                format!("no feasible class (the search stopped at {reason})")
            }
            _ => format!("the run stopped at {reason}"),
        };
    }
    match &r.ending {
        Ending::Goal => format!(
            "goal reached, ascent and descent {}",
            if r.homotopic {
                "homotopic"
            } else {
                "NOT homotopic"
            }
        ),
        Ending::NoFeasibleClass { termination } => {
            format!("no feasible class ({})", termination.describe())
        }
        Ending::GoalCovered => "the goal lies inside an obstacle".to_string(),
        Ending::StepBudget => "the step budget ran out".to_string(),
    }
}

/// A clearance shortfall as one phrase.
fn shortfall(s: &rappel::planners::online::session::ClearanceShortfall) -> String {
    use rappel::planners::online::session::ClearanceShortfall;
    match s {
        ClearanceShortfall::NoPair { failure } => {
            format!("no class has an ascent/descent pair, the taut tether is followed ({failure})")
        }
        ClearanceShortfall::Continuation { failure } => {
            format!(
                "the descent from here cannot keep the clearance, the taut continuation is followed ({failure})"
            )
        }
    }
}

fn print_text(prior: &Path, truth: &Path, r: &SimulationReport) {
    crate::output::outln!("prior        {}", prior.display());
    crate::output::outln!("truth        {}", truth.display());
    if let Some(l) = r.initial_class_length_m {
        crate::output::outln!("planned      class of SHP length {l:.3} m on the prior map");
    }
    if let Some(s) = &r.initial_clearance_shortfall {
        crate::output::outln!(
            "warning      the initial descent does not keep the clearance: {}",
            shortfall(s)
        );
    }
    crate::output::outln!(
        "{:<5} {:<9} {:<14} {:<52} {:<22} {:>9} {:>9}",
        "step",
        "change",
        "difference",
        "case",
        "decision",
        "travel m",
        "back m"
    );
    for e in &r.timeline {
        let diff = match &e.difference {
            rappel::planners::online::simulate::Difference::New { truth } => format!("new {truth}"),
            rappel::planners::online::simulate::Difference::Phantom { prior } => {
                format!("phantom {prior}")
            }
            rappel::planners::online::simulate::Difference::Shifted { prior, truth } => {
                format!("shift {prior}->{truth}")
            }
            rappel::planners::online::simulate::Difference::Boundary => "boundary".into(),
            rappel::planners::online::simulate::Difference::Friction { prior } => {
                format!("friction of PTFO {prior}")
            }
            rappel::planners::online::simulate::Difference::PriorPtfoCheck => {
                "PTFO check of the prior plan".into()
            }
        };
        let decision = match &e.outcome.decision {
            rappel::planners::online::Decision::Switched { backtrack_m, .. } => {
                format!("switched (back {backtrack_m:.2})")
            }
            d => format!("{d:?}").to_lowercase(),
        };
        crate::output::outln!(
            "{:<5} {:<9} {:<14} {:<52} {:<22} {:>9.3} {:>9.3}",
            e.step,
            e.outcome.change,
            diff,
            e.outcome.case.describe(),
            decision,
            e.travelled_m,
            e.backtracked_m
        );
        crate::output::outln!("      {}", e.outcome.reason);
        if let Some(s) = &e.outcome.shorter_class {
            crate::output::outln!(
                "      a shorter class opened: {:.3} m remaining instead of {:.3} m ({:.3} m backtracking){}",
                s.remaining_m,
                s.current_remaining_m,
                s.backtrack_m,
                if s.switched { ", switched" } else { "" }
            );
        }
        if let Some(s) = &e.outcome.clearance_shortfall {
            crate::output::outln!("      warning: {}", shortfall(s));
        }
        if !e.outcome.backtrackable {
            crate::output::outln!(
                "      warning: the backtrackability check failed after this decision"
            );
        }
    }
    crate::output::outln!("verdict      {}", verdict(r));
    crate::output::outln!(
        "travelled    {:.3} m in {} steps, {:.3} m of it backtracking",
        r.travelled_m,
        r.steps,
        r.backtracked_m
    );
    if let Some(l) = r.final_class_length_m {
        crate::output::outln!("final class  SHP length {l:.3} m");
    }
    crate::output::outln!("tether       {:.3} m (taut)", r.tether_length_m);
    crate::output::outln!(
        "kept         {} change(s) outside the sleeve; {} class(es) rejected; {} difference(s) never sensed",
        r.deferred,
        r.rejected,
        r.unsensed
    );
}
