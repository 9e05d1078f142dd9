//! The tension a tether can deliver to a rappelling robot when it is held by a second robot and by
//! winding around anchors (Kumar §II, eqs. 1-2, Definitions 2-3).
//!
//! # Math
//! The holding robot (Robot 1, on flat ground) resists `T_1 <= F_0 + μ_s0 m_1 g` (eq. 1), `F_0`
//! being the pull its wheels can add. Winding over anchors `a_j` with winding angles `φ_j` amplifies
//! this by the capstan effect (thesis eq. 3.20) anchor by anchor:
//! `T_2 <= T_2max = (F_0 + μ_s0 m_1 g) exp(Σ_j μ_aj |φ_j|)` (eq. 2). The winding angle at an
//! interior anchor is the angle between the incoming and outgoing straight tether segments,
//! `φ_j = acos((a_j - a_{j-1})·(a_{j+1} - a_j) / (|a_j - a_{j-1}| |a_{j+1} - a_j|))`.

use crate::capstan::amplification;
use crate::friction::{FrictionError, check_coefficient};
use nalgebra::Point3;
use thiserror::Error;

/// Why a tension limit could not be computed.
#[derive(Debug, Error, Clone, Copy, PartialEq)]
pub enum TensionLimitError {
    /// A friction coefficient is invalid.
    #[error(transparent)]
    Friction(#[from] FrictionError),
    /// A force, mass or gravity is not finite and non-negative.
    #[error("holding robot parameter `{0}` must be finite and >= 0")]
    Parameter(&'static str),
    /// Two consecutive anchors coincide, so a winding angle is undefined; merge them.
    #[error("anchors {0} and {1} coincide")]
    DuplicateAnchor(usize, usize),
    /// An anchor coordinate is not finite.
    #[error("anchor {0} is not finite")]
    NonFiniteAnchor(usize),
}

/// The holding robot of Kumar eq. 1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HoldingRobot {
    /// Extra pull its wheels can exert, `F_0` (N).
    pub max_pull: f64,
    /// Friction coefficient of its ground, `μ_s0`.
    pub friction: f64,
    /// Its mass `m_1` (kg).
    pub mass: f64,
}

impl HoldingRobot {
    /// The largest tether tension it holds, `F_0 + μ_s0 m_1 g` (Kumar eq. 1).
    pub fn holding_limit(&self, gravity: f64) -> Result<f64, TensionLimitError> {
        check_coefficient(self.friction)?;
        for (v, name) in [
            (self.max_pull, "max_pull"),
            (self.mass, "mass"),
            (gravity, "gravity"),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(TensionLimitError::Parameter(name));
            }
        }
        Ok(self.max_pull + self.friction * self.mass * gravity)
    }
}

/// The winding angles `φ_j` at the interior anchors of the tether polyline `anchors` (Kumar's
/// definition before eq. 1); the two end points have none. Returns `anchors.len() - 2` angles
/// (none for fewer than three points).
///
/// # Example
/// ```
/// use nalgebra::Point3;
/// use rappel_mechanics::tension_limit::winding_angles;
/// let a = [Point3::new(0.0, 0.0, 0.0), Point3::new(1.0, 0.0, 0.0), Point3::new(1.0, 1.0, 0.0)];
/// assert!((winding_angles(&a).unwrap()[0] - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
/// ```
pub fn winding_angles(anchors: &[Point3<f64>]) -> Result<Vec<f64>, TensionLimitError> {
    if let Some(i) = anchors
        .iter()
        .position(|a| !a.iter().all(|c| c.is_finite()))
    {
        return Err(TensionLimitError::NonFiniteAnchor(i));
    }
    anchors
        .windows(3)
        .enumerate()
        .map(|(j, w)| {
            let (u, v) = (w[1] - w[0], w[2] - w[1]);
            let (nu, nv) = (u.norm(), v.norm());
            if nu == 0.0 {
                return Err(TensionLimitError::DuplicateAnchor(j, j + 1));
            }
            if nv == 0.0 {
                return Err(TensionLimitError::DuplicateAnchor(j + 1, j + 2));
            }
            Ok((u.dot(&v) / (nu * nv)).clamp(-1.0, 1.0).acos())
        })
        .collect()
}

/// `T_2max = holding_limit · exp(Σ_j μ_aj |φ_j|)` (Kumar eq. 2) for windings `(μ_aj, φ_j)`.
///
/// # Example
/// ```
/// use rappel_mechanics::tension_limit::tension_limit;
/// let t = tension_limit(100.0, &[(0.4, std::f64::consts::PI)]).unwrap();
/// assert!((t - 100.0 * (0.4 * std::f64::consts::PI).exp()).abs() < 1e-9);
/// ```
pub fn tension_limit(
    holding_limit: f64,
    windings: &[(f64, f64)],
) -> Result<f64, TensionLimitError> {
    if !(holding_limit.is_finite() && holding_limit >= 0.0) {
        return Err(TensionLimitError::Parameter("holding_limit"));
    }
    windings.iter().try_fold(holding_limit, |t, &(mu, phi)| {
        if !phi.is_finite() {
            return Err(TensionLimitError::Parameter("winding angle"));
        }
        Ok(t * amplification(mu, phi)?)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_full_turn_around_a_square_post_is_two_pi() {
        let a = [
            Point3::new(-1.0, 0.0, 0.0),
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(0.0, 1.0, 0.0),
            Point3::new(-1.0, 1.0, 0.0),
            Point3::new(-1.0, 0.0, 0.0),
            Point3::new(0.0, 0.0, 0.0),
        ];
        let phis = winding_angles(&a).unwrap();
        assert!((phis.iter().sum::<f64>() - std::f64::consts::TAU).abs() < 1e-12);
        let holding = HoldingRobot {
            max_pull: 50.0,
            friction: 0.4,
            mass: 35.0,
        }
        .holding_limit(9.81)
        .unwrap();
        assert!((holding - (50.0 + 0.4 * 35.0 * 9.81)).abs() < 1e-12);
        let windings: Vec<_> = phis.iter().map(|p| (0.4, *p)).collect();
        let t = tension_limit(holding, &windings).unwrap();
        assert!((t / holding - (0.4 * std::f64::consts::TAU).exp()).abs() < 1e-9);
        assert!(
            winding_angles(&[
                Point3::origin(),
                Point3::origin(),
                Point3::new(1.0, 0.0, 0.0)
            ])
            .is_err()
        );
        assert!(
            HoldingRobot {
                max_pull: -1.0,
                friction: 0.4,
                mass: 1.0
            }
            .holding_limit(9.81)
            .is_err()
        );
    }
}
