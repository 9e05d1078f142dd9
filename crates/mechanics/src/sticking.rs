//! Whether a weightless tether can stay put on frictional ground: the friction rate `ω`
//! (thesis eq. 3.17), Konyukhov's three conditions for static equilibrium (eqs. 3.25-3.27) and the
//! thesis' Algorithm 9 (`TetherSlips`).
//!
//! # Math
//! For a weightless rope, Coulomb friction at every point requires (eq. 3.16)
//! `(dT/ds)² <= (μ² κ_n² - κ_g²) T²`, so the rope can only hold where
//! `ω² = μ² κ_n² - κ_g² > 0` (eq. 3.17), equivalently `tan² φ < μ²` (eq. 3.19). Integrating
//! `-ω T <= dT/ds <= ω T` along the contact gives Konyukhov's conditions (thesis §3.3.2):
//!
//! 1. contact: `F_n = -κ_n T > 0` (eq. 3.25; with the outward normal of [`crate::darboux`], the
//!    rope must bend toward the ground, `κ_n < 0`);
//! 2. friction cone: `-μ < tan φ < μ` (eq. 3.26), i.e. `|κ_g| < μ |κ_n|`;
//! 3. end tensions: `T_0 e^{-∫ω ds} <= T <= T_0 e^{∫ω ds}` (eq. 3.27).
//!
//! Straight stretches (`κ` below [`crate::darboux::STRAIGHT_CURVATURE`]) carry no contact force
//! and no tension change; they are neutral for conditions 1-2 and contribute `ω = 0`. We use the
//! closed form of condition 3: the boundary is limiting equilibrium, as in eq. 3.16's `<=`.
//! The integral `∫ω ds` is the sum of `ω_i ds_i` over the samples (each sample stands for the arc
//! length `ds_i` around it, e.g. a midpoint rule).

use crate::darboux::{DarbouxFrame, STRAIGHT_CURVATURE};
use crate::friction::{FrictionError, check_coefficient};
use thiserror::Error;

/// Why a sticking check could not be made.
#[derive(Debug, Error, Clone, Copy, PartialEq)]
pub enum StickingError {
    /// The friction coefficient is invalid.
    #[error(transparent)]
    Friction(#[from] FrictionError),
    /// A tension is not finite and positive (a taut tether has `T > 0`, eq. 3.6).
    #[error("tension {} must be finite and positive", rappel_geometry::compact::Compact(*.0))]
    Tension(f64),
    /// A sample has a non-finite curvature or a negative or non-finite length.
    #[error("tether sample {index} is invalid (non-finite curvature or bad length)")]
    Sample {
        /// Index of the offending sample.
        index: usize,
    },
    /// There are no samples: the tether does not touch the obstacle.
    #[error("no tether samples given")]
    Empty,
}

/// One sample of a tether lying on the ground: its normal and geodesic curvature and the arc
/// length it stands for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TetherSample {
    /// Normal curvature `κ_n` (1/m, negative over a hump; see [`crate::darboux`]).
    pub normal_curvature: f64,
    /// Geodesic curvature `κ_g` (1/m).
    pub geodesic_curvature: f64,
    /// Arc length represented by this sample (m, >= 0).
    pub ds: f64,
}

impl TetherSample {
    /// A sample from a Darboux frame and the arc length it represents.
    pub fn from_frame(frame: &DarbouxFrame, ds: f64) -> Self {
        TetherSample {
            normal_curvature: frame.normal_curvature,
            geodesic_curvature: frame.geodesic_curvature,
            ds,
        }
    }

    fn is_straight(&self) -> bool {
        self.normal_curvature.hypot(self.geodesic_curvature) < STRAIGHT_CURVATURE
    }
}

/// `ω² = μ² κ_n² - κ_g²` (thesis eq. 3.17). Sticking is possible only where it is positive.
///
/// # Example
/// ```
/// use rappel_mechanics::sticking::omega_squared;
/// // A capstan of radius 0.5 m with μ = 0.4: ω = μ/R = 0.8.
/// assert!((omega_squared(-2.0, 0.0, 0.4) - 0.64).abs() < 1e-12);
/// ```
pub fn omega_squared(normal_curvature: f64, geodesic_curvature: f64, mu: f64) -> f64 {
    mu * mu * normal_curvature * normal_curvature - geodesic_curvature * geodesic_curvature
}

