//! Rover settling on 3D terrain (Paton §IV-A, Fig. 2), for Axel: from a ground point and a yaw,
//! the surface normal over the footprint, a start `delta` above the ground along it, the wheels
//! as circles of [`WHEEL_POINTS`] contact points, a drop along the normal to first contact, a
//! search of the body roll until the lowest contact of each wheel touches, a final drop, and the
//! body collision check (points along the axle against the distance field).
//!
//! The ground is anything with a [`SignedDistance`]: a [`rappel_terrain::sdf::Sdf`] (fast), an
//! exact [`rappel_terrain::mesh::TriMesh`] or an analytic planar terrain.
//!
//! Frames: the settled pose maps the robot frame of [`crate::robot`] (`x` forward, `y` left along
//! the axle, `z` up from the ground; origin on the ground under the axle centre) to the world.
//!
//! The drops are exact where the ground can answer exactly: the vertical drop to the footprint
//! is [`SignedDistance::ground_below`], the drop along the normal casts each of the 24 contact
//! points along it with [`SignedDistance::ground_along`] (an exact segment-triangle test on
//! meshes, the interpolant's exact first zero on grid fields; sphere tracing only on analytic
//! grounds), so the wheel that touches first is the first contact point hit along the drop,
//! however close a wall runs beside it.
//!
//! Bounds: each drop casts the 24 contact points once (sphere tracing, where a ground has no
//! exact answer, at most [`MAX_DROP_STEPS`] steps each), the roll bisection at most
//! [`MAX_ROLL_STEPS`] drops; the footprint normal samples a fixed 3 x 3 grid.

use nalgebra::{Point3, Rotation3, Unit, Vector3};
use rappel_geometry::compact::Rounded;
use rappel_terrain::surface::{DropError, SignedDistance};

use crate::axel::AxelParams;
use crate::robot::{ContactFrame, PlacedRobot, RobotError, RobotModel, TetherLine};

/// Contact points per wheel circle (Paton: 12).
pub const WHEEL_POINTS: usize = 12;
/// Sphere-tracing steps of the default drops ([`SignedDistance::ground_below`],
/// [`SignedDistance::ground_along`]) on grounds without an exact answer.
pub use rappel_terrain::surface::MAX_DROP_STEPS;
/// Bisection steps of the roll search (`2 max_roll / 2^60` is far below any tolerance).
pub const MAX_ROLL_STEPS: usize = 60;

/// How far above a settled contact (along the pose's normal) its ground normal is probed, metres:
/// small against wheel and terrain features, large against the field's rounding.
pub const CONTACT_PROBE: f64 = 0.02;

/// Settling parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SettleParams {
    /// Start height above the ground along the normal, metres (Paton's `delta`).
    pub delta: f64,
    /// A contact is on the ground when its distance is below this, metres.
    pub contact_tolerance: f64,
    /// The largest body roll searched, radians (beyond it: [`SettleError::SlopeBeyondModel`]).
    pub max_roll: f64,
    /// The steepest ground normal accepted, radians from vertical.
    pub max_slope: f64,
    /// Radius of Axel's body around the axle, metres (below the wheel radius; the body collides
    /// when an axle point is closer than this to the ground). Assumed 0.25 m: not in
    /// [`AxelParams`].
    pub body_radius: f64,
    /// Collision points along the axle between the wheels.
    pub body_points: usize,
}

impl Default for SettleParams {
    fn default() -> Self {
        SettleParams {
            delta: 0.5,
            contact_tolerance: 1e-6,
            max_roll: 45f64.to_radians(),
            max_slope: 80f64.to_radians(),
            body_radius: 0.25,
            body_points: 9,
        }
    }
}

/// Why a pose cannot be settled.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SettleError {
    /// The distance field has no answer (off the terrain or its grid) at a point the settler
    /// needed.
    #[error("no ground under the footprint near ({}, {}, {})", Rounded(*.x, 3), Rounded(*.y, 3), Rounded(*.z, 3))]
    NoGround {
        /// The point, world.
        x: f64,
        /// y.
        y: f64,
        /// z.
        z: f64,
    },
    /// No contact point meets the ground within the drop's reach along the normal (the start
    /// height plus the rover's size), or a sphere-traced drop ran out of its [`MAX_DROP_STEPS`].
    #[error("the wheels found no ground within {} m of the start", Rounded(*.0, 3))]
    NoContact(f64),
    /// The ground is steeper than `max_slope`, or no roll within `max_roll` puts both wheels down.
    #[error("slope beyond the model: {0}")]
    SlopeBeyondModel(&'static str),
    /// A body point along the axle is within `body_radius` of the ground (the worst one).
    #[error(
        "body collision at axle point {index} ({}, {}, {}): clearance {clearance:.4} m",
        Rounded(*.x, 3), Rounded(*.y, 3), Rounded(*.z, 3)
    )]
    BodyCollision {
        /// Which collision point (0 = right end).
        index: usize,
        /// World x of the point.
        x: f64,
        /// y.
        y: f64,
        /// z.
        z: f64,
        /// Its distance to the ground minus the body radius (negative).
        clearance: f64,
    },
    /// A parameter out of its domain.
    #[error("invalid settling parameter: {0}")]
    Parameter(&'static str),
}

