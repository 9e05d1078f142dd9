//! Robot models behind one trait, and their placement on a planar slope (Paton §IV-A settling on a
//! plane; Kumar §II): what the stability QP and LP need to know about a robot — its point masses,
//! its ground contacts, and where and in which direction its tether pulls.
//!
//! # Frames
//! * **Robot frame**: `x` forward, `y` left, `z` along the ground normal; the origin on the ground
//!   under the robot's reference point (Axel: under the axle centre).
//! * **Plane frame** of a [`SlopePlane`] of slope `η`: `x` horizontal (across the slope), `y` up the
//!   fall line, `z` the outward normal; its origin is a point of the plane.
//! * **World frame**: `z` up, gravity `(0, 0, -g)`; the plane frame is the world frame rotated by
//!   `η` about `x`.
//!
//! A [`PlanarPose`] puts the robot origin at `(x, y, 0)` in the plane frame with its forward axis
//! at `heading` radians counter-clockwise from the up-slope direction (`heading = π` faces
//! downhill). A tether is described by its last anchor (the point the tether runs straight to;
//! Paton §IV-B, Kumar §III-A) in the plane frame, and optionally the largest tension it can carry.

use nalgebra::{Isometry3, Point2, Point3, Rotation3, Translation3, Unit, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// Standard gravity at the Earth's surface (m/s²), as used by Kumar §IV.
pub const STANDARD_GRAVITY: f64 = 9.81;
/// The steepest slope accepted by [`SlopePlane::new`] (radians): a vertical wall has no meaningful
/// "up-slope" frame for a wheeled robot.
pub const MAX_SLOPE: f64 = 89.0 * std::f64::consts::PI / 180.0;

/// Why a robot model, plane, pose or tether was rejected.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum RobotError {
    /// A parameter is out of range; the message names it and its valid range.
    #[error("invalid robot parameter: {0}")]
    Parameter(&'static str),
    /// The anchor is so close to the tether exit (or below the ground) that the tether direction
    /// is undefined or the boom would dig into the ground; move the pose or the anchor.
    #[error("the tether anchor is too close to the robot or below the boom pivot: {0}")]
    Anchor(&'static str),
}

/// A planar slope: slope angle and wheel-ground friction (thesis §2.1's plane series; Kumar's
/// surfaces `S_ℓ`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SlopePlane {
    slope: f64,
    friction: f64,
}

impl SlopePlane {
    /// A plane of slope `slope` radians (`0 <= slope <= MAX_SLOPE`) with Coulomb coefficient
    /// `friction` between wheels and ground.
    ///
    /// # Example
    /// ```
    /// use rappel_mechanics::robot::SlopePlane;
    /// let p = SlopePlane::new(55f64.to_radians(), 0.4).unwrap();
    /// assert!((p.normal().z - 55f64.to_radians().cos()).abs() < 1e-12);
    /// assert!(SlopePlane::new(-0.1, 0.4).is_err());
    /// ```
    pub fn new(slope: f64, friction: f64) -> Result<Self, RobotError> {
        if !(slope.is_finite() && (0.0..=MAX_SLOPE).contains(&slope)) {
            return Err(RobotError::Parameter("slope must be in [0, 89] degrees"));
        }
        if !(friction.is_finite() && friction >= 0.0) {
            return Err(RobotError::Parameter("friction must be finite and >= 0"));
        }
        Ok(SlopePlane { slope, friction })
    }

    /// Slope angle `η` (radians).
    pub fn slope(&self) -> f64 {
        self.slope
    }

    /// Wheel-ground friction coefficient.
    pub fn friction(&self) -> f64 {
        self.friction
    }

    /// Rotation from the plane frame to the world frame.
    pub fn rotation(&self) -> Rotation3<f64> {
        Rotation3::from_axis_angle(&Vector3::x_axis(), self.slope)
    }

    /// Outward unit normal in the world frame.
    pub fn normal(&self) -> Unit<Vector3<f64>> {
        Unit::new_unchecked(self.rotation() * Vector3::z())
    }
}

/// A robot pose on a plane: position in the plane frame and heading (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlanarPose {
    /// Position `(x across, y up-slope)` in the plane frame (m).
    pub position: Point2<f64>,
    /// Heading of the forward axis, counter-clockwise from up-slope (radians).
    pub heading: f64,
}

