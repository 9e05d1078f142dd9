//! `rappel navigate`: the tethered rover of Paton 2020 §III and §V on a ledge scene, solved by
//! ABIT* ([`rappel_planners::rover::problem::RoverProblem::solve`]) and reported: the path, its
//! headings, the anchors the tether wraps, margins and roll along the re-validated drive, and the
//! planner's counts. One seed per run; [`navigate_seeds`] runs many in parallel.

use std::time::Duration;

use crate::report::deg;
use nalgebra::Point3;
use serde::{Deserialize, Serialize};

pub use rappel_planners::rover::ground::{DistanceReport, DistanceSource};
pub use rappel_planners::rover::problem::{
    RoverProblem, RoverState, SHADOW_RGG_K_FACTOR, SHADOW_SAMPLE_FRACTION,
};
use rappel_planners::sampler::{Stop, Termination};
use rappel_planners::stop::{StopCondition, StopReason};
/// A planning run's outcome.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
pub struct NavigateReport {
    /// The seed.
    pub seed: u64,
    /// Whether a path was found and passed re-validation.
    pub found: bool,
    /// A path the planner reported that failed re-validation (never expected; counted as
    /// unsafe), with the reason.
    pub unsafe_reason: Option<String>,
    /// The states of the path, `[x, y, z]` of the settled origins, start first.
    pub path: Vec<[f64; 3]>,
    /// The headings of the path's states, degrees.
    pub yaw_deg: Vec<f64>,
    /// The anchor history at the goal (re-predicted), root first.
    pub anchors: Vec<[f64; 3]>,
    /// The smallest stability margin along the re-validated path, N.
    pub min_margin_n: Option<f64>,
    /// The largest |roll| along the path, degrees.
    pub max_roll_deg: Option<f64>,
    /// The path's cost (module doc of `rappel::navigate`).
    pub cost: Option<f64>,
    /// Iterations run.
    pub iterations: u64,
    /// Batches of samples.
    pub batches: u64,
    /// States in the graph.
    pub states: usize,
    /// Motions checked.
    pub motions_checked: u64,
    /// Samples drawn from the anchor's shadow (0 with Paton's uniform sampling).
    pub shadow_samples: u64,
    /// Iterations until the first solution.
    pub first_solution_iteration: Option<u64>,
    /// Motions checked until the first solution (OMPL's "collision checked" edges; the
    /// iterations also count edges dropped unchecked).
    #[serde(default)]
    pub first_solution_motions_checked: Option<u64>,
    /// Wall time until the first solution, seconds.
    pub first_solution_s: Option<f64>,
    /// Total wall time, seconds.
    pub elapsed_s: f64,
    /// What ended the search: `iterations` or `time` (the sampler's budgets ran out),
    /// `cost_threshold`, or the stop condition of the call: `time_limit` (its time limit) or
    /// `cancelled` (a cancel request).
    pub stopped_by: StoppedBy,
    /// Which condition stopped the search, typed: the iteration limit, a time limit (the
    /// sampler's or the stop condition's), a cancel request (`null` for the cost threshold).
    #[serde(default)]
    pub stop_reason: Option<StopReason>,
    /// Every settled pose along the re-validated path: origin and margin.
    pub poses: Vec<NavigatePose>,
    /// Where the planner's motion checks read their distances (re-validation reads the exact
    /// mesh whatever this says).
    pub distance_source: DistanceReport,
}

/// One pose along a re-validated path.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
pub struct NavigatePose {
    /// Settled origin, `[x, y, z]` metres.
    pub origin: [f64; 3],
    /// Roll, degrees.
    pub roll_deg: f64,
    /// Best stability margin, N.
    pub margin_n: f64,
}

