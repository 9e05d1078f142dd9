//! Anchor-point prediction (Paton et al. 2020, §IV-B, Alg. 1): how the taut tether's contacts
//! with 3D ground change when its free end (the rover's boom tip) moves a short step.
//!
//! The ground enters only through the [`SignedDistance`] trait (an exact mesh distance, a voxel
//! field, or the analytic distance of a planar-surface terrain); nothing here knows a concrete
//! terrain.
//!
//! # Model
//! An [`AnchorHistory`] is a stack of [`Anchor`]s `a_0 .. a_N`, each a world point `p` and the
//! distance gradient `g` there (Paton's `(p, g)`); `a_0` is the root (where the tether is fixed,
//! never removed). The tether is taut and straight between consecutive anchors and from `a_N` to
//! the tip. [`predict`] moves the tip from `from_tip` to `to_tip` along a straight segment:
//!
//! - **detach** ([`detach_height`], [`is_detached`]): in Paton's frame `F_d` of the top anchor
//!   `a_N` (`x` along `a_N - a_{N-1}`, `z` the anchor's gradient made orthogonal to `x`), the
//!   anchor is released when the tether `tip - a_N` rises above the frame's `x y` plane, i.e.
//!   when the tether would be bent toward the air without it; by more than [`DETACH_MIN_SINE`]
//!   of its length, so that a straight tether (the tip on the plane) keeps its anchor whatever
//!   the rounding of the frame. The height is linear in the tip, so the tip position where it
//!   crosses the plane is solved in closed form and the motion is split there.
//! - **attach** (`attach_anchors`): the tether sweeps the triangle `(a_N, tip_n, tip_end)`. It is
//!   sampled as a fan of rays from `a_N` to tips spaced at most the sampling resolution `h`
//!   apart along the motion, each ray sampled every `h`. A sample is an obstacle when its signed
//!   distance is below `-CONTACT_DEPTH_VOXELS * h` (see [`CONTACT_DEPTH_VOXELS`]). The first ray
//!   with an obstacle is the smallest angle from the old tether direction; the angle is refined by
//!   bisection between the last clear ray and it ([`REFINE_STEPS`]); the deepest sample of the
//!   refined ray, projected onto the surface along its gradient, is the new anchor, and the tip
//!   is moved to where the line from the old anchor through the new one meets the motion. The
//!   sweep repeats from the new anchor on the rest of the motion.
//!
//! Each attach or detach is an [`AnchorEvent`] splitting the motion; [`Prediction::events`] lists
//! them in order. Every loop is bounded: at most [`MAX_EVENTS`] events per step, at most
//! [`PredictParams::max_samples`] distance queries per step (both typed errors when exceeded),
//! [`REFINE_STEPS`] bisection steps per contact.
//!
//! # Assumptions (Paton's)
//! The step is short relative to the tether, the tether is massless, taut and straight between
//! anchors, anchors are removed in reverse order (a stack) and never slide (a contact stays where
//! it first touched; the planar tracker [`crate::tether_tracking`] slides ground anchors along
//! crest edges instead, so the two agree on motions that keep the contact fixed, e.g. radial
//! ones). The current tether `a_N -> from_tip` is assumed clear of the ground (it is, when the
//! history was produced by earlier predictions from a clear start).
//!
//! ```
//! use nalgebra::{Point3, Vector3};
//! use rappel_planners::anchor_prediction::{AnchorHistory, PredictParams, predict_path};
//! use rappel_terrain::surface::SignedDistance;
//!
//! /// A ledge: `z = 0` for `x < 0`, a vertical drop at `x = 0` to `z = -10` (a quarter space).
//! struct Ledge;
//! impl SignedDistance for Ledge {
//!     fn signed_distance(&self, q: &Point3<f64>) -> Option<f64> {
//!         Some(if q.x <= 0.0 { q.z } else if q.z >= 0.0 { (q.x * q.x + q.z * q.z).sqrt() } else { q.x })
//!     }
//!     fn distance_gradient(&self, q: &Point3<f64>) -> Option<Vector3<f64>> {
//!         Some(if q.x <= 0.0 { Vector3::z() } else if q.z >= 0.0 { Vector3::new(q.x, 0.0, q.z).normalize() } else { Vector3::x() })
//!     }
//! }
//! let root = AnchorHistory::new(Point3::new(-5.0, 0.0, 0.5)).unwrap();
//! // Move the tip past the lip, then down the drop: the tether anchors on the lip.
//! let tips = [Point3::new(-1.0, 0.0, 0.3), Point3::new(0.5, 0.0, 0.3), Point3::new(1.0, 0.0, -3.0)];
//! let step = predict_path(&Ledge, &PredictParams::new(0.02), &root, &tips).unwrap();
//! let lip = step.history.last().point;
//! assert_eq!(step.history.len(), 2);
//! assert!(lip.x.abs() < 0.05 && lip.z.abs() < 0.05);
//! ```

