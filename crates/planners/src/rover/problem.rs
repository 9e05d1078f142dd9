//! The tethered-rover problem of Paton 2020 §III and §V for the ABIT* sampler
//! ([`crate::sampler`]): Axel's settled states on a mesh scene, motions that are an
//! in-place turn, a straight drive and a turn into the target heading, validated through
//! interpolated settled poses with the anchor history predicted along them (Paton Alg. 1) and
//! the stability of every pose with the tether from its last anchor (both boom configurations).
//!
//! The planner stays generic; this module is the scene-specific glue. It reuses
//! [`super::stability_map`] for settling ([`settle_from`]), the tether end ([`tether_end`]) and the
//! stability verdict ([`pose_stability`]).
//!
//! # States, motions, cost
//! A [`RoverState`] is a ground point `(x, y)` and a heading `yaw` (radians from `+x`,
//! counter-clockwise); the 3D pose is the settled one ([`settle_from`]), so states live on the
//! surface manifold. Samples are uniform in the problem's bounds and heading (a ground point
//! of the scene and a yaw about the vertical; the settler tilts the pose onto the normal).
//!
//! A motion from `a` to `b` turns in place at `a` to the heading of `b - a` (forward driving
//! only), drives straight (seen from above) to `b`, and turns in place to `b`'s heading. The
//! poses along it ([`motion_poses`]) are at most [`DRIVE_STEP`] apart along the drive and
//! [`TURN_STEP_DEG`] apart in the turns. Every pose must settle (no body collision, slope and
//! roll within the settler's model), consecutive poses may not differ in height by more than
//! [`MAX_CLIMB`] per metre the wheels travel (the drive step, or a wheel's arc in a turn: no
//! driving off a wall, where the settler alone would place the next pose on the ground below), the anchor history is predicted from pose to pose at the boom
//! pivots, and each pose must be stable with the tether from its last anchor.
//!
//! Cost (Paton §III: "a weighted sum of yaw, roll and path length"):
//! `W_LEN * drive length (3D, between pose origins) + W_YAW * |turns| (rad) + W_ROLL * sum
//! |roll| * step length (rad m)`, with [`W_LEN`] = 1 per metre, [`W_YAW`] =
//! 0.5 per radian (a half turn costs as much as 1.57 m of driving) and [`W_ROLL`] = 1 per radian
//! metre (driving 1 m at 10° roll costs 0.17 m extra).
//!
//! Two admissible estimates (`docs/sampler.md`, "A yaw-aware heuristic"): of any path from `a`
//! to `b` ([`StateSpace::cost_heuristic`]), `W_LEN * |b - a|` in the plane `+ W_YAW *
//! |angle_diff(a.yaw, b.yaw)|` (a path turns at least its net heading change); of the one
//! motion from `a` to `b` ([`StateSpace::motion_cost_heuristic`], ABIT*'s edge estimate),
//! `W_LEN * |b - a| + W_YAW *` [`commanded_turning`] (the motion's turns are known before it
//! is checked). Both count the planar drive from [`DRIVE_MARGIN`] on: the 3D drive between
//! settled origins can be a few centimetres shorter than the planar distance where a footprint
//! straddles a slope break (the settled origin is off its ground point along the fitted
//! normal). Roll costs are non-negative.

use std::cell::RefCell;
use std::collections::HashMap;
use std::sync::Arc;

use nalgebra::Point3;
use rand::RngExt;
use rand_chacha::ChaCha8Rng;

use crate::anchor_prediction::{AnchorHistory, PredictParams, predict};
use crate::sampler::{
    Abit, AbitSettings, Informed, MotionValidator, PlannerStatus, StateSpace, Termination,
};
use crate::stop::StopCondition;
use rappel_mechanics::axel::AxelParams;
use rappel_mechanics::boom_contact::{BoomGround, IndexedGround};
use rappel_mechanics::settle::SettledPose;
use rappel_terrain::mesh::TriMesh;
use rappel_terrain::paton_scene::PatonScene;
use rappel_terrain::surface::SignedDistance;

use super::ground::PREDICT_RESOLUTION;
use super::ground::{DistanceReport, DistanceSource, DistanceSourceError, GroundDistances};
use super::shadow::TetherShadow;
use super::stability_map::{pose_stability, settle_from, tether_end};
use super::surface_sampling::SurfaceSampler;
use super::verdict::pose_is_stable;

/// Weight of the drive length in the cost, per metre.
pub const W_LEN: f64 = 1.0;
/// Weight of in-place turning in the cost, per radian turned.
pub const W_YAW: f64 = 0.5;
/// Weight of roll in the cost, per radian of |roll| per metre driven.
pub const W_ROLL: f64 = 1.0;
/// Largest spacing of settled poses along a drive, metres (the motion-check resolution; Axel's
/// wheels are 0.325 m in radius, so no ledge higher than a wheel fits between two poses
/// unnoticed by [`MAX_CLIMB`]).
pub const DRIVE_STEP: f64 = 0.25;
/// Largest heading change between settled poses of an in-place turn, degrees.
pub const TURN_STEP_DEG: f64 = 30.0;
/// Largest height change of consecutive poses per metre the wheels travel (`tan 70°`): steeper than
/// any slope the settler accepts as driveable ground, so only a drop off a wall exceeds it.
pub const MAX_CLIMB: f64 = 2.75;
/// Weight of the heading in the nearest-neighbour key, metres per unit of `(cos yaw, sin yaw)`:
/// states 1 m apart count as near as states at one place 60° apart.
pub const TURN_KEY_WEIGHT: f64 = 1.0;
/// Most poses in one motion (a bound on the work of a motion check; longer motions are invalid).
pub const MAX_MOTION_POSES: usize = 512;

/// Distance within which two anchors count as the same contact when anchor histories are
/// compared ([`histories_compatible`]), metres: half Axel's 1 m boom. Anchor prediction places a
/// contact to within its sampling resolution (5 cm) and a wrap adds one anchor per few
/// centimetres of arc, so histories of neighbouring states differ in their points but not in
/// which features the tether touches.
pub const HISTORY_MATCH_DISTANCE: f64 = 0.5;

