//! Typed reasons of the plan report (thesis Alg. 5 and 6): why an anchor cannot be passed
//! ([`Blocked`]), whether each anchor was passed ([`AnchorPassability`]), and a class's ascent
//! verdict ([`AscentVerdict`]); and how a frictional plan's anchor holds ([`AnchorHold`]). Each is an enum with its data in the report's units (degrees,
//! metres), serialised as an object tagged by `kind`, and its `Display` is the sentence the text
//! output prints. Why a feasible class got no ascent/descent pair is the planner's own typed
//! [`PairFailure`].
//!
//! ```
//! use rappel::verdict::{AscentVerdict, Blocked, BlockedAnchor};
//! let v = AscentVerdict::Blocked {
//!     anchor: Some(BlockedAnchor { index: 2, vertex: 17, obstacle: Some(4) }),
//!     reason: Blocked::NoVisibilityEdge { psi_deg: 61.5, theta_max_deg: 45.0 },
//! };
//! assert_eq!(
//!     v.to_string(),
//!     "anchor 2 (vertex 17 on obstacle 4): no visibility edge: psi 61.50° >= theta_max 45.00° of its plane"
//! );
//! assert!(!v.is_feasible());
//! let json = serde_json::to_value(&v).unwrap();
//! assert_eq!(json["kind"], "blocked");
//! assert_eq!(json["reason"]["kind"], "no_visibility_edge");
//! ```

use crate::report::deg;
use rappel_mechanics::ptfo::PtfoClass;
pub use rappel_planners::feasibility::{Impassability, Passability};
use rappel_planners::frictional::anchor_check::AnchorVerdict;
pub use rappel_planners::path_pair::PairFailure;
use serde::{Deserialize, Serialize};
use std::fmt;

/// Why an anchor (or the goal) cannot be passed: the planner's [`Impassability`] in degrees and
/// metres.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Blocked {
    /// The taut tether cannot hold the robot at the goal: its last segment is `psi_deg` from the
    /// fall line, beyond the goal plane's `theta_max_deg`.
    GoalOutsideReachableSet {
        /// Angle of the last tether segment from the fall line, degrees.
        psi_deg: f64,
        /// The goal plane's limit, degrees.
        theta_max_deg: f64,
    },
    /// Condition 1 of §2.4.2: `theta_max_j <= psi_j`, no visibility edge.
    NoVisibilityEdge {
        /// `psi_j`, degrees.
        psi_deg: f64,
        /// `theta_max_j`, degrees.
        theta_max_deg: f64,
    },
    /// Condition 2 of §2.4.2: `theta_max_{j-1} <= psi_j`, crossing the visibility edge leaves
    /// the previous anchor's reachable set.
    OutsidePreviousReachableSet {
        /// `psi_j`, degrees.
        psi_deg: f64,
        /// `theta_max_{j-1}`, degrees.
        theta_max_deg: f64,
    },
    /// The taut tether to the goal is longer than the robot's tether.
    TetherTooShort {
        /// The taut tether's length, m.
        needed_m: f64,
        /// The robot's tether length, m.
        available_m: f64,
    },
    /// Alg. 5 line 14: no point of the visibility edge is reachable from the robot's position.
    NoReachableWaypoint {
        /// The usable visibility edge examined, m.
        usable_m: f64,
    },
}

impl From<Impassability> for Blocked {
    fn from(i: Impassability) -> Self {
        match i {
            Impassability::GoalOutsideReachableSet { psi, max_angle } => {
                Blocked::GoalOutsideReachableSet {
                    psi_deg: deg(psi),
                    theta_max_deg: deg(max_angle),
                }
            }
            Impassability::NoVisibilityEdge { psi, max_angle } => Blocked::NoVisibilityEdge {
                psi_deg: deg(psi),
                theta_max_deg: deg(max_angle),
            },
            Impassability::OutsidePreviousReachableSet { psi, max_angle } => {
                Blocked::OutsidePreviousReachableSet {
                    psi_deg: deg(psi),
                    theta_max_deg: deg(max_angle),
                }
            }
            Impassability::TetherTooShort { needed, available } => Blocked::TetherTooShort {
                needed_m: needed,
                available_m: available,
            },
            Impassability::NoReachableWaypoint { usable } => {
                Blocked::NoReachableWaypoint { usable_m: usable }
            }
        }
    }
}

