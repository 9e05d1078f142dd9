//! The online planner on scenario files (thesis §3.5, Alg. 11-13; online paper §III-IV): a
//! descent planned on a prior scenario, simulated over the true one, with its serde report and
//! its pictures (the final state and one per event). See `docs/online.md`.

use crate::scenario::Scenario;
use rappel_mechanics::anchor_traversability::AnchorTraversability;
use rappel_mechanics::friction_cone::TetherFrictionCone;
use rappel_mechanics::stability_qp::StabilityQp;
use rappel_mechanics::traversability::StabilitySettings;
use rappel_mechanics::wheeled_tether_cone::WheeledTetherCone;
use rappel_planners::online::simulate::{
    FrictionPair, SimulationError, TimelineEvent, simulate_frictional,
};
use rappel_planners::online::{OnlineSession, SimulationOptions, SimulationReport};
use rappel_planners::terrain::{PlaneSeries, TerrainError};

/// What `rappel online --json` prints: the simulator's report ([`SimulationReport`]).
pub type OnlineReport = SimulationReport;

impl crate::report::Report for SimulationReport {
    const KIND: &'static str = "online";
}

/// Why an online run could not be made (a run without a feasible class is an answer, not an
/// error: its ending says so).
#[derive(Debug, thiserror::Error)]
pub enum OnlineRunError {
    /// The true scenario does not describe the same descent as the prior.
    #[error(
        "the true scenario's {field} differs from the prior's: both must describe the same descent"
    )]
    Mismatch {
        /// `start`, `goal`, `terrain` or `robot`.
        field: &'static str,
    },
    /// The true map's boundary differs from the prior's. The robot senses obstacles (thesis
    /// §3.7, Tanner 2013): a boundary change cannot be discovered, so a run would plan and
    /// report on the prior's boundary as if the change were not there.
    #[error(
        "the true scenario's map boundary differs from the prior's: the online planner senses obstacles, not boundary changes; keep the prior's boundary and give the change (a wall across the route, a collapsed rim) as obstacles of the true map"
    )]
    BoundaryMismatch,
    /// Only one of the two scenarios has PTFOs (a `friction` section): both must label the same
    /// PTFOs (their frictions may differ).
    #[error(
        "only the {which} scenario has a friction section (PTFOs): give both the same PTFOs \
         (their frictions may differ) or neither"
    )]
    FrictionOnOneSide {
        /// `prior` or `true`.
        which: &'static str,
    },
    /// A friction section could not be resolved.
    #[error("the {which} scenario's friction section: {message}")]
    Friction {
        /// `prior` or `true`.
        which: &'static str,
        /// What is wrong.
        message: String,
    },
    /// The terrain planes are unusable.
    #[error("terrain: {0}")]
    Terrain(#[from] TerrainError),
    /// The robot's parameters do not make a valid model.
    #[error("robot: {0}")]
    Robot(String),
    /// The run failed (bad options, a change that covers the robot, ...).
    #[error(transparent)]
    Simulation(#[from] SimulationError),
}

/// A finished run with the session for pictures.
#[derive(Debug, Clone)]
pub struct OnlineRun {
    /// The report (timeline, ending, lengths).
    pub report: SimulationReport,
    /// The session at the end.
    pub session: OnlineSession,
}

/// The plane series of `scenario` with its robot's tether limit (the point robot's friction cone,
/// eq. 2.7, or a wheeled robot's QP cone).
fn plane_series(scenario: &Scenario) -> Result<PlaneSeries, OnlineRunError> {
    let wheeled = crate::robot::wheeled_model(&scenario.robot).map_err(OnlineRunError::Robot)?;
    let qp = StabilityQp::new(StabilitySettings::default());
    let cone = wheeled.as_deref().map(|r| WheeledTetherCone::new(r, &qp));
    let model: &dyn AnchorTraversability = match &cone {
        Some(c) => c,
        None => &TetherFrictionCone,
    };
    Ok(PlaneSeries::new(&scenario.terrain.planes, model)?)
}

/// Simulates the descent planned on `prior` over `truth`; `observe` sees every event with the
/// session as it stands.
///
/// ```
/// use rappel::scenario::Scenario;
/// use rappel::planners::online::SimulationOptions;
/// let prior = Scenario::from_ron_str(r#"(
///     map: (boundary: [(0.0, 0.0), (20.0, 0.0), (20.0, 40.0), (0.0, 40.0)], obstacles: []),
///     start: (10.0, 38.0), goal: (10.0, 2.0))"#).unwrap();
/// let mut truth = prior.clone();
/// truth.map.obstacles.push(rappel::geometry::polygon::Polygon::rectangle(9.0, 20.0, 2.0, 1.0));
/// let run = rappel::online::run(&prior, &truth, &SimulationOptions::default(), &mut |_, _| {}).unwrap();
/// assert!(run.report.ending.reached());
/// assert_eq!(run.report.timeline.len(), 1);
/// assert!(run.report.homotopic);
/// ```
pub fn run(
    prior: &Scenario,
    truth: &Scenario,
    options: &SimulationOptions,
    observe: &mut dyn FnMut(&TimelineEvent, &OnlineSession),
) -> Result<OnlineRun, OnlineRunError> {
    for (field, same) in [
        ("start", prior.start == truth.start),
        ("goal", prior.goal == truth.goal),
        ("terrain", prior.terrain == truth.terrain),
        ("robot", prior.robot == truth.robot),
    ] {
        if !same {
            return Err(OnlineRunError::Mismatch { field });
        }
    }
    if prior.map.boundary != truth.map.boundary {
        return Err(OnlineRunError::BoundaryMismatch);
    }
    let resolve = |s: &Scenario, which: &'static str| {
        s.friction
            .as_ref()
            .map(|f| {
                f.resolve(s.robot.mass_kg, &s.terrain.planes, s.map.obstacles.len())
                    .map(|r| r.model)
            })
            .transpose()
            .map_err(|message| OnlineRunError::Friction { which, message })
    };
    let friction = match (resolve(prior, "prior")?, resolve(truth, "true")?) {
        (Some(prior), Some(truth)) => Some(FrictionPair { prior, truth }),
        (None, None) => None,
        (Some(_), None) => return Err(OnlineRunError::FrictionOnOneSide { which: "prior" }),
        (None, Some(_)) => return Err(OnlineRunError::FrictionOnOneSide { which: "true" }),
    };
    let terrain = plane_series(prior)?;
    let mut options = options.clone();
    options.session.clearance = prior.robot.clearance_m;
    options.session.tether_length = prior.robot.tether_length_m;
    let (report, session) = simulate_frictional(
        &prior.map,
        &truth.map,
        prior.start,
        prior.goal,
        terrain,
        friction.as_ref(),
        &options,
        observe,
    )?;
    Ok(OnlineRun { report, session })
}
