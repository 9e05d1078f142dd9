//! A simulated descent (online paper §IV as an experiment): the robot plans on a prior map,
//! descends by that plan, and every difference between the prior and the true map that comes
//! within sensor range becomes a map change for the session. The run ends at the goal, with a
//! proof that no class within the termination rule is feasible, or at the step budget.
//!
//! # Differences
//! Obstacles equal in both maps (same vertices) are no difference. A prior obstacle without an
//! equal true one is **shifted** when a true obstacle without an equal prior one has its centre
//! within the smaller of their two sizes (bounding-box diagonals) of the prior's centre (the
//! nearest such), else a **phantom**; the remaining true obstacles are **new**. A long wall is
//! thus never the "shift" of a distant rock. A changed boundary is one difference located at the
//! vertices the two boundaries do not share.
//!
//! # Sensing and its order
//! A difference is sensed when the robot comes within the sensor range of either of its
//! outlines. The sensed set is then closed under what its changes need (the sensor sees the area
//! of what it reports): a true outline to be added senses every prior difference whose outline's
//! bounding box meets it, and the boundary when the outline is not inside the prior boundary; a
//! sensed boundary senses every prior difference whose outline is not inside the true boundary;
//! a shifted obstacle pulled in brings its own true outline, so the closure runs to a fixed point
//! (at most one round per difference). The changes are then applied in phases: every removal
//! (phantoms, the old outlines of shifted obstacles), the boundary, every addition (new
//! obstacles, the new outlines). After a step, no obstacle of the map overlaps or touches a true
//! outline to be added later except prior differences not yet sensed, which the closure removes
//! first; so every order in which a truth reveals itself applies (staggered walls whose shifts
//! interleave included).
//!
//! # Safety of the motion model
//! The robot moves at most `step` per iteration and `step < sensor_range` is required, so every
//! true obstacle a move could touch was within range before the move and is already in the map.
//! Each loop is bounded: the run by `max_steps`, sensing by the number of differences.
//! A time limit or cancel flag of the session's search options ([`crate::stop::StopCondition`])
//! bounds the whole run: its clock starts with the run, every search shares it, and it is also
//! read between steps ([`SimulationReport::stopped_by`]).
//!
//! # PTFOs ([`simulate_frictional`])
//! The prior and the truth label the same obstacles as PTFOs; a PTFO whose true friction
//! differs is a difference located at its outline, sensed like the others, and then reclassified
//! by the session (its anchors decided again; slips and rejections are map changes of the
//! session, `session::friction`).

use super::change::MapChange;
use super::classify::polygon_meets_segment;
use super::session::{ChangeOutcome, ClearanceShortfall, OnlineSession, Status};
use super::{OnlineError, OnlineOptions};
use crate::feasibility::distance_to_segment;
use crate::frictional::FrictionModel;
use crate::spt::Termination;
use crate::terrain::PlaneSeries;
use nalgebra::Point2;
use rappel_geometry::btm::Btm;
use rappel_geometry::dcel::ObstacleId;
use rappel_geometry::map::Map;
use rappel_geometry::polygon::{PointInPolygon, Polygon};
use rappel_mechanics::friction::FrictionInterval;
use serde::{Deserialize, Serialize};

/// Default sensor range, m.
pub const DEFAULT_SENSOR_RANGE: f64 = 5.0;
/// Default step, m.
pub const DEFAULT_STEP: f64 = 1.0;
/// Default step budget.
pub const DEFAULT_MAX_STEPS: usize = 10_000;
/// The largest step budget a run accepts (a bound on time and on the trace's memory: each step
/// costs at least one point of the walked path, 16 bytes, and a sensing pass).
pub const MAX_STEPS: usize = 1_000_000;
/// The smallest step, as a fraction of the prior map's diagonal: crossing the map takes at most
/// `1 / MIN_STEP_FRACTION` = 100,000 steps, so a run within [`MAX_STEPS`] can cross it ten times.
pub const MIN_STEP_FRACTION: f64 = 1e-5;

