//! Stability maps over a scenario's terrain planes (Kumar Fig. 5; `rappel stability`): the robot
//! is placed on a square grid over each plane's band of the map, facing away from its tether
//! anchor, and every free-space pose is assessed by the wheel/tether stability QP (Paton eqs. 1-9)
//! or, when a tether tension limit is given, by the tension-limited LP (Kumar eqs. 1-3).
//!
//! The tether at each pose is taut along the shortest path from the scenario's start (where it is
//! anchored) to the robot: it pulls the robot towards its
//! **last anchor** — the start itself in open ground, or the last obstacle vertex it wraps — parallel
//! to the plane at the height where it leaves the robot (on a convex series of planes the taut
//! tether lies on the ground, so in the robot's plane it pulls along the unfolded direction to
//! that anchor). Each pose's last anchor is reported. Poses inside obstacles are skipped. Every
//! free pose's last anchor and tether length come from one shortest path map from the start
//! ([`rappel_planners::shortest_path_map`]: the funnel expansion of the shortest path tree over
//! the BTM, computed once), looked up for all poses in parallel (rayon) before the assessment
//! ([`rappel_planners::tether_anchors`]: the plane bands, the free poses and their tethers). At the
//! start itself no tether pulls. The tension limit, when given, applies at the robot: capstan
//! friction at wrapped anchors (Kumar eq. 2) would raise it, and is not modelled here.
//!
//! A pose whose taut tether is longer than the robot's `tether_length_m` is beyond the tether's
//! reach: it is reported unstable with that reason. A pose on the edge between two planes is
//! assessed once, on the upper plane. A point robot has no contacts: a four-wheel rover of the
//! same mass stands in for it, and the report says so. The grid holds at most
//! [`MAX_SCENARIO_POSES`] poses.

use crate::progress::{Progress, Quiet};
use crate::scenario::ValidScenario;
use nalgebra::Point2;
use rappel_geometry::btm::Btm;
use rappel_mechanics::stability_map::{
    GridSpec, Heading, PoseOutcome, grid_positions_within, stability_map_until,
};
use rappel_mechanics::stability_qp::StabilityQp;
use rappel_mechanics::tension_lp::TensionLimitedLp;
use rappel_mechanics::traversability::{StabilityCriterion, StabilitySettings};
use rappel_planners::shortest_path_map::ShortestPathMap;
use rappel_planners::spt::SearchError;
use rappel_planners::stop::{StopCondition, StopReason};
use rappel_planners::tether_anchors::{TetherTable, free_positions, is_strictly_free, plane_bands};
use serde::{Deserialize, Serialize};

/// The most poses one stability map may assess. Measured on the 1,000-obstacle crater strip at
/// 1 m (149,515 free poses, release build): about 85 us of CPU per pose in all (the QP solve
/// dominates; the shortest path map is built once and a lookup costs microseconds) and about
/// 1 kB of peak memory per pose (146 MB resident for the run, the report's dots included). So
/// 500,000 poses cost about 40 s of CPU (20 s on 2 cores) and 0.5 GB; a 0.05 m grid over a
/// small map (a million poses and more) is still refused.
pub const MAX_SCENARIO_POSES: usize = 500_000;

/// Options of a stability map.
#[derive(Debug, Clone, PartialEq)]
pub struct StabilityOptions {
    /// Grid step, m.
    pub grid_step: f64,
    /// Largest tether tension, N: switches to Kumar's tension-limited LP. `None`: Paton's QP with
    /// an unlimited tether.
    pub tension_limit: Option<f64>,
    /// When to stop ([`rappel_planners::stop`]): its time limit (from the call's start) and
    /// cancel flags bound the shortest path map and the assessment (read before each pose);
    /// its expansion budget bounds the shortest path map (the automatic one: its default). A
    /// stopped map is partial, not an error: [`StabilityReport::stopped_by`].
    pub stop: StopCondition,
}

impl Default for StabilityOptions {
    fn default() -> Self {
        StabilityOptions {
            grid_step: 1.0,
            tension_limit: None,
            stop: StopCondition::none(),
        }
    }
}

/// One pose of the map.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct StabilityDot {
    /// Plane index (top first).
    pub plane: usize,
    /// Position in the unfolded map frame, `[x, y]`.
    #[schemars(with = "[f64; 2]")]
    pub point: Point2<f64>,
    /// Heading, degrees counter-clockwise from up-slope.
    pub heading_deg: f64,
    /// Stable or not.
    pub stable: bool,
    /// Stability margin (larger is safer; QP: eq. 9 normalised, LP: tension headroom), when stable.
    pub margin: Option<f64>,
    /// Tether tension the solution uses, N.
    pub tether_tension_n: Option<f64>,
    /// Why the pose could not be assessed, if it could not.
    pub failure: Option<String>,
    /// The tether's last anchor (the start, or the last obstacle vertex the taut tether wraps).
    #[schemars(with = "Option<[f64; 2]>")]
    pub last_anchor: Option<Point2<f64>>,
    /// The taut tether's length from the start to the pose, m (`None`: no path reaches it).
    pub tether_length_m: Option<f64>,
    /// `true` when the taut tether is longer than the robot's tether: the pose cannot be reached
    /// (reported unstable).
    pub beyond_tether: bool,
}

