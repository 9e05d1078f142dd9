//! Settling a rigid four-wheel rover ([`crate::four_wheel`]) on 3D ground (Paton §IV-A's
//! procedure, carried over from Axel's two wheel circles to four point wheels).
//!
//! A rigid chassis on four point wheels is statically determinate on three of them. From a
//! ground point and a yaw ([`crate::settle`]'s footprint step gives the first normal), the
//! settler repeats:
//! 1. each wheel's ground point: the wheel's position on the current chassis plane, dropped along
//!    the plane's normal onto the ground ([`SignedDistance::ground_along`]: exact on meshes and
//!    grid fields);
//! 2. the **support**: when the four ground points are coplanar (within the contact tolerance)
//!    the chassis rests on all four; otherwise the tetrahedron they span has two upper faces
//!    (planes through three points with the fourth below), split by one diagonal, and the
//!    chassis rests on the upper face whose triangle holds the centre of mass seen along gravity
//!    (the rover tips about the diagonal towards its mass; on the diagonal itself, the face with
//!    the lower-indexed hanging wheel, so the result is deterministic);
//! 3. the new chassis plane is the support's, the frame follows the yaw in it;
//!
//! until the plane stops moving (normal within [`REST_ANGLE`], origin within the contact
//! tolerance), at most [`MAX_REST_ITERATIONS`] rounds (wheel positions move with the tilt, so the
//! ground points are found again each round). The chassis has no body geometry in
//! [`FourWheelParams`]: no body collision is checked.
//!
//! Wheel order: 0 front left, 1 front right, 2 rear left, 3 rear right (the order of
//! [`crate::four_wheel::FourWheelRover`]'s contacts).

use nalgebra::{Point2, Point3, Rotation3, Vector3};
use rappel_geometry::predicates::orient2d;
use rappel_terrain::surface::SignedDistance;

use crate::four_wheel::{FourWheelParams, FourWheelRover};
use crate::robot::{PlacedRobot, RobotError};
use crate::settle::{
    GroundContacts, SettleError, SettleParams, drop_along_normal, footprint, frame_on_plane,
    place_on_ground,
};

/// Most rounds of the rest iteration (module docs); ground of bounded curvature converges in a
/// handful.
pub const MAX_REST_ITERATIONS: usize = 32;

/// The rest iteration stops when the chassis normal turns by less than this, radians.
pub const REST_ANGLE: f64 = 1e-12;

/// A settled four-wheel pose.
#[derive(Debug, Clone, PartialEq)]
pub struct FourWheelPose {
    /// Robot-frame origin (on the chassis plane under the wheelbase centre), world.
    pub origin: Point3<f64>,
    /// Robot frame to world rotation.
    pub rotation: Rotation3<f64>,
    /// Each wheel's ground point (along the chassis normal below the wheel), world.
    pub ground_points: [Point3<f64>; 4],
    /// Each wheel's height above its ground point along the chassis normal, metres (within the
    /// contact tolerance of 0 for the supporting wheels).
    pub wheel_clearance: [f64; 4],
    /// Which wheels carry the rover (three or four).
    pub support: Vec<usize>,
}

impl FourWheelPose {
    /// Pitch, radians: the forward axis' elevation above horizontal.
    pub fn pitch(&self) -> f64 {
        (self.rotation * Vector3::x()).z.clamp(-1.0, 1.0).asin()
    }

    /// Roll, radians: the left axis' elevation above horizontal.
    pub fn roll(&self) -> f64 {
        (self.rotation * Vector3::y()).z.clamp(-1.0, 1.0).asin()
    }

    /// The settled rover as the stability QP sees it: one contact per supporting wheel (frames
    /// from the ground's distance gradient), the tether toward `anchor` (see
    /// [`crate::settle::place_on_ground`]).
    pub fn place<D: SignedDistance + ?Sized>(
        &self,
        rover: &FourWheelRover,
        ground: &D,
        friction: f64,
        anchor: Option<(&Point3<f64>, Option<f64>)>,
    ) -> Result<PlacedRobot, RobotError> {
        let contacts: Vec<Point3<f64>> = self
            .support
            .iter()
            .map(|&w| self.ground_points[w])
            .collect();
        place_on_ground(
            GroundContacts {
                origin: self.origin,
                rotation: self.rotation,
                contacts: &contacts,
                replaces: 4,
            },
            rover,
            ground,
            friction,
            anchor,
        )
    }
}