/// Settings of a simulated descent.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SimulationOptions {
    /// Differences within this distance of the robot are sensed, m (> `step`).
    pub sensor_range: f64,
    /// Distance moved per iteration, m (> 0).
    pub step: f64,
    /// The step budget.
    pub max_steps: usize,
    /// The session's options.
    pub session: OnlineOptions,
}

impl Default for SimulationOptions {
    fn default() -> Self {
        SimulationOptions {
            sensor_range: DEFAULT_SENSOR_RANGE,
            step: DEFAULT_STEP,
            max_steps: DEFAULT_MAX_STEPS,
            session: OnlineOptions::default(),
        }
    }
}

impl SimulationOptions {
    /// Checks `0 < step < sensor_range`, both finite, and a budget of at least one step.
    pub fn validate(&self) -> Result<(), OnlineError> {
        if !(self.step.is_finite() && self.step > 0.0) {
            return Err(OnlineError::Option(format!(
                "step {} must be > 0",
                self.step
            )));
        }
        if !(self.sensor_range.is_finite() && self.sensor_range > self.step) {
            return Err(OnlineError::Option(format!(
                "sensor range {} must be finite and larger than the step {} (module docs)",
                self.sensor_range, self.step
            )));
        }
        if !(1..=MAX_STEPS).contains(&self.max_steps) {
            return Err(OnlineError::Option(format!(
                "max_steps {} must be from 1 to {MAX_STEPS}",
                self.max_steps
            )));
        }
        self.session.validate()
    }

    /// [`SimulationOptions::validate`], and a step of at least [`MIN_STEP_FRACTION`] of the
    /// map's diagonal `diagonal` (m).
    pub fn validate_for(&self, diagonal: f64) -> Result<(), OnlineError> {
        self.validate()?;
        let floor = diagonal * MIN_STEP_FRACTION;
        if self.step < floor {
            return Err(OnlineError::Option(format!(
                "step {} m is below the floor of {} m ({MIN_STEP_FRACTION:e} of the map's {diagonal:.1} m diagonal)",
                rappel_geometry::compact::Compact(self.step),
                rappel_geometry::compact::Rounded(floor, 6)
            )));
        }
        Ok(())
    }
}

/// How a run ended.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case", tag = "ending")]
pub enum Ending {
    /// The robot reached the goal.
    Goal,
    /// No class within the termination rule is feasible.
    NoFeasibleClass {
        /// Why the last search stopped.
        #[serde(with = "crate::search_report::termination_serde")]
        #[schemars(with = "crate::search_report::TerminationName")]
        termination: Termination,
    },
    /// A true obstacle covers the goal.
    GoalCovered,
    /// The step budget ran out.
    StepBudget,
}

impl Ending {
    /// `true` for the goal.
    pub fn reached(&self) -> bool {
        *self == Ending::Goal
    }
}

/// One difference between the prior and the true map.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum Difference {
    /// A true obstacle missing from the prior.
    New {
        /// Index among the true obstacles.
        truth: usize,
    },
    /// A prior obstacle that does not exist.
    Phantom {
        /// Index among the prior obstacles.
        prior: usize,
    },
    /// A prior obstacle that is elsewhere or shaped differently.
    Shifted {
        /// Index among the prior obstacles.
        prior: usize,
        /// Index among the true obstacles.
        truth: usize,
    },
    /// The boundary is different.
    Boundary,
    /// Not a difference: Alg. 8 on the plan made on the prior map, when it has PTFOs (its slips and
    /// rejections, before the descent starts).
    PriorPtfoCheck,
    /// A PTFO on an obstacle equal in both maps has another tether-terrain friction in truth:
    /// once sensed, the session reclassifies it ([`OnlineSession::reclassify_ptfo`]).
    Friction {
        /// Index among the prior obstacles.
        prior: usize,
    },
}