/// The contacts of an anchor history: consecutive anchors closer than
/// [`HISTORY_MATCH_DISTANCE`] chained into one contact (a wrap around a pole, a bend over a
/// lip), each represented by its last anchor (where the tether leaves it).
fn contacts(h: &AnchorHistory) -> Vec<Point3<f64>> {
    let mut out: Vec<Point3<f64>> = Vec::new();
    let mut prev: Option<Point3<f64>> = None;
    for a in h.anchors() {
        match (prev, out.last_mut()) {
            (Some(p), Some(last)) if (a.point - p).norm() < HISTORY_MATCH_DISTANCE => {
                *last = a.point
            }
            _ => out.push(a.point),
        }
        prev = Some(a.point);
    }
    out
}

/// Paton §V-A's compatibility of two anchor histories: the tether touches the same contacts in
/// the same order (anchors chained within [`HISTORY_MATCH_DISTANCE`] count as one contact),
/// each leaving its contact within [`HISTORY_MATCH_DISTANCE`] of the other's.
pub fn histories_compatible(a: &AnchorHistory, b: &AnchorHistory) -> bool {
    let (ca, cb) = (contacts(a), contacts(b));
    ca.len() == cb.len()
        && ca
            .iter()
            .zip(&cb)
            .all(|(p, q)| (p - q).norm() < HISTORY_MATCH_DISTANCE)
}

/// A rover state: ground point and heading.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RoverState {
    /// Ground x, metres.
    pub x: f64,
    /// Ground y, metres.
    pub y: f64,
    /// Heading, radians from `+x`, counter-clockwise.
    pub yaw: f64,
}

/// The smallest signed angle from `a` to `b`, in `(-pi, pi]`.
fn angle_diff(a: f64, b: f64) -> f64 {
    let d = (b - a).rem_euclid(std::f64::consts::TAU);
    if d > std::f64::consts::PI {
        d - std::f64::consts::TAU
    } else {
        d
    }
}

/// The state space: ground points in an axis-aligned box, any heading; its bias distribution
/// ([`StateSpace::sample_biased`]) is the root anchor's shadow ([`TetherShadow`]).
#[derive(Debug, Clone, PartialEq)]
pub struct RoverSpace {
    /// Lower `(x, y)` corner of the sampled region.
    pub lo: [f64; 2],
    /// Upper corner.
    pub hi: [f64; 2],
    /// The shadow the biased samples are drawn from (`None`: no bias).
    pub shadow: Option<TetherShadow>,
    /// Uniform samples over the ground's surface area ([`SurfaceSampler`]) instead of its
    /// footprint (`None`: uniform in the box).
    pub surface: Option<SurfaceSampler>,
}

impl StateSpace<4> for RoverSpace {
    type State = RoverState;

    fn sample_uniform(&self, rng: &mut ChaCha8Rng) -> RoverState {
        // Over the surface's area when asked, else over the box.
        let (x, y) = match &self.surface {
            Some(s) => s.sample(rng),
            None => (
                rng.random_range(self.lo[0]..self.hi[0]),
                rng.random_range(self.lo[1]..self.hi[1]),
            ),
        };
        RoverState {
            x,
            y,
            yaw: rng.random_range(-std::f64::consts::PI..std::f64::consts::PI),
        }
    }

    fn sample_biased(&self, rng: &mut ChaCha8Rng) -> Option<RoverState> {
        let (x, y, yaw) = self.shadow.as_ref()?.sample(rng)?;
        Some(RoverState { x, y, yaw })
    }

    fn sample_informed(
        &self,
        _: &mut ChaCha8Rng,
        _: &RoverState,
        _: &RoverState,
        _: f64,
    ) -> Informed<RoverState> {
        Informed::Unsupported
    }

    fn distance(&self, a: &RoverState, b: &RoverState) -> f64 {
        let ka = self.key(a);
        let kb = self.key(b);
        ka.iter()
            .zip(kb)
            .map(|(p, q)| (p - q) * (p - q))
            .sum::<f64>()
            .sqrt()
    }

    /// Any path from `a` to `b` drives at least their planar distance and turns at least their
    /// net heading change (the turns of a path add up along the circle of headings, and the
    /// shorter arc is the least they can cover): `W_LEN` x planar distance + `W_YAW` x
    /// `|angle_diff(a.yaw, b.yaw)|`, the net change reduced by [`TURN_SLACK`] for rounding.
    /// The drive is counted from [`DRIVE_MARGIN`] on (the settled origins of the ends can be
    /// closer than their ground points).
    fn cost_heuristic(&self, a: &RoverState, b: &RoverState) -> f64 {
        let net = (angle_diff(a.yaw, b.yaw).abs() - TURN_SLACK).max(0.0);
        W_LEN * least_drive(a, b) + W_YAW * net
    }

    /// The motion from `a` to `b` is deterministic (the module doc): it drives at least the
    /// planar distance less [`DRIVE_MARGIN`] and turns exactly [`commanded_turning`], which the
    /// validator charges bit for bit (`W_YAW` times the same sum of the same commanded
    /// headings).
    fn motion_cost_heuristic(&self, a: &RoverState, b: &RoverState) -> f64 {
        W_LEN * least_drive(a, b) + W_YAW * commanded_turning(a, b)
    }

    fn interpolate(&self, a: &RoverState, b: &RoverState, t: f64) -> RoverState {
        RoverState {
            x: a.x + t * (b.x - a.x),
            y: a.y + t * (b.y - a.y),
            yaw: a.yaw + t * angle_diff(a.yaw, b.yaw),
        }
    }

    fn key(&self, s: &RoverState) -> [f64; 4] {
        [
            s.x,
            s.y,
            TURN_KEY_WEIGHT * s.yaw.cos(),
            TURN_KEY_WEIGHT * s.yaw.sin(),
        ]
    }

    fn dimension(&self) -> usize {
        3
    }
}

/// The headings of the in-place turn from heading `from` to `to` after the pose at `from`: the
/// shorter way round, in steps of at most [`TURN_STEP_DEG`], the last exactly `to`; none when
/// `angle_diff(from, to)` is 0. The one source of a motion's turning poses
/// ([`motion_poses`]) and of its turning cost estimate ([`commanded_turning`]).
fn turn_headings(from: f64, to: f64) -> impl Iterator<Item = f64> {
    let d = angle_diff(from, to);
    let n = (d.abs() / TURN_STEP_DEG.to_radians()).ceil() as usize;
    (1..=n).map(move |k| {
        if k == n {
            to
        } else {
            from + d * k as f64 / n as f64
        }
    })
}