impl PlanarPose {
    /// A pose at `(x, y)` with `heading`.
    pub fn new(x: f64, y: f64, heading: f64) -> Self {
        PlanarPose {
            position: Point2::new(x, y),
            heading,
        }
    }

    /// The isometry from the robot frame to the plane frame: the robot's forward axis maps to
    /// `(-sin heading, cos heading, 0)`.
    pub fn to_plane(&self) -> Isometry3<f64> {
        Isometry3::from_parts(
            Translation3::new(self.position.x, self.position.y, 0.0),
            UnitQuaternion::from_axis_angle(
                &Vector3::z_axis(),
                self.heading + std::f64::consts::FRAC_PI_2,
            ),
        )
    }
}

/// A tether running from the robot straight to its last anchor.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct TetherSpec {
    /// The last anchor, in the plane frame (m).
    pub anchor: Point3<f64>,
    /// The largest tension the tether can carry (N), if limited (Kumar eq. 3e).
    pub max_tension: Option<f64>,
}

impl TetherLine {
    /// The tether leaving `exit` along `toward_anchor` (any length above
    /// [`MIN_TETHER_LENGTH`]; normalised here), with the tension limit `max_tension`.
    pub(crate) fn toward(
        exit: Point3<f64>,
        toward_anchor: Vector3<f64>,
        max_tension: Option<f64>,
    ) -> Result<TetherLine, RobotError> {
        let direction = Unit::try_new(toward_anchor, MIN_TETHER_LENGTH)
            .ok_or(RobotError::Anchor("anchor coincides with the tether exit"))?;
        Ok(TetherLine {
            exit,
            direction,
            max_tension,
        })
    }
}

/// A point mass in the robot frame.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PointMass {
    /// Mass (kg).
    pub mass: f64,
    /// Centre of mass (m).
    pub position: Point3<f64>,
}

/// A robot's configuration in its own frame for one tether situation.
#[derive(Clone, Debug, PartialEq)]
pub struct RobotConfiguration {
    /// The bodies (Paton eq. 7: `m_1`, `m_2`).
    pub masses: Vec<PointMass>,
    /// Ground contact points (all on the plane `z = 0`, normal `+z`).
    pub contacts: Vec<Point3<f64>>,
    /// Where the tether leaves the robot (Paton's `r_t`).
    pub tether_exit: Point3<f64>,
}

impl RobotConfiguration {
    /// The bodies moved into the world by `to_world` (a map of robot-frame points).
    pub(crate) fn world_masses(
        &self,
        to_world: impl Fn(&Point3<f64>) -> Point3<f64>,
    ) -> Vec<PointMass> {
        self.masses
            .iter()
            .map(|m| PointMass {
                mass: m.mass,
                position: to_world(&m.position),
            })
            .collect()
    }
}

/// A robot model: masses, contacts and tether exit for a given anchor (the seam a new robot type
/// implements; GUIDE §2).
pub trait RobotModel: Sync {
    /// A short name for reports.
    fn name(&self) -> &str;

    /// The moment bound coefficient `μ_m` (m) of its contacts (Paton eqs. 4-6): a contact patch
    /// carries moments up to `μ_m` times its normal force. Zero for point contacts.
    fn contact_moment_coefficient(&self) -> f64;

    /// The configuration given the last anchor in the robot frame (`None`: no tether).
    fn configuration(&self, anchor: Option<&Point3<f64>>)
    -> Result<RobotConfiguration, RobotError>;

    /// The Coulomb coefficient of the configuration's contact `index` where it differs from the
    /// wheel-ground one the placement is given (`None`: that one). Axel's boom tip resting on
    /// the ground ([`crate::axel::AxelParams::boom_friction`]).
    fn contact_friction(&self, index: usize) -> Option<f64> {
        let _ = index;
        None
    }

    /// Whether the configuration's contact `index` is a point contact (no moment, see
    /// [`ContactFrame::point`]); `false` by default. Axel's boom tip on the ground.
    fn contact_is_point(&self, index: usize) -> bool {
        let _ = index;
        false
    }