/// The PTFOs of a frictional run: the prior's model and the truth's. They must label the same
/// obstacles (equal outlines in both maps); only the frictions may differ.
#[derive(Debug, Clone, PartialEq)]
pub struct FrictionPair {
    /// The model the robot plans with.
    pub prior: FrictionModel,
    /// The model of the true terrain (indices among the true obstacles).
    pub truth: FrictionModel,
}

/// The friction differences of `pair` between the maps (module docs), with the true friction.
fn friction_differences(
    prior: &Map,
    truth: &Map,
    pair: &FrictionPair,
) -> Result<Vec<(usize, FrictionInterval)>, OnlineError> {
    let equal_in_truth = |i: usize| {
        let want = prior.obstacles[i].to_counter_clockwise();
        truth
            .obstacles
            .iter()
            .position(|o| o.to_counter_clockwise() == want)
    };
    let mut out = Vec::new();
    for p in &pair.prior.ptfos {
        let t = equal_in_truth(p.obstacle).and_then(|j| pair.truth.ptfo_of(j));
        match t {
            Some(t) if t.friction != p.friction => out.push((p.obstacle, t.friction)),
            Some(_) => {}
            None => {
                return Err(OnlineError::Option(format!(
                    "prior PTFO on obstacle {} has no PTFO on an equal obstacle in truth: the two \
                     scenarios must label the same PTFOs (only frictions may differ)",
                    p.obstacle
                )));
            }
        }
    }
    if pair.truth.ptfos.len() != pair.prior.ptfos.len() {
        return Err(OnlineError::Option(format!(
            "truth has {} PTFOs, the prior {}: the two scenarios must label the same PTFOs",
            pair.truth.ptfos.len(),
            pair.prior.ptfos.len()
        )));
    }
    Ok(out)
}

/// One row of the timeline.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct TimelineEvent {
    /// The iteration.
    pub step: usize,
    /// Where the robot was.
    #[schemars(with = "[f64; 2]")]
    pub robot: Point2<f64>,
    /// Distance travelled so far, m.
    pub travelled_m: f64,
    /// Distance backtracked so far, m.
    pub backtracked_m: f64,
    /// The difference sensed.
    pub difference: Difference,
    /// What the session made of it.
    pub outcome: ChangeOutcome,
}

/// The result of a run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct SimulationReport {
    /// How it ended.
    pub ending: Ending,
    /// The time limit or cancel flag of the search options' [`crate::stop::StopCondition`] that
    /// ended the run, counted over the whole run and read between steps and inside every search
    /// (`None`: it ended otherwise). Between steps the run then ends as
    /// [`Ending::StepBudget`]; inside a search as [`Ending::NoFeasibleClass`] with a
    /// [`Termination::TimeLimit`] or [`Termination::Cancelled`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stopped_by: Option<crate::stop::StopReason>,
    /// Iterations used.
    pub steps: usize,
    /// Every change handled, in order.
    pub timeline: Vec<TimelineEvent>,
    /// Differences never sensed.
    pub unsensed: usize,
    /// SHP length of the class planned on the prior map, m.
    pub initial_class_length_m: Option<f64>,
    /// Why the plan made on the prior map does not keep the clearance (`None`: it is Alg. 6's
    /// pair, the one `rappel plan` chooses on the prior).
    pub initial_clearance_shortfall: Option<ClearanceShortfall>,
    /// SHP length of the final class, m.
    pub final_class_length_m: Option<f64>,
    /// Length of the taut tether at the end (SHP of the laid tether), m.
    pub tether_length_m: f64,
    /// Distance travelled, m.
    pub travelled_m: f64,
    /// Distance backtracked, m.
    pub backtracked_m: f64,
    /// Whether the descent travelled and the selected ascent are homotopic at the end.
    pub homotopic: bool,
    /// Changes kept for later (outside the sleeve when they came).
    pub deferred: usize,
    /// Classes rejected and still in the constraints.
    pub rejected: usize,
    /// The robot's path.
    #[schemars(with = "Vec<[f64; 2]>")]
    pub travelled: Vec<Point2<f64>>,
    /// The final selected ascent, goal to start (empty without a class).
    #[schemars(with = "Vec<[f64; 2]>")]
    pub ascent: Vec<Point2<f64>>,
}