use nalgebra::{Point3, Vector3};
use rappel_terrain::surface::SignedDistance;
use serde::{Deserialize, Serialize};

/// The contact threshold, in units of the sampling resolution `h`: a sample of the swept triangle
/// is an obstacle when its signed distance is below `-CONTACT_DEPTH_VOXELS * h`, i.e. the swept
/// tether would pass that deep into the ground.
///
/// A penetration depth rather than a positive clearance, so that a tether lying along a surface
/// (distance 0 all along, as below a lip or along a slope) is not mistaken for a new contact.
/// It must exceed a voxel field's interpolation error (`rappel_terrain::sdf::INTERPOLATION_BOUND`
/// = `0.87 h`) so that rays through an anchor on the surface read no contact; 1 voxel does.
/// The cost: a contact is found once the sweep is `h` deep, so around a curved obstacle of
/// radius `R` consecutive anchors are about `acos(1 - h / R)` apart (a polygonal wrap).
pub const CONTACT_DEPTH_VOXELS: f64 = 1.0;

/// Bisection steps refining the first contact angle between the last clear ray and the first
/// ray with an obstacle (the angle is then known to `1 / 2^8` of one ray spacing).
pub const REFINE_STEPS: usize = 8;

/// Most anchor events (attach or detach) in one step; a short step makes a handful. Beyond it the
/// step is refused ([`AnchorError::EventLimit`]): split the motion.
pub const MAX_EVENTS: usize = 64;

/// The default cap on distance queries in one step ([`PredictParams::max_samples`]).
pub const DEFAULT_MAX_SAMPLES: usize = 200_000;

/// The detach threshold ([`is_detached`]): the top anchor is released when the tether beyond it
/// rises above the plane of its frame `F_d` by more than this fraction of its length (the sine of
/// the angle it rises by). Dimensionless, so the same at every scale; far above the rounding of
/// the frame and of the height (a few ulps, `1e-15` of the length), far below any bend the
/// sampling at resolution `h` can see. A tip exactly on the plane (the tether straight past the
/// anchor, or turning in the plane) keeps the anchor.
pub const DETACH_MIN_SINE: f64 = 1e-9;

/// The frame `F_d` of an anchor exists when the component of its gradient orthogonal to the
/// incoming tether is more than this fraction of the gradient's norm (the sine of the angle
/// between them); otherwise the anchor never detaches ([`detach_height`] is `None`).
/// Dimensionless.
pub const FRAME_MIN_SINE: f64 = 1e-9;

/// A distance gradient with a norm at most this is treated as zero (the anchor gets a zero
/// gradient, and so no detach frame). Relative to the unit norm of the gradient of a distance
/// (eikonal), so dimensionless; a voxel field's gradient is that small only at a medial point.
pub const MIN_GRADIENT_NORM: f64 = 1e-12;

