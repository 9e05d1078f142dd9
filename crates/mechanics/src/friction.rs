//! Coulomb friction coefficients known only as an interval (thesis §3.6.1, "Risk mitigation via a
//! conservative model"): questions of the form "will it hold?" use the lowest coefficient, and
//! "will it slide?" the highest, so that friction-modelling errors only ever make the answer more
//! cautious.

use serde::{Deserialize, Serialize};
use thiserror::Error;

/// Why a friction coefficient or interval was rejected.
#[derive(Debug, Error, Clone, Copy, PartialEq)]
pub enum FrictionError {
    /// A coefficient is negative, NaN or infinite; use a finite `μ >= 0`.
    #[error("friction coefficient {} must be finite and non-negative", rappel_geometry::compact::Compact(*.0))]
    Invalid(f64),
    /// The interval's lower end exceeds its upper end; swap them.
    #[error("friction interval [{lo}, {hi}] is empty")]
    Empty {
        /// Lower end.
        lo: f64,
        /// Upper end.
        hi: f64,
    },
}

/// A closed interval `[lo, hi]` of Coulomb friction coefficients (`0 <= lo <= hi`, finite).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct FrictionInterval {
    lo: f64,
    hi: f64,
}

impl FrictionInterval {
    /// The interval `[lo, hi]`.
    ///
    /// # Example
    /// ```
    /// use rappel_mechanics::friction::FrictionInterval;
    /// let mu = FrictionInterval::new(0.25, 0.45).unwrap();
    /// assert_eq!((mu.for_holding(), mu.for_sliding()), (0.25, 0.45));
    /// assert!(FrictionInterval::new(0.5, 0.4).is_err());
    /// ```
    pub fn new(lo: f64, hi: f64) -> Result<Self, FrictionError> {
        check_coefficient(lo)?;
        check_coefficient(hi)?;
        if lo > hi {
            return Err(FrictionError::Empty { lo, hi });
        }
        Ok(FrictionInterval { lo, hi })
    }

    /// A single known coefficient.
    pub fn exact(mu: f64) -> Result<Self, FrictionError> {
        Self::new(mu, mu)
    }

    /// The coefficient to use when asking "will it hold?" (the lowest).
    pub fn for_holding(&self) -> f64 {
        self.lo
    }

    /// The coefficient to use when asking "will it slide?" (the highest).
    pub fn for_sliding(&self) -> f64 {
        self.hi
    }
}

/// Checks that `mu` is a usable Coulomb coefficient (finite, non-negative).
pub fn check_coefficient(mu: f64) -> Result<f64, FrictionError> {
    if mu.is_finite() && mu >= 0.0 {
        Ok(mu)
    } else {
        Err(FrictionError::Invalid(mu))
    }
}