/// A failure during a run: where and which difference.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{}: {source}", match difference { Some(d) => format!("step {step}, {d:?}"), None => "set-up".to_string() })]
pub struct SimulationError {
    /// The iteration.
    pub step: usize,
    /// The difference being applied (`None` while setting up).
    pub difference: Option<Difference>,
    /// What went wrong.
    #[source]
    pub source: Box<OnlineError>,
}

/// The obstacle of `btm` with exactly the vertices of `polygon` (any order and orientation).
fn find_obstacle(btm: &Btm, polygon: &Polygon) -> Option<ObstacleId> {
    let key = |p: &Polygon| {
        let mut v: Vec<(u64, u64)> = p
            .vertices
            .iter()
            .map(|q| (q.x.to_bits(), q.y.to_bits()))
            .collect();
        v.sort_unstable();
        v
    };
    let want = key(polygon);
    btm.obstacle_ids()
        .find(|&o| btm.obstacle_polygon(o).is_some_and(|p| key(&p) == want))
}

fn distance_to_polygon(p: &Point2<f64>, polygon: &Polygon) -> f64 {
    if polygon.locate(p) != PointInPolygon::Outside {
        return 0.0;
    }
    polygon
        .edges()
        .map(|(a, b)| distance_to_segment(p, a, b))
        .fold(f64::INFINITY, f64::min)
}

/// `true` when the closed `outline` lies strictly inside `boundary` (exact).
fn inside(boundary: &Polygon, outline: &Polygon) -> bool {
    outline
        .vertices
        .iter()
        .all(|p| boundary.locate(p) == PointInPolygon::Inside)
        && !boundary
            .edges()
            .any(|(a, b)| polygon_meets_segment(outline, a, b))
}

/// Closes the differences `sensed` in one step under what their changes need (module docs,
/// "Sensing and its order"), moving them from `pending`; returns what stays pending.
fn close_sensed(
    prior: &Map,
    truth: &Map,
    sensed: &mut Vec<Difference>,
    mut pending: Vec<Difference>,
) -> Vec<Difference> {
    // How far `sensed` has been scanned for the outlines it adds.
    let mut scanned = 0;
    let mut additions: Vec<&Polygon> = Vec::new();
    let mut boundary = false;
    while scanned < sensed.len() {
        for d in &sensed[scanned..] {
            match d {
                Difference::New { truth: j } | Difference::Shifted { truth: j, .. } => {
                    additions.push(&truth.obstacles[*j]);
                }
                Difference::Boundary => boundary = true,
                _ => {}
            }
        }
        scanned = sensed.len();
        let boxes: Vec<_> = additions.iter().map(|p| p.aabb()).collect();
        let mut rest = Vec::with_capacity(pending.len());
        for d in pending {
            let needed = match &d {
                Difference::Phantom { prior: i } | Difference::Shifted { prior: i, .. } => {
                    let outline = &prior.obstacles[*i];
                    let b = outline.aabb();
                    boxes.iter().any(|x| x.intersects(&b))
                        || (boundary && !inside(&truth.boundary, outline))
                }
                Difference::Boundary => additions.iter().any(|p| !inside(&prior.boundary, p)),
                _ => false,
            };
            if needed {
                sensed.push(d);
            } else {
                rest.push(d);
            }
        }
        pending = rest;
    }
    pending
}

