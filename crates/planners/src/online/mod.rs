//! Online planning with map changes discovered during the descent (thesis §3.5, Alg. 11-13;
//! online paper §III, Alg. 1-3). Definitions and choices are collected in `docs/online.md`.
//!
//! | module | computes | source |
//! |---|---|---|
//! | [`change`] | map changes: new, phantom, reshaped obstacles, changed boundary | §3.5.2 |
//! | [`classify`] | the case of a change against the current sleeve, from its sides | §3.5.3 |
//! | [`replan`] | H-signature constraints, junctions, backtracking, continuations | Alg. 13 |
//! | [`session`] | the session: BTM, class, progress, constraints, deferred updates | Alg. 11-13 |
//! | [`mod@simulate`] | a descent on a prior map with the true map revealed within sensor range | §IV |
//!
//! ```
//! use nalgebra::Point2;
//! use rappel_geometry::{map::Map, polygon::Polygon};
//! use rappel_planners::online::{MapChange, OnlineOptions, OnlineSession, ChangeCase};
//! use rappel_planners::terrain::PlaneSeries;
//! let p = |x, y| Point2::new(x, y);
//! let map = Map::new(Polygon::new(vec![p(0., 0.), p(20., 0.), p(20., 40.), p(0., 40.)]), vec![]);
//! let mut session = OnlineSession::new(&map, p(10., 38.), p(10., 2.), PlaneSeries::flat(),
//!     OnlineOptions::default()).unwrap();
//! session.advance(5.0);
//! // A rock right on the straight way down: the sleeve splits around it.
//! let rock = Polygon::new(vec![p(9., 20.), p(11., 20.), p(10., 22.)]);
//! let out = session.apply(&MapChange::Add(rock)).unwrap();
//! assert_eq!(out[0].case, ChangeCase::Split);
//! while session.advance(1.0) > 0.0 {}
//! assert_eq!(session.robot(), p(10., 2.));
//! assert!(session.ascent_descent_homotopic().unwrap());
//! ```

pub mod change;
pub mod classify;
pub mod replan;
pub mod session;
pub mod simulate;

pub use change::MapChange;
pub use classify::ChangeCase;
pub use session::{ChangeOutcome, ClearanceShortfall, Decision, OnlineSession, Status};
pub use simulate::{SimulationOptions, SimulationReport, simulate, simulate_with};

use crate::spt::{SearchError, SearchOptions};
use nalgebra::Point2;
use rappel_geometry::btm::BtmError;
use rappel_geometry::map::MapError;
use rappel_homotopy::{HomotopyError, PathError};
use serde::Serialize;

/// Default number of classes each (re)planning search examines beyond the rejected ones.
pub const DEFAULT_ONLINE_CLASSES: usize = 8;

/// Settings of an online session.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OnlineOptions {
    /// The SPT search of every (re)plan: its class count (raised by the number of rejected
    /// classes), length factor and expansion budget are the termination rule of a "no".
    pub search: SearchOptions,
    /// Clearance of the ascent/descent pair, m.
    pub clearance: f64,
    /// Beyond the thesis: switch to a shorter class a removal opened when it saves more than
    /// the backtracking costs (off by default; the outcome reports it either way).
    pub switch_to_shorter: bool,
    /// The robot's tether length, m (`None`: unlimited): a class whose taut tether is longer is
    /// infeasible, as in the offline planner ([`crate::feasibility::FeasibilityContext`]).
    pub tether_length: Option<f64>,
}

impl Default for OnlineOptions {
    /// [`DEFAULT_ONLINE_CLASSES`] classes, the search's default expansion budget, 0.5 m
    /// clearance, no switching.
    fn default() -> Self {
        OnlineOptions {
            search: SearchOptions::default()
                .with_max_classes(Some(DEFAULT_ONLINE_CLASSES))
                .unwrap_or_default(),
            clearance: 0.5,
            switch_to_shorter: false,
            tether_length: None,
        }
    }
}

impl OnlineOptions {
    /// Checks the clearance (finite, `>= 0`) and the tether length (finite, `> 0`).
    pub fn validate(&self) -> Result<(), OnlineError> {
        if let Some(l) = self.tether_length
            && !(l.is_finite() && l > 0.0)
        {
            return Err(OnlineError::Option(format!(
                "tether length {l} must be a finite number > 0"
            )));
        }
        if !(self.clearance.is_finite() && self.clearance >= 0.0) {
            return Err(OnlineError::Option(format!(
                "clearance {} must be a finite number >= 0",
                self.clearance
            )));
        }
        Ok(())
    }
}

/// Why the session refused a change or could not run.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum OnlineError {
    /// The change's outline covers the robot.
    #[error("the change covers the robot at ({}, {})", at.x, at.y)]
    CoversRobot {
        /// The robot's position.
        at: Point2<f64>,
    },
    /// The change's outline covers the start (the anchor).
    #[error("the change covers the start (the tether anchor) at ({}, {})", at.x, at.y)]
    CoversStart {
        /// The start.
        at: Point2<f64>,
    },
    /// The change's outline meets the tether already laid.
    #[error("the change meets the laid tether near ({}, {})", at.x, at.y)]
    CoversTether {
        /// The first point of the tether segment it meets.
        at: Point2<f64>,
    },
    /// A new boundary leaves the robot, start or goal outside.
    #[error("the new boundary leaves the {which} at ({}, {}) outside", at.x, at.y)]
    OutsideNewBoundary {
        /// `robot`, `start` or `goal`.
        which: &'static str,
        /// The point.
        at: Point2<f64>,
    },
    /// The map or a new outline is invalid.
    #[error(transparent)]
    Map(#[from] MapError),
    /// The local update or the build was refused.
    #[error(transparent)]
    Btm(#[from] BtmError),
    /// The search refused its input.
    #[error(transparent)]
    Search(#[from] SearchError),
    /// A homotopy computation failed on a path.
    #[error(transparent)]
    Homotopy(#[from] HomotopyError),
    /// A path is invalid.
    #[error(transparent)]
    Path(#[from] PathError),
    /// An option is out of range.
    #[error("invalid option: {0}")]
    Option(String),
    /// The friction model or a frictional check failed (the frictional error's message).
    #[error("friction: {0}")]
    Friction(String),
    /// A bug, reported instead of a panic.
    #[error("internal error: {0}")]
    Internal(String),
}

impl From<crate::frictional::FrictionalError> for OnlineError {
    fn from(e: crate::frictional::FrictionalError) -> Self {
        OnlineError::Friction(e.to_string())
    }
}
