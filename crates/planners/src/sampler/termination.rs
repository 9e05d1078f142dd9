//! When the anytime planner stops: after a number of iterations, a wall-clock time, or once a
//! solution is at most a cost threshold, whichever comes first (OMPL's planner termination
//! conditions combined with "or").

use std::time::Duration;

use super::settings::SettingsError;
use super::stop::Stop;

/// A termination condition. At least one of iterations or time must be set so that the planning
/// loop is bounded; a cost threshold alone is rejected by [`Termination::validate`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Termination {
    pub(crate) max_iterations: Option<u64>,
    pub(crate) max_time: Option<Duration>,
    pub(crate) cost_threshold: Option<f64>,
}

impl Termination {
    /// Stop after `n` iterations (one iteration processes one edge or starts one search).
    pub fn iterations(n: u64) -> Self {
        Self {
            max_iterations: Some(n),
            ..Self::default()
        }
    }

    /// Stop after wall-clock time `t` (results then depend on the machine's speed).
    pub fn time(t: Duration) -> Self {
        Self {
            max_time: Some(t),
            ..Self::default()
        }
    }

    /// Also stop after `n` iterations.
    pub fn or_iterations(mut self, n: u64) -> Self {
        self.max_iterations = Some(n);
        self
    }

    /// Also stop after wall-clock time `t`.
    pub fn or_time(mut self, t: Duration) -> Self {
        self.max_time = Some(t);
        self
    }

    /// Also stop as soon as a solution of cost `<= c` is found (OMPL's exact-solution /
    /// cost-threshold condition).
    pub fn or_cost_at_most(mut self, c: f64) -> Self {
        self.cost_threshold = Some(c);
        self
    }

    /// Checks that the loop is bounded and the values are meaningful.
    pub fn validate(&self) -> Result<(), SettingsError> {
        if self.max_iterations.is_none() && self.max_time.is_none() {
            return Err(SettingsError::OutOfRange {
                name: "termination",
                value: "no iteration or time limit".into(),
                reason: "an iteration or time limit is required to bound the loop",
            });
        }
        if let Some(c) = self.cost_threshold
            && !(c.is_finite() && c >= 0.0)
        {
            return Err(SettingsError::OutOfRange {
                name: "cost_threshold",
                value: c.to_string(),
                reason: "must be finite and >= 0",
            });
        }
        Ok(())
    }

    /// Why to stop now, if so (a reached cost threshold first, then time, then iterations).
    pub(crate) fn reason(
        &self,
        iterations: u64,
        elapsed: Duration,
        best_cost: f64,
    ) -> Option<Stop> {
        if self.cost_threshold.is_some_and(|c| best_cost <= c) {
            Some(Stop::CostThreshold)
        } else if self.max_time.is_some_and(|t| elapsed >= t) {
            Some(Stop::Time)
        } else if self.max_iterations.is_some_and(|n| iterations >= n) {
            Some(Stop::Iterations)
        } else {
            None
        }
    }
}
