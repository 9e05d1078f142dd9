//! The online session (thesis §3.5, Alg. 11-13; online paper §III, Alg. 3): the BTM, the chosen
//! class (sleeve, SHP, anchors, ascent/descent pair), the robot's progress along the descent
//! (the tether laid so far is fixed), the H-signature constraints of rejected classes, and the
//! changes outside the current sleeve kept for later (§3.5.3).
//!
//! # One change (Alg. 13 lines 4-24, once per change as §3.5.4 prescribes)
//! 1. Refuse, before anything changes, a change that covers the robot, the start or the laid
//!    tether (a positioned error); one that covers the goal is a clean "no".
//! 2. Retriangulate locally (Lemma 3.5.1) and classify against the current sleeve
//!    ([`crate::online::classify`]).
//! 3. Outside the sleeve: keep it for later, nothing else changes.
//! 4. Otherwise update the sleeve by tracing the **reference path** (the laid tether followed by
//!    the remaining plan) through the new BTM, and its SHP by the funnel.
//! 5. Same SHP: keep the plan, but check that the ascent path is still in free space and
//!    homotopic to the descent (Alg. 13 line 18) and select new paths if not. New SHP: check it
//!    (Alg. 12); feasible, continue from the robot along it; infeasible, add its H-signature to
//!    the constraints and replan. Reference path blocked by the new obstacle: replan.
//! 6. Replanning ([`crate::online::replan`]): the constrained SPT search over the updated BTM;
//!    as in Alg. 6 a feasible candidate with an ascent/descent pair comes first, and among those
//!    the one with the least remaining travel (backtrack plus continuation) is chosen. From the
//!    start (preplanning, Alg. 11) this is exactly Alg. 6's class and pair. The descent past the
//!    junction keeps the clearance from the anchors of its continuation and of the class
//!    ([`crate::path_pair::descent_with_clearance`]); where no pair or no such descent exists the
//!    session says why ([`ClearanceShortfall`], in every outcome) instead of silently following
//!    a taut tether.
//! 7. After every decision, check backtrackability ([`OnlineSession::backtrackable`]): the
//!    class's ascent is feasible (Alg. 12) and the selected ascent is in free space in the class;
//!    [`OnlineSession::laid_tether_climbable`] is the stronger Alg. 5 check from the robot.
//!
//! Beyond the thesis, a removal (the only change that can shorten a class) triggers a search for
//! a shorter class; the outcome reports it, and with [`OnlineOptions::switch_to_shorter`] the
//! session switches when the saving exceeds the cost of backtracking.

mod friction;
mod session_friction;

use super::change::{MapChange, covers, interior_point, outside_boundary};
use super::classify::{
    ChangeCase, SleeveSides, case_of_addition, cut_sides, polygon_meets_segment,
};
use super::replan::{Junction, RejectedClass, continuation, junction, polyline_length};
use super::{OnlineError, OnlineOptions};
use crate::feasibility::{FeasibilityContext, FeasibilityReport, check_feasibility};
use crate::path_pair::{PairFailure, PathPair, descent_with_clearance, path_pair};
use crate::spt::{RankedShp, SptPlanner, Termination, is_simple_class};
use crate::terrain::PlaneSeries;
use nalgebra::Point2;
use rappel_geometry::btm::{Btm, Location, UpdateReport};
use rappel_geometry::dcel::{ObstacleId, TriangleId};
use rappel_geometry::map::Map;
use rappel_geometry::polygon::Polygon;
use rappel_homotopy::crossing::CrossingSequence;
use rappel_homotopy::h_signature::{HSignature, Poles};
use rappel_homotopy::path::Path;
use rappel_homotopy::shp::{ShortestHomotopicPath, shortest_homotopic_path};
use rappel_homotopy::sleeve::Sleeve;
use serde::{Deserialize, Serialize};

/// Relative length difference below which two remaining routes count as equally long (rounding
/// of sums of square roots), times the map's diagonal.
pub const LENGTH_TOLERANCE: f64 = 1e-9;

/// Where the session stands.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "snake_case", tag = "status")]
pub enum Status {
    /// Descending along the plan.
    Descending,
    /// The robot is at the goal.
    AtGoal,
    /// No class within the search's termination rule is feasible: the search's reason.
    NoFeasibleClass {
        /// Why the search stopped.
        termination: Termination,
        /// Classes skipped as rejected.
        rejected: usize,
    },
    /// The goal lies inside an obstacle.
    GoalCovered,
}

/// What the session decided after a change.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case", tag = "decision")]
pub enum Decision {
    /// Outside the current sleeve: kept for later, the plan goes on.
    Deferred,
    /// The plan goes on unchanged.
    Continue,
    /// Same class, new SHP or paths: the robot goes on along the new plan from where it is.
    NewPaths,
    /// Another class (Alg. 13 `A*(H_c, update)`): the robot backtracks to the junction (maybe
    /// zero metres) and descends the new sleeve.
    Switched {
        /// The junction on the travelled path.
        #[schemars(with = "[f64; 2]")]
        junction: Point2<f64>,
        /// Ascent back to it, m.
        backtrack_m: f64,
        /// The new class's SHP length, m.
        length_m: f64,
    },
    /// No feasible class is left within the search's termination rule (a clean "no").
    NoFeasibleClass,
    /// The goal is inside the new obstacle (a clean "no").
    GoalCovered,
}

