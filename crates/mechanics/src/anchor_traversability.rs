//! The traversability seam of the Chapter-2 planner (thesis §2.4, Definitions 2.1-2.3; GUIDE §2):
//! an [`AnchorTraversability`] model tells a planner, for a plane of the terrain, how far from the
//! fall line the taut tether may point while the robot still holds without slipping.
//!
//! # Anchor reachable sets from a tether limit
//! While anchor `a_j` is the robot's proximal anchor, the taut tether runs straight from `a_j` to
//! the robot. The robot holds at `q` when the tether direction, measured as the angle `theta`
//! between the fall line and the segment from `a_j` down to `q`, stays within the model's limit
//! `theta_max` on the plane under `q` ([`TetherLimit::Cone`]); the set of such points is a wedge
//! below `a_j`, the friction cone of thesis Fig. 2.20. On a *tether-free* plane (thesis §2.1.2) the
//! robot holds anywhere by its wheels alone ([`TetherLimit::TetherFree`]). Planners intersect the
//! wedge with a visibility half-plane and free space to get the anchor reachable set `C_{i,j}`
//! (thesis Def. 2.1), and test passability (Def. 2.3) with the two conditions of §2.4.2,
//! `theta_max_j > psi_j` and `theta_max_{j-1} > psi_j`, through [`TetherLimit::admits`].
//!
//! The first implementation is the thesis' tether friction cone of a point robot
//! ([`crate::friction_cone::TetherFrictionCone`], eq. 2.7); a wheeled model that derives its limit
//! from the stability QP is one more implementation, with no change to the planners.

use crate::robot::SlopePlane;
use serde::{Deserialize, Serialize};

/// How far from the fall line the taut tether may point on one plane.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum TetherLimit {
    /// The robot holds anywhere on this plane without the tether (thesis §2.1.2, §2.2.4).
    TetherFree,
    /// The robot holds only while the tether's angle from the fall line is strictly below
    /// `max_angle` radians (`0 <= max_angle <= pi/2`): the half-angle of the friction cone.
    Cone {
        /// The largest tether angle from the fall line, radians.
        max_angle: f64,
    },
}

impl TetherLimit {
    /// `true` when a taut tether at `psi` radians from the fall line (`psi` in `[0, pi]`) can hold
    /// the robot: always on a tether-free plane, else `psi < max_angle` (the strict inequality of
    /// thesis §2.4.2).
    ///
    /// ```
    /// use rappel_mechanics::anchor_traversability::TetherLimit;
    /// let cone = TetherLimit::Cone { max_angle: 0.4 };
    /// assert!(cone.admits(0.39) && !cone.admits(0.4));
    /// assert!(TetherLimit::TetherFree.admits(std::f64::consts::PI));
    /// ```
    pub fn admits(&self, psi: f64) -> bool {
        match *self {
            TetherLimit::TetherFree => true,
            TetherLimit::Cone { max_angle } => psi < max_angle,
        }
    }

    /// The cone's half-angle, radians; `None` on a tether-free plane.
    pub fn max_angle(&self) -> Option<f64> {
        match *self {
            TetherLimit::TetherFree => None,
            TetherLimit::Cone { max_angle } => Some(max_angle),
        }
    }

    /// `true` on a tether-demand plane (the robot needs the tether to hold).
    pub fn is_tether_demand(&self) -> bool {
        matches!(self, TetherLimit::Cone { .. })
    }
}

/// A traversability model of a tethered robot, as the Chapter-2 planner uses it: the
/// [`TetherLimit`] on each plane. Implementations must be pure functions of the plane.
pub trait AnchorTraversability: Sync {
    /// A short name for reports.
    fn name(&self) -> &str;
    /// The tether limit on `plane`.
    fn tether_limit(&self, plane: &SlopePlane) -> TetherLimit;
}