/// The friction rate `ω = sqrt(max(ω², 0))` (1/m): the largest relative tension change per unit
/// length the ground can hold (eq. 3.21).
pub fn omega(normal_curvature: f64, geodesic_curvature: f64, mu: f64) -> f64 {
    omega_squared(normal_curvature, geodesic_curvature, mu)
        .max(0.0)
        .sqrt()
}

/// The outcome of Konyukhov's three conditions on one tether configuration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StickingCheck {
    /// Condition 1 (eq. 3.25): the rope presses on the ground everywhere it bends.
    pub contact: bool,
    /// Condition 2 (eq. 3.26): the curve normal lies inside the friction cone everywhere.
    pub friction_cone: bool,
    /// Condition 3 (eq. 3.27): the end tensions are within the capstan bounds.
    pub tension: bool,
    /// `∫ω ds` over the samples.
    pub omega_integral: f64,
}

impl StickingCheck {
    /// All three conditions hold: the rope can stay in static equilibrium.
    pub fn sticks(&self) -> bool {
        self.contact && self.friction_cone && self.tension
    }
}

fn validate(samples: &[TetherSample], mu: f64) -> Result<(), StickingError> {
    check_coefficient(mu)?;
    if samples.is_empty() {
        return Err(StickingError::Empty);
    }
    for (index, s) in samples.iter().enumerate() {
        if !(s.normal_curvature.is_finite()
            && s.geodesic_curvature.is_finite()
            && s.ds.is_finite()
            && s.ds >= 0.0)
        {
            return Err(StickingError::Sample { index });
        }
    }
    Ok(())
}

fn check_tension(t: f64) -> Result<f64, StickingError> {
    if t.is_finite() && t > 0.0 {
        Ok(t)
    } else {
        Err(StickingError::Tension(t))
    }
}

/// `∫ω ds` over the samples for friction coefficient `mu` (the exponent of eqs. 3.24 and 3.27).
pub fn omega_integral(samples: &[TetherSample], mu: f64) -> Result<f64, StickingError> {
    validate(samples, mu)?;
    Ok(samples
        .iter()
        .map(|s| omega(s.normal_curvature, s.geodesic_curvature, mu) * s.ds)
        .sum())
}

/// Condition 1 (eq. 3.25) at every sample (straight samples are neutral).
pub(crate) fn contact_holds(samples: &[TetherSample]) -> bool {
    samples
        .iter()
        .all(|s| s.is_straight() || s.normal_curvature < 0.0)
}

/// Condition 2 (eq. 3.26) at every sample: `|tan φ| < μ`, i.e. `|κ_g| < μ |κ_n|`.
fn cone_holds(samples: &[TetherSample], mu: f64) -> bool {
    samples.iter().all(|s| {
        s.is_straight() || omega_squared(s.normal_curvature, s.geodesic_curvature, mu) > 0.0
    })
}

/// Konyukhov's three conditions (thesis eqs. 3.25-3.27) for a weightless tether with tension
/// `t0` at the start of the samples and `t` at their end.
///
/// # Example
/// ```
/// use rappel_mechanics::sticking::{konyukhov_conditions, TetherSample};
/// // A quarter turn around a capstan of radius 0.5 m (κ_n = -2), μ = 0.4: ratio limit e^{0.2π}.
/// let quarter = std::f64::consts::FRAC_PI_2 * 0.5;
/// let samples = [TetherSample { normal_curvature: -2.0, geodesic_curvature: 0.0, ds: quarter }];
/// assert!(konyukhov_conditions(&samples, 0.4, 100.0, 180.0).unwrap().sticks());
/// assert!(!konyukhov_conditions(&samples, 0.4, 100.0, 190.0).unwrap().sticks());
/// ```
pub fn konyukhov_conditions(
    samples: &[TetherSample],
    mu: f64,
    t0: f64,
    t: f64,
) -> Result<StickingCheck, StickingError> {
    check_tension(t0)?;
    check_tension(t)?;
    let integral = omega_integral(samples, mu)?;
    let ratio = (t / t0).ln().abs();
    Ok(StickingCheck {
        contact: contact_holds(samples),
        friction_cone: cone_holds(samples, mu),
        tension: ratio <= integral,
        omega_integral: integral,
    })
}

