//! `rappel plan FILE [--classes K] [--max-length-factor F] [--simple-only] [--max-expansions N|auto]
//! [--time-limit SECONDS] [--json | --jsonl] [--reachable-areas] [--svg OUT] [--html OUT] [--window XMIN,YMIN,XMAX,YMAX]
//! [--export OUT.fgb|OUT.geojson|OUT.csv] [--progress]`:
//! the Chapter-2 planner (thesis Alg. 3-6). Lists the homotopy classes shortest first (rank,
//! length, anchors, feasible or why not, waypoints) and the chosen ascent/descent pair; `--svg`
//! draws the BTM, sleeve, SHP, anchors, friction cones, visibility edges, waypoints and both paths,
//! and every infeasible class's tether with its blocking anchor marked; `--html` the same picture as
//! an interactive page.
//! A scenario without a feasible class is an answer, not an error: exit code 1, the reason printed.
//! With PTFOs (a `friction` section) the frictional planner runs too, and its verdict decides.
//! Without a picture the classes are streamed (`rappel::plan::plan_streamed`): each class's block
//! is printed as soon as the class is decided and its geometry dropped, then the summary (model,
//! planes, class count, verdict); `--json` prints the one envelope at the end; `--jsonl` prints one
//! JSON object per class as it is decided and a final `summary` object (`rappel::plan_stream`).
//! A run that fails after its output began ends that output with a marker, so that it cannot be
//! taken for complete: the text's last line is `error        MESSAGE (the output above is
//! incomplete)`; with `--jsonl` every failed run's last object has `"type": "error"`; the exit
//! code is 2 and the usual `error:` line goes to stderr. A complete text report ends with its `verdict` (and
//! friction) lines, a complete `--jsonl` stream with its `summary` object.
//! `--time-limit SECONDS` bounds the whole plan and Ctrl-C stops it ([`crate::stop`]): the
//! classes found so far are reported, the verdict names the condition ("the search stopped at
//! the time limit of 0.5 s"), stderr says `stopped: ...`, and without a feasible class the exit
//! code is 1 as for any "no".
//! `--progress` forces the progress over the K classes on stderr (`crate::progress`), which is
//! otherwise shown only when stderr is a terminal.

use crate::output::{Answer, CliError, PictureArgs, refuse_clashing_outputs};
use crate::progress::{Progress, Show};
use crate::window::WindowArg;
use rappel::plan::{
    ClassReport, PlanOptions, PlanOutcome, PlanReport, PlanSetting, plan_detailed_each,
    plan_streamed, plan_summary,
};
use rappel::plan_stream::{PlanStreamLine, PlanSummary};
use rappel::scenario::Scenario;
use rappel_render::export::export_plan;
use std::path::{Path, PathBuf};

