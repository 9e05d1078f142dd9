//! Alg. 7 (thesis §3.4.2): the SPT search with PTFOs treated as obstacles; each SHP it yields, in
//! non-decreasing length, goes through Alg. 8 ([`super::anchor_check`]), then Alg. 10
//! ([`super::feasibility2`]); the first feasible class is the answer. Slips change only the
//! class's own copy of the map ([`super::slip::SlipState`]), so later classes are searched on the
//! map as given. Bounded by the search's options (classes, expansions, length factor).

use super::anchor_check::{AnchorVerdict, PtfoCheck, check_ptfos};
use super::feasibility2::{Feasibility2Report, check_feasibility2};
use super::holding::{HoldingReport, holding};
use super::slip::SlipState;
use super::{FrictionModel, FrictionalError, validate_model};
use crate::feasibility::FeasibilityContext;
use crate::path_pair::{AnchorClearance, PairFailure, PairInput, PathPair, path_pair_with};
use crate::spt::{SearchError, SearchOptions, SptPlanner, Termination};
use crate::terrain::PlaneSeries;
use nalgebra::Point2;
use rappel_geometry::btm::Btm;
use rappel_geometry::map::Map;
use rappel_homotopy::crossing::CrossingSequence;
use rappel_homotopy::homotopy::HomotopyError;
use rappel_homotopy::path::Path;
use rappel_mechanics::ptfo::PtfoClass;
use serde::{Deserialize, Serialize};

/// One class examined by Alg. 7.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FrictionalClass {
    /// Rank in the frictionless search (1 = shortest).
    pub rank: usize,
    /// The SHP's length as searched, m.
    pub searched_length: f64,
    /// Alg. 8: anchors, verdicts, slips.
    pub check: PtfoCheck,
    /// Alg. 10 (`None` when the class is volatile).
    pub feasibility: Option<Feasibility2Report>,
    /// Tensions along the tether (`None` when volatile).
    pub holding: Option<HoldingReport>,
    /// The map after this class's slips (for pictures); `None` without slips.
    pub clipped_map: Option<Map>,
    /// The ascent/descent pair of a feasible class (Alg. 6 with friction anchors driven over,
    /// [`pair_for_class`]); `None` when the class is not feasible or no pair was built.
    pub pair: Option<PathPair>,
    /// Why no pair was built for a feasible class (the class then does not count as feasible).
    pub pair_failure: Option<PairFailure>,
}

impl FrictionalClass {
    /// `true` when no anchor is volatile, the ascent is feasible and its ascent/descent pair was
    /// built.
    pub fn feasible(&self) -> bool {
        self.ascent_feasible() && self.pair.is_some()
    }

    /// `true` when no anchor is volatile and Alg. 10 passes (whether or not a pair was built).
    pub fn ascent_feasible(&self) -> bool {
        self.check.volatile.is_none() && self.feasibility.as_ref().is_some_and(|f| f.feasible())
    }

    /// One line: feasible, volatile, or what blocks it.
    pub fn describe(&self) -> String {
        if let Some(k) = self.check.volatile {
            let a = &self.check.anchors[k].anchor;
            return format!(
                "volatile friction anchor at ({:.3}, {:.3}): unsafe",
                a.point.x, a.point.y
            );
        }
        if let Some(e) = &self.pair_failure {
            return format!("feasible ascent, but no ascent/descent pair: {e}");
        }
        match &self.feasibility {
            Some(f) => f.blocked.clone().unwrap_or_else(|| "feasible".into()),
            None => "not checked".into(),
        }
    }
}

/// What Alg. 7 returns.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FrictionalPlan {
    /// Every class examined, in search order; the last is the feasible one when there is one.
    pub classes: Vec<FrictionalClass>,
    /// Index into `classes` of the first feasible class.
    pub chosen: Option<usize>,
    /// Why the search stopped when nothing was feasible.
    pub termination: Option<Termination>,
}

/// Inputs of Alg. 7 besides the map.
#[derive(Debug, Clone, Copy)]
pub struct FrictionalQuery<'a> {
    /// The planes and their tether limits.
    pub terrain: &'a PlaneSeries,
    /// Clearance of geometric anchors' waypoints, m.
    pub clearance: f64,
    /// Start (top anchor) and goal.
    pub start: Point2<f64>,
    /// Goal.
    pub goal: Point2<f64>,
    /// Search bounds.
    pub options: &'a SearchOptions,
    /// Holding limit at `a_0` for Kumar eq. 2, N.
    pub holding_limit: Option<f64>,
    /// The robot's tether length, m (`None`: unlimited); a class whose taut tether after the slips
    /// is longer is infeasible (as in [`FeasibilityContext::tether_length`]).
    pub tether_length: Option<f64>,
}