/// Parallel test of the closest approach between the line through the old and the new anchor and
/// the motion: the lines count as parallel when `|u|^2 |v|^2 - (u . v)^2 <= PARALLEL_REL |u|^2
/// |v|^2` (the squared sine of their angle at most this), where the difference is the rounding of
/// its two products (a few `EPSILON`s of them) rather than a signal. Then the tip is put at the
/// bracket's end where the contact is known.
pub const PARALLEL_REL: f64 = 64.0 * f64::EPSILON;

/// One anchor (Paton's `a_i`): where the tether touches the ground and the distance gradient
/// there (pointing away from the ground).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Anchor {
    /// World point (on the surface for predicted anchors; anywhere for the root).
    pub point: Point3<f64>,
    /// Unit distance gradient at the point (zero for the root, which is never tested).
    pub gradient: Vector3<f64>,
}

/// The anchor history of a state: a stack `a_0 .. a_N`, root first, never empty.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AnchorHistory {
    anchors: Vec<Anchor>,
}

impl AnchorHistory {
    /// A history with only the root anchor (a fixed point: a stake, a winch, another rover).
    pub fn new(root: Point3<f64>) -> Result<Self, AnchorError> {
        if !root.iter().all(|c| c.is_finite()) {
            return Err(AnchorError::NonFinite { what: "the root" });
        }
        Ok(AnchorHistory {
            anchors: vec![Anchor {
                point: root,
                gradient: Vector3::zeros(),
            }],
        })
    }

    /// The anchors, root first.
    pub fn anchors(&self) -> &[Anchor] {
        &self.anchors
    }

    /// The root anchor.
    pub fn root(&self) -> &Anchor {
        &self.anchors[0]
    }

    /// The last anchor: where the free tether to the tip starts (the one that sets the tether
    /// force's direction for stability).
    pub fn last(&self) -> &Anchor {
        // Never empty: the root is never popped.
        &self.anchors[self.anchors.len() - 1]
    }

    /// Number of anchors, root included (`>= 1`).
    pub fn len(&self) -> usize {
        self.anchors.len()
    }

    /// Always false (the root is always there); for clippy's `len` convention.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// Length of the tether from the root through the anchors to `tip`, metres.
    pub fn tether_length(&self, tip: &Point3<f64>) -> f64 {
        self.anchors
            .windows(2)
            .map(|w| (w[1].point - w[0].point).norm())
            .sum::<f64>()
            + (tip - self.last().point).norm()
    }
}

/// Sampling parameters of one prediction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PredictParams {
    /// Sampling resolution `h`, metres (`> 0`): ray spacing along the motion, sample spacing
    /// along each ray, and the unit of the contact threshold. For a voxel field use its
    /// resolution; for exact distances the smallest feature the tether should notice.
    pub resolution: f64,
    /// Most distance queries in one step (`>= 1`).
    pub max_samples: usize,
    /// The distances are exact Euclidean distances to the ground whose sign changes only across
    /// the ground (a closed mesh, or a terrain sheet away from its open boundary): a sample at
    /// distance `D > 0` then proves every point closer than `D` to it to be in the air, and the
    /// samples of a ray inside that clear ball are skipped without a query (sphere tracing along
    /// the ray). The anchors are the same as without skipping (no skipped sample can be an
    /// obstacle); only the number of queries drops, several-fold on a tether in open air. Off
    /// by [`PredictParams::new`]: a voxel field's interpolated distance is not exact.
    pub skip_clear: bool,
}

/// Slack of the clear-ball skipping ([`PredictParams::skip_clear`]), relative to the ray's
/// length: a sample is skipped only when it lies this much inside the clear ball, so rounding of
/// the sample positions never skips a sample on the ball's boundary.
pub const CLEAR_BALL_SLACK_REL: f64 = 1e-9;

impl PredictParams {
    /// Resolution `h`, [`DEFAULT_MAX_SAMPLES`], no clear-ball skipping.
    pub fn new(resolution: f64) -> Self {
        PredictParams {
            resolution,
            max_samples: DEFAULT_MAX_SAMPLES,
            skip_clear: false,
        }
    }