/// A settled Axel pose.
#[derive(Debug, Clone, PartialEq)]
pub struct SettledPose {
    /// Robot-frame origin in the world (on the ground under the axle centre).
    pub origin: Point3<f64>,
    /// Robot frame to world rotation.
    pub rotation: Rotation3<f64>,
    /// The lowest contact point of each wheel (right, left), world.
    pub contacts: [Point3<f64>; 2],
    /// Their ground distances (each below the contact tolerance once settled).
    pub contact_distances: [f64; 2],
    /// Smallest clearance of the axle points (distance minus body radius).
    pub body_clearance: f64,
}

impl SettledPose {
    /// Pitch, radians: the forward axis' elevation above horizontal.
    pub fn pitch(&self) -> f64 {
        (self.rotation * Vector3::x()).z.clamp(-1.0, 1.0).asin()
    }
    /// Roll, radians: the left (axle) axis' elevation above horizontal.
    pub fn roll(&self) -> f64 {
        (self.rotation * Vector3::y()).z.clamp(-1.0, 1.0).asin()
    }
}

/// A dropped pose: origin, rotation and the lowest (distance, point) of each wheel.
type Dropped = (Point3<f64>, Rotation3<f64>, [(f64, Point3<f64>); 2]);

impl SettledPose {
    /// The settled robot as the stability QP sees it (Paton §IV-C): the model's masses and tether
    /// exit carried by the settled pose, the tether toward the last anchor `anchor` (world;
    /// `None`: untethered) with its optional tension limit, and one contact per settled wheel
    /// contact with its frame's `z` along the ground's distance gradient there and `x` along the
    /// robot's forward axis. The model's contacts beyond the first two (Axel's in-contact boom
    /// tip) are carried by the pose: on the settled pose's ground plane (an approximation where
    /// the ground under the boom tip is not that plane).
    pub fn place<D: SignedDistance + ?Sized>(
        &self,
        model: &dyn RobotModel,
        ground: &D,
        friction: f64,
        anchor: Option<(&Point3<f64>, Option<f64>)>,
    ) -> Result<PlacedRobot, RobotError> {
        place_on_ground(
            GroundContacts {
                origin: self.origin,
                rotation: self.rotation,
                contacts: &self.contacts,
                replaces: 2,
            },
            model,
            ground,
            friction,
            anchor,
        )
    }
}

/// A settled pose's placement data for [`place_on_ground`]: the robot frame, the settled ground
/// contacts (world), and how many of the model's own contacts they stand in for (the first
/// `replaces`; the model's further contacts are carried by the pose).
#[derive(Debug, Clone, Copy)]
pub struct GroundContacts<'a> {
    /// Robot-frame origin in the world.
    pub origin: Point3<f64>,
    /// Robot frame to world rotation.
    pub rotation: Rotation3<f64>,
    /// The settled contacts on the ground, world.
    pub contacts: &'a [Point3<f64>],
    /// How many of the model's contacts (from the first) the settled ones replace.
    pub replaces: usize,
}