impl From<Blocked> for Impassability {
    fn from(b: Blocked) -> Self {
        let rad = f64::to_radians;
        match b {
            Blocked::GoalOutsideReachableSet {
                psi_deg,
                theta_max_deg,
            } => Impassability::GoalOutsideReachableSet {
                psi: rad(psi_deg),
                max_angle: rad(theta_max_deg),
            },
            Blocked::NoVisibilityEdge {
                psi_deg,
                theta_max_deg,
            } => Impassability::NoVisibilityEdge {
                psi: rad(psi_deg),
                max_angle: rad(theta_max_deg),
            },
            Blocked::OutsidePreviousReachableSet {
                psi_deg,
                theta_max_deg,
            } => Impassability::OutsidePreviousReachableSet {
                psi: rad(psi_deg),
                max_angle: rad(theta_max_deg),
            },
            Blocked::TetherTooShort {
                needed_m,
                available_m,
            } => Impassability::TetherTooShort {
                needed: needed_m,
                available: available_m,
            },
            Blocked::NoReachableWaypoint { usable_m } => {
                Impassability::NoReachableWaypoint { usable: usable_m }
            }
        }
    }
}

impl fmt::Display for Blocked {
    /// The planner's sentence ([`Impassability::describe`]), one source for both.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&Impassability::from(*self).describe())
    }
}

/// Whether an anchor was passed on the ascent.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum AnchorPassability {
    /// Passed (its waypoint is the anchor report's `waypoint`).
    Passable,
    /// Not passable, and why.
    Impassable {
        /// Why.
        reason: Blocked,
    },
    /// Not examined: the ascent failed lower down.
    NotReached,
}

impl From<Passability> for AnchorPassability {
    fn from(p: Passability) -> Self {
        match p {
            Passability::Passable { .. } => AnchorPassability::Passable,
            Passability::Impassable(r) => AnchorPassability::Impassable { reason: r.into() },
            Passability::NotReached => AnchorPassability::NotReached,
        }
    }
}

impl fmt::Display for AnchorPassability {
    /// `passable`, `impassable: <why>` or `not reached`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            AnchorPassability::Passable => f.write_str("passable"),
            AnchorPassability::Impassable { reason } => write!(f, "impassable: {reason}"),
            AnchorPassability::NotReached => f.write_str("not reached"),
        }
    }
}

/// The anchor that blocks an ascent.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct BlockedAnchor {
    /// `j`, from 1 (nearest the start).
    pub index: usize,
    /// Its BTM vertex.
    pub vertex: usize,
    /// Its obstacle (`None`: the map boundary).
    pub obstacle: Option<usize>,
}

/// A class's ascent verdict (thesis Def. 2.4, Alg. 5).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum AscentVerdict {
    /// Every anchor is passable and the goal is held.
    Feasible,
    /// The ascent is blocked at `anchor` (`None`: at the goal itself) for `reason`.
    Blocked {
        /// The blocking anchor, or `None` for the goal.
        anchor: Option<BlockedAnchor>,
        /// Why.
        reason: Blocked,
    },
}

impl AscentVerdict {
    /// `true` for [`AscentVerdict::Feasible`].
    pub fn is_feasible(&self) -> bool {
        matches!(self, AscentVerdict::Feasible)
    }
}

impl fmt::Display for AscentVerdict {
    /// `feasible`, or the blocking anchor and why (the planner's
    /// [`FeasibilityReport::describe`](rappel_planners::feasibility::FeasibilityReport::describe)).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            AscentVerdict::Feasible => f.write_str("feasible"),
            AscentVerdict::Blocked {
                anchor: None,
                reason,
            } => write!(f, "{reason}"),
            AscentVerdict::Blocked {
                anchor: Some(a),
                reason,
            } => {
                let on = a
                    .obstacle
                    .map_or_else(|| "the map boundary".into(), |o| format!("obstacle {o}"));
                write!(
                    f,
                    "anchor {} (vertex {} on {on}): {reason}",
                    a.index, a.vertex
                )
            }
        }
    }
}

/// How an anchor of a frictional plan holds (thesis §3.3): on a geometric obstacle, or on a
/// potential tether friction obstacle (PTFO) as classified by its friction. Serialised as the
/// lower-case word, which is also its `Display`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum AnchorHold {
    /// A geometric anchor: an obstacle vertex that holds the tether whatever the friction.
    Geometric,
    /// A PTFO that holds under every expected tension (a TFO).
    Solid,
    /// A PTFO the tether slides over at normal tension changes: not an anchor.
    Slides,
    /// A PTFO that holds at driving tension but not against surges.
    Volatile,
}

impl From<AnchorVerdict> for AnchorHold {
    fn from(v: AnchorVerdict) -> Self {
        match v {
            AnchorVerdict::Geometric => AnchorHold::Geometric,
            AnchorVerdict::Friction(PtfoClass::Solid) => AnchorHold::Solid,
            AnchorVerdict::Friction(PtfoClass::Slides) => AnchorHold::Slides,
            AnchorVerdict::Friction(PtfoClass::Volatile) => AnchorHold::Volatile,
        }
    }
}

impl fmt::Display for AnchorHold {
    /// `geometric`, `solid`, `slides` or `volatile`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            AnchorHold::Geometric => "geometric",
            AnchorHold::Solid => "solid",
            AnchorHold::Slides => "slides",
            AnchorHold::Volatile => "volatile",
        })
    }
}
