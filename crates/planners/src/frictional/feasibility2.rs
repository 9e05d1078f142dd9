//! Alg. 10 `CheckFeasibility2` (thesis §3.4.2): the Chapter-2 passability test (Alg. 5,
//! [`crate::feasibility`]) on the SHP left by Alg. 8, with two changes at friction anchors:
//!
//! * **the waypoint is the anchor itself**: the robot may drive over a friction anchor, and
//!   driving around it may make the tether stick on it again; Alg. 5 runs with those anchors as
//!   their own waypoints ([`crate::feasibility::check_feasibility_with`]), so the geometric
//!   clearance never blocks a solid friction anchor;
//! * **the tether must stick over the ascent sweep**: as the robot climbs toward `a_j` its tether
//!   direction at `a_j` sweeps from the SHP's (or the far limit `θ_max`) to the visibility line
//!   `ψ_j`, where the turn at `a_j` is 0.
//!
//! # Decided exactly, by monotonicity
//! On the wrap model ([`rappel_mechanics::ptfo_surface`]) the integrand of `∫ω ds` is constant, so
//! `I(α) = c α` with `c = I(θ)/θ` for any turn `α` at `a_j`; condition 2 (the friction cone) does
//! not depend on `α`. The tether therefore holds the driving change `T_d → T_d + ε` (Alg. 10
//! line 7) exactly for the turns `α >= α_r = ln((T_d + ε)/T_d) / c`, every turn above the release
//! turn `α_r` at once. Below `α_r` the tether slides off `a_j` before the robot reaches it: an early
//! release. It is safe iff the robot is then already held by `a_{j-1}`: the robot's tether
//! directions from `a_{j-1}` over the release wedge (directions from `a_j` within `α_r` of `ψ_j`,
//! on the anchor's side) run from `ψ_j` to `ψ_j` rotated by `α_r`, so it suffices and is necessary
//! (for an unbounded wedge) that both ends lie in `a_{j-1}`'s tether limit. No sampling, and no
//! float angle compared: each end is put inside or outside the limit's wedge by the exact test
//! Alg. 5 uses ([`admits_direction`]), on the input points and on the turned direction as
//! computed (the turn `α_r` itself is transcendental).

use super::FrictionModel;
use super::anchor_check::{AnchorVerdict, PtfoCheck};
use crate::feasibility::{
    FeasibilityContext, FeasibilityReport, Passability, admits_direction, check_feasibility_with,
};
use nalgebra::{Point2, Rotation2, Vector2};
use rappel_homotopy::funnel::Side;
use rappel_mechanics::anchor_traversability::TetherLimit;
use rappel_mechanics::ptfo::PtfoClass;
use serde::{Deserialize, Serialize};

/// The ascent sweep at one friction anchor.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct SweepCheck {
    /// `j`, from 1 (nearest the start).
    pub index: usize,
    /// The turn at the SHP, radians (reported in degrees).
    #[serde(rename = "turn_deg", with = "crate::report_units::radians_as_degrees")]
    #[schemars(with = "f64")]
    pub turn: f64,
    /// `α_r`: below this turn the tether slides off the anchor, radians (reported in degrees).
    #[serde(
        rename = "release_turn_deg",
        with = "crate::report_units::radians_as_degrees"
    )]
    #[schemars(with = "f64")]
    pub release_turn: f64,
    /// Whether the early release is covered by the previous anchor's tether limit.
    pub release_safe: bool,
}

/// The outcome of Alg. 10 for one class.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Feasibility2Report {
    /// Alg. 5 on the final SHP (passability, reachable sets, its own waypoints).
    pub base: FeasibilityReport,
    /// The waypoints in ascent order, friction anchors at the anchor itself.
    pub waypoints: Vec<Point2<f64>>,
    /// The sweep at every friction anchor.
    pub sweeps: Vec<SweepCheck>,
    /// `None` when feasible, else why not.
    pub blocked: Option<String>,
}

impl Feasibility2Report {
    /// `true` when the class can be ascended.
    pub fn feasible(&self) -> bool {
        self.blocked.is_none()
    }
}

/// `true` when the tether limit `limit` of `a_{j-1}` holds both ends of the release wedge: the
/// tether's direction `prev -> anchor` (`a_{j-1} -> a_j`) and that direction turned by the release
/// turn (`rotated`, computed). Each is decided exactly, as Alg. 5 decides wedges
/// ([`admits_direction`]: the wedge's edge directions and Shewchuk's predicates), on the input
/// points and on the computed vector as it stands, so no float angle is compared.
fn release_held(
    limit: &TetherLimit,
    prev: &Point2<f64>,
    anchor: &Point2<f64>,
    rotated: &Vector2<f64>,
) -> bool {
    admits_direction(limit, prev, anchor)
        && admits_direction(limit, &Point2::origin(), &Point2::from(*rotated))
}