/// Arguments of `rappel plan`.
#[derive(clap::Args)]
pub struct Args {
    /// The scenario file (.ron or .json).
    file: PathBuf,
    /// How many homotopy classes to list, shortest first (at most 1000).
    #[arg(long, value_name = "K", default_value_t = rappel::plan::DEFAULT_CLASSES, allow_negative_numbers = true)]
    classes: usize,
    /// List only classes at most F times longer than the shortest (F >= 1).
    #[arg(long, value_parser = crate::numbers::finite, value_name = "F", allow_negative_numbers = true)]
    max_length_factor: Option<f64>,
    /// List only simple classes: no tether winds around an obstacle or returns to one.
    #[arg(long)]
    simple_only: bool,
    /// Funnel expansion budget of the search: `auto` (the default) scales it to the map's
    /// triangles and the classes asked for, under a memory cap; a number fixes it. When it runs
    /// out the report says which limit stopped the search and how to raise it.
    #[arg(long, value_name = "N|auto", default_value = "auto", value_parser = rappel::planners::budget::ExpansionBudget::parse)]
    max_expansions: rappel::planners::budget::ExpansionBudget,
    /// The time limit of the whole plan (Ctrl-C stops it too): the verdict then says "the
    /// search stopped at the time limit of SECONDS s".
    #[command(flatten)]
    time_limit: crate::stop::TimeLimitArg,
    /// Print the report as JSON.
    #[arg(long, conflicts_with = "jsonl")]
    json: bool,
    /// Stream the report as JSON lines: one object per class as it is decided, then a
    /// `summary` object (or an `error` object when the run fails); `docs/output-format.md`.
    #[arg(long, conflicts_with_all = ["svg", "html"])]
    jsonl: bool,
    /// Show progress over the classes on stderr even when it is not a terminal (plain lines; a
    /// bar on a terminal, where it is shown anyway).
    #[arg(long)]
    progress: bool,
    /// Cut each anchor reachable set to free space and report its area (`reachable_area_m2` in
    /// the JSON; a polygon overlay per anchor of every class, so off by default).
    #[arg(long)]
    reachable_areas: bool,
    /// The picture of the plan (infeasible classes and their blocking anchors marked).
    #[command(flatten)]
    picture: PictureArgs,
    /// The picture's crop.
    #[command(flatten)]
    window: WindowArg,
    /// Export tethers, anchors, waypoints and paths to this file: FlatGeobuf (.fgb, carries any
    /// CRS), GeoJSON (.geojson, WGS 84 or EPSG CRSs) or CSV (.csv), in the DEM's coordinates and
    /// CRS for scenarios made by `rappel dem`.
    #[arg(long, value_name = "OUT")]
    export: Option<PathBuf>,
}

/// Runs `rappel plan`: [`Answer::Yes`] when a class is feasible and has an ascent/descent pair.
/// A failure after the text output began, or any failure with `--jsonl`, ends the output with the
/// error marker (module docs).
pub fn run(args: &Args) -> Result<Answer, CliError> {
    let mut began = false;
    let result = run_marked(args, &mut began);
    if let Err(e) = &result {
        if args.jsonl {
            crate::output::outln!(
                "{}",
                PlanStreamLine::Error {
                    message: e.0.clone()
                }
                .to_line()
            );
        } else if began {
            crate::output::outln!("{}", error_marker(&e.0));
        }
    }
    result
}

/// The last line of a text report whose run failed after some of it was printed.
fn error_marker(message: &str) -> String {
    format!("error        {message} (the output above is incomplete)")
}