/// How much shorter than the planar distance of its ends a path's drive can be, metres. The cost
/// counts the drive between *settled* pose origins, and the settler drops a pose along its
/// footprint's fitted normal, so an origin sits off its commanded ground point by the normal's
/// horizontal part times its height: equally for all poses on one plane, differently where the
/// footprint straddles a slope break. A motion ending at the foot of test 3's slope was charged
/// 0.021 m less drive than its planar length; over 3000 settled random motions of up to 1.5 m
/// around the lip and the foot (`x` in `[-1, 4.5]`) the largest shortfall was 0.047 m (a
/// motion ending on the foot). The margin is twice that: an empirical bound on these scenes,
/// not a proof; `rover::tests_heuristic` checks it on motions ending at the foot and the lip.
/// A path's drive, like a motion's, is at least the distance between the settled origins of
/// its ends: one margin per path as per motion.
pub const DRIVE_MARGIN: f64 = 0.1;

/// The least drive of any path from `a` to `b`, metres: their planar distance less
/// [`DRIVE_MARGIN`], at least 0.
fn least_drive(a: &RoverState, b: &RoverState) -> f64 {
    ((b.x - a.x).hypot(b.y - a.y) - DRIVE_MARGIN).max(0.0)
}

/// Headroom of the rover's path estimate ([`StateSpace::cost_heuristic`]) on the net heading
/// change, radians: the turns of a path are summed pose by pose in floating point, which may
/// fall short of the net change by a few ulps; 1e-9 rad (5e-10 of cost) covers that and is
/// far below any cost difference the search acts on.
pub const TURN_SLACK: f64 = 1e-9;

/// The turning, radians, of the motion from `a` to `b` ([`motion_poses`]): `|angle_diff|` of
/// consecutive commanded headings summed in the order [`RoverProblem::walk`] sums them, so
/// `W_YAW` times it is bit for bit the turning cost a valid motion is charged. With `a` and `b`
/// at different points it is `|angle_diff(a.yaw, h)| + |angle_diff(h, b.yaw)|`, `h` the
/// heading of `b - a` (forward driving only), up to rounding; at one point, the turn
/// `|angle_diff(a.yaw, b.yaw)|`. Known before the motion is checked: the rover's edge-cost
/// estimate ([`StateSpace::motion_cost_heuristic`]).
///
/// ```
/// use rappel_planners::rover::problem::{RoverState, commanded_turning};
/// use std::f64::consts::{FRAC_PI_2, PI};
/// let a = RoverState { x: 0.0, y: 0.0, yaw: 0.0 };
/// // To (0, 1) facing -x: a quarter turn left to face +y, drive, a quarter turn left.
/// let b = RoverState { x: 0.0, y: 1.0, yaw: PI };
/// assert!((commanded_turning(&a, &b) - PI).abs() < 1e-12);
/// // At one point: only the turn into the new heading.
/// let c = RoverState { yaw: -FRAC_PI_2, ..a };
/// assert!((commanded_turning(&a, &c) - FRAC_PI_2).abs() < 1e-12);
/// ```
pub fn commanded_turning(a: &RoverState, b: &RoverState) -> f64 {
    let (dx, dy) = (b.x - a.x, b.y - a.y);
    let mut yaw = a.yaw;
    let mut sum = 0.0;
    let turn_to = |sum: &mut f64, yaw: &mut f64, to: f64| {
        for y in turn_headings(*yaw, to) {
            *sum += angle_diff(*yaw, y).abs();
            *yaw = y;
        }
    };
    if dx.hypot(dy) > 0.0 {
        let h = dy.atan2(dx);
        turn_to(&mut sum, &mut yaw, h);
        // The first drive pose (heading `h`; 0 after a turn, which ends exactly at `h`).
        sum += angle_diff(yaw, h).abs();
        yaw = h;
    }
    turn_to(&mut sum, &mut yaw, b.yaw);
    sum
}

/// The indices `0..n` in the order OMPL's `DiscreteMotionValidator` checks the states of a
/// motion: the two ends, then the midpoint of the whole, then the midpoints of its halves, and
/// so on (breadth first), so an obstacle anywhere along the motion is met after a few checks.
pub fn bisection_order(n: usize) -> Vec<usize> {
    let mut order: Vec<usize> = match n {
        0 => return Vec::new(),
        1 => return vec![0],
        _ => vec![0, n - 1],
    };
    let mut intervals = std::collections::VecDeque::from([(0, n - 1)]);
    while let Some((a, b)) = intervals.pop_front() {
        if b - a < 2 {
            continue;
        }
        let m = a + (b - a) / 2;
        order.push(m);
        intervals.push_back((a, m));
        intervals.push_back((m, b));
    }
    order
}

/// The poses of the motion from `a` to `b` (see the module doc), `a` first and `b` last, each
/// with the drive length since the previous pose (0 in turns). `None` when it needs more than
/// [`MAX_MOTION_POSES`] poses.
pub fn motion_poses(a: &RoverState, b: &RoverState) -> Option<Vec<(RoverState, f64)>> {
    let (dx, dy) = (b.x - a.x, b.y - a.y);
    let len = dx.hypot(dy);
    let mut out = vec![(*a, 0.0)];
    let turn = |out: &mut Vec<(RoverState, f64)>, x: f64, y: f64, from: f64, to: f64| {
        out.extend(turn_headings(from, to).map(|yaw| (RoverState { x, y, yaw }, 0.0)));
    };
    let n = (len / DRIVE_STEP).ceil();
    if !(n.is_finite() && n < MAX_MOTION_POSES as f64) {
        return None;
    }
    let mut yaw = a.yaw;
    if len > 0.0 {
        let h = dy.atan2(dx);
        turn(&mut out, a.x, a.y, a.yaw, h);
        yaw = h;
        let n = n as usize;
        for k in 1..=n {
            let t = k as f64 / n as f64;
            out.push((
                RoverState {
                    x: a.x + t * dx,
                    y: a.y + t * dy,
                    yaw: h,
                },
                len / n as f64,
            ));
        }
    }
    turn(&mut out, b.x, b.y, yaw, b.yaw);
    Some(out)
}