/// Alg. 10 on the result of Alg. 8 (module docs). `ctx.btm` must be the BTM the check ended on.
pub fn check_feasibility2(
    ctx: &FeasibilityContext<'_>,
    model: &FrictionModel,
    check: &PtfoCheck,
) -> Feasibility2Report {
    // Solid friction anchors are their own waypoints, with no clearance (module docs).
    let solid = |j: usize| {
        check
            .anchors
            .get(j - 1)
            .is_some_and(|d| d.verdict == AnchorVerdict::Friction(PtfoClass::Solid))
    };
    let base = check_feasibility_with(ctx, &check.taut, &solid);
    let mut blocked = (!base.feasible()).then(|| base.describe());
    let ln_drive = ((model.tensions.t_d() + model.tensions.epsilon()) / model.tensions.t_d()).ln();
    let mut sweeps = Vec::new();
    let mut friction_waypoint = vec![None; base.anchors.len()];
    for (k, d) in check.anchors.iter().enumerate() {
        if d.verdict != AnchorVerdict::Friction(PtfoClass::Solid) {
            continue;
        }
        let Some(assess) = base.anchors.get(k) else {
            continue;
        };
        friction_waypoint[k] = Some(d.anchor.point);
        let turn = d.anchor.turning_angle;
        let c = d.omega_integral_hold / turn;
        let release_turn = if c > 0.0 { ln_drive / c } else { f64::INFINITY };
        let prev = if k == 0 {
            check.taut.points[0]
        } else {
            check.anchors[k - 1].anchor.point
        };
        let u = d.anchor.point - prev;
        let sign = if d.anchor.side == Side::Left {
            1.0
        } else {
            -1.0
        };
        let rotated = Rotation2::new(sign * release_turn.min(turn)) * u;
        let release_safe = release_turn < turn
            && release_held(&assess.previous_limit, &prev, &d.anchor.point, &rotated);
        if !release_safe && blocked.is_none() {
            blocked = Some(format!(
                "friction anchor {} at ({:.3}, {:.3}): it releases {:.1} deg before the \
                 visibility line, outside the previous anchor's tether limit",
                k + 1,
                d.anchor.point.x,
                d.anchor.point.y,
                release_turn.to_degrees()
            ));
        }
        sweeps.push(SweepCheck {
            index: k + 1,
            turn,
            release_turn,
            release_safe,
        });
    }
    // Waypoints: base order passes a_n first; friction anchors are their own waypoint.
    let mut waypoints = Vec::new();
    for (k, a) in base.anchors.iter().enumerate().rev() {
        if let Some(p) = friction_waypoint[k] {
            waypoints.push(p);
        } else if let Passability::Passable { waypoint, .. } = a.passability {
            waypoints.push(waypoint);
        }
    }
    Feasibility2Report {
        base,
        waypoints,
        sweeps,
        blocked,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::feasibility::wedge_edges;

    /// Directions on an edge of the wedge and one ulp either side: the verdict follows the exact
    /// side (strictly inside the open wedge), whether the direction is given by two points or as a
    /// computed vector. The reference: each direction differs from the edge direction `(s, -c)` only
    /// in `x`, so it is inside exactly when its `|x|` is below `s`.
    #[test]
    fn the_release_wedge_is_decided_on_the_exact_side_of_its_edges() {
        let o = Point2::origin();
        for max_angle in [0.1_f64, 0.342_345_678, 0.5, 0.9, 1.2] {
            let limit = TetherLimit::Cone { max_angle };
            let [right, left] = wedge_edges(max_angle);
            for edge in [right, left] {
                let (s, c) = (edge.x, edge.y);
                let inside = Vector2::new(if s > 0.0 { s.next_down() } else { s.next_up() }, c);
                let outside = Vector2::new(if s > 0.0 { s.next_up() } else { s.next_down() }, c);
                let held = |v: &Vector2<f64>| release_held(&limit, &o, &Point2::from(*v), v);
                assert!(!held(&edge), "{max_angle}: on the edge");
                assert!(held(&inside), "{max_angle}: one ulp inside");
                assert!(!held(&outside), "{max_angle}: one ulp outside");
                // Either end alone outside the wedge releases the robot.
                let fall = Vector2::new(0.0, -1.0);
                assert!(!release_held(&limit, &o, &Point2::from(fall), &outside));
                assert!(!release_held(&limit, &o, &Point2::from(outside), &fall));
                assert!(release_held(&limit, &o, &Point2::from(fall), &inside));
            }
        }
        // A tether-free plane holds every direction.
        let v = Vector2::new(1.0, 5.0);
        assert!(release_held(
            &TetherLimit::TetherFree,
            &o,
            &Point2::from(v),
            &v
        ));
    }
}