/// Errors of Alg. 7.
#[derive(Debug, thiserror::Error)]
pub enum FrictionalPlanError {
    /// The search failed.
    #[error(transparent)]
    Search(#[from] SearchError),
    /// A frictional step failed.
    #[error(transparent)]
    Frictional(#[from] FrictionalError),
}

/// The ascent/descent pair of a class that passed Alg. 8 and Alg. 10 (thesis §3.4.2 with §2.4.3):
/// Alg. 6's construction on the SHP left by the slips, in the BTM the slips ended on
/// (`ctx.btm`), along Alg. 10's route; geometric anchors keep `ctx.clearance`, solid friction
/// anchors are driven over ([`AnchorClearance::DriveOver`]). The outer `Err` is a failure to
/// trace the SHP (a bug), the inner one why no pair exists.
pub fn pair_for_class(
    ctx: &FeasibilityContext<'_>,
    rank: usize,
    check: &PtfoCheck,
    feasibility: &Feasibility2Report,
) -> Result<Result<PathPair, PairFailure>, FrictionalError> {
    let trace = |e| FrictionalError::Trace(HomotopyError::Path(e));
    let path = Path::new(check.taut.points.clone()).map_err(trace)?;
    let crossings = CrossingSequence::reduced_of_path(ctx.btm, &path).map_err(trace)?;
    let anchors: Vec<AnchorClearance> = check
        .anchors
        .iter()
        .map(|d| {
            if d.verdict == AnchorVerdict::Friction(PtfoClass::Solid) {
                AnchorClearance::DriveOver
            } else {
                AnchorClearance::Keep
            }
        })
        .collect();
    Ok(path_pair_with(
        ctx,
        PairInput {
            rank,
            taut: &check.taut,
            crossings: &crossings,
            route: &feasibility.base.route,
            anchors: &anchors,
        },
    ))
}

/// Alg. 7 on `btm = Btm::from_map(map)` (module docs).
pub fn plan_frictional(
    btm: &Btm,
    map: &Map,
    model: &FrictionModel,
    query: &FrictionalQuery<'_>,
) -> Result<FrictionalPlan, FrictionalPlanError> {
    validate_model(model, map.obstacles.len())?;
    let ptfo_vertices: usize = model
        .ptfos
        .iter()
        .map(|p| map.obstacles[p.obstacle].len())
        .sum();
    let planner = SptPlanner::new(btm);
    let mut search = planner.search(query.start, query.goal, query.options)?;
    let mut classes = Vec::new();
    while let Some(ranked) = search.next_best()? {
        let mut state = SlipState::new(btm, map);
        let searched_length = ranked.length();
        let check = check_ptfos(model, &mut state, ranked.shp.taut, ptfo_vertices)?;
        let (feasibility, hold) = if check.volatile.is_none() {
            let ctx = FeasibilityContext {
                btm: state.btm(),
                terrain: query.terrain,
                clearance: query.clearance,
                tether_length: query.tether_length,
            };
            let f = check_feasibility2(&ctx, model, &check);
            let h = holding(&check, model, query.holding_limit)
                .map_err(|e| FrictionalError::Internal(format!("capstan along the tether: {e}")))?;
            (Some(f), Some(h))
        } else {
            (None, None)
        };
        let (pair, pair_failure) = match &feasibility {
            Some(f) if f.feasible() => {
                let ctx = FeasibilityContext {
                    btm: state.btm(),
                    terrain: query.terrain,
                    clearance: query.clearance,
                    tether_length: query.tether_length,
                };
                match pair_for_class(&ctx, ranked.rank, &check, f)? {
                    Ok(p) => (Some(p), None),
                    Err(e) => (None, Some(e)),
                }
            }
            _ => (None, None),
        };
        let class = FrictionalClass {
            rank: ranked.rank,
            searched_length,
            clipped_map: (!check.slips.is_empty()).then(|| state.current_map()),
            check,
            feasibility,
            holding: hold,
            pair,
            pair_failure,
        };
        let ok = class.feasible();
        classes.push(class);
        if ok {
            let chosen = Some(classes.len() - 1);
            return Ok(FrictionalPlan {
                classes,
                chosen,
                termination: None,
            });
        }
    }
    Ok(FrictionalPlan {
        classes,
        chosen: None,
        termination: search.termination(),
    })
}