/// A settled robot as the stability QP sees it (Paton §IV-C), for any settler: the model's masses
/// and tether exit carried by the pose, the tether toward the last anchor `anchor` (world;
/// `None`: untethered) with its optional tension limit, one contact per settled ground contact
/// with its frame's `z` along the ground's distance gradient there (probed [`CONTACT_PROBE`]
/// above it) and `x` along the robot's forward axis, and the model's contacts beyond the first
/// `replaces` carried by the pose (on the settled pose's ground plane).
pub fn place_on_ground<D: SignedDistance + ?Sized>(
    pose: GroundContacts<'_>,
    model: &dyn RobotModel,
    ground: &D,
    friction: f64,
    anchor: Option<(&Point3<f64>, Option<f64>)>,
) -> Result<PlacedRobot, RobotError> {
    let GroundContacts {
        origin,
        rotation,
        contacts: settled,
        replaces,
    } = pose;
    if !(friction.is_finite() && friction >= 0.0) {
        return Err(RobotError::Parameter("friction must be finite and >= 0"));
    }
    let to_world = |q: &Point3<f64>| origin + rotation * q.coords;
    let anchor_robot = anchor.map(|(a, _)| Point3::from(rotation.inverse() * (a - origin)));
    let config = model.configuration(anchor_robot.as_ref())?;
    let forward = rotation * Vector3::x();
    let frame =
        |at: &Point3<f64>| -> Result<Rotation3<f64>, RobotError> {
            // Evaluated just above the contact: at the contact itself the direction from the
            // closest point is rounding noise.
            let probe = at + rotation * Vector3::z() * CONTACT_PROBE;
            let g = ground
                .distance_gradient(&probe)
                .and_then(|g| g.try_normalize(1e-12))
                .ok_or(RobotError::Parameter(
                    "no ground gradient at a settled contact",
                ))?;
            let x = (forward - g * forward.dot(&g)).try_normalize(1e-9).ok_or(
                RobotError::Parameter("contact normal along the forward axis"),
            )?;
            Ok(Rotation3::from_basis_unchecked(&[x, g.cross(&x), g]))
        };
    let mut contacts = Vec::with_capacity(settled.len() + config.contacts.len());
    for c in settled {
        contacts.push(ContactFrame {
            position: *c,
            rotation: frame(c)?,
            friction: None,
            point: false,
        });
    }
    for (i, c) in config.contacts.iter().enumerate().skip(replaces) {
        contacts.push(ContactFrame {
            position: to_world(c),
            rotation,
            friction: model.contact_friction(i),
            point: model.contact_is_point(i),
        });
    }
    let tether = match (anchor, anchor_robot) {
        (Some((a, max_tension)), Some(_)) => {
            let exit = to_world(&config.tether_exit);
            Some(TetherLine::toward(exit, a - exit, max_tension)?)
        }
        _ => None,
    };
    Ok(PlacedRobot {
        masses: config.world_masses(to_world),
        contacts,
        tether,
        friction,
        moment_coefficient: model.contact_moment_coefficient(),
        reference: origin,
    })
}

pub(crate) fn dist<D: SignedDistance + ?Sized>(d: &D, q: &Point3<f64>) -> Result<f64, SettleError> {
    d.signed_distance(q).ok_or(SettleError::NoGround {
        x: q.x,
        y: q.y,
        z: q.z,
    })
}

/// The wheel contact points in the robot frame: two circles of [`WHEEL_POINTS`] in the `x z`
/// plane at `y = -track / 2` (right) and `+track / 2` (left), centred `wheel_radius` above the
/// origin.
pub fn wheel_points(p: &AxelParams) -> [Vec<Point3<f64>>; 2] {
    let circle = |y: f64| {
        (0..WHEEL_POINTS)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / WHEEL_POINTS as f64;
                Point3::new(
                    p.wheel_radius * a.cos(),
                    y,
                    p.wheel_radius + p.wheel_radius * a.sin(),
                )
            })
            .collect()
    };
    [circle(-0.5 * p.track), circle(0.5 * p.track)]
}

/// The ground under a footprint: the ground point under the start, the footprint normal, and
/// the robot frame on it.
pub(crate) struct Footprint {
    /// The ground point under `(x, y)`.
    pub ground: Point3<f64>,
    /// The upward footprint normal.
    pub normal: Vector3<f64>,
    /// The robot frame: `x` forward in the footprint plane along the yaw (seen from above), `z`
    /// the normal.
    pub base: Rotation3<f64>,
}

/// A drop's failure as a settling error: no distance or no ground on the line is
/// [`SettleError::NoGround`] there, an exhausted sphere trace [`SettleError::NoContact`] within
/// `reach`.
pub(crate) fn drop_error(e: DropError, reach: f64) -> SettleError {
    match e {
        DropError::Undefined(p) | DropError::Missed(p) => SettleError::NoGround {
            x: p.x,
            y: p.y,
            z: p.z,
        },
        DropError::NotReached => SettleError::NoContact(reach),
    }
}