    /// Total mass (kg).
    fn total_mass(&self) -> f64 {
        self.configuration(None)
            .map(|c| c.masses.iter().map(|m| m.mass).sum())
            .unwrap_or(0.0)
    }

    /// The ground contact points of the robot at `pose` on `plane`, in the world frame.
    fn contact_points(
        &self,
        pose: &PlanarPose,
        plane: &SlopePlane,
    ) -> Result<Vec<Point3<f64>>, RobotError> {
        let to_world = world_from_robot(pose, plane);
        Ok(self
            .configuration(None)?
            .contacts
            .iter()
            .map(|c| to_world * c)
            .collect())
    }
}

fn world_from_robot(pose: &PlanarPose, plane: &SlopePlane) -> Isometry3<f64> {
    let plane_to_world = Isometry3::from_parts(
        Translation3::identity(),
        UnitQuaternion::from_rotation_matrix(&plane.rotation()),
    );
    plane_to_world * pose.to_plane()
}

/// A contact in the world frame: its point and its frame (`z` along the contact normal, `x` along
/// the robot's forward axis).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactFrame {
    /// Contact point (world).
    pub position: Point3<f64>,
    /// Rotation from the contact frame to the world frame (Paton's `R_ci`).
    pub rotation: Rotation3<f64>,
    /// This contact's Coulomb coefficient where it differs from the robot's wheel-ground
    /// [`PlacedRobot::friction`] (`None`: that one); Axel's boom resting on the ground carries
    /// [`crate::axel::AxelParams::boom_friction`].
    pub friction: Option<f64>,
    /// A **point contact**: no contact patch, so no moment (only a force in its friction
    /// pyramid) whatever the robot's [`PlacedRobot::moment_coefficient`]. Axel's boom on the
    /// ground (Paton §IV-C grants moments to the wheels' grouser patches).
    pub point: bool,
}

/// The tether force line in the world frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TetherLine {
    /// Tether exit point (Paton's `r_t`).
    pub exit: Point3<f64>,
    /// Unit direction of the pull, from the exit toward the anchor.
    pub direction: Unit<Vector3<f64>>,
    /// Largest tension (N), if limited.
    pub max_tension: Option<f64>,
}

/// A robot placed on a plane, in the world frame: everything a stability check needs.
#[derive(Clone, Debug, PartialEq)]
pub struct PlacedRobot {
    /// Point masses (world positions).
    pub masses: Vec<PointMass>,
    /// Contacts.
    pub contacts: Vec<ContactFrame>,
    /// The tether, if any.
    pub tether: Option<TetherLine>,
    /// Wheel-ground friction coefficient `μ`.
    pub friction: f64,
    /// Moment bound coefficient `μ_m` (m).
    pub moment_coefficient: f64,
    /// The robot origin in the world frame (the moment reference point).
    pub reference: Point3<f64>,
}

impl PlacedRobot {
    /// The Coulomb coefficient of contact `i`: its own ([`ContactFrame::friction`]) or the
    /// robot's.
    pub fn contact_friction(&self, i: usize) -> f64 {
        self.contacts[i].friction.unwrap_or(self.friction)
    }

    /// The moment bound coefficient of contact `i`: the robot's `μ_m`, zero for a point contact
    /// ([`ContactFrame::point`]).
    pub fn contact_moment_coefficient(&self, i: usize) -> f64 {
        if self.contacts[i].point {
            0.0
        } else {
            self.moment_coefficient
        }
    }
}

/// Shortest allowed tether between exit and anchor (m): closer, its direction is ill-defined.
pub const MIN_TETHER_LENGTH: f64 = 1e-6;