/// What a walk along poses found: cost, the history at the end, and per pose its stability.
#[derive(Debug, Clone)]
pub struct Walk {
    /// The cost of the poses (module doc).
    pub cost: f64,
    /// The anchor history at the last pose.
    pub history: AnchorHistory,
    /// Per pose: origin, roll (radians) and the best stability margin (N; 0 for a pose held
    /// by [`RoverProblem::held_within_boom_reach`]).
    pub poses: Vec<([f64; 3], f64, f64)>,
}

/// The tethered-rover problem on a mesh scene: the ground, the root anchor, the sampled region.
#[derive(Debug, Clone)]
pub struct RoverProblem {
    /// The ground (exact mesh distances).
    pub ground: TriMesh,
    /// The root anchor.
    pub root: Point3<f64>,
    /// The sampled region and headings.
    pub space: RoverSpace,
    /// The start state.
    pub start: RoverState,
    /// The goal state.
    pub goal: RoverState,
    /// Count a pose whose last anchor lies within the boom's reach of its pivot
    /// ([`AxelParams::boom_length`]) as held (margin 0) when the QP finds it unstable. Before
    /// the boom was swept against the mesh (`rappel_mechanics::boom_contact`) the faithful
    /// model made the poses just past the lip unstable and this switch stood in for the boom
    /// resting on the lip; with the mesh contact search those poses are stable in the faithful
    /// model (tested), so it is kept only as a comparison. Off by default (the faithful model).
    pub held_within_boom_reach: bool,
    /// The planner's distances ([`GroundDistances`]): its motion checks (settling, anchor
    /// prediction; the boom sweeps of the stability verdict need the triangles) query them
    /// instead of `ground`'s brute-force exact distances: by default the same mesh behind
    /// parry's BVH (same triangles, same pseudo-normal sign; only floating-point rounding
    /// differs), with [`RoverProblem::use_distances`] the sparse distance field.
    /// [`RoverProblem::revalidate`] re-checks every reported path on `ground`, whatever these are.
    fast: Arc<GroundDistances>,
    /// Fraction of the planner's samples drawn from the root anchor's shadow
    /// ([`TetherShadow`], ABIT*'s `biased_sample_fraction`). 0 (the default of
    /// [`RoverProblem::paton`]) is Paton's uniform sampling; [`SHADOW_SAMPLE_FRACTION`] is ours,
    /// which `rappel::navigate` pairs with [`SHADOW_RGG_K_FACTOR`].
    pub shadow_sample_fraction: f64,
    /// Height from which states are settled: 1 m above the mesh's top.
    z_top: f64,
}

impl RoverProblem {
    /// Paton §VI-A on a ledge scene: the start on the ledge facing the slope, the goal 2 m beyond
    /// the slope's foot on the flat ground facing `+x`, the root anchor `scene.anchors[anchor]`,
    /// the sampled region the ledge's top and slope and 3 m of ground beyond, 3 m either side of
    /// the centre line (assumed: the paper gives neither the goal nor a region).
    pub fn paton(scene: &PatonScene, anchor: usize) -> Result<Self, String> {
        let ground = scene.mesh().map_err(|e| e.to_string())?;
        let root = *scene.anchor_points().get(anchor).ok_or_else(|| {
            format!(
                "anchor {anchor}: the scene has {} anchors",
                scene.anchors.len()
            )
        })?;
        let s = scene.start();
        let foot = scene.slope_foot_x();
        let half = (0.5 * scene.length - 0.5).clamp(0.5, 3.0);
        let fast = Arc::new(
            GroundDistances::new(&ground, DistanceSource::Exact).map_err(|e| e.to_string())?,
        );
        let (bottom, top) = ground.bounds();
        let z_top = fast.z_top();
        let (lo, hi) = ([-scene.width + 0.5, -half], [foot + 3.0, half]);
        Ok(RoverProblem {
            space: RoverSpace {
                lo,
                hi,
                shadow: Some(TetherShadow::new(
                    fast.bvh().clone(),
                    root,
                    lo,
                    hi,
                    bottom.z,
                    top.z,
                )),
                surface: None,
            },
            fast,
            shadow_sample_fraction: 0.0,
            z_top,
            ground,
            root,
            start: RoverState {
                x: s.x,
                y: s.y,
                yaw: 0.0,
            },
            goal: RoverState {
                x: foot + 2.0,
                y: 0.0,
                yaw: 0.0,
            },
            held_within_boom_reach: false,
        })
    }

    /// Draws the planner's uniform samples over the ground's surface area (`true`,
    /// [`SurfaceSampler`]: our reading of Paton §III's samples from the reconstructed voxel
    /// space) or over the sampled box's footprint (`false`, the default). An error when asked
    /// for and the ground has no upward-facing surface in the box (nothing to draw from).
    pub fn sample_surface_area(&mut self, on: bool) -> Result<(), String> {
        self.space.surface = if on {
            let (lo, hi) = (self.space.lo, self.space.hi);
            Some(SurfaceSampler::new(&self.ground, lo, hi).ok_or_else(|| {
                format!("no upward-facing ground in the sampled box {lo:?}..{hi:?}")
            })?)
        } else {
            None
        };
        Ok(())
    }

    /// The settled pose of a state on the exact mesh.
    pub fn settle(&self, s: &RoverState) -> Result<SettledPose, String> {
        settle_from(&self.ground, self.z_top, s.x, s.y, s.yaw.to_degrees())
    }

    /// The settled pose of a state on the planner's distances.
    fn settle_fast(&self, s: &RoverState) -> Result<SettledPose, String> {
        self.fast
            .settle(s.x, s.y, s.yaw.to_degrees())
            .map_err(|e| e.to_string())
    }

    /// Makes the planner's motion checks read `source`'s distances of the ground (the sparse
    /// field: `rappel navigate --field RES`; by default parry's exact BVH distances). Anchor
    /// prediction then samples at the field's resolution. Re-validation stays on the exact mesh.
    pub fn use_distances(&mut self, source: DistanceSource) -> Result<(), DistanceSourceError> {
        self.fast = Arc::new(GroundDistances::new(&self.ground, source)?);
        Ok(())
    }