/// The ground point straight below `q` ([`SignedDistance::ground_below`]: sphere tracing by
/// default, an exact vertical ray on meshes, the interpolant's exact zero on grid fields).
pub(crate) fn drop_vertically<D: SignedDistance + ?Sized>(
    ground: &D,
    q: Point3<f64>,
    tolerance: f64,
) -> Result<Point3<f64>, SettleError> {
    ground
        .ground_below(&q, tolerance)
        .map_err(|e| drop_error(e, q.z.abs() + 1.0))
}

/// How far `q` moves along `-n` (`n` a unit vector) to its first ground contact
/// ([`SignedDistance::ground_along`]): positive from the air, negative from below the ground,
/// `None` beyond `reach`.
pub(crate) fn drop_along_normal<D: SignedDistance + ?Sized>(
    ground: &D,
    q: &Point3<f64>,
    n: &Vector3<f64>,
    reach: f64,
    tolerance: f64,
) -> Result<Option<f64>, SettleError> {
    ground
        .ground_along(q, &Unit::new_unchecked(-n), reach, tolerance)
        .map_err(|e| drop_error(e, reach))
}

/// Paton §IV-A's first step for a footprint of half-lengths `half = [forward, sideways]` at
/// ground point `(x, y)` with heading `yaw`: the ground under it (dropped from `z_top`), the
/// least-squares plane `z = a x + b y + c` through the ground points under a 3 x 3 grid over the
/// footprint (in coordinates centred on the start point), its normal (refused beyond
/// `max_slope`) and the robot frame on it.
pub(crate) fn footprint<D: SignedDistance + ?Sized>(
    ground: &D,
    x: f64,
    y: f64,
    z_top: f64,
    yaw: f64,
    half: [f64; 2],
    p: &SettleParams,
) -> Result<Footprint, SettleError> {
    let pm = drop_vertically(ground, Point3::new(x, y, z_top), p.contact_tolerance)?;
    let (s, c) = yaw.sin_cos();
    let fwd = Vector3::new(c, s, 0.0);
    let left = Vector3::new(-s, c, 0.0);
    let mut ata = nalgebra::Matrix3::zeros();
    let mut atb = Vector3::zeros();
    for i in [-1.0, 0.0, 1.0] {
        for j in [-1.0, 0.0, 1.0] {
            let q = pm + fwd * (i * half[0]) + left * (j * half[1]);
            let g = drop_vertically(ground, Point3::new(q.x, q.y, z_top), p.contact_tolerance)?;
            let row = Vector3::new(g.x - pm.x, g.y - pm.y, 1.0);
            ata += row * row.transpose();
            atb += row * (g.z - pm.z);
        }
    }
    let abc = ata.lu().solve(&atb).ok_or(SettleError::SlopeBeyondModel(
        "no surface normal over the footprint",
    ))?;
    let n = Vector3::new(-abc.x, -abc.y, 1.0).normalize();
    if n.z.clamp(-1.0, 1.0).acos() > p.max_slope {
        return Err(SettleError::SlopeBeyondModel(
            "ground steeper than max_slope",
        ));
    }
    Ok(Footprint {
        ground: pm,
        normal: n,
        base: frame_on_plane(yaw, &n)?,
    })
}

/// The robot frame on a plane of upward normal `n` with heading `yaw`: `x` forward in the plane,
/// its horizontal part along the yaw; `z` the normal.
pub(crate) fn frame_on_plane(yaw: f64, n: &Vector3<f64>) -> Result<Rotation3<f64>, SettleError> {
    let (s, c) = yaw.sin_cos();
    let fwd = Vector3::new(c, s, 0.0);
    let xa = (fwd - Vector3::z() * (fwd.dot(n) / n.z))
        .try_normalize(1e-9)
        .ok_or(SettleError::SlopeBeyondModel("heading along the normal"))?;
    let ya = n.cross(&xa);
    Ok(Rotation3::from_basis_unchecked(&[xa, ya, *n]))
}