    /// [`PredictParams::new`] for exact distances: with clear-ball skipping
    /// ([`PredictParams::skip_clear`]).
    ///
    /// ```
    /// use rappel_planners::anchor_prediction::PredictParams;
    /// let p = PredictParams::exact(0.05);
    /// assert!(p.skip_clear && p.resolution == 0.05);
    /// ```
    pub fn exact(resolution: f64) -> Self {
        PredictParams {
            skip_clear: true,
            ..PredictParams::new(resolution)
        }
    }
}

/// What changed at one split of the motion.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum EventKind {
    /// A new anchor was pushed.
    Attach,
    /// The top anchor was popped.
    Detach,
}

/// One split of the motion where the anchors change.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct AnchorEvent {
    /// Attach or detach.
    pub kind: EventKind,
    /// Fraction of the motion `from_tip -> to_tip` at which it happens, in `[0, 1]`.
    pub t: f64,
    /// The tip there.
    pub tip: Point3<f64>,
    /// The anchor pushed or popped.
    pub anchor: Anchor,
}

/// The result of one step.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Prediction {
    /// The anchor history at `to_tip`.
    pub history: AnchorHistory,
    /// The anchor changes in order along the motion (`t` non-decreasing).
    pub events: Vec<AnchorEvent>,
}

/// Why a step cannot be predicted.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum AnchorError {
    /// A point is NaN or infinite.
    #[error("{what} is not finite")]
    NonFinite {
        /// Which point.
        what: &'static str,
    },
    /// A parameter out of its domain.
    #[error("anchor prediction parameter {name} = {value}: {why}")]
    BadParameter {
        /// The parameter.
        name: &'static str,
        /// Its value.
        value: f64,
        /// The domain.
        why: &'static str,
    },
    /// A tip is inside the ground (deeper than the contact threshold).
    #[error("{what} ({x}, {y}, {z}) is {depth} m inside the ground")]
    TipInGround {
        /// Which tip.
        what: &'static str,
        /// World x.
        x: f64,
        /// World y.
        y: f64,
        /// World z.
        z: f64,
        /// Depth below the surface, metres.
        depth: f64,
    },
    /// The distance model has no answer at a point the tether sweeps (outside a field's grid, off
    /// a terrain's surfaces).
    #[error("no ground distance at ({x}, {y}, {z}), which the tether sweeps")]
    NoDistance {
        /// World x.
        x: f64,
        /// World y.
        y: f64,
        /// World z.
        z: f64,
    },
    /// The distance-query budget of one step ran out.
    #[error(
        "anchor prediction needs more than {limit} distance queries for this step (split the motion or coarsen the resolution)"
    )]
    SampleBudget {
        /// The budget.
        limit: usize,
    },
    /// More than [`MAX_EVENTS`] anchor changes in one step (a degenerate or too long motion).
    #[error("more than {limit} anchor changes in one step (split the motion)")]
    EventLimit {
        /// The bound.
        limit: usize,
    },
}

/// Distance queries with the step's budget.
struct Probe<'a, D: SignedDistance + ?Sized> {
    field: &'a D,
    used: usize,
    limit: usize,
    /// [`PredictParams::skip_clear`].
    skip_clear: bool,
}

impl<D: SignedDistance + ?Sized> Probe<'_, D> {
    fn distance(&mut self, q: &Point3<f64>) -> Result<f64, AnchorError> {
        self.used += 1;
        if self.used > self.limit {
            return Err(AnchorError::SampleBudget { limit: self.limit });
        }
        self.field
            .signed_distance(q)
            .ok_or(AnchorError::NoDistance {
                x: q.x,
                y: q.y,
                z: q.z,
            })
    }

    /// The deepest sample of the ray `apex -> tip` (spacing `h`, the apex excluded) below
    /// `-depth`, with its distance.
    fn deepest_on_ray(
        &mut self,
        apex: &Point3<f64>,
        tip: &Point3<f64>,
        h: f64,
        depth: f64,
    ) -> Result<Option<(Point3<f64>, f64)>, AnchorError> {
        let v = tip - apex;
        let len = v.norm();
        // Samples at h, 2h, .. short of the tip (the tip itself is checked to be out of the
        // ground); at most len / h + 1 of them, each counted against the budget.
        let n = (len / h).floor() as usize;
        let slack = CLEAR_BALL_SLACK_REL * len;
        let mut best: Option<(Point3<f64>, f64)> = None;
        // Each pass queries sample j and moves j forward by at least one.
        let mut j = 1;
        while j <= n {
            let s = apex + v * (j as f64 * h / len);
            let d = self.distance(&s)?;
            if d < -depth && best.is_none_or(|(_, b)| d < b) {
                best = Some((s, d));
            }
            // Samples j + k with k h < d - slack lie in the clear ball of sample j.
            let clear = if self.skip_clear && d > slack {
                ((d - slack) / h).floor() as usize
            } else {
                0
            };
            j += clear.max(1);
        }
        Ok(best)
    }
}

