//! Frictional planning on a scenario (thesis Alg. 7; [`rappel_planners::frictional`]): run by
//! `rappel plan` whenever the scenario has a `friction` section. The report lists, per class, each
//! anchor's kind and verdict (geometric, or a PTFO that is solid, slides or is volatile), every
//! slip event (which vertex was clipped and how the SHP changed), the ascent sweep at friction
//! anchors (Alg. 10), the capstan along the tether and the verdict; the picture colours PTFOs by
//! verdict and marks the sticking points and the clipped vertices.

use crate::pair::PairReport;
use crate::ptfo_spec::ResolvedFriction;
use crate::scenario::Scenario;
use crate::verdict::AnchorHold;
use nalgebra::Point2;
use rappel_geometry::btm::Btm;
use rappel_planners::frictional::feasibility2::SweepCheck;
use rappel_planners::frictional::holding::HoldingReport;
use rappel_planners::frictional::search::{
    FrictionalPlan, FrictionalPlanError, FrictionalQuery, plan_frictional,
};
use rappel_planners::frictional::slip::SlipEvent;
use rappel_planners::spt::{SearchOptions, Termination};
use rappel_planners::terrain::PlaneSeries;
use serde::{Deserialize, Serialize};

/// The tension model in force, N.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct TensionReport {
    /// `T_min`.
    pub t_min_n: f64,
    /// `T_max`.
    pub t_max_n: f64,
    /// `T_d`.
    pub t_d_n: f64,
    /// `ε`.
    pub epsilon_n: f64,
}

/// One anchor of a class after Alg. 8.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct FrictionAnchorReport {
    /// Position.
    #[schemars(with = "[f64; 2]")]
    pub point: Point2<f64>,
    /// Map obstacle index (`null` on the boundary).
    pub obstacle: Option<usize>,
    /// `geometric`, or `solid` / `slides` / `volatile` for a PTFO.
    pub verdict: AnchorHold,
    /// Turning angle, degrees.
    pub turn_deg: f64,
    /// `∫ω ds` with the lowest friction.
    pub omega_integral_hold: f64,
    /// Why the tether does not touch the surface, when it does not.
    pub no_contact: Option<String>,
}

/// One class examined by Alg. 7.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct FrictionClassReport {
    /// Rank in the frictionless search.
    pub rank: usize,
    /// Length as searched, m.
    pub searched_length_m: f64,
    /// Length after the slips, m.
    pub length_m: f64,
    /// The final SHP.
    #[schemars(with = "Vec<[f64; 2]>")]
    pub points: Vec<Point2<f64>>,
    /// Its anchors.
    pub anchors: Vec<FrictionAnchorReport>,
    /// The slips, in order.
    pub slips: Vec<SlipEvent>,
    /// Alg. 10 at friction anchors.
    pub sweeps: Vec<SweepCheck>,
    /// Waypoints in ascent order (friction anchors are their own).
    #[schemars(with = "Vec<[f64; 2]>")]
    pub waypoints: Vec<Point2<f64>>,
    /// The capstan along the tether.
    pub holding: Option<HoldingReport>,
    /// The ascent/descent pair of a feasible class (geometric anchors kept at the robot's
    /// clearance, solid friction anchors driven over), `null` otherwise.
    pub pair: Option<PairReport>,
    /// Feasible (no volatile anchor, ascent feasible, a pair built).
    pub feasible: bool,
    /// Why not, or `feasible`.
    pub verdict: String,
}

/// The frictional part of `rappel plan`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct FrictionReport {
    /// The tensions in force.
    pub tensions: TensionReport,
    /// How derived tensions were obtained.
    pub notes: Vec<String>,
    /// Map obstacle indices that are PTFOs.
    pub ptfos: Vec<usize>,
    /// The classes examined, in search order.
    pub classes: Vec<FrictionClassReport>,
    /// Rank of the chosen class.
    pub chosen: Option<usize>,
    /// One line.
    pub verdict: String,
    /// Why the search stopped without a feasible class.
    #[serde(with = "rappel_planners::search_report::option_termination_serde")]
    #[schemars(with = "Option<rappel_planners::search_report::TerminationName>")]
    pub termination: Option<Termination>,
}

/// Runs Alg. 7 on the scenario's map (`btm = Btm::from_map(&scenario.map)`).
pub fn plan_friction(
    scenario: &Scenario,
    resolved: &ResolvedFriction,
    btm: &Btm,
    terrain: &PlaneSeries,
    options: &SearchOptions,
) -> Result<(FrictionReport, FrictionalPlan), FrictionalPlanError> {
    let query = FrictionalQuery {
        terrain,
        clearance: scenario.robot.clearance_m,
        start: scenario.start,
        goal: scenario.goal,
        options,
        holding_limit: resolved.holding_limit,
        tether_length: scenario.robot.tether_length_m,
    };
    let plan = plan_frictional(btm, &scenario.map, &resolved.model, &query)?;
    let classes: Vec<FrictionClassReport> = plan
        .classes
        .iter()
        .map(|c| FrictionClassReport {
            rank: c.rank,
            searched_length_m: c.searched_length,
            length_m: c.check.taut.length,
            points: c.check.taut.points.clone(),
            anchors: c
                .check
                .anchors
                .iter()
                .map(|d| FrictionAnchorReport {
                    point: d.anchor.point,
                    obstacle: d.obstacle,
                    verdict: d.verdict.into(),
                    turn_deg: d.anchor.turning_angle.to_degrees(),
                    omega_integral_hold: d.omega_integral_hold,
                    no_contact: d.no_contact.clone(),
                })
                .collect(),
            slips: c.check.slips.clone(),
            sweeps: c
                .feasibility
                .as_ref()
                .map(|f| f.sweeps.clone())
                .unwrap_or_default(),
            waypoints: c
                .feasibility
                .as_ref()
                .map(|f| f.waypoints.clone())
                .unwrap_or_default(),
            holding: c.holding.clone(),
            pair: c.pair.as_ref().map(PairReport::from),
            feasible: c.feasible(),
            verdict: c.describe(),
        })
        .collect();
    let chosen = plan.chosen.map(|i| plan.classes[i].rank);
    let verdict = match (chosen, classes.first()) {
        (Some(rank), _) => {
            let c = classes.iter().find(|c| c.rank == rank).expect("chosen");
            format!(
                "class {rank} is the first feasible class with friction: {:.2} m, {} slip(s)",
                c.length_m,
                c.slips.len()
            )
        }
        (None, None) => "no class found".to_string(),
        (None, Some(_)) => format!(
            "no feasible class with friction among the {} examined ({})",
            classes.len(),
            plan.termination.map_or("stopped", |t| t.describe())
        ),
    };
    let t = resolved.model.tensions;
    let report = FrictionReport {
        tensions: TensionReport {
            t_min_n: t.t_min(),
            t_max_n: t.t_max(),
            t_d_n: t.t_d(),
            epsilon_n: t.epsilon(),
        },
        notes: resolved.notes.clone(),
        ptfos: resolved.model.ptfos.iter().map(|p| p.obstacle).collect(),
        classes,
        chosen,
        verdict,
        termination: plan.termination,
    };
    Ok((report, plan))
}
