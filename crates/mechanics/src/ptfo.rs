//! Classifying a potential tether friction obstacle (PTFO) under a tether configuration as a solid
//! obstacle, one the tether slides over, or a volatile one (thesis §3.4.1, Alg. 9, §3.6.1).
//!
//! # Math
//! With `I(μ) = ∫ω ds` over the tether's contact with the PTFO (eq. 3.17) and the tension
//! assumptions `T_min <= T_d - ε < T_d + ε <= T_max` (§3.4.1):
//!
//! 1. **solid** if the tether holds against the most extreme tension difference with the lowest
//!    friction: conditions 1-2 hold with `μ_lo` and `T_max < T_min e^{I(μ_lo)}`;
//! 2. **slides** if even the highest friction cannot hold a normal driving change: conditions 1-2
//!    fail with `μ_hi`, or `T_d + ε > T_d e^{I(μ_hi)}`;
//! 3. **volatile** otherwise: it holds at driving tensions but a slip or surge frees it.
//!
//! Using `μ_lo` for "will it hold" and `μ_hi` for "will it slide" is the conservative use of a
//! friction interval of §3.6.1: uncertainty moves obstacles into the volatile class only. The
//! ordering `T_d + ε <= T_max`, `T_min <= T_d - ε` makes the two tests exclusive.

use crate::friction::FrictionInterval;
use crate::sticking::{StickingError, TetherSample, contact_holds, omega_integral, tether_slips};
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// Why a PTFO could not be classified.
#[derive(Debug, Error, Clone, Copy, PartialEq)]
pub enum PtfoError {
    /// The tension assumptions are inconsistent; they must satisfy
    /// `0 < T_min <= T_d - ε`, `ε >= 0`, `T_d + ε <= T_max`, all finite.
    #[error(
        "tension assumptions must satisfy 0 < T_min <= T_d - eps <= T_d + eps <= T_max (all finite)"
    )]
    Tensions,
    /// The tether samples are invalid.
    #[error(transparent)]
    Sticking(#[from] StickingError),
}

/// Expected tether tensions while driving (thesis §3.4.1).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct TensionAssumptions {
    t_min: f64,
    t_max: f64,
    t_d: f64,
    epsilon: f64,
}

impl TensionAssumptions {
    /// Minimum and maximum expected tensions, the usual driving tension `t_d` and its deviation
    /// `epsilon` (all N).
    ///
    /// # Example
    /// ```
    /// use rappel_mechanics::ptfo::TensionAssumptions;
    /// assert!(TensionAssumptions::new(50.0, 700.0, 200.0, 20.0).is_ok());
    /// assert!(TensionAssumptions::new(50.0, 700.0, 60.0, 20.0).is_err()); // T_d - eps < T_min
    /// ```
    pub fn new(t_min: f64, t_max: f64, t_d: f64, epsilon: f64) -> Result<Self, PtfoError> {
        let finite = [t_min, t_max, t_d, epsilon].iter().all(|v| v.is_finite());
        if !(finite
            && t_min > 0.0
            && epsilon >= 0.0
            && t_min <= t_d - epsilon
            && t_d + epsilon <= t_max)
        {
            return Err(PtfoError::Tensions);
        }
        Ok(TensionAssumptions {
            t_min,
            t_max,
            t_d,
            epsilon,
        })
    }

    /// `T_min`.
    pub fn t_min(&self) -> f64 {
        self.t_min
    }
    /// `T_max`.
    pub fn t_max(&self) -> f64 {
        self.t_max
    }
    /// `T_d`.
    pub fn t_d(&self) -> f64 {
        self.t_d
    }
    /// `ε`.
    pub fn epsilon(&self) -> f64 {
        self.epsilon
    }
}

/// The class of a PTFO under one tether configuration.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum PtfoClass {
    /// A tether friction obstacle (TFO) that holds under every expected tension.
    Solid,
    /// The tether slides over it at normal driving tension changes: not an obstacle.
    Slides,
    /// Holds at driving tension but not against surges: avoid.
    Volatile,
}