/// Settle Axel at ground point `(x, y)` (the ground is found by sphere tracing down from `z_top`)
/// with heading `yaw` radians from world `+x`, counter-clockwise.
pub fn settle_axel<D: SignedDistance + ?Sized>(
    ground: &D,
    axel: &AxelParams,
    x: f64,
    y: f64,
    z_top: f64,
    yaw: f64,
    p: &SettleParams,
) -> Result<SettledPose, SettleError> {
    let positive = [p.delta, p.contact_tolerance, p.max_roll, p.max_slope]
        .iter()
        .all(|v| *v > 0.0 && v.is_finite());
    let body_ok = p.body_radius >= 0.0 && p.body_radius < axel.wheel_radius;
    if !positive
        || !body_ok
        || p.body_points < 2
        || ![x, y, z_top, yaw].iter().all(|v| v.is_finite())
    {
        return Err(SettleError::Parameter(
            "delta, tolerance, roll and slope must be positive, body_radius below the wheel radius, body_points >= 2, inputs finite",
        ));
    }
    let Footprint {
        ground: pm,
        normal: n,
        base,
    } = footprint(
        ground,
        x,
        y,
        z_top,
        yaw,
        [axel.wheel_radius, 0.5 * axel.track],
        p,
    )?;
    let mut wheels = wheel_points(axel);
    // Lowest first: the first hit bounds the later casts' reach.
    for w in &mut wheels {
        w.sort_by(|a, b| a.z.total_cmp(&b.z));
    }
    let max_fall = p.delta + 2.0 * axel.wheel_radius + axel.track;
    // Drop at roll `phi` (about the robot x axis through the origin) from `delta` above the
    // footprint: every contact point cast along `-n`, the pose moved by the first hit (a point
    // starting on or below the ground touches at once: 0), then the origin and the lowest
    // distance of each wheel there (Paton's "two minimum contact points").
    let drop = |phi: f64| -> Result<Dropped, SettleError> {
        let rot = base * Rotation3::from_axis_angle(&Unit::new_unchecked(Vector3::x()), phi);
        let start = pm + n * p.delta;
        let mut first = f64::INFINITY;
        for c in wheels.iter().flatten() {
            let q = start + rot * c.coords;
            let reach = first.min(max_fall);
            if let Some(t) = drop_along_normal(ground, &q, &n, reach, p.contact_tolerance)? {
                first = first.min(t.max(0.0));
            }
        }
        if !first.is_finite() {
            return Err(SettleError::NoContact(max_fall));
        }
        let o = start - n * first;
        let mut lows = [(f64::INFINITY, Point3::origin()); 2];
        for (w, pts) in wheels.iter().enumerate() {
            for c in pts {
                let q = o + rot * c.coords;
                let d = dist(ground, &q)?;
                if d < lows[w].0 {
                    lows[w] = (d, q);
                }
            }
        }
        Ok((o, rot, lows))
    };
    // Roll: bisection on (left lowest - right lowest) after a drop. The settled pose is the drop
    // at the last roll the search tried (`best`): kept from the search, not dropped again.
    let mut last: Option<(f64, Dropped)> = None;
    let mut gap = |phi: f64| -> Result<f64, SettleError> {
        let dropped = drop(phi)?;
        let g = dropped.2[1].0 - dropped.2[0].0;
        last = Some((phi, dropped));
        Ok(g)
    };
    let (mut lo, mut hi) = (-p.max_roll, p.max_roll);
    let mut best = 0.0;
    let g0 = gap(0.0)?;
    if g0.abs() > p.contact_tolerance {
        let (glo, ghi) = (gap(lo)?, gap(hi)?);
        if glo.signum() == ghi.signum() {
            return Err(SettleError::SlopeBeyondModel(
                "no roll within max_roll puts both wheels on the ground",
            ));
        }
        let rising = ghi > glo;
        for _ in 0..MAX_ROLL_STEPS {
            let mid = 0.5 * (lo + hi);
            let g = gap(mid)?;
            best = mid;
            if g.abs() < p.contact_tolerance {
                break;
            }
            if (g > 0.0) == rising {
                hi = mid;
            } else {
                lo = mid;
            }
        }
    }
    let (origin, rotation, lows) = match last {
        Some((phi, dropped)) if phi.to_bits() == f64::to_bits(best) => dropped,
        _ => drop(best)?,
    };
    // Body collision points along the axle, inside the wheels.
    // The worst point (smallest clearance) is the one reported.
    let mut worst = (f64::INFINITY, 0, origin);
    for k in 0..p.body_points {
        let t = -0.5 + k as f64 / (p.body_points - 1) as f64;
        let q = origin + rotation * Vector3::new(0.0, t * axel.track, axel.wheel_radius);
        let c = dist(ground, &q)? - p.body_radius;
        if c < worst.0 {
            worst = (c, k, q);
        }
    }
    let (clearance, index, q) = worst;
    if clearance < 0.0 {
        return Err(SettleError::BodyCollision {
            index,
            x: q.x,
            y: q.y,
            z: q.z,
            clearance,
        });
    }
    Ok(SettledPose {
        origin,
        rotation,
        contacts: [lows[0].1, lows[1].1],
        contact_distances: [lows[0].0, lows[1].0],
        body_clearance: clearance,
    })
}