/// The differences between two maps (module docs).
pub fn differences(prior: &Map, truth: &Map) -> Vec<Difference> {
    let same = |a: &Polygon, b: &Polygon| {
        let mut x = a.to_counter_clockwise().vertices;
        let mut y = b.to_counter_clockwise().vertices;
        x.sort_by(|p, q| p.x.total_cmp(&q.x).then(p.y.total_cmp(&q.y)));
        y.sort_by(|p, q| p.x.total_cmp(&q.x).then(p.y.total_cmp(&q.y)));
        x == y
    };
    let mut truth_used = vec![false; truth.obstacles.len()];
    let mut prior_left = Vec::new();
    for (i, p) in prior.obstacles.iter().enumerate() {
        match (0..truth.obstacles.len()).find(|&j| !truth_used[j] && same(p, &truth.obstacles[j])) {
            Some(j) => truth_used[j] = true,
            None => prior_left.push(i),
        }
    }
    let centre = |p: &Polygon| {
        let b = p.aabb();
        Point2::new((b.min.x + b.max.x) / 2.0, (b.min.y + b.max.y) / 2.0)
    };
    let size = |p: &Polygon| {
        let (w, h) = p.aabb().size();
        w.hypot(h)
    };
    let mut out = Vec::new();
    for i in prior_left {
        let p = &prior.obstacles[i];
        let near = (0..truth.obstacles.len())
            .filter(|&j| !truth_used[j])
            .map(|j| (j, (centre(p) - centre(&truth.obstacles[j])).norm()))
            .filter(|&(j, d)| d <= size(p).min(size(&truth.obstacles[j])))
            .min_by(|a, b| a.1.total_cmp(&b.1));
        match near {
            Some((j, _)) => {
                truth_used[j] = true;
                out.push(Difference::Shifted { prior: i, truth: j });
            }
            None => out.push(Difference::Phantom { prior: i }),
        }
    }
    out.extend(
        (0..truth.obstacles.len())
            .filter(|&j| !truth_used[j])
            .map(|truth| Difference::New { truth }),
    );
    if prior.boundary.to_counter_clockwise() != truth.boundary.to_counter_clockwise() {
        out.push(Difference::Boundary);
    }
    out
}

/// Simulates a descent planned on `prior` over the true map `truth` (module docs). Both maps
/// must be valid with the start and goal in free space; the terrain is shared.
pub fn simulate(
    prior: &Map,
    truth: &Map,
    start: Point2<f64>,
    goal: Point2<f64>,
    terrain: PlaneSeries,
    options: &SimulationOptions,
) -> Result<(SimulationReport, OnlineSession), SimulationError> {
    simulate_with(prior, truth, start, goal, terrain, options, &mut |_, _| {})
}

/// [`simulate`], calling `observe` after every change with the event and the session as it
/// stands (for pictures of each event).
pub fn simulate_with(
    prior: &Map,
    truth: &Map,
    start: Point2<f64>,
    goal: Point2<f64>,
    terrain: PlaneSeries,
    options: &SimulationOptions,
    observe: &mut dyn FnMut(&TimelineEvent, &OnlineSession),
) -> Result<(SimulationReport, OnlineSession), SimulationError> {
    simulate_frictional(prior, truth, start, goal, terrain, None, options, observe)
}