/// The first contact of the tether swept from `apex -> from` to `apex -> to` (Paton's
/// `attach_anchors`, one anchor): the new anchor and the fraction of `from -> to` where the tip
/// is when it touches.
fn first_contact<D: SignedDistance + ?Sized>(
    probe: &mut Probe<'_, D>,
    apex: &Point3<f64>,
    from: &Point3<f64>,
    to: &Point3<f64>,
    h: f64,
) -> Result<Option<(Anchor, f64)>, AnchorError> {
    let depth = CONTACT_DEPTH_VOXELS * h;
    let motion = to - from;
    let tip_at = |t: f64| from + motion * t;
    // Rays to tips at most h apart along the motion; ray 0 is the current tether (clear).
    let rays = ((motion.norm() / h).ceil() as usize).max(1);
    let mut found = None;
    for k in 1..=rays {
        let t = k as f64 / rays as f64;
        if let Some(hit) = probe.deepest_on_ray(apex, &tip_at(t), h, depth)? {
            found = Some(((k - 1) as f64 / rays as f64, t, hit));
            break;
        }
    }
    let Some((mut lo, mut hi, mut hit)) = found else {
        return Ok(None);
    };
    for _ in 0..REFINE_STEPS {
        let mid = 0.5 * (lo + hi);
        match probe.deepest_on_ray(apex, &tip_at(mid), h, depth)? {
            Some(s) => {
                hi = mid;
                hit = s;
            }
            None => lo = mid,
        }
    }
    let (s, d) = hit;
    let g = probe
        .field
        .distance_gradient(&s)
        .ok_or(AnchorError::NoDistance {
            x: s.x,
            y: s.y,
            z: s.z,
        })?
        .try_normalize(MIN_GRADIENT_NORM)
        .unwrap_or_else(Vector3::zeros);
    // Project the deepest sample onto the surface (exact for an exact distance).
    let point = s - g * d;
    // The tip where the line apex -> point meets the motion (closest approach, within the
    // refined bracket).
    let t = line_segment_parameter(apex, &point, from, to).clamp(lo, hi);
    Ok(Some((Anchor { point, gradient: g }, t)))
}

/// The parameter `t` on `from -> to` of the closest approach to the line through `a` and `b`;
/// 1 when they are parallel within [`PARALLEL_REL`] (the caller's clamp turns it into the
/// bracket's `hi` end).
fn line_segment_parameter(
    a: &Point3<f64>,
    b: &Point3<f64>,
    from: &Point3<f64>,
    to: &Point3<f64>,
) -> f64 {
    let u = b - a;
    let v = to - from;
    let w = from - a;
    let (uu, uv, vv) = (u.dot(&u), u.dot(&v), v.dot(&v));
    let (uw, vw) = (u.dot(&w), v.dot(&w));
    let den = uu * vv - uv * uv;
    if !(den > PARALLEL_REL * uu * vv && den.is_finite()) {
        return 1.0;
    }
    (uv * uw - uu * vw) / den
}