/// The stability criterion a map was judged by, as a report names it.
///
/// ```
/// use rappel::stability::CriterionName;
/// assert_eq!(CriterionName::KumarLp.to_string(), "kumar-lp");
/// assert_eq!(serde_json::to_string(&CriterionName::PatonQp).unwrap(), "\"paton-qp\"");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum CriterionName {
    /// Paton's wheel/tether QP (no tension limit given).
    PatonQp,
    /// Kumar's tension-limited LP (a tension limit given).
    KumarLp,
}

impl std::fmt::Display for CriterionName {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            CriterionName::PatonQp => "paton-qp",
            CriterionName::KumarLp => "kumar-lp",
        })
    }
}

/// A stability map.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct StabilityReport {
    /// The criterion used: `"paton-qp"` or `"kumar-lp"`.
    pub criterion: CriterionName,
    /// The robot model's name.
    pub robot: String,
    /// What the judged robot stands in for, when it is not the scenario's own (a point robot has
    /// no contacts: a four-wheel rover of the same mass is judged instead).
    pub stand_in_for: Option<String>,
    /// The robot's tether length, m (`None`: unlimited).
    pub tether_length_m: Option<f64>,
    /// Grid step, m.
    pub grid_step_m: f64,
    /// Tension limit, N, if any.
    pub tension_limit_n: Option<f64>,
    /// Stable poses.
    pub stable: usize,
    /// Poses assessed (in free space).
    pub assessed: usize,
    /// Every assessed pose.
    pub dots: Vec<StabilityDot>,
    /// The condition that stopped the map early (a time limit or a cancel request,
    /// [`StabilityOptions::stop`]): the map is then partial, its dots the poses assessed before
    /// (none when the shortest path map from the start was stopped). `null` for a whole map.
    #[serde(default)]
    pub stopped_by: Option<StopReason>,
}

crate::report::report!(StabilityReport, "stability");

/// Why a stability map could not be made.
#[derive(Debug, thiserror::Error)]
pub enum StabilityError {
    /// The scenario has no terrain planes.
    #[error(
        "the scenario has no terrain planes: add terrain.planes (slope and friction per plane)"
    )]
    NoPlanes,
    /// A setting is out of range.
    #[error("{0}")]
    Setting(String),
    /// The mechanics refused the input.
    #[error(transparent)]
    Grid(#[from] rappel_mechanics::stability_map::MapError),
}

/// The stability map of `scenario` (see the module docs). It takes the [`ValidScenario`] proof,
/// so the map is validated once by the caller and its BTM built without validating it again.
///
/// ```
/// use rappel::scenario::Scenario;
/// use rappel::stability::{stability_over_scenario, StabilityOptions};
/// let s = Scenario::from_ron_str(r#"(
///     map: (boundary: [(0.0, 0.0), (4.0, 0.0), (4.0, 20.0), (0.0, 20.0)]),
///     start: (2.0, 19.5), goal: (2.0, 0.5),
///     terrain: (planes: [(y_top: 20.0, y_bottom: 0.0, slope_deg: 30.0, friction: 0.6)]))"#).unwrap();
/// let valid = s.validate().unwrap();
/// let options = StabilityOptions { grid_step: 2.0, ..Default::default() };
/// let r = stability_over_scenario(valid, &options).unwrap();
/// assert!(r.assessed > 0 && r.stable > 0);
/// ```
pub fn stability_over_scenario(
    valid: ValidScenario<'_>,
    options: &StabilityOptions,
) -> Result<StabilityReport, StabilityError> {
    stability_observed(valid, options, &Quiet)
}