    /// Where the planner's motion checks read their distances.
    pub fn distance_report(&self) -> DistanceReport {
        self.fast.report()
    }

    /// Walks `poses` (each with the drive length since the previous one) from `history` at the
    /// first pose: settles each, checks the height change against [`MAX_CLIMB`], predicts the
    /// anchor history from pivot to pivot and checks every pose's stability with it. The first
    /// pose is checked too. The history-free checks (settling, climb) come first, the poses
    /// settled in bisection order ([`bisection_order`], as OMPL's `DiscreteMotionValidator`
    /// checks states), so a motion through an obstacle fails without predicting the tether; then
    /// prediction and stability from the first pose on. The error names the first failing pose
    /// found in that order. On the exact mesh (its
    /// brute-force distances and triangles: independent of the planner's BVH).
    pub fn walk(
        &self,
        history: &AnchorHistory,
        poses: &[(RoverState, f64)],
    ) -> Result<Walk, String> {
        self.walk_on(
            &self.ground,
            &self.ground,
            &PredictParams::new(PREDICT_RESOLUTION),
            history,
            poses,
            None,
        )
    }

    /// [`RoverProblem::walk`] on `ground` (the exact mesh, or the planner's distances), anchor
    /// prediction with `params`, the boom swept against `boom_ground`. With a `memo` (the
    /// planner's runs, [`navigate`]): verdicts only (each pose's margin is NaN), the first and
    /// last poses' settling and the first pose's stability looked up in the run's memo
    /// ([`MotionMemo`]); the verdict, cost and history are those without it.
    fn walk_on<D: SignedDistance + ?Sized, G: BoomGround + ?Sized>(
        &self,
        ground: &D,
        boom_ground: &G,
        params: &PredictParams,
        history: &AnchorHistory,
        poses: &[(RoverState, f64)],
        memo: Option<&MotionMemo>,
    ) -> Result<Walk, String> {
        let axel = AxelParams::default();
        let last = poses.len().saturating_sub(1);
        let at = |k: usize, why: String| {
            let s = &poses[k].0;
            format!("pose {k} at ({:.3}, {:.3}): {why}", s.x, s.y)
        };
        // The history-free checks: every pose settled, in bisection order.
        let mut settled: Vec<Option<SettledPose>> = vec![None; poses.len()];
        for k in bisection_order(poses.len()) {
            let s = &poses[k].0;
            let settle = || settle_from(ground, self.z_top, s.x, s.y, s.yaw.to_degrees());
            settled[k] = Some(
                match memo {
                    // The ends of a motion are graph states: settled when sampled, and again
                    // by every motion from or to them.
                    Some(m) if k == 0 || k == last => m.settled(s, settle),
                    _ => settle(),
                }
                .map_err(|e| at(k, e))?,
            );
        }
        let settled: Vec<SettledPose> = settled.into_iter().flatten().collect();
        // The climb between consecutive poses.
        for k in 1..settled.len() {
            // The wheels' travel since the previous pose: the drive step, or in a turn the
            // arc of a wheel about the axle centre.
            let step = poses[k].1;
            let travel = if step > 0.0 {
                step
            } else {
                0.5 * axel.track * angle_diff(poses[k - 1].0.yaw, poses[k].0.yaw).abs()
            };
            let dz = (settled[k].origin.z - settled[k - 1].origin.z).abs();
            if dz > MAX_CLIMB * travel {
                return Err(at(
                    k,
                    format!("height changes {dz:.3} m over {travel:.3} m"),
                ));
            }
        }
        // The tether: prediction and stability from the first pose on.
        let mut h = history.clone();
        let mut cost = 0.0;
        let mut prev: Option<&SettledPose> = None;
        let mut out = Vec::with_capacity(poses.len());
        for (k, ((s, step), pose)) in poses.iter().zip(&settled).enumerate() {
            let at = |why: String| at(k, why);
            if let Some(p) = prev {
                h = predict(
                    ground,
                    params,
                    &h,
                    &tether_end(p, &axel),
                    &tether_end(pose, &axel),
                )
                .map_err(|e| at(e.to_string()))?
                .history;
                cost += W_LEN * (pose.origin - p.origin).norm() + W_ROLL * pose.roll().abs() * step;
            }
            let (stable, margin) = match memo {
                None => {
                    let st = pose_stability(boom_ground, pose, &h);
                    (st.stable, st.margin)
                }
                Some(m) => {
                    let verdict = || pose_is_stable(boom_ground, pose, &axel, &h);
                    // The first pose of every motion from a tree state is that state with its
                    // history: checked once per run.
                    let stable = if k == 0 {
                        m.stable(s, &h, verdict)
                    } else {
                        verdict()
                    };
                    (stable, f64::NAN)
                }
            };
            let held = self.held_within_boom_reach
                && (h.last().point - tether_end(pose, &axel)).norm() < axel.boom_length;
            if !stable && !held {
                return Err(at(format!(
                    "unstable with the tether to the anchor at ({:.3}, {:.3}, {:.3})",
                    h.last().point.x,
                    h.last().point.y,
                    h.last().point.z
                )));
            }
            out.push((
                [pose.origin.x, pose.origin.y, pose.origin.z],
                pose.roll(),
                margin,
            ));
            prev = Some(pose);
        }
        // Turning cost from the commanded headings (settling keeps the heading about the normal).
        cost += W_YAW
            * poses
                .windows(2)
                .map(|w| angle_diff(w[0].0.yaw, w[1].0.yaw).abs())
                .sum::<f64>();
        Ok(Walk {
            cost,
            history: h,
            poses: out,
        })
    }

    /// Independent re-validation of a planned path: every motion's poses re-settled, the anchor
    /// history re-predicted from the root along the whole path in one walk (not the planner's
    /// stored histories) and every pose's stability rechecked.
    pub fn revalidate(&self, path: &[RoverState]) -> Result<Walk, String> {
        let root = AnchorHistory::new(self.root).map_err(|e| e.to_string())?;
        let mut poses = vec![(*path.first().ok_or("an empty path")?, 0.0)];
        for (i, w) in path.windows(2).enumerate() {
            let m = motion_poses(&w[0], &w[1])
                .ok_or_else(|| format!("motion {i} needs more than {MAX_MOTION_POSES} poses"))?;
            poses.extend_from_slice(&m[1..]);
        }
        self.walk(&root, &poses)
    }
}