/// Paton's `F_d` frame test: the signed height of `tip` above the `x y` plane of the frame of
/// the top anchor `a` (after `prev`); [`is_detached`] decides from it. `None` when the frame is
/// degenerate (`a` and `prev` the same point, a zero gradient, or the gradient within
/// [`FRAME_MIN_SINE`] of the incoming tether's direction): never detaches.
pub fn detach_height(prev: &Anchor, a: &Anchor, tip: &Point3<f64>) -> Option<f64> {
    // Any two distinct points give a direction: no length threshold, so no scale.
    let x = (a.point - prev.point).try_normalize(0.0)?;
    let g = a.gradient;
    let z = g - x * g.dot(&x);
    let (zn, gn) = (z.norm(), g.norm());
    if zn.is_nan() || zn <= FRAME_MIN_SINE * gn {
        return None;
    }
    Some((tip - a.point).dot(&(z / zn)))
}

/// Whether the tether from `a` (after `prev`) to `tip` releases `a`: its height above the frame's
/// plane ([`detach_height`]) exceeds [`DETACH_MIN_SINE`] of its length `|tip - a|`.
///
/// ```
/// use nalgebra::{Point3, Vector3};
/// use rappel_planners::anchor_prediction::{Anchor, is_detached};
/// let prev = Anchor { point: Point3::origin(), gradient: Vector3::zeros() };
/// let lip = Anchor { point: Point3::new(1.0, 0.0, 0.0), gradient: Vector3::z() };
/// assert!(!is_detached(&prev, &lip, &Point3::new(3.0, 0.0, 0.0))); // straight on
/// assert!(!is_detached(&prev, &lip, &Point3::new(2.0, 0.0, -1.0))); // bent over the lip
/// assert!(is_detached(&prev, &lip, &Point3::new(2.0, 0.0, 0.5)));
/// ```
pub fn is_detached(prev: &Anchor, a: &Anchor, tip: &Point3<f64>) -> bool {
    detach_height(prev, a, tip).is_some_and(|f| rises(f, &a.point, tip))
}

/// [`is_detached`]'s threshold on a height `f` already computed.
fn rises(f: f64, a: &Point3<f64>, tip: &Point3<f64>) -> bool {
    f > DETACH_MIN_SINE * (tip - a).norm()
}