/// The wheel positions in the robot frame, in the module's order.
fn wheels(r: &FourWheelParams) -> [Vector3<f64>; 4] {
    let (a, b) = (0.5 * r.wheelbase, 0.5 * r.track);
    [
        Vector3::new(a, b, 0.0),
        Vector3::new(a, -b, 0.0),
        Vector3::new(-a, b, 0.0),
        Vector3::new(-a, -b, 0.0),
    ]
}

/// The ground point on the line through `q` along the unit normal `n`: down from `q` in the air,
/// up from it below the ground ([`SignedDistance::ground_along`]: exact on meshes and grid
/// fields), within `reach`.
fn drop_along<D: SignedDistance + ?Sized>(
    ground: &D,
    q: Point3<f64>,
    n: &Vector3<f64>,
    tolerance: f64,
    reach: f64,
) -> Result<Point3<f64>, SettleError> {
    drop_along_normal(ground, &q, n, reach, tolerance)?
        .map(|t| q - n * t)
        .ok_or(SettleError::NoContact(reach))
}

/// The upward unit normal of the plane through `a, b, c`, `None` when they are collinear.
fn plane_normal(a: &Point3<f64>, b: &Point3<f64>, c: &Point3<f64>) -> Option<Vector3<f64>> {
    let n = (b - a).cross(&(c - a)).try_normalize(0.0)?;
    Some(if n.z < 0.0 { -n } else { n })
}

/// `true` when the vertical line through `p` meets triangle `t` (closed), in plan view.
fn over_triangle(p: &Point3<f64>, t: [&Point3<f64>; 3]) -> bool {
    let plan = |q: &Point3<f64>| Point2::new(q.x, q.y);
    let o = |a: &Point3<f64>, b: &Point3<f64>| orient2d(&plan(a), &plan(b), &plan(p));
    let s = [o(t[0], t[1]), o(t[1], t[2]), o(t[2], t[0])];
    s.iter().all(|v| *v >= 0.0) || s.iter().all(|v| *v <= 0.0)
}