impl RoverProblem {
    /// The planner's check of the motion from `from` (reached with `history`) to `to`, on the
    /// planner's distances, with the reason when it fails and every pose's margin (for
    /// diagnostics; the planner's own check, [`MotionValidator::motion`], finds the same verdict,
    /// cost and history without the margins).
    pub fn check_motion(
        &self,
        from: &RoverState,
        history: &AnchorHistory,
        to: &RoverState,
    ) -> Result<Walk, String> {
        self.planner_walk(from, history, to, None)
    }

    /// The motion from `from` to `to` on the planner's distances: settling and prediction
    /// through [`GroundDistances`] (on exact distances with clear-ball skipping,
    /// [`GroundDistances::predict_params`]), the boom swept against the mesh's triangles
    /// through its BVH ([`IndexedGround`]: the brute force's contacts).
    fn planner_walk(
        &self,
        from: &RoverState,
        history: &AnchorHistory,
        to: &RoverState,
        memo: Option<&MotionMemo>,
    ) -> Result<Walk, String> {
        let poses = motion_poses(from, to)
            .ok_or_else(|| format!("the motion needs more than {MAX_MOTION_POSES} poses"))?;
        self.walk_on(
            self.fast.distance(),
            &self.boom_ground(),
            &self.fast.predict_params(),
            history,
            &poses,
            memo,
        )
    }

    /// The mesh with the planner's BVH, for the boom sweeps of the planner's stability checks.
    fn boom_ground(&self) -> IndexedGround<'_> {
        IndexedGround {
            mesh: &self.ground,
            bvh: self.fast.bvh(),
        }
    }
}

/// The stability verdicts of one state under the histories asked about: `(history, stable)`.
type StateVerdicts = Vec<(AnchorHistory, bool)>;

/// The planner's memo of one run ([`navigate`]): what the motion checks of a run would compute
/// again. Every motion starts and ends at graph states, which were settled when sampled, and
/// starts with the stability of its first state under that state's history, which every other
/// motion from the state checks again. The memo is exact: an entry is the value the check would
/// compute (same ground, same arguments), so a run's results are those without it.
///
/// Bounds: one settled pose per valid state the run samples (failed samples are not kept), one
/// verdict per (state, history) pair whose stability a motion's first pose or a copied history
/// ([`MotionValidator::history_valid`]) asked for: both at most the run's samples and motion
/// checks, which its iteration budget bounds.
#[derive(Debug, Default)]
struct MotionMemo {
    /// Settled poses of states, by the bits of `(x, y, yaw)`.
    settled: RefCell<HashMap<[u64; 3], SettledPose>>,
    /// Stability verdicts of states under histories, by the bits of the state.
    stable: RefCell<HashMap<[u64; 3], StateVerdicts>>,
}

/// The memo's key of a state: the bits of its coordinates.
fn state_key(s: &RoverState) -> [u64; 3] {
    [s.x.to_bits(), s.y.to_bits(), s.yaw.to_bits()]
}

impl MotionMemo {
    /// The settled pose of `s`, from the memo or from `settle` (kept when it settles).
    fn settled(
        &self,
        s: &RoverState,
        settle: impl FnOnce() -> Result<SettledPose, String>,
    ) -> Result<SettledPose, String> {
        let key = state_key(s);
        if let Some(p) = self.settled.borrow().get(&key) {
            return Ok(p.clone());
        }
        let p = settle()?;
        self.settled.borrow_mut().insert(key, p.clone());
        Ok(p)
    }

    /// The stability of `s` under history `h`, from the memo or from `verdict`.
    fn stable(&self, s: &RoverState, h: &AnchorHistory, verdict: impl FnOnce() -> bool) -> bool {
        let key = state_key(s);
        if let Some(v) = self
            .stable
            .borrow()
            .get(&key)
            .and_then(|l| l.iter().find(|(k, _)| k == h))
        {
            return v.1;
        }
        let v = verdict();
        self.stable
            .borrow_mut()
            .entry(key)
            .or_default()
            .push((h.clone(), v));
        v
    }
}

/// The rover problem as one planning run checks it: [`RoverProblem`]'s checks with the run's
/// [`MotionMemo`] and verdict-only stability (the planner keeps no margin).
struct PlanningRun<'a> {
    problem: &'a RoverProblem,
    memo: MotionMemo,
}

impl MotionValidator<RoverSpace, 4> for PlanningRun<'_> {
    type History = AnchorHistory;

    fn initial_history(&self, s: &RoverState) -> AnchorHistory {
        self.problem.initial_history(s)
    }

    fn state_valid(&self, s: &RoverState) -> bool {
        self.memo.settled(s, || self.problem.settle_fast(s)).is_ok()
    }

    fn compatible(&self, a: &AnchorHistory, b: &AnchorHistory) -> bool {
        histories_compatible(a, b)
    }

    fn history_valid(&self, s: &RoverState, h: &AnchorHistory) -> bool {
        let p = self.problem;
        self.memo.settled(s, || p.settle_fast(s)).is_ok_and(|pose| {
            self.memo.stable(s, h, || {
                pose_is_stable(&p.boom_ground(), &pose, &AxelParams::default(), h)
            })
        })
    }

    fn motion(
        &self,
        from: &RoverState,
        history: &AnchorHistory,
        to: &RoverState,
    ) -> Option<(f64, AnchorHistory)> {
        self.problem
            .planner_walk(from, history, to, Some(&self.memo))
            .ok()
            .map(|w| (w.cost, w.history))
    }
}

impl MotionValidator<RoverSpace, 4> for RoverProblem {
    type History = AnchorHistory;

    fn initial_history(&self, _: &RoverState) -> AnchorHistory {
        AnchorHistory::new(self.root).unwrap_or_else(|_| {
            // `NavigateError` rejects a non-finite root before planning starts.
            AnchorHistory::new(Point3::origin()).expect("the origin is finite")
        })
    }

    fn state_valid(&self, s: &RoverState) -> bool {
        self.settle_fast(s).is_ok()
    }

    fn compatible(&self, a: &AnchorHistory, b: &AnchorHistory) -> bool {
        histories_compatible(a, b)
    }