/// The thesis' Algorithm 9, `TetherSlips(f, T_small, T_big)`: true when the tether slips with
/// tensions `t_small` and `t_big` at its two ends. Condition 1 is assumed checked when the
/// potential obstacle was found (thesis §3.4.2); this checks condition 2 and then condition 3.
pub fn tether_slips(
    samples: &[TetherSample],
    mu: f64,
    t_small: f64,
    t_big: f64,
) -> Result<bool, StickingError> {
    check_tension(t_small)?;
    check_tension(t_big)?;
    validate(samples, mu)?;
    if !cone_holds(samples, mu) {
        return Ok(true);
    }
    let integral = omega_integral(samples, mu)?;
    Ok(t_big.max(t_small) > t_small.min(t_big) * integral.exp())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn arc(kn: f64, kg: f64, len: f64, n: usize) -> Vec<TetherSample> {
        (0..n)
            .map(|_| TetherSample {
                normal_curvature: kn,
                geodesic_curvature: kg,
                ds: len / n as f64,
            })
            .collect()
    }

    #[test]
    fn omega_matches_tan_phi_criterion() {
        // eq. 3.19: ω² > 0 ⇔ tan²φ < μ², with tan φ = -κ_g/κ_n.
        for &(kn, kg, mu) in &[
            (-1.0, 0.3, 0.4),
            (-1.0, 0.5, 0.4),
            (-2.0, -0.7, 0.4),
            (-0.5, 0.1, 0.1),
        ] {
            let tan_phi: f64 = -kg / kn;
            assert_eq!(omega_squared(kn, kg, mu) > 0.0, tan_phi * tan_phi < mu * mu);
        }
    }

    #[test]
    fn conditions_reject_concave_and_off_cone_curves() {
        let concave = arc(1.0, 0.0, 1.0, 4);
        let c = konyukhov_conditions(&concave, 0.4, 10.0, 10.0).unwrap();
        assert!(!c.contact && !c.sticks());
        let off_cone = arc(-1.0, 0.5, 1.0, 4);
        let c = konyukhov_conditions(&off_cone, 0.4, 10.0, 10.0).unwrap();
        assert!(c.contact && !c.friction_cone && !c.sticks());
        assert!(tether_slips(&off_cone, 0.4, 10.0, 10.0).unwrap());
        // Inside the cone: limit ratio exp(ω L) with ω = sqrt(0.16 - 0.01).
        let ok = arc(-1.0, 0.1, 2.0, 8);
        let limit = (0.15f64.sqrt() * 2.0).exp();
        assert!(!tether_slips(&ok, 0.4, 10.0, 10.0 * limit * 0.999).unwrap());
        assert!(tether_slips(&ok, 0.4, 10.0, 10.0 * limit * 1.001).unwrap());
        // Condition 3 is symmetric in which end is larger (eq. 3.27).
        assert!(
            konyukhov_conditions(&ok, 0.4, 10.0, 10.0 / limit * 1.001)
                .unwrap()
                .sticks()
        );
        assert!(
            !konyukhov_conditions(&ok, 0.4, 10.0, 10.0 / limit * 0.999)
                .unwrap()
                .sticks()
        );
    }

    #[test]
    fn bad_inputs_are_errors() {
        let s = arc(-1.0, 0.0, 1.0, 1);
        assert!(matches!(
            konyukhov_conditions(&s, -0.1, 1.0, 1.0),
            Err(StickingError::Friction(_))
        ));
        assert!(matches!(
            konyukhov_conditions(&s, 0.4, 0.0, 1.0),
            Err(StickingError::Tension(_))
        ));
        assert!(matches!(
            konyukhov_conditions(&[], 0.4, 1.0, 1.0),
            Err(StickingError::Empty)
        ));
        let bad = [TetherSample {
            normal_curvature: f64::NAN,
            geodesic_curvature: 0.0,
            ds: 1.0,
        }];
        assert!(matches!(
            omega_integral(&bad, 0.4),
            Err(StickingError::Sample { index: 0 })
        ));
    }
}