/// A shorter class a change opened (beyond the thesis: it prefers to stay in its sleeve).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct ShorterClass {
    /// Remaining travel in it (backtrack plus continuation), m.
    pub remaining_m: f64,
    /// Remaining travel in the current plan, m.
    pub current_remaining_m: f64,
    /// Backtracking it needs, m.
    pub backtrack_m: f64,
    /// Whether the session switched to it.
    pub switched: bool,
}

/// What one change did (one row of the timeline).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct ChangeOutcome {
    /// `add`, `remove` or `boundary` (a reshape is a removal and an addition).
    pub change: String,
    /// The obstacle id concerned (the new id for an addition).
    pub obstacle: Option<u32>,
    /// The case (thesis §3.5.3).
    pub case: ChangeCase,
    /// Why: the affected sleeve positions, the sides cut, the anchors before and after.
    pub reason: String,
    /// The decision.
    pub decision: Decision,
    /// Free triangles the retriangulation removed and added.
    pub triangles_replaced: (usize, usize),
    /// Sleeve triangles among the removed ones.
    pub sleeve_triangles_affected: usize,
    /// SHP length before and after, m.
    pub shp_length_m: (Option<f64>, Option<f64>),
    /// A shorter class the change opened, if any.
    pub shorter_class: Option<ShorterClass>,
    /// The backtrackability check after the decision (module docs, step 7).
    pub backtrackable: bool,
    /// Why the plan followed after the decision does not keep the clearance from every anchor
    /// (`None`: it does; [`OnlineSession::clearance_shortfall`]).
    pub clearance_shortfall: Option<ClearanceShortfall>,
}

/// Why the plan the session follows does not keep the clearance from every anchor of its class
/// (module docs, "Clearance"). Without one, the descent still to travel is the class's Alg. 6
/// descent (from the start) or a descent with clearance along the taut continuation (from a
/// junction), and the selected ascent is the pair's.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum ClearanceShortfall {
    /// No class the search examined has an Alg. 6 pair: the feasible class with the least
    /// remaining travel is followed, its ascent and descent are its taut tether.
    NoPair {
        /// Why that class's pair failed.
        failure: PairFailure,
    },
    /// The class has its pair, but the descent from the junction cannot keep the clearance (the
    /// robot stands, or the continuation must pass, too close to an anchor): the robot follows
    /// the taut continuation.
    Continuation {
        /// Why the descent with clearance failed.
        failure: PairFailure,
    },
}

/// The chosen class with what the session needs to classify changes quickly.
#[derive(Debug, Clone)]
pub struct CurrentClass {
    /// Its SHP, reduced crossing sequence and sleeve.
    pub shp: ShortestHomotopicPath,
    /// Its H-signature (the session's poles).
    pub h_signature: HSignature,
    /// Alg. 12 on its SHP.
    pub feasibility: FeasibilityReport,
    /// The selected ascent path, goal to start (the pair's, or the taut tether reversed when
    /// no pair with clearance exists, see `pair_failure`).
    pub ascent: Vec<Point2<f64>>,
    /// The selected descent path, start to goal (the pair's, or the taut tether).
    pub descent: Vec<Point2<f64>>,
    /// Why Alg. 6 built no pair for this class (`None`: `ascent` and `descent` are its pair).
    pub pair_failure: Option<PairFailure>,
    sides: SleeveSides,
    /// (triangle, sleeve position), sorted.
    positions: Vec<(TriangleId, usize)>,
}

impl CurrentClass {
    fn affected(&self, report: &UpdateReport) -> Vec<usize> {
        let mut out = Vec::new();
        for t in &report.removed {
            let from = self.positions.partition_point(|(u, _)| u < t);
            out.extend(
                self.positions[from..]
                    .iter()
                    .take_while(|(u, _)| u == t)
                    .map(|(_, i)| *i),
            );
        }
        out.sort_unstable();
        out
    }
}

/// A candidate of the constrained search.
struct Candidate {
    class: RankedShp,
    feasibility: FeasibilityReport,
    junction: Junction,
    continuation: ShortestHomotopicPath,
    pair: Result<PathPair, PairFailure>,
    cost: f64,
}

/// An online planning session (module docs).
#[derive(Debug, Clone)]
pub struct OnlineSession {
    btm: Btm,
    terrain: PlaneSeries,
    options: OnlineOptions,
    start: Point2<f64>,
    goal: Point2<f64>,
    poles: Vec<Option<Point2<f64>>>,
    class: Option<CurrentClass>,
    travelled: Vec<Point2<f64>>,
    route: Vec<Point2<f64>>,
    /// Why the route's descent past its junction is the taut continuation (module docs).
    continuation_failure: Option<PairFailure>,
    backtrack_left: f64,
    constraints: Vec<RejectedClass>,
    deferred: Vec<ChangeOutcome>,
    status: Status,
    /// The PTFOs and tension model, when the session plans with tether friction.
    friction: Option<session_friction::SessionFriction>,
    travelled_length: f64,
    backtracked_length: f64,
    scale: f64,
}

/// Obstacle vertices a new session reserves room for in its mesh
/// ([`OnlineSession::reserve_for_updates`]): a few dozen discovered rocks of typical outline.
pub const UPDATE_HEADROOM_VERTICES: usize = 1024;