/// Classifies a PTFO from the tether samples in contact with it (see the module docs).
///
/// # Example
/// ```
/// use rappel_mechanics::friction::FrictionInterval;
/// use rappel_mechanics::ptfo::{classify, PtfoClass, TensionAssumptions};
/// use rappel_mechanics::sticking::TetherSample;
/// // Half a turn over a 0.5 m round boulder: I = μ π.
/// let wrap = [TetherSample { normal_curvature: -2.0, geodesic_curvature: 0.0, ds: 0.5 * std::f64::consts::PI }];
/// let tensions = TensionAssumptions::new(100.0, 300.0, 200.0, 20.0).unwrap();
/// let mu = FrictionInterval::new(0.4, 0.5).unwrap();
/// assert_eq!(classify(&wrap, mu, &tensions).unwrap(), PtfoClass::Solid); // e^{0.4π} = 3.5 > 3
/// ```
pub fn classify(
    samples: &[TetherSample],
    mu: FrictionInterval,
    tensions: &TensionAssumptions,
) -> Result<PtfoClass, PtfoError> {
    let (lo, hi) = (mu.for_holding(), mu.for_sliding());
    // Validates the samples and the coefficients before any verdict.
    let integral_lo = omega_integral(samples, lo)?;
    omega_integral(samples, hi)?;
    let contact = contact_holds(samples);
    // Alg. 9 accepts the limiting case; solidity needs the strict `T_max < T_min e^{I}` of §3.4.1.
    let holds_hard = contact
        && !tether_slips(samples, lo, tensions.t_min, tensions.t_max)?
        && tensions.t_max < tensions.t_min * integral_lo.exp();
    if holds_hard {
        return Ok(PtfoClass::Solid);
    }
    let slides =
        !contact || tether_slips(samples, hi, tensions.t_d, tensions.t_d + tensions.epsilon)?;
    Ok(if slides {
        PtfoClass::Slides
    } else {
        PtfoClass::Volatile
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wrap(angle: f64, kg: f64) -> Vec<TetherSample> {
        vec![TetherSample {
            normal_curvature: -1.0,
            geodesic_curvature: kg,
            ds: angle,
        }]
    }

    #[test]
    fn classes_follow_the_three_rules() {
        let t = TensionAssumptions::new(100.0, 400.0, 200.0, 20.0).unwrap();
        let mu = FrictionInterval::exact(0.4).unwrap();
        // ln 4 / 0.4 = 3.47 rad needed for solid; ln 1.1 / 0.4 = 0.238 rad to hold driving changes.
        assert_eq!(classify(&wrap(3.6, 0.0), mu, &t).unwrap(), PtfoClass::Solid);
        assert_eq!(
            classify(&wrap(3.3, 0.0), mu, &t).unwrap(),
            PtfoClass::Volatile
        );
        assert_eq!(
            classify(&wrap(0.2, 0.0), mu, &t).unwrap(),
            PtfoClass::Slides
        );
        // Outside the friction cone: slides whatever the wrap.
        assert_eq!(
            classify(&wrap(10.0, 0.5), mu, &t).unwrap(),
            PtfoClass::Slides
        );
        // Concave contact never holds.
        let concave = vec![TetherSample {
            normal_curvature: 1.0,
            geodesic_curvature: 0.0,
            ds: 10.0,
        }];
        assert_eq!(classify(&concave, mu, &t).unwrap(), PtfoClass::Slides);
    }

    #[test]
    fn friction_uncertainty_only_moves_obstacles_to_volatile() {
        let t = TensionAssumptions::new(100.0, 400.0, 200.0, 20.0).unwrap();
        for angle in [0.1, 0.22, 0.25, 0.5, 2.0, 3.4, 3.5, 4.0, 6.0] {
            let exact =
                classify(&wrap(angle, 0.0), FrictionInterval::exact(0.4).unwrap(), &t).unwrap();
            let wide = classify(
                &wrap(angle, 0.0),
                FrictionInterval::new(0.35, 0.45).unwrap(),
                &t,
            )
            .unwrap();
            assert!(
                wide == exact || wide == PtfoClass::Volatile,
                "angle {angle}: {exact:?} -> {wide:?}"
            );
        }
        assert!(TensionAssumptions::new(100.0, 150.0, 140.0, 20.0).is_err());
        assert!(TensionAssumptions::new(0.0, 150.0, 100.0, 20.0).is_err());
    }
}