/// [`simulate_with`] with PTFOs: the session plans with `friction.prior`
/// ([`OnlineSession::set_friction`], its outcomes are the timeline's first events, as
/// [`Difference::PriorPtfoCheck`]), and a PTFO whose true friction differs is
/// reclassified when sensed ([`Difference::Friction`]).
#[allow(clippy::too_many_arguments)]
pub fn simulate_frictional(
    prior: &Map,
    truth: &Map,
    start: Point2<f64>,
    goal: Point2<f64>,
    terrain: PlaneSeries,
    friction: Option<&FrictionPair>,
    options: &SimulationOptions,
    observe: &mut dyn FnMut(&TimelineEvent, &OnlineSession),
) -> Result<(SimulationReport, OnlineSession), SimulationError> {
    let at_start = |source| SimulationError {
        step: 0,
        difference: None,
        source: Box::new(source),
    };
    let b = prior.aabb();
    options
        .validate_for((b.max - b.min).norm())
        .map_err(at_start)?;
    truth
        .validate()
        .map_err(|e| at_start(OnlineError::Map(e)))?;
    // One clock for the whole run: every search of the session shares its deadline.
    let stop = options.session.search.stop().started();
    let mut session_options = options.session.clone();
    session_options.search = session_options
        .search
        .with_stop(stop.clone())
        .map_err(|e| at_start(OnlineError::Search(e)))?;
    let mut session =
        OnlineSession::new(prior, start, goal, terrain, session_options).map_err(at_start)?;
    let mut timeline = Vec::new();
    let mut true_frictions = Vec::new();
    if let Some(pair) = friction {
        true_frictions = friction_differences(prior, truth, pair).map_err(at_start)?;
        for outcome in session.set_friction(pair.prior.clone()).map_err(at_start)? {
            let event = TimelineEvent {
                step: 0,
                robot: start,
                travelled_m: 0.0,
                backtracked_m: 0.0,
                difference: Difference::PriorPtfoCheck,
                outcome,
            };
            observe(&event, &session);
            timeline.push(event);
        }
    }
    let initial_class_length_m = session.class().map(|c| c.shp.taut.length);
    let initial_clearance_shortfall = session.clearance_shortfall();
    let boundary_points: Vec<Point2<f64>> = prior
        .boundary
        .vertices
        .iter()
        .filter(|p| !truth.boundary.vertices.contains(p))
        .chain(
            truth
                .boundary
                .vertices
                .iter()
                .filter(|p| !prior.boundary.vertices.contains(p)),
        )
        .copied()
        .collect();
    let outlines = |d: &Difference| -> Vec<&Polygon> {
        match d {
            Difference::New { truth: j } => vec![&truth.obstacles[*j]],
            Difference::Phantom { prior: i } => vec![&prior.obstacles[*i]],
            Difference::Shifted { prior: i, truth: j } => {
                vec![&prior.obstacles[*i], &truth.obstacles[*j]]
            }
            Difference::Friction { prior: i } => vec![&prior.obstacles[*i]],
            Difference::Boundary | Difference::PriorPtfoCheck => Vec::new(),
        }
    };
    let mut pending = differences(prior, truth);
    pending.extend(
        true_frictions
            .iter()
            .map(|&(prior, _)| Difference::Friction { prior }),
    );
    let mut steps = 0;
    let mut stopped_by = None;
    let ending = loop {
        let robot = session.robot();
        let r = options.sensor_range;
        let near = |d: &Difference| match d {
            Difference::Boundary => boundary_points.iter().any(|p| (p - robot).norm() <= r),
            Difference::PriorPtfoCheck => false,
            _ => outlines(d)
                .iter()
                .any(|p| distance_to_polygon(&robot, p) <= r),
        };
        let mut sensed: Vec<Difference> = Vec::new();
        let mut keep = Vec::new();
        for d in pending.drain(..) {
            if near(&d) {
                sensed.push(d);
            } else {
                keep.push(d);
            }
        }
        pending = close_sensed(prior, truth, &mut sensed, keep);
        // Every removal (phantoms, the old outlines of shifted obstacles) before the boundary,
        // and the boundary before any addition (new obstacles, the new outlines): a shifted
        // obstacle is removed and added again (thesis §3.5.2), and its new outline may need the
        // room another one leaves (module docs).
        let mut changes: Vec<(u8, Difference)> = Vec::new();
        for d in sensed {
            match d {
                Difference::Phantom { .. } => changes.push((0, d)),
                Difference::Shifted { .. } => {
                    changes.push((0, d.clone()));
                    changes.push((2, d));
                }
                Difference::Boundary => changes.push((1, d)),
                Difference::New { .. } | Difference::Friction { .. } => changes.push((2, d)),
                Difference::PriorPtfoCheck => changes.push((3, d)),
            }
        }
        changes.sort_by_key(|(phase, _)| *phase);
        for (phase, d) in changes {
            let fail = |source| SimulationError {
                step: steps,
                difference: Some(d.clone()),
                source: Box::new(source),
            };
            let find = |i: usize| {
                find_obstacle(session.btm(), &prior.obstacles[i]).ok_or_else(|| {
                    fail(OnlineError::Internal(format!(
                        "prior obstacle {i} is no longer in the map"
                    )))
                })
            };
            let change = match (&d, phase) {
                (Difference::Phantom { prior: i }, _)
                | (Difference::Shifted { prior: i, .. }, 0) => Some(MapChange::Remove(find(*i)?)),
                (Difference::New { truth: j }, _) | (Difference::Shifted { truth: j, .. }, _) => {
                    Some(MapChange::Add(truth.obstacles[*j].clone()))
                }
                (Difference::Boundary, _) => Some(MapChange::Boundary(truth.boundary.clone())),
                (Difference::Friction { .. } | Difference::PriorPtfoCheck, _) => None,
            };
            let outcomes = match (change, &d) {
                (Some(change), _) => session.apply(&change).map_err(fail)?,
                (None, Difference::Friction { prior: i }) => {
                    let mu = true_frictions
                        .iter()
                        .find(|(o, _)| o == i)
                        .map(|(_, mu)| *mu)
                        .ok_or_else(|| fail(OnlineError::Internal("lost friction".into())))?;
                    session.reclassify_ptfo(*i, mu).map_err(fail)?
                }
                (None, _) => Vec::new(),
            };
            for outcome in outcomes {
                let event = TimelineEvent {
                    step: steps,
                    robot,
                    travelled_m: session.travelled_length(),
                    backtracked_m: session.backtracked_length(),
                    difference: d.clone(),
                    outcome,
                };
                observe(&event, &session);
                timeline.push(event);
            }
            if session.status() != &Status::Descending {
                break;
            }
        }
        match session.status() {
            Status::AtGoal => break Ending::Goal,
            Status::GoalCovered => break Ending::GoalCovered,
            Status::NoFeasibleClass { termination, .. } => {
                break Ending::NoFeasibleClass {
                    termination: *termination,
                };
            }
            Status::Descending => {}
        }
        if steps == options.max_steps {
            break Ending::StepBudget;
        }
        if let Some(reason) = stop.poll() {
            stopped_by = Some(reason);
            break Ending::StepBudget;
        }
        session.advance(options.step);
        steps += 1;
    };
    if stopped_by.is_none()
        && let Ending::NoFeasibleClass {
            termination: Termination::TimeLimit | Termination::Cancelled,
        } = ending
    {
        // A search of the session was stopped by the run's clock or a cancel.
        stopped_by = stop.poll();
    }
    let tether_length_m = session
        .laid_tether()
        .map(|t| t.taut.length)
        .unwrap_or(f64::NAN);
    let homotopic = ending.reached() && session.ascent_descent_homotopic().unwrap_or(false);
    let report = SimulationReport {
        ending,
        stopped_by,
        steps,
        timeline,
        unsensed: pending.len(),
        initial_class_length_m,
        initial_clearance_shortfall,
        final_class_length_m: session.class().map(|c| c.shp.taut.length),
        tether_length_m,
        travelled_m: session.travelled_length(),
        backtracked_m: session.backtracked_length(),
        homotopic,
        deferred: session.deferred().len(),
        rejected: session.constraints().len(),
        travelled: session.travelled().to_vec(),
        ascent: session
            .class()
            .map(|c| c.ascent.clone())
            .unwrap_or_default(),
    };
    Ok((report, session))
}