    fn history_valid(&self, s: &RoverState, h: &AnchorHistory) -> bool {
        self.settle_fast(s)
            .is_ok_and(|p| pose_is_stable(&self.boom_ground(), &p, &AxelParams::default(), h))
    }

    fn motion(
        &self,
        from: &RoverState,
        history: &AnchorHistory,
        to: &RoverState,
    ) -> Option<(f64, AnchorHistory)> {
        self.check_motion(from, history, to)
            .ok()
            .map(|w| (w.cost, w.history))
    }
}

/// The planner's settings for the rover (`docs/sampler.md`): ABIT*'s greedy first search
/// (initial inflation 1e6, the default), history copy fraction 0.5, batches of 100, history
/// copies on expansion (so the greedy search's first-connected history cannot claim a region
/// for good).
pub fn rover_settings(seed: u64) -> AbitSettings {
    AbitSettings::default()
        .with_history_copy_fraction(0.5)
        .and_then(|s| s.with_batch_size(100))
        .expect("constant settings are in range")
        .with_history_copies_on_expansion(true)
        .with_seed(seed)
}

/// Our shadow-sampling fraction ([`RoverProblem::shadow_sample_fraction`]): a fifth of the
/// samples from the root anchor's shadow (`docs/sampler.md`, test 3).
pub const SHADOW_SAMPLE_FRACTION: f64 = 0.2;

/// ABIT*'s `rgg_k_factor` (OMPL's rewire factor) with shadow sampling: 0.6 of the default
/// (OMPL's 1.1), so 0.66: `k` = 12 nearest in the first batch of 100, the state's own included,
/// so 11 neighbours instead of 18 (the 11 it had as 0.6 of the old default 1.0 before `k`
/// followed OMPL's count). The shadow samples keep the region behind a wrapped feature dense, so
/// fewer neighbours suffice there, and every motion check saved on the open ledge top (where
/// the unwrapped class fails its descents one by one) comes off the time to the first wrapped
/// solution (`docs/sampler.md`, measured on test 3; "OMPL's neighbour count" for 0.6 against
/// 0.66).
pub const SHADOW_RGG_K_FACTOR: f64 = 0.66;

impl RoverProblem {
    /// Solves the problem with ABIT* ([`crate::sampler::Abit`]) under [`rover_settings`] with
    /// `seed`, the shadow bias of [`RoverProblem::shadow_sample_fraction`] (paired with
    /// [`SHADOW_RGG_K_FACTOR`]), each motion checked once per run (memoised), until
    /// `termination`. The solution, if any, is the planner's: re-validate it with
    /// [`RoverProblem::revalidate`] for its poses, margins and anchors.
    pub fn solve(
        &self,
        seed: u64,
        termination: Termination,
    ) -> Result<PlannerStatus<RoverState, AnchorHistory>, String> {
        self.solve_until(seed, termination, &StopCondition::none())
    }

    /// [`RoverProblem::solve`] that also stops at `stop` ([`crate::stop`]; read on every
    /// iteration and between the samples of a batch, [`Abit::solve_until`]): a time limit
    /// (counted from this call unless `stop` was [started](StopCondition::started)) and cancel
    /// flags another thread sets. [`PlannerStatus::stop_reason`] says which condition fired.
    pub fn solve_until(
        &self,
        seed: u64,
        termination: Termination,
        stop: &StopCondition,
    ) -> Result<PlannerStatus<RoverState, AnchorHistory>, String> {
        self.solve_with(self.settings(seed)?, termination, stop)
    }

    /// The planner settings [`RoverProblem::solve`] uses with `seed`: [`rover_settings`], the
    /// shadow bias of [`RoverProblem::shadow_sample_fraction`] and with it
    /// [`SHADOW_RGG_K_FACTOR`].
    pub fn settings(&self, seed: u64) -> Result<AbitSettings, String> {
        let mut settings = rover_settings(seed)
            .with_biased_sample_fraction(self.shadow_sample_fraction)
            .map_err(|e| e.to_string())?;
        if self.shadow_sample_fraction > 0.0 {
            settings = settings
                .with_rgg_k_factor(SHADOW_RGG_K_FACTOR)
                .map_err(|e| e.to_string())?;
        }
        Ok(settings)
    }