/// Places `model` at `pose` on `plane` with an optional tether (see the module docs).
///
/// # Example
/// ```
/// use nalgebra::Point3;
/// use rappel_mechanics::axel::Axel;
/// use rappel_mechanics::robot::{place, PlanarPose, SlopePlane, TetherSpec};
/// let plane = SlopePlane::new(0.5, 0.8).unwrap();
/// let tether = TetherSpec { anchor: Point3::new(0.0, 20.0, 0.0), max_tension: None };
/// let placed = place(&Axel::default(), &PlanarPose::new(0.0, 0.0, std::f64::consts::PI), &plane, Some(&tether)).unwrap();
/// assert_eq!(placed.contacts.len(), 2);
/// assert!(placed.tether.unwrap().direction.z > 0.0); // pulling up the slope
/// ```
pub fn place(
    model: &dyn RobotModel,
    pose: &PlanarPose,
    plane: &SlopePlane,
    tether: Option<&TetherSpec>,
) -> Result<PlacedRobot, RobotError> {
    if !(pose.position.iter().all(|c| c.is_finite()) && pose.heading.is_finite()) {
        return Err(RobotError::Parameter("pose must be finite"));
    }
    if let Some(t) = tether {
        if !t.anchor.iter().all(|c| c.is_finite()) {
            return Err(RobotError::Parameter("anchor must be finite"));
        }
        if t.max_tension.is_some_and(|m| !(m.is_finite() && m >= 0.0)) {
            return Err(RobotError::Parameter("max tension must be finite and >= 0"));
        }
    }
    let robot_in_plane = pose.to_plane();
    let to_world = world_from_robot(pose, plane);
    let anchor_robot = tether.map(|t| robot_in_plane.inverse_transform_point(&t.anchor));
    let config = model.configuration(anchor_robot.as_ref())?;
    let contact_rotation = *to_world.rotation.to_rotation_matrix().matrix();
    let tether_line = match (tether, anchor_robot) {
        (Some(t), Some(a)) => Some(TetherLine::toward(
            to_world * config.tether_exit,
            to_world.transform_vector(&(a - config.tether_exit)),
            t.max_tension,
        )?),
        _ => None,
    };
    Ok(PlacedRobot {
        masses: config.world_masses(|p| to_world * p),
        contacts: config
            .contacts
            .iter()
            .enumerate()
            .map(|(i, c)| ContactFrame {
                position: to_world * c,
                rotation: Rotation3::from_matrix_unchecked(contact_rotation),
                friction: model.contact_friction(i),
                point: model.contact_is_point(i),
            })
            .collect(),
        tether: tether_line,
        friction: plane.friction(),
        moment_coefficient: model.contact_moment_coefficient(),
        reference: to_world * Point3::origin(),
    })
}

/// Checks that a robot parameter is finite and positive.
pub(crate) fn positive(v: f64, what: &'static str) -> Result<f64, RobotError> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(RobotError::Parameter(what))
    }
}

/// Checks that a robot parameter is finite and non-negative.
pub(crate) fn non_negative(v: f64, what: &'static str) -> Result<f64, RobotError> {
    if v.is_finite() && v >= 0.0 {
        Ok(v)
    } else {
        Err(RobotError::Parameter(what))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::four_wheel::FourWheelRover;

    #[test]
    fn placement_puts_contacts_on_the_plane_and_tether_toward_anchor() {
        let plane = SlopePlane::new(0.7, 0.5).unwrap();
        let rover = FourWheelRover::default();
        let pose = PlanarPose::new(1.0, -2.0, 2.5);
        let n = plane.normal();
        for c in rover.contact_points(&pose, &plane).unwrap() {
            assert!(c.coords.dot(&n).abs() < 1e-12, "contact off the plane");
        }
        let anchor = Point3::new(3.0, 10.0, 0.0);
        let placed = place(
            &rover,
            &pose,
            &plane,
            Some(&TetherSpec {
                anchor,
                max_tension: Some(100.0),
            }),
        )
        .unwrap();
        let t = placed.tether.unwrap();
        let anchor_world = plane.rotation() * anchor;
        let expect = (anchor_world - t.exit).normalize();
        assert!((t.direction.into_inner() - expect).norm() < 1e-12);
        for c in &placed.contacts {
            assert!((c.rotation * Vector3::z() - n.into_inner()).norm() < 1e-12);
        }
        assert!(place(&rover, &PlanarPose::new(f64::NAN, 0.0, 0.0), &plane, None).is_err());
    }
}