impl OnlineSession {
    /// Builds the BTM of `map` and preplans (Alg. 11): the shortest feasible class and its
    /// ascent/descent pair. A map without a feasible class gives a session whose status says so.
    pub fn new(
        map: &Map,
        start: Point2<f64>,
        goal: Point2<f64>,
        terrain: PlaneSeries,
        options: OnlineOptions,
    ) -> Result<OnlineSession, OnlineError> {
        options.validate()?;
        let valid = map.validate()?;
        map.validate_point("start", &start)?;
        map.validate_point("goal", &goal)?;
        let btm = Btm::build(valid)?;
        let mut poles = Vec::new();
        for id in btm.obstacle_ids() {
            let polygon = btm
                .obstacle_polygon(id)
                .ok_or_else(|| OnlineError::Internal(format!("obstacle {id} has no polygon")))?;
            if poles.len() <= id.index() {
                poles.resize(id.index() + 1, None);
            }
            poles[id.index()] = interior_point(&polygon);
        }
        let (w, h) = map.aabb().size();
        let mut session = OnlineSession {
            btm,
            terrain,
            options,
            start,
            goal,
            poles,
            class: None,
            travelled: vec![start],
            route: vec![start],
            continuation_failure: None,
            backtrack_left: 0.0,
            constraints: Vec::new(),
            deferred: Vec::new(),
            status: Status::Descending,
            friction: None,
            travelled_length: 0.0,
            backtracked_length: 0.0,
            scale: w.hypot(h),
        };
        session.reserve_for_updates(UPDATE_HEADROOM_VERTICES);
        // Alg. 11 by Alg. 6: the first class of the search with a feasible ascent and a pair;
        // from the start the robot follows that pair's descent (`follow`).
        session.replan()?;
        if start == goal && session.class.is_some() {
            session.status = Status::AtGoal;
        }
        Ok(session)
    }

    /// Reserves room for map changes adding up to `vertices` obstacle vertices in all, so that
    /// handling them does not reallocate the mesh (see [`Btm::reserve_for_updates`]). A new
    /// session reserves [`UPDATE_HEADROOM_VERTICES`]; a clone reserves nothing, so call this on a
    /// clone that will take time-critical changes.
    pub fn reserve_for_updates(&mut self, vertices: usize) {
        self.btm.reserve_for_updates(vertices);
    }

    /// The current BTM.
    pub fn btm(&self) -> &Btm {
        &self.btm
    }

    /// The chosen class, if any.
    pub fn class(&self) -> Option<&CurrentClass> {
        self.class.as_ref()
    }

    /// The status.
    pub fn status(&self) -> &Status {
        &self.status
    }

    /// The robot's position.
    pub fn robot(&self) -> Point2<f64> {
        *self.travelled.last().unwrap_or(&self.start)
    }

    /// The start (the anchor `a_0`).
    pub fn start(&self) -> Point2<f64> {
        self.start
    }

    /// The goal.
    pub fn goal(&self) -> Point2<f64> {
        self.goal
    }

    /// The robot's path so far, backtracks included: the tether laid (reduced, it is its class).
    pub fn travelled(&self) -> &[Point2<f64>] {
        &self.travelled
    }

    /// The remaining plan, from the robot to the goal.
    pub fn route(&self) -> &[Point2<f64>] {
        &self.route
    }

    /// Distance travelled so far, m.
    pub fn travelled_length(&self) -> f64 {
        self.travelled_length
    }

    /// Distance travelled backwards (backtracking) so far, m.
    pub fn backtracked_length(&self) -> f64 {
        self.backtracked_length
    }

    /// The rejected classes (the constraints `H_c`).
    pub fn constraints(&self) -> &[RejectedClass] {
        &self.constraints
    }

    /// The changes outside the sleeve, kept for later (§3.5.3).
    pub fn deferred(&self) -> &[ChangeOutcome] {
        &self.deferred
    }

    /// The options.
    pub fn options(&self) -> &OnlineOptions {
        &self.options
    }

    /// Why the plan followed now does not keep the clearance from every anchor of its class
    /// (`None`: it does, or there is no class).
    pub fn clearance_shortfall(&self) -> Option<ClearanceShortfall> {
        let c = self.class.as_ref()?;
        if let Some(failure) = &c.pair_failure {
            return Some(ClearanceShortfall::NoPair {
                failure: failure.clone(),
            });
        }
        self.continuation_failure
            .clone()
            .map(|failure| ClearanceShortfall::Continuation { failure })
    }

    /// The descent along the taut continuation `cont` keeping the clearance from its anchors and
    /// the current class's ([`descent_with_clearance`]); where it cannot, the taut continuation
    /// itself, and the reason is kept for [`OnlineSession::clearance_shortfall`].
    fn descent_along(&mut self, cont: &ShortestHomotopicPath) -> Vec<Point2<f64>> {
        if self.options.clearance == 0.0 {
            return cont.taut.points.clone();
        }
        let class_anchors: Vec<Point2<f64>> = self
            .class
            .as_ref()
            .map(|c| c.shp.taut.anchors.iter().map(|a| a.point).collect())
            .unwrap_or_default();
        match descent_with_clearance(&self.ctx(), &cont.taut, &cont.crossings, &class_anchors) {
            Ok(d) => d,
            Err(failure) => {
                self.continuation_failure = Some(failure);
                cont.taut.points.clone()
            }
        }
    }