/// [`run`] without the marker; `began` is set once something is printed on stdout.
fn run_marked(args: &Args, began: &mut bool) -> Result<Answer, CliError> {
    if args.classes == 0 {
        return Err(CliError("--classes 0: list at least one class".into()));
    }
    if args.classes > rappel::plan::MAX_CLASSES {
        return Err(CliError(format!(
            "--classes {}: at most {} classes can be listed (each class costs a search, a feasibility check and its report)",
            args.classes,
            rappel::plan::MAX_CLASSES
        )));
    }
    let mut outputs: Vec<(&str, &Path)> = args.picture.outputs();
    let window = args.window.aabb()?;
    if let Some(out) = &args.export {
        outputs.push(("--export", out.as_path()));
    }
    refuse_clashing_outputs(&outputs, &[&args.file])?;
    let export = match &args.export {
        None => None,
        Some(out) => Some((out, crate::gis_out::export_format(out)?)),
    };
    if let Some(f) = args.max_length_factor
        && !(f.is_finite() && f >= 1.0)
    {
        return Err(CliError(format!(
            "--max-length-factor {f}: must be a number >= 1"
        )));
    }
    let stop = crate::stop::condition(args.max_expansions, &args.time_limit)?;
    // Read, then validated once: the proof carries the valid map to the BTM build.
    let s = Scenario::read(&args.file)?;
    let s = s.validate_at(&args.file)?;
    let options = PlanOptions {
        classes: args.classes,
        max_length_factor: args.max_length_factor,
        simple_only: args.simple_only,
        stop,
        reachable_areas: args.reachable_areas,
    };
    // Without a picture the classes are streamed: each class's block is printed as soon as it
    // is decided and its geometry dropped (text mode: the classes first, then the summary).
    let streamed = !args.picture.wanted();
    let show = if args.progress {
        Show::Always
    } else {
        Show::Auto
    };
    let progress = Progress::with(options.classes as u64, "classes", show);
    let fail = |e: rappel::plan::PlanError| CliError(format!("{}: {e}", args.file.display()));
    // `--json` and `--export` need every class's report at the end; otherwise nothing of a class
    // is kept once it is printed (`plan_summary`).
    let keep_reports = args.json || export.is_some();
    let (json, jsonl) = (args.json, args.jsonl);
    let mut print = |c: &ClassReport| {
        progress.inc(1);
        if jsonl {
            *began = true;
            crate::output::outln!("{}", PlanStreamLine::Class(Box::new(c.clone())).to_line());
        } else if !json {
            *began = true;
            print_class(c);
        }
    };
    let summary = if streamed && !keep_reports {
        let r = plan_summary(&s, &options, &mut print);
        progress.finish();
        r.map_err(fail)?
    } else {
        let report = if streamed {
            let r = plan_streamed(&s, &options, &mut print);
            progress.finish();
            r.map_err(fail)?
        } else {
            let plan = plan_detailed_each(&s, &options, &mut |_| progress.inc(1));
            progress.finish();
            let plan = plan.map_err(fail)?;
            let title = match &plan.outcome.pair {
                Some(p) => format!("{}: class {} (ascent/descent pair)", s.name, p.rank),
                None => format!("{}: no feasible class", s.name),
            };
            // A scenario made from a DEM is drawn over the DEM's hillshade; a DEM that cannot be
            // read leaves the picture without it, and says so.
            let ground = match rappel_render::dem::scenario_hillshade(&s, &args.file) {
                Some(Ok(g)) => Some(g),
                Some(Err(e)) => {
                    eprintln!(
                        "warning: {}: {e}; the picture has no hillshade",
                        args.file.display()
                    );
                    None
                }
                None => None,
            };
            args.picture.write(
                &rappel_render::plan::picture_over(
                    &plan,
                    &s,
                    window.as_ref(),
                    ground.as_ref().map(|(shade, frame)| (shade, frame)),
                ),
                &title,
            )?;
            plan.report
        };
        if let Some((out, format)) = export {
            let geo = s.georeference.as_ref();
            let bytes = export_plan(&report, geo, format)
                .map_err(|e| CliError(format!("--export {}: {e}", out.display())))?;
            crate::gis_out::write_export(out, &bytes, geo, format, "the plan")?;
        }
        if args.json {
            crate::output::print_report(&report)?;
        } else if !streamed {
            print_text(&args.file.display().to_string(), &report);
        }
        PlanSummary::from(&report)
    };
    // With PTFOs (a `friction` section) the frictional planner's choice is the answer
    // (docs/friction.md); otherwise the Chapter-2 planner's.
    let feasible = match &summary.outcome.friction {
        Some(f) => f.chosen.is_some(),
        None => summary.outcome.chosen.is_some(),
    };
    let answer = if feasible { Answer::Yes } else { Answer::No };
    crate::stop::say(summary.outcome.stop_reason);
    if args.jsonl {
        let line = PlanStreamLine::Summary(Box::new(summary));
        crate::output::outln!("{}", line.to_line());
    } else if !args.json {
        if streamed {
            let file = args.file.display().to_string();
            print_head(
                &file,
                &summary.setting,
                summary.class_count,
                &summary.outcome,
            );
            print_verdict(&summary.setting, &summary.outcome);
        }
        if let Some(f) = &summary.outcome.friction {
            crate::friction_out::print_friction(f);
        }
        for (_, out) in args.picture.outputs() {
            crate::output::outln!("picture      {}", out.display());
        }
    }
    Ok(answer)
}

fn degrees(v: Option<f64>) -> String {
    v.map_or_else(|| "free".to_string(), |d| format!("{d:.2}°"))
}

