//! The seam between planners and stability models (GUIDE §2): a [`StabilityCriterion`] answers
//! "is this placed robot statically stable, and by how much?". The wheel/tether QP
//! ([`crate::stability_qp`], Paton §IV-C) and the tension-limited LP ([`crate::tension_lp`],
//! Kumar §III-B) implement it; a point-robot friction cone (thesis eq. 2.7) can implement it later
//! without touching the planners.

use crate::conic::SolverSettings;
use crate::robot::{PlacedRobot, STANDARD_GRAVITY};
use crate::stability_error::StabilityError;
use serde::{Deserialize, Serialize};

/// A stability verdict with a margin a planner can compare (larger is safer; margins are
/// comparable only between assessments by the same criterion).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Assessment {
    /// The robot can be held in static equilibrium.
    pub stable: bool,
    /// The criterion's margin (0 when not stable); see the criterion's docs.
    pub margin: f64,
    /// The tether tension of the solution (N), if tethered and stable.
    pub tether_tension: Option<f64>,
    /// The solver reported reduced accuracy (`AlmostSolved` / `AlmostPrimalInfeasible`).
    pub reduced_accuracy: bool,
}

/// A static-stability model of a placed robot.
pub trait StabilityCriterion: Sync {
    /// A short name for reports.
    fn name(&self) -> &str;
    /// Assesses `robot`.
    fn assess(&self, robot: &PlacedRobot) -> Result<Assessment, StabilityError>;
}

/// Settings shared by the stability checks: gravity and the solver's settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StabilitySettings {
    gravity: f64,
    solver: SolverSettings,
}

impl Default for StabilitySettings {
    /// Earth gravity ([`STANDARD_GRAVITY`]) and clarabel's defaults.
    fn default() -> Self {
        StabilitySettings {
            gravity: STANDARD_GRAVITY,
            solver: SolverSettings::default(),
        }
    }
}

impl StabilitySettings {
    /// Sets the gravitational acceleration (m/s², finite and positive; 3.71 on Mars, 1.62 on the
    /// Moon).
    pub fn with_gravity(mut self, g: f64) -> Result<Self, StabilityError> {
        if !(g.is_finite() && g > 0.0) {
            return Err(StabilityError::Input("gravity must be finite and positive"));
        }
        self.gravity = g;
        Ok(self)
    }

    /// Sets the solver settings.
    pub fn with_solver(mut self, solver: SolverSettings) -> Self {
        self.solver = solver;
        self
    }

    /// Gravitational acceleration (m/s²).
    pub fn gravity(&self) -> f64 {
        self.gravity
    }

    /// Solver settings.
    pub fn solver(&self) -> SolverSettings {
        self.solver
    }
}