/// [`stability_over_scenario`], telling `progress` of the tethers it looks up
/// ([`crate::progress`]).
pub fn stability_observed(
    valid: ValidScenario<'_>,
    options: &StabilityOptions,
    progress: &dyn Progress,
) -> Result<StabilityReport, StabilityError> {
    let scenario = valid.scenario();
    let stop = options.stop.started();
    if scenario.terrain.planes.is_empty() {
        return Err(StabilityError::NoPlanes);
    }
    if let Some(t) = options.tension_limit
        && !(t.is_finite() && t > 0.0)
    {
        return Err(StabilityError::Setting(format!(
            "tension limit {t} N: must be a positive number"
        )));
    }
    // A point robot has no contacts: its stability is judged as a four-wheel rover's, and the
    // report says so.
    let robot = crate::robot::contact_model(&scenario.robot).map_err(StabilityError::Setting)?;
    let stand_in_for = (scenario.robot.model == crate::scenario::RobotModel::Point)
        .then(|| "the scenario's point robot (it has no wheel contacts to judge)".to_string());
    let (criterion, name): (Box<dyn StabilityCriterion>, CriterionName) =
        match options.tension_limit {
            Some(_) => (
                Box::new(TensionLimitedLp::default()),
                CriterionName::KumarLp,
            ),
            None => (
                Box::new(StabilityQp::new(StabilitySettings::default())),
                CriterionName::PatonQp,
            ),
        };
    let planes = plane_bands(&scenario.terrain.planes, &scenario.map.aabb())
        .map_err(|e| StabilityError::Setting(e.to_string()))?;
    let exit_height = robot
        .configuration(None)
        .map_err(|e| StabilityError::Setting(e.to_string()))?
        .tether_exit
        .z;
    let btm = Btm::build(valid.map()).map_err(|e| StabilityError::Setting(e.to_string()))?;
    let grid = GridSpec::new(options.grid_step, Heading::AwayFromAnchor)?;
    // The count is checked against the scenario's limit before any position is stored.
    let positions = grid_positions_within(&planes, &grid, MAX_SCENARIO_POSES)?;
    // Free space strictly (not on a ring), located in the BTM; the tether of each free pose is
    // looked up once (poses inside obstacles are not).
    let free = |p: &Point2<f64>| is_strictly_free(&btm, p);
    let free_positions = free_positions(&btm, &positions);
    // One shortest path map from the start answers every pose's tether.
    let stopped = std::sync::OnceLock::new();
    let spm = match ShortestPathMap::build_until(&btm, scenario.start, &stop) {
        Err(SearchError::Stopped { reason, .. }) => {
            let _ = stopped.set(reason);
            None
        }
        r => Some(r),
    };
    let spm = spm.transpose().map_err(|e| {
        StabilityError::Setting(match e {
            SearchError::BudgetExhausted { expansions } => format!(
                "the shortest path map from the start needs more than {expansions} funnel expansions: the map is too large for a stability run"
            ),
            e => format!("the shortest path map from the start: {e}"),
        })
    })?;
    let halt = || {
        stopped.get().is_some()
            || stop.poll().is_some_and(|r| {
                let _ = stopped.set(r);
                true
            })
    };
    let (anchors, verdicts) = match &spm {
        Some(spm) => {
            progress.begin("tethers", free_positions.len() as u64);
            let inc = |n| progress.advance(n);
            let anchors = TetherTable::new(
                spm,
                &free_positions,
                exit_height,
                options.tension_limit,
                &inc,
            );
            progress.end();
            let verdicts = stability_map_until(
                robot.as_ref(),
                criterion.as_ref(),
                &planes,
                &anchors,
                &grid,
                &halt,
            )?;
            (Some(anchors), verdicts)
        }
        None => (None, Vec::new()),
    };
    // A pose on the edge between two planes lies on the grid of both: keep the first (upper).
    let mut seen = std::collections::HashSet::new();
    let dots: Vec<StabilityDot> = verdicts
        .into_iter()
        .filter(|v| free(&v.pose.position))
        .filter(|v| seen.insert((v.pose.position.x.to_bits(), v.pose.position.y.to_bits())))
        .map(|v| {
            let looked_up = anchors.as_ref().map_or(Ok(None), |a| a.taut(&v.pose.position));
            let (taut, search_failure) = match looked_up {
                Ok(t) => (t, None),
                Err(e) => (None, Some(format!("tether not traced: {e}"))),
            };
            let tether_length = taut.map(|(_, l)| l);
            let beyond_tether = matches!(
                (tether_length, scenario.robot.tether_length_m),
                (Some(need), Some(have)) if need > have
            );
            let (stable, margin, tether_tension, failure) = match v.outcome {
                _ if search_failure.is_some() => (false, None, None, search_failure),
                _ if beyond_tether => (
                    false,
                    None,
                    None,
                    Some(format!(
                        "beyond the tether's reach: the taut tether is {:.2} m, the robot's {:.2} m",
                        tether_length.unwrap_or_default(),
                        scenario.robot.tether_length_m.unwrap_or_default()
                    )),
                ),
                PoseOutcome::Stable {
                    margin,
                    tether_tension,
                } => (true, Some(margin), tether_tension, None),
                PoseOutcome::Unstable => (false, None, None, None),
                PoseOutcome::Failed { reason } => (false, None, None, Some(reason)),
            };
            StabilityDot {
                plane: v.plane,
                point: v.pose.position,
                heading_deg: crate::report::deg(v.pose.heading),
                stable,
                margin,
                tether_tension_n: tether_tension,
                failure,
                last_anchor: taut.map(|(a, _)| a),
                tether_length_m: tether_length,
                beyond_tether,
            }
        })
        .collect();
    Ok(StabilityReport {
        criterion: name,
        robot: robot.name().to_string(),
        stand_in_for,
        tether_length_m: scenario.robot.tether_length_m,
        grid_step_m: options.grid_step,
        tension_limit_n: options.tension_limit,
        stable: dots.iter().filter(|d| d.stable).count(),
        assessed: dots.len(),
        dots,
        stopped_by: stopped.get().copied(),
    })
}