/// The whole text report: summary head, every class, verdict.
fn print_text(file: &str, r: &PlanReport) {
    print_head(file, &r.setting, r.classes.len(), &r.outcome);
    for c in &r.classes {
        print_class(c);
    }
    print_verdict(&r.setting, &r.outcome);
}

/// The scenario, model, planes, warnings and class count.
fn print_head(file: &str, r: &PlanSetting, class_count: usize, o: &PlanOutcome) {
    crate::output::outln!("scenario     {file}");
    crate::output::outln!("model        {}", r.traversability);
    if r.planes.is_empty() {
        crate::output::outln!("planes       none (flat, tether-free ground)");
    }
    for p in &r.planes {
        crate::output::outln!(
            "plane {}      y {:.1}..{:.1}  slope {:.1}°  mu {:.2}  {}",
            p.index,
            p.y_bottom_m,
            p.y_top_m,
            p.slope_deg,
            p.friction,
            if p.tether_demand {
                format!("tether-demand, cone {}", degrees(p.max_tether_angle_deg))
            } else {
                "tether-free".to_string()
            }
        );
    }
    for w in &o.warnings {
        crate::output::outln!("warning      {w}");
    }
    let bound = match o.stats.bound_expansions {
        0 => String::new(),
        n => format!(", and {n} for the distance bounds"),
    };
    crate::output::outln!(
        "classes      {} ({}; {} of {} expansions{bound})",
        class_count,
        o.termination.describe(),
        o.stats.expansions,
        o.stats.expansion_limit
    );
}

/// One class's block, formatted whole and written at once (a class around a long obstacle has
/// thousands of anchor lines: one write, not one per line).
fn print_class(c: &ClassReport) {
    use std::fmt::Write as _;
    let mut block = format!(
        "class {:<3}    length {:.3} m, {} anchors{}: {}",
        c.rank,
        c.length_m,
        c.anchors.len(),
        if c.simple { "" } else { ", not simple" },
        c.verdict
    );
    // Writing to a String cannot fail.
    for a in &c.anchors {
        let on = a
            .obstacle
            .map_or_else(|| "boundary".to_string(), |o| format!("obstacle {o}"));
        let _ = write!(
            block,
            "\n  a{:<3} ({:.3}, {:.3}) {on}, psi {:.2}°, theta_max {} (previous {}), {}",
            a.index,
            a.point.x,
            a.point.y,
            a.psi_deg,
            degrees(a.theta_max_deg),
            degrees(a.previous_theta_max_deg),
            a.passability
        );
    }
    if !c.waypoints.is_empty() {
        block.push_str("\n  waypoints ");
        for w in &c.waypoints {
            let _ = write!(block, " ({:.3}, {:.3})", w.x, w.y);
        }
    }
    if let Some(f) = &c.pair_failure {
        let _ = write!(block, "\n  no pair    {f}");
    }
    crate::output::outln!("{block}");
}

/// The verdict and the chosen pair.
fn print_verdict(r: &PlanSetting, o: &PlanOutcome) {
    crate::output::outln!("verdict      {}", o.verdict);
    if let Some(p) = &o.chosen {
        let fmt = |pts: &[rappel::nalgebra::Point2<f64>]| {
            pts.iter()
                .map(|q| format!("({:.3}, {:.3})", q.x, q.y))
                .collect::<Vec<_>>()
                .join(" ")
        };
        crate::output::outln!(
            "ascent       {:.3} m: {}",
            p.ascent_length_m,
            fmt(&p.ascent)
        );
        crate::output::outln!(
            "descent      {:.3} m{}: {}",
            p.descent_length_m,
            if p.descent_is_reversed_ascent {
                " (the ascent reversed)"
            } else {
                ""
            },
            fmt(&p.descent)
        );
        if let Some(d) = p.min_anchor_distance_m {
            crate::output::outln!(
                "clearance    {d:.3} m from the nearest anchor (asked {:.3} m)",
                r.clearance_m
            );
        }
    }
}