/// Settle `rover` at ground point `(x, y)` (found by sphere tracing down from `z_top`) with
/// heading `yaw` radians from world `+x`, counter-clockwise (module docs). Uses `p.delta`,
/// `p.contact_tolerance` and `p.max_slope`.
///
/// ```
/// use rappel_mechanics::four_wheel::FourWheelParams;
/// use rappel_mechanics::four_wheel_settle::settle_four_wheel;
/// use rappel_mechanics::settle::SettleParams;
/// use rappel_terrain::surface::SignedDistance;
/// use nalgebra::{Point3, Vector3};
/// // The plane z = 0.2 x (11.3° up towards +x).
/// struct Ramp;
/// impl SignedDistance for Ramp {
///     fn signed_distance(&self, q: &Point3<f64>) -> Option<f64> {
///         Some((q.z - 0.2 * q.x) / (1.0f64 + 0.04).sqrt())
///     }
///     fn distance_gradient(&self, _: &Point3<f64>) -> Option<Vector3<f64>> {
///         Some(Vector3::new(-0.2, 0.0, 1.0).normalize())
///     }
/// }
/// let pose = settle_four_wheel(&Ramp, &FourWheelParams::default(), 1.0, 0.0, 5.0, 0.0,
///     &SettleParams::default()).unwrap();
/// assert_eq!(pose.support.len(), 4);
/// assert!((pose.pitch() - 0.2f64.atan()).abs() < 1e-9);
/// ```
pub fn settle_four_wheel<D: SignedDistance + ?Sized>(
    ground: &D,
    rover: &FourWheelParams,
    x: f64,
    y: f64,
    z_top: f64,
    yaw: f64,
    p: &SettleParams,
) -> Result<FourWheelPose, SettleError> {
    let ok = [p.delta, p.contact_tolerance, p.max_slope]
        .iter()
        .all(|v| *v > 0.0 && v.is_finite())
        && [rover.wheelbase, rover.track]
            .iter()
            .all(|v| *v > 0.0 && v.is_finite())
        && rover.com_height.is_finite()
        && [x, y, z_top, yaw].iter().all(|v| v.is_finite());
    if !ok {
        return Err(SettleError::Parameter(
            "delta, tolerance, slope, wheelbase and track must be positive, inputs finite",
        ));
    }
    let start = footprint(
        ground,
        x,
        y,
        z_top,
        yaw,
        [0.5 * rover.wheelbase, 0.5 * rover.track],
        p,
    )?;
    let w = wheels(rover);
    let reach = p.delta + rover.wheelbase + rover.track;
    let (mut origin, mut n, mut rotation) = (start.ground, start.normal, start.base);
    for _ in 0..MAX_REST_ITERATIONS {
        let mut g = [Point3::origin(); 4];
        for k in 0..4 {
            let above = origin + rotation * w[k] + n * p.delta;
            g[k] = drop_along(ground, above, &n, p.contact_tolerance, reach)?;
        }
        let com = origin + rotation * Vector3::new(0.0, 0.0, rover.com_height);
        // Height of point `q` above the plane through `tri` along its normal.
        let above_plane = |tri: [usize; 3], q: &Point3<f64>| {
            plane_normal(&g[tri[0]], &g[tri[1]], &g[tri[2]]).map(|m| (m, (q - g[tri[0]]).dot(&m)))
        };
        let all = [0usize, 1, 2, 3];
        let coplanar =
            above_plane([0, 1, 2], &g[3]).is_some_and(|(_, h)| h.abs() < p.contact_tolerance);
        let (support, new_n): (Vec<usize>, Vector3<f64>) = if coplanar {
            let m = plane_normal(&g[0], &g[1], &g[2]).unwrap_or(n);
            (all.to_vec(), m)
        } else {
            // The upper faces: the fourth point below the plane. The rover rests on the one
            // over whose triangle its centre of mass lies.
            let mut chosen = None;
            for hang in 0..4 {
                let tri: Vec<usize> = all.iter().copied().filter(|&k| k != hang).collect();
                let tri = [tri[0], tri[1], tri[2]];
                let Some((m, h)) = above_plane(tri, &g[hang]) else {
                    continue;
                };
                if h <= 0.0 && over_triangle(&com, [&g[tri[0]], &g[tri[1]], &g[tri[2]]]) {
                    chosen = Some((tri.to_vec(), m));
                    break;
                }
            }
            chosen.ok_or(SettleError::SlopeBeyondModel(
                "the centre of mass is over no support triangle (the rover tips over)",
            ))?
        };
        if new_n.z.clamp(-1.0, 1.0).acos() > p.max_slope {
            return Err(SettleError::SlopeBeyondModel(
                "support plane steeper than max_slope",
            ));
        }
        let new_rotation = frame_on_plane(yaw, &new_n)?;
        // The origin: on the support plane, under the wheelbase centre of the current pose.
        let anchor_point = g[support[0]];
        let centre = origin + n * p.delta;
        let new_origin = centre - new_n * (centre - anchor_point).dot(&new_n);
        let turned = new_n.dot(&n).clamp(-1.0, 1.0).acos();
        let moved = (new_origin - origin).norm();
        (origin, n, rotation) = (new_origin, new_n, new_rotation);
        if turned < REST_ANGLE && moved < p.contact_tolerance {
            let mut ground_points = [Point3::origin(); 4];
            let mut wheel_clearance = [0.0; 4];
            for k in 0..4 {
                let wheel = origin + rotation * w[k];
                ground_points[k] =
                    drop_along(ground, wheel + n * p.delta, &n, p.contact_tolerance, reach)?;
                wheel_clearance[k] = (wheel - ground_points[k]).dot(&n);
            }
            return Ok(FourWheelPose {
                origin,
                rotation,
                ground_points,
                wheel_clearance,
                support,
            });
        }
    }
    Err(SettleError::SlopeBeyondModel(
        "the chassis did not come to rest within the iteration bound",
    ))
}