/// Plans on `problem` with `seed` until `termination` (the sampler's own iteration, time and
/// cost budgets) or `stop` (the stop condition shared by every long call,
/// [`rappel_planners::stop`]: its time limit, counted from this call unless `stop` was
/// [started](StopCondition::started), and cancel flags another thread sets; a fixed expansion
/// budget counts iterations), whichever fires first ([`RoverProblem::solve_until`]); the best
/// path is re-validated ([`RoverProblem::revalidate`]) before it counts as found. A stopped run
/// is a report, not an error: `stopped_by` says `time_limit` or `cancelled` and `found` whether
/// a path was found before.
pub fn navigate(
    problem: &RoverProblem,
    seed: u64,
    termination: Termination,
    stop: &StopCondition,
) -> Result<NavigateReport, String> {
    let began = std::time::Instant::now();
    let status = problem.solve_until(seed, termination, stop)?;
    let first = status.events.first();
    let mut report = NavigateReport {
        seed,
        found: false,
        unsafe_reason: None,
        path: Vec::new(),
        yaw_deg: Vec::new(),
        anchors: Vec::new(),
        min_margin_n: None,
        max_roll_deg: None,
        cost: None,
        iterations: status.iterations,
        batches: status.batches,
        states: status.states,
        motions_checked: status.motions_checked,
        shadow_samples: status.biased_samples,
        first_solution_iteration: first.map(|e| e.iteration),
        first_solution_motions_checked: first.map(|e| e.motions_checked),
        first_solution_s: first.map(|e| e.elapsed.as_secs_f64()),
        elapsed_s: began.elapsed().as_secs_f64(),
        stopped_by: stopped_by(status.stopped_by, status.stop_reason, stop),
        stop_reason: status.stop_reason,
        poses: Vec::new(),
        distance_source: problem.distance_report(),
    };
    let Some(sol) = status.solution else {
        return Ok(report);
    };
    report.cost = Some(sol.cost);
    report.yaw_deg = sol.path.iter().map(|s| deg(s.yaw)).collect();
    match problem.revalidate(&sol.path) {
        Ok(w) => {
            report.found = true;
            let p = |q: &Point3<f64>| [q.x, q.y, q.z];
            report.anchors = w.history.anchors().iter().map(|a| p(&a.point)).collect();
            report.min_margin_n = w.poses.iter().map(|q| q.2).reduce(f64::min);
            report.max_roll_deg = w.poses.iter().map(|q| deg(q.1.abs())).reduce(f64::max);
            report.poses = w
                .poses
                .iter()
                .map(|q| NavigatePose {
                    origin: q.0,
                    roll_deg: deg(q.1),
                    margin_n: q.2,
                })
                .collect();
            report.path = sol
                .path
                .iter()
                .map(|s| {
                    problem
                        .settle(s)
                        .map(|q| p(&q.origin))
                        .unwrap_or([s.x, s.y, f64::NAN])
                })
                .collect();
        }
        Err(why) => report.unsafe_reason = Some(why),
    }
    Ok(report)
}

/// The report's `stopped_by`: a cancel is `cancelled`; a time limit is `time_limit` when it is
/// the stop condition's (the tighter of the two, or equal to the sampler's own) and `time` when
/// it is the sampler's [`Termination::max_time`].
fn stopped_by(
    stop: Option<Stop>,
    reason: Option<StopReason>,
    condition: &StopCondition,
) -> StoppedBy {
    match (reason, stop) {
        (Some(StopReason::Cancelled), _) => StoppedBy::Cancelled,
        (Some(StopReason::TimeLimit { limit }), _) if condition.time_limit() == Some(limit) => {
            StoppedBy::TimeLimit
        }
        (_, Some(Stop::Time)) => StoppedBy::Time,
        (_, Some(Stop::CostThreshold)) => StoppedBy::CostThreshold,
        (_, Some(Stop::Iterations) | None) => StoppedBy::Iterations,
    }
}

/// What ended a navigate search (the report's `stopped_by`, serialised as its snake-case name,
/// which is also its `Display`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum StoppedBy {
    /// The sampler's iteration limit ([`Termination::max_iterations`]).
    Iterations,
    /// The sampler's own wall-time bound ([`Termination::max_time`]).
    Time,
    /// A path at or below the cost threshold was found.
    CostThreshold,
    /// The call's stop condition: its time limit.
    TimeLimit,
    /// The call's stop condition: a cancel request.
    Cancelled,
}

impl StoppedBy {
    /// Whether the call's stop condition (a time limit or a cancel request) ended the search,
    /// rather than the sampler's own rules.
    pub fn by_condition(self) -> bool {
        matches!(self, StoppedBy::TimeLimit | StoppedBy::Cancelled)
    }
}

impl std::fmt::Display for StoppedBy {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            StoppedBy::Iterations => "iterations",
            StoppedBy::Time => "time",
            StoppedBy::CostThreshold => "cost_threshold",
            StoppedBy::TimeLimit => "time_limit",
            StoppedBy::Cancelled => "cancelled",
        })
    }
}

/// Runs [`navigate`] for every seed in `seeds`, in parallel (rayon), all stopped by `stop` (one
/// clock for the whole call); reports in seed order.
pub fn navigate_seeds(
    problem: &RoverProblem,
    seeds: &[u64],
    termination: Termination,
    stop: &StopCondition,
) -> Result<Vec<NavigateReport>, String> {
    use rayon::prelude::*;
    let stop = stop.started();
    seeds
        .par_iter()
        .map(|&s| navigate(problem, s, termination, &stop))
        .collect()
}

/// Iterations Paton ran per planning problem (§VI-A).
pub const PATON_ITERATIONS: u64 = 750;

/// A default wall-time bound for one run, as a safety net beside the iteration limit.
pub const DEFAULT_TIME: Duration = Duration::from_secs(120);

crate::report::report!(NavigateReport, "navigate");