    /// [`RoverProblem::solve_until`] with the planner settings given (for studies of the
    /// settings; [`RoverProblem::settings`] gives the default ones).
    pub fn solve_with(
        &self,
        settings: AbitSettings,
        termination: Termination,
        stop: &StopCondition,
    ) -> Result<PlannerStatus<RoverState, AnchorHistory>, String> {
        if !self.root.iter().all(|c| c.is_finite()) {
            return Err("the root anchor is not finite".into());
        }
        let run = PlanningRun {
            problem: self,
            memo: MotionMemo::default(),
        };
        let mut abit = Abit::new(&self.space, &run, self.start, self.goal, settings)
            .map_err(|e| e.to_string())?;
        abit.solve_until(termination, stop)
            .map_err(|e| e.to_string())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn problem(anchor: usize, pole: bool) -> RoverProblem {
        RoverProblem::paton(&PatonScene::paper(pole), anchor).unwrap()
    }

    /// Surface-area samples stay in the sampled box; a box with no ground under it is an
    /// error, not a silent return to box sampling.
    #[test]
    fn surface_area_samples_stay_in_the_box_and_need_ground() {
        let mut p = problem(1, true);
        p.sample_surface_area(true).unwrap();
        let mut rng = <ChaCha8Rng as rand::SeedableRng>::seed_from_u64(3);
        for _ in 0..1000 {
            let s = p.space.sample_uniform(&mut rng);
            assert!((p.space.lo[0]..=p.space.hi[0]).contains(&s.x));
            assert!((p.space.lo[1]..=p.space.hi[1]).contains(&s.y));
        }
        p.sample_surface_area(false).unwrap();
        assert!(p.space.surface.is_none());
        p.space.lo = [1e3, 1e3];
        p.space.hi = [1e3 + 1.0, 1e3 + 1.0];
        let e = p.sample_surface_area(true).unwrap_err();
        assert!(e.contains("no upward-facing ground"), "{e}");
    }

    #[test]
    fn bisection_order_visits_every_pose_once_ends_then_midpoints() {
        assert_eq!(bisection_order(0), Vec::<usize>::new());
        assert_eq!(bisection_order(1), vec![0]);
        assert_eq!(bisection_order(2), vec![0, 1]);
        assert_eq!(bisection_order(9), vec![0, 8, 4, 2, 6, 1, 3, 5, 7]);
        for n in 0..70 {
            let mut o = bisection_order(n);
            o.sort_unstable();
            assert_eq!(o, (0..n).collect::<Vec<_>>());
        }
    }

    #[test]
    fn motion_poses_start_and_end_at_the_states_within_the_resolution() {
        let a = RoverState {
            x: 0.0,
            y: 0.0,
            yaw: 3.0,
        };
        let b = RoverState {
            x: 1.3,
            y: -0.7,
            yaw: -2.0,
        };
        let m = motion_poses(&a, &b).unwrap();
        assert_eq!(m[0].0, a);
        assert_eq!(m.last().unwrap().0, b);
        let mut driven = 0.0;
        for w in m.windows(2) {
            let (p, q) = (w[0].0, w[1].0);
            let d = (q.x - p.x).hypot(q.y - p.y);
            assert!(d <= DRIVE_STEP + 1e-12);
            assert!((d - w[1].1).abs() < 1e-12);
            assert!(angle_diff(p.yaw, q.yaw).abs() <= TURN_STEP_DEG.to_radians() + 1e-12);
            // A pose either turns in place or drives along the heading of b - a.
            if d > 0.0 {
                assert!(angle_diff(q.yaw, (-0.7f64).atan2(1.3)).abs() < 1e-12);
            }
            driven += d;
        }
        assert!((driven - 1.3f64.hypot(0.7)).abs() < 1e-9);
    }

    #[test]
    fn straight_descent_is_valid_with_the_test_1_anchor_only() {
        let t = std::time::Instant::now();
        let one = problem(0, false);
        let h = one.initial_history(&one.start);
        let poses = motion_poses(&one.start, &one.goal).unwrap();
        // The faithful model descends over the lip: just past it the boom, swept against the
        // mesh, rests on the lip (in contact) or clears the top that falls away behind it
        // (inline); every pose has a positive margin, none needs `held_within_boom_reach`.
        let w = one.walk(&h, &poses).expect("test 1 descends");
        let (cost, h1) = (w.cost, w.history);
        assert!(w.poses.iter().all(|p| p.2 > 0.0), "{:?}", w.poses);
        assert!(w.poses.iter().any(|p| p.0[0] > 0.0 && p.0[0] < 0.7));
        // Paton Fig. 9: one intermediate anchor on the lip (x = 0, z = 4).
        assert_eq!(h1.len(), 2);
        let lip = h1.last().point;
        assert!(lip.x.abs() < 0.1 && (lip.z - 4.0).abs() < 0.1, "{lip:?}");
        // The drive is at least as long as start to goal in 3D (4 m down, 5.8 m along).
        let chord = (5.8f64 * 5.8 + 4.0 * 4.0).sqrt();
        assert!(cost >= chord && cost < chord + 2.0, "{cost}");
        let two = problem(1, false);
        let h = two.initial_history(&two.start);
        assert!(two.motion(&two.start, &h, &two.goal).is_none());
        eprintln!("two motion checks: {:?}", t.elapsed());
    }

    #[test]
    fn wrapped_histories_are_compatible_with_each_other_not_with_the_unwrapped() {
        let three = problem(1, true);
        let st = |x: f64, y: f64, yaw_deg: f64| RoverState {
            x,
            y,
            yaw: yaw_deg.to_radians(),
        };
        // Two loops behind the pole, 0.2 m apart, ending at one place on the ledge top.
        let wrap = |back: f64| {
            let path = [
                st(-1.0, 0.0, 0.0),
                st(-1.0, 1.3, 180.0),
                st(back, 1.3, -90.0),
                st(back, -1.3, 0.0),
                st(-0.5, -1.3, 0.0),
            ];
            three.revalidate(&path).unwrap().history
        };
        let (a, b) = (wrap(-4.0), wrap(-4.2));
        let direct = three
            .revalidate(&[st(-1.0, 0.0, 0.0), st(-0.5, -1.3, 0.0)])
            .unwrap()
            .history;
        // Different anchor points (so equality would keep them apart), one class.
        assert!(a.len() > 2 && a != b);
        assert!(histories_compatible(&a, &b) && histories_compatible(&b, &a));
        assert!(histories_compatible(&a, &a));
        assert!(!histories_compatible(&a, &direct) && !histories_compatible(&direct, &b));
        // The class is the pole contact: one chained contact besides the root.
        assert_eq!(contacts(&a).len(), 2);
        assert_eq!(contacts(&direct).len(), 1);
    }

    #[test]
    fn a_hand_made_path_around_the_pole_descends_in_test_3() {
        let three = problem(1, true);
        let st = |x: f64, y: f64, yaw_deg: f64| RoverState {
            x,
            y,
            yaw: yaw_deg.to_radians(),
        };
        let path = [
            st(-1.0, 0.0, 0.0),
            st(-1.0, 1.3, 180.0),
            st(-4.0, 1.3, -90.0),
            st(-4.0, -1.3, 0.0),
            st(-0.5, -1.3, 0.0),
            st(2.0, -1.3, 0.0),
            three.goal,
        ];
        // Paton Fig. 8 right: around the back of the pole, then down the slope: the pole
        // anchors (on its 0.3 m surface, above the top) and then the lip.
        let w = three
            .revalidate(&path)
            .expect("the wrapped descent is valid");
        let a = w.history.anchors();
        let pole = |p: &Point3<f64>| ((p.x + 2.5).hypot(p.y) - 0.3).abs() < 0.05 && p.z > 4.0;
        assert!(a[1..a.len() - 1].iter().all(|x| pole(&x.point)) && a.len() > 3);
        assert!(a[a.len() - 1].point.x.abs() < 0.1 && (a[a.len() - 1].point.z - 4.0).abs() < 0.1);
        // Without the loop behind the pole the same descent is unstable.
        let direct = [path[0], path[4], path[5], path[6]];
        assert!(three.revalidate(&direct).is_err());
    }
}
