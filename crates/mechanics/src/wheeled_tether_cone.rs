//! The tether limit of a wheeled robot from its stability criterion (Paton §IV-C; thesis §2.4):
//! the second implementation of [`AnchorTraversability`], so a planner asks an Axel or a
//! four-wheel rover the same question it asks the point robot of eq. 2.7 — how far from the fall
//! line may the taut tether point while the robot still holds?
//!
//! On a plane the robot is placed facing away from its anchor (the rappelling pose) with the
//! tether leaving at its exit point and running parallel to the plane towards an anchor
//! [`PROBE_TETHER_LENGTH`] metres away at angle `theta` from the fall line. The plane is
//! *tether-free* when the robot holds there without any tether facing straight downhill; otherwise
//! the limit is the largest `theta` at which the criterion finds it stable, found by bisection to
//! [`ANGLE_TOLERANCE`] (stability is assumed to shrink as the tether swings away from the fall line,
//! which is what Kumar's and Paton's models give: the tether's uphill component falls as
//! `cos theta` while its cross-slope pull grows). A criterion failure (solver trouble) counts as
//! "not stable", the conservative answer.

use crate::anchor_traversability::{AnchorTraversability, TetherLimit};
use crate::robot::{PlanarPose, RobotModel, SlopePlane, TetherSpec, place};
use crate::traversability::StabilityCriterion;
use nalgebra::{Point2, Point3};

/// Distance from the robot to the probing anchor, metres: far enough that the robot's own size
/// does not bend the tether direction noticeably.
pub const PROBE_TETHER_LENGTH: f64 = 50.0;

/// Bisection stops when the bracket on the limit angle is this narrow, radians (about 0.006°).
pub const ANGLE_TOLERANCE: f64 = 1e-4;

/// A robot model and a stability criterion, seen as a tether cone.
///
/// ```
/// use rappel_mechanics::anchor_traversability::{AnchorTraversability, TetherLimit};
/// use rappel_mechanics::four_wheel::FourWheelRover;
/// use rappel_mechanics::robot::SlopePlane;
/// use rappel_mechanics::stability_qp::StabilityQp;
/// use rappel_mechanics::traversability::StabilitySettings;
/// use rappel_mechanics::wheeled_tether_cone::WheeledTetherCone;
/// let rover = FourWheelRover::default();
/// let qp = StabilityQp::new(StabilitySettings::default());
/// let model = WheeledTetherCone::new(&rover, &qp);
/// // Gentle ground holds the rover by its wheels; a steep wall needs the tether.
/// assert_eq!(model.tether_limit(&SlopePlane::new(10f64.to_radians(), 0.6).unwrap()), TetherLimit::TetherFree);
/// let steep = model.tether_limit(&SlopePlane::new(50f64.to_radians(), 0.6).unwrap());
/// assert!(steep.max_angle().is_some_and(|a| a > 0.0));
/// ```
pub struct WheeledTetherCone<'a> {
    robot: &'a (dyn RobotModel + Sync),
    criterion: &'a dyn StabilityCriterion,
}

impl<'a> WheeledTetherCone<'a> {
    /// The cone of `robot` judged by `criterion`.
    pub fn new(robot: &'a (dyn RobotModel + Sync), criterion: &'a dyn StabilityCriterion) -> Self {
        WheeledTetherCone { robot, criterion }
    }

    /// `true` when the robot holds on `plane` with the tether at `theta` from the fall line
    /// (`None`: no tether, facing downhill).
    fn holds(&self, plane: &SlopePlane, theta: Option<f64>) -> bool {
        let Ok(config) = self.robot.configuration(None) else {
            return false;
        };
        let (pose, tether) = match theta {
            None => (
                PlanarPose {
                    position: Point2::origin(),
                    heading: std::f64::consts::PI,
                },
                None,
            ),
            Some(t) => {
                let anchor = Point3::new(
                    PROBE_TETHER_LENGTH * t.sin(),
                    PROBE_TETHER_LENGTH * t.cos(),
                    config.tether_exit.z,
                );
                // Facing away from the anchor: heading measured counter-clockwise from up-slope.
                let pose = PlanarPose {
                    position: Point2::origin(),
                    heading: std::f64::consts::PI - t,
                };
                (
                    pose,
                    Some(TetherSpec {
                        anchor,
                        max_tension: None,
                    }),
                )
            }
        };
        match place(self.robot, &pose, plane, tether.as_ref()) {
            Ok(placed) => self.criterion.assess(&placed).is_ok_and(|a| a.stable),
            Err(_) => false,
        }
    }
}

impl AnchorTraversability for WheeledTetherCone<'_> {
    fn name(&self) -> &str {
        "wheeled robot, tether cone from its stability criterion"
    }

    fn tether_limit(&self, plane: &SlopePlane) -> TetherLimit {
        if self.holds(plane, None) {
            return TetherLimit::TetherFree;
        }
        if !self.holds(plane, Some(0.0)) {
            return TetherLimit::Cone { max_angle: 0.0 };
        }
        let (mut lo, mut hi) = (0.0, std::f64::consts::FRAC_PI_2);
        if self.holds(plane, Some(hi)) {
            return TetherLimit::Cone { max_angle: hi };
        }
        while hi - lo > ANGLE_TOLERANCE {
            let mid = 0.5 * (lo + hi);
            if self.holds(plane, Some(mid)) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        TetherLimit::Cone { max_angle: lo }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::four_wheel::FourWheelRover;
    use crate::friction_cone::TetherFrictionCone;
    use crate::stability_qp::StabilityQp;
    use crate::traversability::StabilitySettings;

    #[test]
    fn the_wheeled_cone_narrows_as_the_slope_steepens_and_is_bounded_by_the_point_robot() {
        let rover = FourWheelRover::default();
        let qp = StabilityQp::new(StabilitySettings::default());
        let model = WheeledTetherCone::new(&rover, &qp);
        let mut last = f64::INFINITY;
        for deg in [35.0, 45.0, 55.0, 65.0] {
            let plane = SlopePlane::new(f64::to_radians(deg), 0.5).unwrap();
            let Some(wheeled) = model.tether_limit(&plane).max_angle() else {
                panic!("{deg} deg should need the tether at mu 0.5")
            };
            assert!(wheeled < last, "{deg}: {wheeled} !< {last}");
            last = wheeled;
            // A rigid rover's cone can only be narrower than a point robot's with the same mu
            // (its cross-slope friction is shared with tipping moments): eq. 2.7 bounds it.
            let point = TetherFrictionCone
                .tether_limit(&plane)
                .max_angle()
                .unwrap_or(f64::INFINITY);
            assert!(
                wheeled <= point + 2.0 * ANGLE_TOLERANCE,
                "{deg}: wheeled {wheeled} > point {point}"
            );
        }
    }
}