    fn ctx(&self) -> FeasibilityContext<'_> {
        FeasibilityContext {
            btm: &self.btm,
            terrain: &self.terrain,
            clearance: self.options.clearance,
            tether_length: self.options.tether_length,
        }
    }

    fn pole_set(&self) -> Poles {
        Poles::from_points(
            self.poles
                .iter()
                .enumerate()
                .filter_map(|(i, p)| p.map(|p| (ObstacleId(i as u32), p))),
        )
    }

    fn alive(&self, o: ObstacleId) -> bool {
        self.poles.get(o.index()).is_some_and(Option::is_some)
    }

    fn constrained(&self, h: &HSignature) -> bool {
        self.constraints
            .iter()
            .any(|c| c.matches(h, |o| self.alive(o)))
    }

    fn reject(&mut self, h: HSignature, length: f64, reason: String) {
        let obstacles = (0..self.poles.len())
            .map(|i| ObstacleId(i as u32))
            .filter(|o| self.alive(*o))
            .collect();
        self.constraints.push(RejectedClass {
            h_signature: h,
            obstacles,
            length,
            reason,
        });
    }

    /// The laid tether followed by the remaining plan: a path of the current class.
    fn reference_path(&self) -> Vec<Point2<f64>> {
        let mut pts = self.travelled.clone();
        for p in self.route.iter().skip(1) {
            if pts.last() != Some(p) {
                pts.push(*p);
            }
        }
        pts
    }

    /// `shp` as a ranked class with the session's H-signature `h`.
    fn ranked(shp: ShortestHomotopicPath, h: HSignature) -> RankedShp {
        RankedShp {
            rank: 0,
            simple: is_simple_class(&shp.taut),
            shp,
            h_signature: h,
            expansions: 0,
        }
    }

    /// Makes `ranked` (its `h_signature` the session's) the current class with its Alg. 6 pair,
    /// or its taut tether both ways when `pair` failed (the failure is kept and reported).
    fn adopt(
        &mut self,
        ranked: RankedShp,
        feasibility: FeasibilityReport,
        pair: Result<PathPair, PairFailure>,
    ) {
        let (ascent, descent, pair_failure) = match pair {
            Ok(pair) => (pair.ascent, pair.descent, None),
            Err(failure) => (
                ranked.shp.taut.points.iter().rev().copied().collect(),
                ranked.shp.taut.points.clone(),
                Some(failure),
            ),
        };
        let sides = SleeveSides::of(&self.btm, &ranked.shp.sleeve);
        let positions = sleeve_positions(&ranked.shp.sleeve);
        self.class = Some(CurrentClass {
            shp: ranked.shp,
            h_signature: ranked.h_signature,
            feasibility,
            ascent,
            descent,
            pair_failure,
            sides,
            positions,
        });
    }

    /// Updates the current class in place after a change that kept its SHP: new sleeve, same
    /// SHP, feasibility and pair.
    fn refresh_sleeve(&mut self, shp: ShortestHomotopicPath) {
        if let Some(c) = &mut self.class {
            c.sides = SleeveSides::of(&self.btm, &shp.sleeve);
            c.positions = sleeve_positions(&shp.sleeve);
            c.shp = shp;
        }
    }

    /// Applies one map change (module docs) and returns what happened, one outcome per local
    /// update (a reshape gives two). With PTFOs ([`OnlineSession::set_friction`]) the anchors of
    /// the resulting SHP are then decided again, and the outcomes of any slips follow. Errors of
    /// the change itself leave the session as it was.
    pub fn apply(&mut self, change: &MapChange) -> Result<Vec<ChangeOutcome>, OnlineError> {
        let mut outcomes = self.apply_change(change)?;
        if self.friction.is_some() {
            outcomes.extend(self.settle_friction()?);
        }
        Ok(outcomes)
    }

    /// [`OnlineSession::apply`] without the friction check.
    fn apply_change(&mut self, change: &MapChange) -> Result<Vec<ChangeOutcome>, OnlineError> {
        if let Some(p) = change.new_polygon() {
            self.check_cover(p)?;
        }
        match change {
            MapChange::Add(p) => {
                let o = self.add(p)?;
                Ok(vec![self.finish(o)])
            }
            MapChange::Remove(id) => {
                let o = self.remove(*id)?;
                Ok(vec![self.finish(o)])
            }
            MapChange::Reshape { obstacle, polygon } => {
                if self.btm.obstacle_polygon(*obstacle).is_none() {
                    return Err(OnlineError::Btm(
                        rappel_geometry::btm::BtmError::UnknownObstacle(*obstacle),
                    ));
                }
                // Check the addition against the map without the old outline before removing.
                let mut trial = self.btm.map();
                let index = self.btm.obstacle_ids().position(|o| o == *obstacle);
                if let Some(i) = index {
                    trial.obstacles.remove(i);
                }
                trial.obstacles.push(polygon.clone());
                trial.validate()?;
                let first = self.remove(*obstacle)?;
                let first = self.finish(first);
                let second = self.add(polygon)?;
                let second = self.finish(second);
                if let (Some(f), Some(new)) = (&mut self.friction, second.obstacle) {
                    f.renamed(*obstacle, ObstacleId(new));
                }
                Ok(vec![first, second])
            }
            MapChange::Boundary(b) => {
                let o = self.rebuild(b)?;
                Ok(vec![self.finish(o)])
            }
        }
    }

    /// `o` with the clearance shortfall of the plan as it stands after it.
    fn finish(&self, mut o: ChangeOutcome) -> ChangeOutcome {
        o.clearance_shortfall = self.clearance_shortfall();
        o
    }

    /// Refuses a new outline that covers the robot, the start or the laid tether.
    fn check_cover(&self, p: &Polygon) -> Result<(), OnlineError> {
        let robot = self.robot();
        if covers(p, &robot) {
            return Err(OnlineError::CoversRobot { at: robot });
        }
        if covers(p, &self.start) {
            return Err(OnlineError::CoversStart { at: self.start });
        }
        for w in self.travelled.windows(2) {
            if w[0] != w[1] && polygon_meets_segment(p, &w[0], &w[1]) {
                return Err(OnlineError::CoversTether { at: w[0] });
            }
        }
        Ok(())
    }

    fn outcome(
        &self,
        change: &'static str,
        obstacle: Option<ObstacleId>,
        case: ChangeCase,
        report: &UpdateReport,
        affected: usize,
        before: Option<f64>,
    ) -> ChangeOutcome {
        ChangeOutcome {
            change: change.to_string(),
            obstacle: obstacle.map(|o| o.0),
            case,
            reason: String::new(),
            decision: Decision::Continue,
            triangles_replaced: (report.removed.len(), report.added.len()),
            sleeve_triangles_affected: affected,
            shp_length_m: (before, self.class.as_ref().map(|c| c.shp.taut.length)),
            shorter_class: None,
            backtrackable: true,
            clearance_shortfall: None,
        }
    }

    /// Keeps a change outside the sleeve for later (§3.5.3) and returns its outcome.
    fn defer(
        &mut self,
        change: &'static str,
        id: ObstacleId,
        report: &UpdateReport,
        before: Option<f64>,
        reason: String,
    ) -> ChangeOutcome {
        let mut o = self.outcome(
            change,
            Some(id),
            ChangeCase::OutsideSleeve,
            report,
            0,
            before,
        );
        o.decision = Decision::Deferred;
        o.reason = reason;
        self.deferred.push(o.clone());
        o
    }

    fn add(&mut self, polygon: &Polygon) -> Result<ChangeOutcome, OnlineError> {
        let goal_covered = covers(polygon, &self.goal);
        let (id, report) = self.btm.insert_obstacle(polygon)?;
        if self.poles.len() <= id.index() {
            self.poles.resize(id.index() + 1, None);
        }
        self.poles[id.index()] = interior_point(polygon);
        let before = self.class.as_ref().map(|c| c.shp.taut.length);
        if goal_covered {
            self.status = Status::GoalCovered;
            self.class = None;
            let mut o = self.outcome("add", Some(id), ChangeCase::Blocked, &report, 0, before);
            o.reason = format!("obstacle {id} covers the goal");
            o.decision = Decision::GoalCovered;
            return Ok(o);
        }
        let Some(class) = &self.class else {
            return Ok(self.defer("add", id, &report, before, "no current class".into()));
        };
        let affected = class.affected(&report);
        if affected.is_empty() {
            let reason = format!(
                "obstacle {id} meets none of the {} sleeve triangles",
                class.positions.len()
            );
            return Ok(self.defer("add", id, &report, before, reason));
        }
        let (left, right) = cut_sides(&self.btm, &class.sides, &affected, polygon);
        let old_points = class.shp.taut.points.clone();
        let old_anchors = anchor_list(&class.shp);
        let traced = Path::new(self.reference_path())
            .ok()
            .and_then(|p| shortest_homotopic_path(&self.btm, &p).ok());
        let changed = traced.as_ref().is_none_or(|s| s.taut.points != old_points);
        let case = case_of_addition(left, right, changed);
        let mut o = self.outcome("add", Some(id), case, &report, affected.len(), before);
        let span = format!(
            "obstacle {id} meets sleeve positions {}..={} of {}; crosses the left side: {}, the right side: {}",
            affected[0],
            affected[affected.len() - 1],
            class.positions.len(),
            yes(left),
            yes(right)
        );
        match traced {
            None => {
                o.reason = format!("{span}; the planned route crosses it");
                o.decision = self.replan()?;
            }
            Some(shp) if !changed => {
                o.reason = format!("{span}; SHP unchanged (anchors {old_anchors})");
                self.refresh_sleeve(shp);
                o.decision = self.check_pair()?;
            }
            Some(shp) => {
                o.reason = format!("{span}; anchors {old_anchors} -> {}", anchor_list(&shp));
                o.decision = self.take_new_shp(shp)?;
            }
        }
        o.shp_length_m.1 = self.class.as_ref().map(|c| c.shp.taut.length);
        // `check_pair` has just traced the ascent when it let the plan go on: only the
        // feasibility verdict is left to read.
        o.backtrackable = if o.decision == Decision::Continue && !changed {
            self.class
                .as_ref()
                .is_some_and(|c| c.feasibility.feasible())
        } else {
            self.backtrackable()
        };
        Ok(o)
    }

    fn remove(&mut self, id: ObstacleId) -> Result<ChangeOutcome, OnlineError> {
        let report = self.btm.remove_obstacle(id)?;
        if let Some(p) = self.poles.get_mut(id.index()) {
            *p = None;
        }
        // A removal can make a rejected class feasible again (replan module docs).
        self.constraints.clear();
        let before = self.class.as_ref().map(|c| c.shp.taut.length);
        let Some(class) = &self.class else {
            return Ok(self.defer("remove", id, &report, before, "no current class".into()));
        };
        let affected = class.affected(&report);
        let mut o;
        if affected.is_empty() {
            o = self.outcome(
                "remove",
                Some(id),
                ChangeCase::OutsideSleeve,
                &report,
                0,
                before,
            );
            o.decision = Decision::Deferred;
            o.reason = format!("obstacle {id} bordered none of the sleeve triangles");
        } else {
            let old_points = class.shp.taut.points.clone();
            let old_anchors = anchor_list(&class.shp);
            let path = Path::new(self.reference_path())?;
            let shp = shortest_homotopic_path(&self.btm, &path)?;
            let changed = shp.taut.points != old_points;
            let case = if changed {
                ChangeCase::AnchorsChanged
            } else {
                ChangeCase::SleeveOpened
            };
            o = self.outcome("remove", Some(id), case, &report, affected.len(), before);
            o.reason = format!(
                "obstacle {id} bordered {} of {} sleeve triangles; anchors {old_anchors} -> {}",
                affected.len(),
                class.positions.len(),
                anchor_list(&shp)
            );
            o.decision = if changed {
                self.take_new_shp(shp)?
            } else {
                self.refresh_sleeve(shp);
                Decision::Continue
            };
        }
        if self.status == Status::Descending && self.class.is_some() {
            o.shorter_class = self.shorter_class()?;
            if o.shorter_class.as_ref().is_some_and(|s| s.switched) {
                o.decision = Decision::NewPaths;
            }
        }
        if o.decision == Decision::Deferred {
            self.deferred.push(o.clone());
        }
        o.shp_length_m.1 = self.class.as_ref().map(|c| c.shp.taut.length);
        o.backtrackable = self.backtrackable();
        Ok(o)
    }

    fn rebuild(&mut self, boundary: &Polygon) -> Result<ChangeOutcome, OnlineError> {
        for (which, p) in [
            ("robot", self.robot()),
            ("start", self.start),
            ("goal", self.goal),
        ] {
            if outside_boundary(boundary, &p) {
                return Err(OnlineError::OutsideNewBoundary { which, at: p });
            }
        }
        let mut map = self.btm.map();
        map.boundary = boundary.clone();
        let btm = Btm::build(map.validate()?)?;
        let before = self.class.as_ref().map(|c| c.shp.taut.length);
        let report = UpdateReport::default();
        self.btm = btm;
        self.poles = self
            .btm
            .obstacle_ids()
            .map(|id| {
                self.btm
                    .obstacle_polygon(id)
                    .and_then(|p| interior_point(&p))
            })
            .collect();
        self.constraints.clear();
        self.deferred.clear();
        let mut o = self.outcome("boundary", None, ChangeCase::Rebuilt, &report, 0, before);
        let traced = Path::new(self.reference_path())
            .ok()
            .and_then(|p| shortest_homotopic_path(&self.btm, &p).ok());
        o.decision = match traced {
            Some(shp) => {
                o.reason = "the BTM was rebuilt; the plan traces through it".into();
                self.take_new_shp(shp)?
            }
            None => {
                o.reason = "the BTM was rebuilt; the plan leaves the new boundary".into();
                self.replan()?
            }
        };
        o.shp_length_m.1 = self.class.as_ref().map(|c| c.shp.taut.length);
        o.backtrackable = self.backtrackable();
        Ok(o)
    }

    /// Alg. 13 lines 11-16: a new SHP for the current class.
    fn take_new_shp(&mut self, shp: ShortestHomotopicPath) -> Result<Decision, OnlineError> {
        let h = HSignature::of_path(&self.pole_set(), &shp.taut.to_path());
        let feasibility = check_feasibility(&self.ctx(), &shp.taut);
        if !feasibility.feasible() {
            let why = feasibility.describe();
            self.reject(h, shp.taut.length, why);
            return self.replan();
        }
        let ranked = Self::ranked(shp, h);
        let pair = path_pair(&self.ctx(), &ranked, &feasibility);
        if pair.is_err() {
            // Alg. 6 passes over a class without a pair: the search picks the class with a pair
            // and the least remaining travel, this one again (with its failure reported) when
            // no class has one.
            return self.replan();
        }
        let last = self.travelled.len() - 1;
        let cont = continuation(&self.btm, &self.travelled, last, &ranked.shp.taut.points)?;
        let from_start = last == 0;
        self.adopt(ranked, feasibility, pair);
        self.continuation_failure = None;
        self.route = match &self.class {
            Some(c) if from_start => c.descent.clone(),
            _ => self.descent_along(&cont),
        };
        self.backtrack_left = 0.0;
        Ok(Decision::NewPaths)
    }

    /// Alg. 13 line 18: the SHP is the same, but is the ascent still in free space and homotopic
    /// to the descent? If not, select new paths (or reject the class when the SHP has become
    /// infeasible).
    fn check_pair(&mut self) -> Result<Decision, OnlineError> {
        let Some(c) = &self.class else {
            return Ok(Decision::Continue);
        };
        let reversed: Vec<Point2<f64>> = c.ascent.iter().rev().copied().collect();
        let ok = Path::new(reversed)
            .ok()
            .and_then(|p| CrossingSequence::reduced_of_path(&self.btm, &p).ok())
            .is_some_and(|w| w == c.shp.crossings);
        if ok {
            return Ok(Decision::Continue);
        }
        let shp = c.shp.clone();
        let h = c.h_signature.clone();
        let feasibility = check_feasibility(&self.ctx(), &shp.taut);
        if !feasibility.feasible() {
            self.reject(h, shp.taut.length, feasibility.describe());
            return self.replan();
        }
        let ranked = Self::ranked(shp, h);
        let pair = path_pair(&self.ctx(), &ranked, &feasibility);
        if pair.is_err() {
            // As in `take_new_shp`: a class with a pair first.
            return self.replan();
        }
        // The route is unchanged (still free and in the class): only the pair is new.
        self.adopt(ranked, feasibility, pair);
        Ok(Decision::NewPaths)
    }

    /// The constrained search (replan module): the feasible candidate with the least remaining
    /// travel, rejecting infeasible classes on the way.
    fn best_candidate(&mut self) -> Result<(Option<Candidate>, Termination, usize), OnlineError> {
        let poles = self.pole_set();
        let planner = SptPlanner::new(&self.btm);
        let k = self
            .options
            .search
            .max_classes()
            .map(|k| k + self.constraints.len());
        let opts = self.options.search.clone().with_max_classes(k)?;
        let mut search = planner.search(self.start, self.goal, &opts)?;
        // The best candidate with an Alg. 6 pair, and the best feasible one without.
        let mut best: Option<Candidate> = None;
        let mut fallback: Option<Candidate> = None;
        let mut skipped = 0;
        let mut rejected = Vec::new();
        while let Some(mut class) = search.next_best()? {
            let h = HSignature::of_path(&poles, &class.shp.taut.to_path());
            if self.constrained(&h) {
                skipped += 1;
                continue;
            }
            if best.as_ref().is_some_and(|b| class.length() >= b.cost) {
                // Every later class is at least this long: none can beat the best.
                break;
            }
            let feasibility = check_feasibility(&self.ctx(), &class.shp.taut);
            if !feasibility.feasible() {
                rejected.push((h, class.length(), feasibility.describe()));
                continue;
            }
            let j = junction(&self.btm, &self.travelled, &class.shp.taut)?;
            // From the start the continuation is the class's SHP itself (the same numbers, so
            // that the costs there are the search's lengths and its order decides, as in Alg. 6).
            let cont = if j.index == 0 {
                class.shp.clone()
            } else {
                continuation(&self.btm, &self.travelled, j.index, &class.shp.taut.points)?
            };
            let cost = j.backtrack + cont.taut.length;
            if best.as_ref().is_some_and(|b| cost >= b.cost) {
                continue;
            }
            class.h_signature = h;
            let pair = path_pair(&self.ctx(), &class, &feasibility);
            let slot = if pair.is_ok() {
                &mut best
            } else {
                &mut fallback
            };
            if slot.as_ref().is_none_or(|b| cost < b.cost) {
                *slot = Some(Candidate {
                    class,
                    feasibility,
                    junction: j,
                    continuation: cont,
                    pair,
                    cost,
                });
            }
        }
        let termination = search.termination().unwrap_or(Termination::Exhausted);
        drop(search);
        for (h, length, why) in rejected {
            self.reject(h, length, why);
        }
        Ok((best.or(fallback), termination, skipped))
    }

    /// Follows `c`: backtrack along the travelled path to the junction, then its continuation.
    fn follow(&mut self, c: Candidate) -> Decision {
        let j = c.junction.clone();
        let length = c.class.length();
        self.adopt(c.class, c.feasibility, c.pair);
        self.continuation_failure = None;
        // Back to the start: the class's own descent (its pair's, Alg. 6). From a later
        // junction: a descent with clearance along the taut continuation.
        let onward = match &self.class {
            Some(k) if j.index == 0 => k.descent.clone(),
            _ => self.descent_along(&c.continuation),
        };
        let mut route: Vec<Point2<f64>> = self.travelled[j.index..].iter().rev().copied().collect();
        for p in onward.into_iter().skip(1) {
            if route.last() != Some(&p) {
                route.push(p);
            }
        }
        self.route = route;
        self.backtrack_left = j.backtrack;
        Decision::Switched {
            junction: j.point,
            backtrack_m: j.backtrack,
            length_m: length,
        }
    }

    /// Alg. 13 `A*(H_c, update)` and the backtrack to the junction.
    fn replan(&mut self) -> Result<Decision, OnlineError> {
        let (best, termination, skipped) = self.best_candidate()?;
        match best {
            Some(c) => Ok(self.follow(c)),
            None => {
                self.class = None;
                self.continuation_failure = None;
                self.route = vec![self.robot()];
                self.status = Status::NoFeasibleClass {
                    termination,
                    rejected: skipped + self.constraints.len(),
                };
                Ok(Decision::NoFeasibleClass)
            }
        }
    }

    /// Beyond the thesis: is there a class with less remaining travel than the current plan?
    fn shorter_class(&mut self) -> Result<Option<ShorterClass>, OnlineError> {
        let current = polyline_length(&self.route);
        let (best, _, _) = self.best_candidate()?;
        let Some(c) = best else {
            return Ok(None);
        };
        let same = self
            .class
            .as_ref()
            .is_some_and(|k| k.shp.crossings == c.class.shp.crossings);
        if same || c.cost >= current - LENGTH_TOLERANCE * self.scale {
            return Ok(None);
        }
        let backtrack_m = c.junction.backtrack;
        let remaining_m = c.cost;
        let switched = self.options.switch_to_shorter;
        if switched {
            self.follow(c);
        }
        Ok(Some(ShorterClass {
            remaining_m,
            current_remaining_m: current,
            backtrack_m,
            switched,
        }))
    }

    /// The SHP of the tether laid so far (start to robot).
    pub fn laid_tether(&self) -> Result<ShortestHomotopicPath, OnlineError> {
        Ok(shortest_homotopic_path(
            &self.btm,
            &Path::new(self.travelled.clone())?,
        )?)
    }

    /// The backtrackability check run after every decision (module docs, step 7): the class's
    /// ascent is feasible (Alg. 12) and the selected ascent path lies in free space in the class,
    /// so the descent was chosen among feasible ascents; the travelled path itself stays free
    /// (changes that meet it are refused), so the robot can always retrace it.
    pub fn backtrackable(&self) -> bool {
        let Some(c) = &self.class else {
            return self.status != Status::Descending || self.travelled.len() == 1;
        };
        if !c.feasibility.feasible() {
            return false;
        }
        let reversed: Vec<Point2<f64>> = c.ascent.iter().rev().copied().collect();
        Path::new(reversed)
            .ok()
            .and_then(|p| CrossingSequence::reduced_of_path(&self.btm, &p).ok())
            .is_some_and(|w| w == c.shp.crossings)
    }

    /// The stronger, slower check: Alg. 5 on the SHP of the tether laid so far, with the robot as
    /// the goal (can it climb back from exactly where it is?). Linear in the map's size.
    pub fn laid_tether_climbable(&self) -> bool {
        if self.robot() == self.start {
            return true;
        }
        self.laid_tether()
            .map(|t| check_feasibility(&self.ctx(), &t.taut).feasible())
            .unwrap_or(false)
    }

    /// Moves the robot `distance` metres along its plan (fewer at the goal); returns the distance
    /// moved. An interpolated position that rounding puts inside an obstacle (a route along an
    /// obstacle edge) is replaced by the segment's end.
    pub fn advance(&mut self, distance: f64) -> f64 {
        if self.status != Status::Descending || distance.is_nan() || distance <= 0.0 {
            return 0.0;
        }
        let mut left = distance;
        let mut moved = 0.0;
        let mut k = 0;
        while left > 0.0 && k + 1 < self.route.len() {
            let (a, b) = (self.route[k], self.route[k + 1]);
            let seg = (b - a).norm();
            let mut to = b;
            let mut step = seg;
            if seg > left {
                let p = a + (b - a) * (left / seg);
                if !matches!(
                    self.btm.locate(&p),
                    Location::Obstacle(_) | Location::Outside
                ) {
                    to = p;
                    step = left;
                }
            }
            if to == b {
                k += 1;
            } else {
                self.route[k] = to;
            }
            if self.travelled.last() != Some(&to) {
                self.travelled.push(to);
            }
            let back = step.min(self.backtrack_left);
            self.backtrack_left -= back;
            self.backtracked_length += back;
            moved += step;
            left -= step;
        }
        self.route.drain(..k);
        self.travelled_length += moved;
        if self.route.len() <= 1 && self.robot() == self.goal {
            self.status = Status::AtGoal;
        }
        moved
    }

    /// `true` when the tether laid (the robot's whole path) and the selected ascent, reversed,
    /// are both in the current class: the ascent and the descent are homotopic.
    pub fn ascent_descent_homotopic(&self) -> Result<bool, OnlineError> {
        let Some(c) = &self.class else {
            return Ok(false);
        };
        let descent =
            CrossingSequence::reduced_of_path(&self.btm, &Path::new(self.reference_path())?)?;
        let ascent: Vec<Point2<f64>> = c.ascent.iter().rev().copied().collect();
        let ascent = CrossingSequence::reduced_of_path(&self.btm, &Path::new(ascent)?)?;
        Ok(descent == c.shp.crossings && ascent == c.shp.crossings)
    }
}

fn yes(b: bool) -> &'static str {
    if b { "yes" } else { "no" }
}

/// The anchors of an SHP as `[v12 v40]` (map vertex ids).
fn anchor_list(shp: &ShortestHomotopicPath) -> String {
    let ids: Vec<String> = shp
        .taut
        .anchors
        .iter()
        .map(|a| format!("v{}", a.vertex.0))
        .collect();
    format!("[{}]", ids.join(" "))
}

/// Each sleeve triangle with its position along the sleeve, sorted by triangle id (binary search
/// from a triangle to its position).
fn sleeve_positions(sleeve: &Sleeve) -> Vec<(TriangleId, usize)> {
    let mut positions: Vec<(TriangleId, usize)> = sleeve
        .triangles()
        .iter()
        .enumerate()
        .map(|(i, t)| (*t, i))
        .collect();
    positions.sort_unstable();
    positions
}