/// One step of Paton's Alg. 1: the anchor history after the tip moves straight from `from_tip`
/// to `to_tip`, with the motion split where anchors attach or detach.
///
/// Errors: non-finite tips ([`AnchorError::NonFinite`]), a tip or a point of the motion (sampled
/// every `h`) deeper than the contact threshold in the ground ([`AnchorError::TipInGround`]), a sweep leaving the distance model
/// ([`AnchorError::NoDistance`]), a bad resolution, or a budget exceeded.
pub fn predict<D: SignedDistance + ?Sized>(
    field: &D,
    params: &PredictParams,
    history: &AnchorHistory,
    from_tip: &Point3<f64>,
    to_tip: &Point3<f64>,
) -> Result<Prediction, AnchorError> {
    let h = params.resolution;
    if !(h.is_finite() && h > 0.0) {
        return Err(AnchorError::BadParameter {
            name: "resolution",
            value: h,
            why: "must be finite and > 0",
        });
    }
    if params.max_samples == 0 {
        return Err(AnchorError::BadParameter {
            name: "max_samples",
            value: 0.0,
            why: "must be >= 1",
        });
    }
    let mut probe = Probe {
        field,
        used: 0,
        limit: params.max_samples,
        skip_clear: params.skip_clear,
    };
    for (what, p) in [("the start tip", from_tip), ("the end tip", to_tip)] {
        if !p.iter().all(|c| c.is_finite()) {
            return Err(AnchorError::NonFinite { what });
        }
        let d = probe.distance(p)?;
        if d < -CONTACT_DEPTH_VOXELS * h {
            return Err(AnchorError::TipInGround {
                what,
                x: p.x,
                y: p.y,
                z: p.z,
                depth: -d,
            });
        }
    }
    // The tip's own path must stay out of the ground (samples every h between the ends).
    let motion = to_tip - from_tip;
    let legs = (motion.norm() / h).ceil() as usize;
    for k in 1..legs {
        let q = from_tip + motion * (k as f64 / legs as f64);
        let d = probe.distance(&q)?;
        if d < -CONTACT_DEPTH_VOXELS * h {
            return Err(AnchorError::TipInGround {
                what: "the motion",
                x: q.x,
                y: q.y,
                z: q.z,
                depth: -d,
            });
        }
    }
    let mut anchors = history.anchors.clone();
    let mut events = Vec::new();
    // The tip's progress along from_tip -> to_tip.
    let mut t = 0.0;
    let tip_at = |t: f64| from_tip + motion * t;
    // Each pass either records one event (bounded by MAX_EVENTS) or ends the step.
    loop {
        if events.len() > MAX_EVENTS {
            return Err(AnchorError::EventLimit { limit: MAX_EVENTS });
        }
        let n = anchors.len();
        let top = anchors[n - 1];
        let pos = tip_at(t);
        // Detach along the rest of the motion (never the root).
        let mut end = 1.0;
        if n >= 2 {
            let prev = anchors[n - 2];
            if let (Some(f0), Some(f1)) = (
                detach_height(&prev, &top, &pos),
                detach_height(&prev, &top, to_tip),
            ) && rises(f1, &top.point, to_tip)
                && f1 > f0
            {
                let s = if f0 <= 0.0 { f0 / (f0 - f1) } else { 0.0 };
                end = t + (1.0 - t) * s.clamp(0.0, 1.0);
            }
        }
        // Attach while the top anchor holds (Alg. 1 sweeps before the detach point too).
        if end > t
            && let Some((anchor, s)) = first_contact(&mut probe, &top.point, &pos, &tip_at(end), h)?
        {
            t += (end - t) * s;
            anchors.push(anchor);
            events.push(AnchorEvent {
                kind: EventKind::Attach,
                t,
                tip: tip_at(t),
                anchor,
            });
            continue;
        }
        if end < 1.0 {
            t = end;
            anchors.pop();
            events.push(AnchorEvent {
                kind: EventKind::Detach,
                t,
                tip: tip_at(t),
                anchor: top,
            });
            continue;
        }
        break;
    }
    Ok(Prediction {
        history: AnchorHistory { anchors },
        events,
    })
}

