//! The tether friction cone of a holonomic point robot (thesis §2.4.2, eq. 2.7, after
//! Abad-Manterola): the first [`AnchorTraversability`] model.
//!
//! # Derivation (thesis Fig. 2.19)
//! On a plane of slope `eta` a point robot of mass `m` feels, in the plane, gravity
//! `G = m g sin(eta)` down the fall line, the tether tension `T >= 0` along the unit vector `u` from
//! the robot to its proximal anchor, and a friction force `f` with `|f| <= mu N`, `N = m g cos(eta)`.
//! It holds when some `T >= 0` makes `|T u + G| <= mu N`. If the tether points at `theta` from the
//! fall line (the anchor is above the robot, `u` at `theta` from up-slope), the smallest residual
//! over `T` is `m g sin(eta) sin(theta)` for `theta <= pi/2` (the distance from `-G` to the ray of
//! `T u`), and `m g sin(eta)` beyond. So the robot holds exactly when
//!
//! ```text
//! sin(theta) <= mu cot(eta),   i.e.   |theta| <= theta_max = asin(mu cot eta)      (eq. 2.7)
//! ```
//!
//! and when `mu cot(eta) >= 1` (equivalently `mu cos(eta) >= sin(eta)`, friction alone holds the
//! robot) every direction is allowed: the plane is **tether-free** for this robot. The mass and
//! gravity cancel. The comparison is made as `mu cos(eta) >= sin(eta)`, which stays finite on flat
//! ground where `cot(eta)` is infinite.

use crate::anchor_traversability::{AnchorTraversability, TetherLimit};
use crate::robot::SlopePlane;

/// The point-robot tether friction cone of thesis eq. 2.7.
///
/// ```
/// use rappel_mechanics::anchor_traversability::{AnchorTraversability, TetherLimit};
/// use rappel_mechanics::friction_cone::TetherFrictionCone;
/// use rappel_mechanics::robot::SlopePlane;
/// let cone = TetherFrictionCone;
/// // mu 0.4 on 45 degrees (thesis Fig. 2.36): theta_max = asin(0.4) = 23.58 degrees.
/// let limit = cone.tether_limit(&SlopePlane::new(45f64.to_radians(), 0.4).unwrap());
/// assert!((limit.max_angle().unwrap() - 0.4f64.asin()).abs() < 1e-12);
/// // mu 0.4 on 20 degrees: mu cot(eta) = 1.1 >= 1, tether-free.
/// let flat = cone.tether_limit(&SlopePlane::new(20f64.to_radians(), 0.4).unwrap());
/// assert_eq!(flat, TetherLimit::TetherFree);
/// ```
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct TetherFrictionCone;

impl TetherFrictionCone {
    /// `theta_max = asin(mu cot eta)` in radians, or `None` when the plane is tether-free.
    pub fn max_tether_angle(plane: &SlopePlane) -> Option<f64> {
        let (s, c) = plane.slope().sin_cos();
        let holding = plane.friction() * c;
        (holding < s).then(|| (holding / s).asin())
    }
}

impl AnchorTraversability for TetherFrictionCone {
    fn name(&self) -> &str {
        "tether friction cone (point robot, thesis eq. 2.7)"
    }

    fn tether_limit(&self, plane: &SlopePlane) -> TetherLimit {
        match Self::max_tether_angle(plane) {
            Some(max_angle) => TetherLimit::Cone { max_angle },
            None => TetherLimit::TetherFree,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector2;

    /// Independent check of eq. 2.7 by the force balance itself: does some tension `T >= 0`
    /// leave a residual within the friction disc? Scanned over `T` on a fine grid.
    fn holds_by_force_balance(eta: f64, mu: f64, theta: f64) -> bool {
        let gravity = Vector2::new(0.0, -eta.sin());
        let u = Vector2::new(theta.sin(), theta.cos());
        let friction = mu * eta.cos();
        (0..=20_000)
            .map(|i| i as f64 * 1e-4)
            .any(|t| (u * t + gravity).norm() <= friction + 1e-9)
    }

    #[test]
    fn the_cone_matches_the_force_balance() {
        for &(eta_deg, mu) in &[
            (45.0, 0.4),
            (45.0, 0.3),
            (60.0, 0.3),
            (35.0, 0.5),
            (70.0, 0.8),
        ] {
            let eta: f64 = f64::to_radians(eta_deg);
            let plane = SlopePlane::new(eta, mu).unwrap();
            let theta_max = TetherFrictionCone::max_tether_angle(&plane).expect("tether-demand");
            for k in 1..40 {
                let theta = k as f64 * 0.04;
                if (theta - theta_max).abs() < 0.01 {
                    continue;
                }
                assert_eq!(
                    holds_by_force_balance(eta, mu, theta),
                    theta < theta_max,
                    "eta {eta_deg}, mu {mu}, theta {theta}"
                );
            }
        }
    }

    #[test]
    fn tether_free_exactly_when_friction_alone_holds() {
        for &(eta_deg, mu, free) in &[
            (0.0, 0.0, true),
            (20.0, 0.4, true),
            (21.8, 0.4, true),
            (22.0, 0.4, false),
            (45.0, 1.0, true),
            (45.0, 0.99, false),
        ] {
            let plane = SlopePlane::new(f64::to_radians(eta_deg), mu).unwrap();
            let limit = TetherFrictionCone.tether_limit(&plane);
            assert_eq!(!limit.is_tether_demand(), free, "eta {eta_deg}, mu {mu}");
            assert_eq!(holds_by_force_balance(plane.slope(), mu, 3.0), free);
        }
    }
}