/// Predicts along a polyline of tips (each leg one [`predict`] step); the events' `t` are per
/// leg, in `leg + fraction` form (leg `i` from `tips[i]` to `tips[i + 1]`).
pub fn predict_path<D: SignedDistance + ?Sized>(
    field: &D,
    params: &PredictParams,
    history: &AnchorHistory,
    tips: &[Point3<f64>],
) -> Result<Prediction, AnchorError> {
    let mut out = Prediction {
        history: history.clone(),
        events: Vec::new(),
    };
    for (i, w) in tips.windows(2).enumerate() {
        let step = predict(field, params, &out.history, &w[0], &w[1])?;
        out.history = step.history;
        out.events.extend(step.events.into_iter().map(|mut e| {
            e.t += i as f64;
            e
        }));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Ground far below everything: no contact, no tip in the ground.
    struct Clear;
    impl SignedDistance for Clear {
        fn signed_distance(&self, _: &Point3<f64>) -> Option<f64> {
            Some(1e3)
        }
        fn distance_gradient(&self, _: &Point3<f64>) -> Option<Vector3<f64>> {
            Some(Vector3::z())
        }
    }

    fn history(points: &[(Point3<f64>, Vector3<f64>)]) -> AnchorHistory {
        AnchorHistory {
            anchors: points
                .iter()
                .map(|&(point, gradient)| Anchor { point, gradient })
                .collect(),
        }
    }

    /// A tip moving onto the straight continuation of the tether past its top anchor (on the
    /// plane of `F_d` exactly: dyadic points, the tip `2 (a - prev)` beyond `a`) never detaches
    /// it, whatever the rounding of the frame; rising above the plane does.
    #[test]
    fn a_tip_on_the_frame_plane_keeps_its_anchor() {
        let mut cases = 0;
        for i in 1..=12 {
            for j in -6..=6 {
                for k in -3..=3 {
                    let prev = Point3::new(0.0, 0.0, 0.0);
                    let a =
                        Point3::new(f64::from(i) / 8.0, f64::from(j) / 64.0, f64::from(k) / 16.0);
                    // A gradient leaning against the tether (not orthogonal to it).
                    let g = Vector3::new(-0.375, 0.125, 1.0).normalize();
                    let h = history(&[(prev, Vector3::zeros()), (a, g)]);
                    let to = a + (a - prev) * 2.0;
                    let from = to - g;
                    let step = predict(&Clear, &PredictParams::new(1.0), &h, &from, &to).unwrap();
                    assert!(step.events.is_empty(), "{a:?}: {:?}", step.events);
                    let up = to + g * 0.25;
                    let step = predict(&Clear, &PredictParams::new(1.0), &h, &from, &up).unwrap();
                    assert_eq!(step.events.len(), 1, "{a:?}");
                    cases += 1;
                }
            }
        }
        assert_eq!(cases, 12 * 13 * 7);
    }

    /// The detach test has no length scale: a scene shrunk by `2^-44` (anchors `1e-13` m apart,
    /// below the former fixed `1e-12` m frame threshold) or grown by `2^40` detaches exactly as
    /// the unit one does.
    #[test]
    fn detaching_is_the_same_at_every_scale() {
        let g = Vector3::new(0.25, 0.0, 1.0).normalize();
        for scale in [1.0, 2f64.powi(-44), 2f64.powi(40)] {
            let p = |x: f64, y: f64, z: f64| Point3::new(x * scale, y * scale, z * scale);
            let prev = Anchor {
                point: p(0.0, 0.0, 0.5),
                gradient: Vector3::zeros(),
            };
            let a = Anchor {
                point: p(1.0, 0.0, 0.0),
                gradient: g,
            };
            assert!(is_detached(&prev, &a, &p(2.0, 0.5, 0.25)), "{scale}");
            assert!(!is_detached(&prev, &a, &p(2.0, 0.5, -1.0)), "{scale}");
            assert!(!is_detached(&prev, &a, &p(3.0, 0.0, -1.0)), "{scale}");
            let h = history(&[(prev.point, prev.gradient), (a.point, a.gradient)]);
            let params = PredictParams::new(scale);
            let step = predict(&Clear, &params, &h, &p(2.0, 0.0, -1.0), &p(2.0, 0.0, 1.0)).unwrap();
            assert_eq!(step.history.len(), 1, "{scale}");
            assert!(matches!(
                step.events[..],
                [AnchorEvent {
                    kind: EventKind::Detach,
                    ..
                }]
            ));
        }
    }

    /// The closest approach of two parallel lines falls back to the motion's end at every scale,
    /// whatever noise the rounding leaves in the parallel test; crossing lines give their
    /// parameter.
    #[test]
    fn parallel_lines_fall_back_to_the_end_of_the_motion() {
        for scale in [1.0, 1e-30, 1e30] {
            let u = Vector3::new(0.1, 0.7, 0.3) * scale;
            let a = Point3::new(0.3, 0.2, 0.1) * scale;
            let from = Point3::new(1.1, -0.4, 0.9) * scale;
            for k in [3.0, 0.3, -7.0] {
                let t = line_segment_parameter(&a, &(a + u), &from, &(from + u * k));
                assert_eq!(t, 1.0, "{scale} {k}");
            }
            // Crossing: the motion along x through the line's point at t = 0.25.
            let o = Point3::origin();
            let t = line_segment_parameter(
                &o,
                &(o + Vector3::z() * scale),
                &Point3::new(-0.25 * scale, 0.0, 0.5 * scale),
                &Point3::new(0.75 * scale, 0.0, 0.5 * scale),
            );
            assert_eq!(t, 0.25, "{scale}");
        }
    }
}
