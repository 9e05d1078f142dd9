//! Stability of settled poses on 3D ground with their anchor histories (Paton §IV-B, §IV-C) and
//! stability maps of mesh scenes like Paton's Fig. 8: the rover drives from a start under a root
//! anchor, [`crate::anchor_prediction`] carries the anchor history along, and the last
//! predicted anchor sets the tether's direction in the stability QP (both boom configurations,
//! [`super::verdict::boom_verdicts`]).
//!
//! The robot is a [`MapRobot`]: Axel ([`AxelMap`]) or the rigid four-wheel rover
//! ([`FourWheelMap`]). The tether end used for prediction is Axel's boom pivot (the axle centre):
//! with the boom inline the tether from the last anchor to the boom tip lies on the segment from
//! the anchor to the pivot, so the prediction is exact for it; with the boom in contact the tip is
//! lower (an approximation, as the in-contact boom's own ground contact is, see `docs/mesh.md`).
//! The four-wheel rover's tether end is its tether exit on the body, exact for its one verdict.
//!
//! A map is a grid of ground points; every cell is settled (in parallel), then the anchor
//! histories spread from the start cell outward ring by ring (Chebyshev rings, each in
//! parallel): a cell's history is its parent's, predicted over one step from the parent's
//! pivot to its own. The parent is the neighbour one step toward the start (diagonal first),
//! else the first neighbour on the inner ring that has a history, else (no inner neighbour has
//! one: a ring of poses that did not settle) the nearest cell with a history on the line of
//! diagonal-first steps toward the start, the prediction then spanning the unsettled cells. This
//! is the tree a sampling planner would grow (Paton §V), on a grid.

use nalgebra::{Point2, Point3, Vector3};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::anchor_prediction::{AnchorError, AnchorHistory, PredictParams, predict, predict_path};
use crate::stop::{StopCondition, StopReason};
use rappel_mechanics::axel::AxelParams;
use rappel_mechanics::boom_contact::{BoomGround, IndexedGround};
use rappel_mechanics::settle::{SettleParams, SettledPose, settle_axel};
use rappel_terrain::mesh::TriMesh;
use rappel_terrain::surface::SignedDistance;
use std::sync::OnceLock;

pub use super::ground::PREDICT_RESOLUTION;
use super::ground::{DistanceReport, DistanceSource, GroundDistances};
use super::verdict::{BoomVerdict, SettleRobot, boom_verdicts, four_wheel_verdict};
use rappel_geometry::compact::Compact;
use rappel_mechanics::four_wheel::FourWheelParams;
use rappel_mechanics::four_wheel_settle::FourWheelPose;

/// Spacing of the settled poses along a drive from the start ([`drive_and_check`]), metres.
pub const PATH_STEP: f64 = 0.25;

/// Most poses along one drive (a bound on the work; longer drives are refused).
pub const MAX_PATH_POSES: usize = 4096;

/// How far inside the ground a root anchor may lie before it is refused, metres: a physical
/// tolerance (a stake driven flush with the surface reads a few micrometres either side of it).
pub const ROOT_DEPTH_TOLERANCE: f64 = 1e-3;

/// Most cells in one map.
pub const MAX_MAP_CELLS: usize = 1_000_000;

/// Why a drive or a map cannot be computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MeshStabilityError {
    /// A required pose does not settle.
    #[error("settling at ({x}, {y}): {why}")]
    Settle {
        /// Ground x.
        x: f64,
        /// Ground y.
        y: f64,
        /// The settling error.
        why: String,
    },
    /// Anchor prediction failed.
    #[error("anchor prediction: {0}")]
    Anchor(#[from] AnchorError),
    /// A parameter out of its domain.
    #[error("{0}")]
    Parameter(String),
}

/// A settled pose with its anchor history and stability.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
pub struct PoseStability {
    /// Robot origin (ground under the axle centre), world.
    pub origin: [f64; 3],
    /// The anchor history, root first.
    pub anchors: Vec<[f64; 3]>,
    /// The verdict per boom configuration with the tether to the last anchor.
    pub verdicts: Vec<BoomVerdict>,
    /// Stable in some boom configuration.
    pub stable: bool,
    /// The best margin among the stable configurations (0 when not stable).
    pub margin: f64,
}

/// Axel's boom pivot (the axle centre) of a settled pose: the tether end for prediction.
pub fn tether_end(pose: &SettledPose, axel: &AxelParams) -> Point3<f64> {
    pose.origin + pose.rotation * Vector3::z() * axel.wheel_radius
}

/// Axel settled at ground point `(x, y)` heading `yaw_deg` on `ground` (found from
/// [`super::ground::SETTLE_START_HEIGHT`] above the mesh's top; distances through the
/// mesh's parry BVH, built for this call: [`GroundDistances::settle`]), with the default
/// [`AxelParams`] and [`SettleParams`]; the error is the
/// [`rappel_mechanics::settle::SettleError`]'s message.
pub fn settle(ground: &TriMesh, x: f64, y: f64, yaw_deg: f64) -> Result<SettledPose, String> {
    GroundDistances::new(ground, DistanceSource::Exact)
        .map_err(|e| e.to_string())?
        .settle(x, y, yaw_deg)
        .map_err(|e| e.to_string())
}

/// [`settle`] on any [`SignedDistance`] ground (e.g. the same mesh behind parry's BVH), found
/// from height `z_top`.
pub fn settle_from<D: SignedDistance + ?Sized>(
    ground: &D,
    z_top: f64,
    x: f64,
    y: f64,
    yaw_deg: f64,
) -> Result<SettledPose, String> {
    settle_axel(
        ground,
        &AxelParams::default(),
        x,
        y,
        z_top,
        yaw_deg.to_radians(),
        &SettleParams::default(),
    )
    .map_err(|e| e.to_string())
}

/// The stability of `pose` with anchor history `history` (the tether from its last anchor); the
/// boom is swept against the mesh's triangles.
pub fn pose_stability<G: BoomGround + ?Sized>(
    ground: &G,
    pose: &SettledPose,
    history: &AnchorHistory,
) -> PoseStability {
    let verdicts = boom_verdicts(ground, pose, &AxelParams::default(), history);
    let margin = verdicts
        .iter()
        .filter(|v| v.stable == Some(true))
        .map(|v| v.margin)
        .fold(f64::NEG_INFINITY, f64::max);
    let stable = margin > f64::NEG_INFINITY;
    let p = |q: &Point3<f64>| [q.x, q.y, q.z];
    PoseStability {
        origin: p(&pose.origin),
        anchors: history.anchors().iter().map(|a| p(&a.point)).collect(),
        verdicts,
        stable,
        margin: if stable { margin } else { 0.0 },
    }
}

/// Axel drives straight (seen from above) from ground point `start` to `target`, heading
/// `yaw_deg`, under the root anchor of `root`: settled every [`PATH_STEP`] (intermediate poses
/// that do not settle are skipped; the ends must settle), the anchor history predicted along the
/// pivots, and the target's stability with it. Settling and prediction through parry's exact
/// BVH distances ([`drive_and_check_with`] and [`DistanceSource::Exact`]).
pub fn drive_and_check(
    ground: &TriMesh,
    root: &AnchorHistory,
    start: [f64; 2],
    target: [f64; 2],
    yaw_deg: f64,
) -> Result<PoseStability, MeshStabilityError> {
    let distances = GroundDistances::new(ground, DistanceSource::Exact)
        .map_err(|e| MeshStabilityError::Parameter(e.to_string()))?;
    drive_and_check_with(ground, &distances, root, start, target, yaw_deg).map(|d| d.stability)
}

/// A drive's verdict ([`drive_and_check_with`]): the target's stability with its predicted
/// anchor history, and where settling and prediction read their distances.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
pub struct DriveCheck {
    /// The target pose's stability.
    pub stability: PoseStability,
    /// The distance source of settling and anchor prediction.
    pub distance_source: DistanceReport,
}

/// [`drive_and_check`] with settling and anchor prediction through `distances` (built from
/// `ground`: exact or through the sparse field, [`GroundDistances`], the same path as
/// [`stability_map_with`]; prediction's `h` is [`GroundDistances::predict_resolution`]); the
/// boom sweep and the placement through its BVH. The answer states its distance source.
pub fn drive_and_check_with(
    ground: &TriMesh,
    distances: &GroundDistances,
    root: &AnchorHistory,
    start: [f64; 2],
    target: [f64; 2],
    yaw_deg: f64,
) -> Result<DriveCheck, MeshStabilityError> {
    let (s, t) = (Point2::from(start), Point2::from(target));
    let n = ((t - s).norm() / PATH_STEP).ceil();
    if !(n.is_finite() && n < MAX_PATH_POSES as f64) {
        return Err(MeshStabilityError::Parameter(format!(
            "a drive of {} m needs more than {MAX_PATH_POSES} poses",
            (t - s).norm()
        )));
    }
    let n = (n as usize).max(1);
    let axel = AxelParams::default();
    let bvh = &**distances.bvh();
    let mut tips = Vec::with_capacity(n + 1);
    let mut last = None;
    for k in 0..=n {
        let q = s + (t - s) * (k as f64 / n as f64);
        match distances
            .settle(q.x, q.y, yaw_deg)
            .map_err(|e| e.to_string())
        {
            Ok(p) => {
                tips.push(tether_end(&p, &axel));
                last = Some(p);
            }
            Err(why) if k == 0 || k == n => {
                return Err(MeshStabilityError::Settle {
                    x: q.x,
                    y: q.y,
                    why,
                });
            }
            Err(_) => {}
        }
    }
    let pose =
        last.ok_or_else(|| MeshStabilityError::Parameter("the drive has no settled pose".into()))?;
    let out = predict_path(
        distances.distance(),
        &PredictParams::new(distances.predict_resolution()),
        root,
        &tips,
    )?;
    Ok(DriveCheck {
        stability: pose_stability(&IndexedGround { mesh: ground, bvh }, &pose, &out.history),
        distance_source: distances.report(),
    })
}

/// A robot whose settled poses a stability map checks (the map's seam for robot models): how a
/// pose settles, where the tether leaves it (the point anchor prediction carries the history
/// to) and its stability with the tether from its last anchor. Axel: [`AxelMap`]; the rigid
/// four-wheel rover: [`FourWheelMap`].
pub trait MapRobot: Sync {
    /// A settled pose.
    type Pose: Send + Sync;
    /// Which robot, for reports.
    fn robot(&self) -> SettleRobot;
    /// The pose at ground point `(x, y)` heading `yaw_deg` (degrees from `+x`), settled through
    /// `distances`; the error's message otherwise.
    fn settle(
        &self,
        distances: &GroundDistances,
        x: f64,
        y: f64,
        yaw_deg: f64,
    ) -> Result<Self::Pose, String>;
    /// Where the tether leaves the robot at `pose`, world.
    fn tether_end(&self, pose: &Self::Pose) -> Point3<f64>;
    /// The stability of `pose` with anchor history `history`, the mesh behind `ground`.
    fn stability(
        &self,
        ground: &IndexedGround<'_>,
        pose: &Self::Pose,
        history: &AnchorHistory,
    ) -> PoseStability;
}

/// Axel with the default [`AxelParams`] on a map: settled by [`GroundDistances::settle`], the
/// tether end its boom pivot ([`tether_end`]), both boom configurations ([`pose_stability`]).
///
/// ```
/// use rappel_planners::rover::stability_map::{AxelMap, MapRobot};
/// use rappel_planners::rover::verdict::SettleRobot;
/// assert_eq!(AxelMap.robot(), SettleRobot::Axel);
/// ```
#[derive(Debug, Clone, Copy, Default)]
pub struct AxelMap;

impl MapRobot for AxelMap {
    type Pose = SettledPose;
    fn robot(&self) -> SettleRobot {
        SettleRobot::Axel
    }
    fn settle(
        &self,
        distances: &GroundDistances,
        x: f64,
        y: f64,
        yaw_deg: f64,
    ) -> Result<SettledPose, String> {
        distances.settle(x, y, yaw_deg).map_err(|e| e.to_string())
    }
    fn tether_end(&self, pose: &SettledPose) -> Point3<f64> {
        tether_end(pose, &AxelParams::default())
    }
    fn stability(
        &self,
        ground: &IndexedGround<'_>,
        pose: &SettledPose,
        history: &AnchorHistory,
    ) -> PoseStability {
        pose_stability(ground, pose, history)
    }
}

/// The rigid four-wheel rover with the default [`FourWheelParams`] on a map: settled by
/// [`GroundDistances::settle_four_wheel`], the tether end its tether exit on the body, one
/// verdict without a boom ([`four_wheel_verdict`]: contact frames from the mesh's exact
/// distances through the BVH).
///
/// ```
/// use rappel_planners::rover::stability_map::{FourWheelMap, MapRobot};
/// use rappel_planners::rover::verdict::SettleRobot;
/// assert_eq!(FourWheelMap.robot(), SettleRobot::FourWheel);
/// ```
#[derive(Debug, Clone, Copy, Default)]
pub struct FourWheelMap;

impl MapRobot for FourWheelMap {
    type Pose = FourWheelPose;
    fn robot(&self) -> SettleRobot {
        SettleRobot::FourWheel
    }
    fn settle(
        &self,
        distances: &GroundDistances,
        x: f64,
        y: f64,
        yaw_deg: f64,
    ) -> Result<FourWheelPose, String> {
        distances
            .settle_four_wheel(x, y, yaw_deg)
            .map_err(|e| e.to_string())
    }
    fn tether_end(&self, pose: &FourWheelPose) -> Point3<f64> {
        pose.origin + pose.rotation * FourWheelParams::default().tether_exit.coords
    }
    fn stability(
        &self,
        ground: &IndexedGround<'_>,
        pose: &FourWheelPose,
        history: &AnchorHistory,
    ) -> PoseStability {
        let last = history.last().point;
        let verdict = four_wheel_verdict(pose, ground.bvh, &last);
        let stable = verdict.stable == Some(true);
        let p = |q: &Point3<f64>| [q.x, q.y, q.z];
        PoseStability {
            origin: p(&pose.origin),
            anchors: history.anchors().iter().map(|a| p(&a.point)).collect(),
            margin: if stable { verdict.margin } else { 0.0 },
            verdicts: vec![verdict],
            stable,
        }
    }
}

/// A map's grid: ground points `(x0 + i step, y0 + j step)` within the bounds, every pose
/// heading `yaw_deg`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct MapSpec {
    /// `(min, max)` along x, metres.
    #[serde(rename = "x_range_m")]
    pub x: (f64, f64),
    /// `(min, max)` along y, metres.
    #[serde(rename = "y_range_m")]
    pub y: (f64, f64),
    /// Grid spacing, metres (`> 0`).
    #[serde(rename = "step_m")]
    pub step: f64,
    /// Heading of every pose, degrees counter-clockwise from `+x`.
    pub yaw_deg: f64,
    /// The start's ground point (snapped to the nearest cell).
    pub start: [f64; 2],
}

impl MapSpec {
    /// Paton Fig. 8's view of the ledge scene `scene` at 0.5 m: x from -2 to 2.5 m (over the lip
    /// and down the slope), y within ±2 m, every pose heading `+x` (down the slope), from the
    /// scene's start.
    ///
    /// ```
    /// use rappel_planners::rover::stability_map::MapSpec;
    /// use rappel_terrain::paton_scene::PatonScene;
    /// let spec = MapSpec::fig8(&PatonScene::paper(false));
    /// assert_eq!(spec.step, 0.5);
    /// ```
    pub fn fig8(scene: &rappel_terrain::paton_scene::PatonScene) -> MapSpec {
        let s = scene.start();
        MapSpec {
            x: (-2.0, 2.5),
            y: (-2.0, 2.0),
            step: 0.5,
            yaw_deg: 0.0,
            start: [s.x, s.y],
        }
    }

    /// The grid's columns and rows `(nx, ny)`, as floats (a spec far over [`MAX_MAP_CELLS`]
    /// may count more cells than a `usize` holds). Meaningful after [`MapSpec::validate`].
    pub fn size(&self) -> (f64, f64) {
        let count = |(a, b): (f64, f64)| ((b - a) / self.step).floor() + 1.0;
        (count(self.x), count(self.y))
    }

    /// Checks the spec: finite ordered bounds, a positive finite step, a finite heading and
    /// start; a refusal names the field.
    ///
    /// ```
    /// use rappel_planners::rover::stability_map::MapSpec;
    /// use rappel_terrain::paton_scene::PatonScene;
    /// let mut spec = MapSpec::fig8(&PatonScene::paper(false));
    /// assert!(spec.validate().is_ok());
    /// spec.yaw_deg = f64::NAN;
    /// assert_eq!(spec.validate().unwrap_err().to_string(), "yaw_deg = NaN: must be finite");
    /// ```
    pub fn validate(&self) -> Result<(), MeshStabilityError> {
        let bad = |field: &str, value: String, why: &str| {
            Err(MeshStabilityError::Parameter(format!(
                "{field} = {value}: {why}"
            )))
        };
        let pair = |(a, b): (f64, f64)| format!("({}, {})", Compact(a), Compact(b));
        for (field, (a, b)) in [("x", self.x), ("y", self.y)] {
            if !(a.is_finite() && b.is_finite() && a <= b) {
                return bad(field, pair((a, b)), "the bounds must be finite, min <= max");
            }
        }
        if !(self.step.is_finite() && self.step > 0.0) {
            return bad(
                "step",
                Compact(self.step).to_string(),
                "must be finite and > 0",
            );
        }
        if !self.yaw_deg.is_finite() {
            return bad(
                "yaw_deg",
                Compact(self.yaw_deg).to_string(),
                "must be finite",
            );
        }
        if !self.start.iter().all(|v| v.is_finite()) {
            return bad(
                "start",
                pair((self.start[0], self.start[1])),
                "must be finite",
            );
        }
        Ok(())
    }
}

/// One map cell.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
pub struct MapCell {
    /// The cell's ground point `[x, y]`.
    pub ground: [f64; 2],
    /// The settled pose and its stability, when it settled and its history could be predicted.
    pub pose: Option<PoseStability>,
    /// Why not, otherwise.
    pub failure: Option<String>,
}

/// A stability map.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
pub struct StabilityMap {
    /// The robot settled in every cell.
    pub robot: SettleRobot,
    /// The grid.
    pub spec: MapSpec,
    /// Cells along x.
    pub nx: usize,
    /// Cells along y.
    pub ny: usize,
    /// Cells, row by row (`j` major).
    pub cells: Vec<MapCell>,
    /// The root anchor.
    pub root: [f64; 3],
    /// Stable cells.
    pub stable: usize,
    /// Settled, history known, not stable.
    pub unstable: usize,
    /// Not settled or no history.
    pub failed: usize,
    /// Where settling and anchor prediction read their distances.
    pub distance_source: DistanceReport,
    /// The condition that stopped the map before every cell was computed (a time limit or a
    /// cancel request, [`stability_map_for`]): the map is then partial, its cells not computed
    /// counted as failed, with the failure "not computed: the map stopped at ...". `null` for a
    /// whole map.
    #[serde(default)]
    pub stopped_by: Option<StopReason>,
}

/// As [`stability_map`], with settling and anchor prediction (the tether's swept triangle and the
/// body-collision points along the axle) reading the sparse distance field of `ground` at
/// `resolution` metres ([`DistanceSource::Field`]: propagated to its default `max_distance`;
/// prediction's `h` the field's resolution) instead of parry's exact BVH distances; the boom
/// sweep and the stability placement stay on the mesh. The field's interpolation error
/// (`SparseSdf::error_bound`, about 0.11 m at 10 cm, `docs/mesh.md`) moves settled heights and
/// contacts by up to that much, so verdicts may differ from the exact path on poses near a
/// threshold (measured on the Fig. 8 map: `tests`).
pub fn stability_map_through_field(
    ground: &TriMesh,
    root: &AnchorHistory,
    spec: &MapSpec,
    resolution: f64,
) -> Result<StabilityMap, MeshStabilityError> {
    let distances = GroundDistances::new(
        ground,
        DistanceSource::Field {
            resolution_m: resolution,
        },
    )
    .map_err(|e| MeshStabilityError::Parameter(format!("distance field: {e}")))?;
    stability_map_with(ground, &distances, root, spec)
}

/// The stability map of `spec` under root anchor `root` (see the module doc), settling and
/// predicting through parry's exact BVH distances ([`DistanceSource::Exact`]: they agree with the
/// brute-force mesh distance to 1e-9, `terrain::parry_mesh`; the sweep finds the brute force's
/// contacts, `boom_contact`).
pub fn stability_map(
    ground: &TriMesh,
    root: &AnchorHistory,
    spec: &MapSpec,
) -> Result<StabilityMap, MeshStabilityError> {
    let distances = GroundDistances::new(ground, DistanceSource::Exact)
        .map_err(|e| MeshStabilityError::Parameter(e.to_string()))?;
    stability_map_with(ground, &distances, root, spec)
}

/// The stability map of `spec` under root anchor `root` on `ground` (see the module doc), with
/// settling and anchor prediction through `distances` (built from `ground`: exact or through the
/// field, [`GroundDistances`]); the boom sweep and the placement through its BVH. The map states
/// its distance source. Axel's map: [`stability_map_for`] with [`AxelMap`].
pub fn stability_map_with(
    ground: &TriMesh,
    distances: &GroundDistances,
    root: &AnchorHistory,
    spec: &MapSpec,
) -> Result<StabilityMap, MeshStabilityError> {
    stability_map_for(
        &AxelMap,
        ground,
        distances,
        root,
        spec,
        &StopCondition::none(),
    )
}

/// [`stability_map_with`] for any [`MapRobot`]: every cell settled by `robot`, the anchor
/// histories carried along its tether ends, its verdicts; stopped by `stop`.
///
/// # Stopping
/// The time limit (counted from this call unless `stop` was [started](StopCondition::started))
/// and the cancel flags of `stop` ([`crate::stop`]) are read before each cell's settling, anchor
/// prediction and stability check (each takes milliseconds; cells run in parallel). Once one
/// fires, the map is not an error but **partial**: the cells done are kept, the others are
/// failed with "not computed: the map stopped at REASON", and [`StabilityMap::stopped_by`] names
/// the condition, so a picture of what was computed can still be drawn. Its expansion budget
/// does not apply (the map's size is bounded by [`MAX_MAP_CELLS`]). A condition that never
/// fires reads no clock: the map is the one without it, bit for bit.
///
/// ```
/// use rappel_planners::anchor_prediction::AnchorHistory;
/// use rappel_planners::rover::ground::{DistanceSource, GroundDistances};
/// use rappel_planners::rover::stability_map::{AxelMap, MapSpec, stability_map_for};
/// use rappel_planners::stop::{CancelFlag, StopCondition, StopReason};
/// use rappel_terrain::paton_scene::PatonScene;
/// let scene = PatonScene::paper(false);
/// let ground = scene.mesh().unwrap();
/// let d = GroundDistances::new(&ground, DistanceSource::Exact).unwrap();
/// let root = AnchorHistory::new(scene.anchor_points()[0]).unwrap();
/// let flag = CancelFlag::new();
/// flag.cancel();
/// let stop = StopCondition::cancel(flag);
/// let map = stability_map_for(&AxelMap, &ground, &d, &root, &MapSpec::fig8(&scene), &stop).unwrap();
/// assert_eq!(map.stopped_by, Some(StopReason::Cancelled));
/// assert_eq!(map.failed, map.cells.len());
/// assert!(map.cells[0].failure.as_ref().unwrap().contains("a cancel request"));
/// ```
pub fn stability_map_for<R: MapRobot>(
    robot: &R,
    ground: &TriMesh,
    distances: &GroundDistances,
    root: &AnchorHistory,
    spec: &MapSpec,
    stop: &StopCondition,
) -> Result<StabilityMap, MeshStabilityError> {
    stability_map_observed(robot, ground, distances, root, spec, stop, &|| {})
}

/// The work units of a map of `cells` cells that [`stability_map_observed`] reports: each cell
/// is settled, given its anchor history and checked (three units).
pub const UNITS_PER_CELL: usize = 3;

/// [`stability_map_for`], calling `tick` once per unit of work done ([`UNITS_PER_CELL`] per
/// cell, from the worker threads), for a progress bar over `UNITS_PER_CELL * cells`.
///
/// ```
/// use rappel_planners::rover::ground::{DistanceSource, GroundDistances};
/// use rappel_planners::rover::stability_map::{AxelMap, MapSpec, UNITS_PER_CELL, stability_map_observed};
/// use rappel_planners::anchor_prediction::AnchorHistory;
/// use rappel_planners::stop::StopCondition;
/// use rappel_terrain::paton_scene::PatonScene;
/// use std::sync::atomic::{AtomicUsize, Ordering};
/// let scene = PatonScene::paper(false);
/// let ground = scene.mesh().unwrap();
/// let d = GroundDistances::new(&ground, DistanceSource::Exact).unwrap();
/// let root = AnchorHistory::new(scene.anchor_points()[0]).unwrap();
/// let mut spec = MapSpec::fig8(&scene);
/// spec.step = 1.5;
/// let ticks = AtomicUsize::new(0);
/// let map = stability_map_observed(&AxelMap, &ground, &d, &root, &spec, &StopCondition::none(), &|| {
///     ticks.fetch_add(1, Ordering::Relaxed);
/// })
/// .unwrap();
/// assert_eq!(ticks.into_inner(), UNITS_PER_CELL * map.nx * map.ny);
/// ```
pub fn stability_map_observed<R: MapRobot>(
    robot: &R,
    ground: &TriMesh,
    distances: &GroundDistances,
    root: &AnchorHistory,
    spec: &MapSpec,
    stop: &StopCondition,
    tick: &(dyn Fn() + Sync),
) -> Result<StabilityMap, MeshStabilityError> {
    let (bvh, distance) = (&**distances.bvh(), distances.distance());
    spec.validate()?;
    let root_point = root.root().point;
    let depth = -ground.signed_distance(&root_point);
    if depth > ROOT_DEPTH_TOLERANCE {
        return Err(MeshStabilityError::Parameter(format!(
            "the root anchor ({}, {}, {}) is {depth:.3} m inside the ground; an anchor must lie on or above the surface",
            Compact(root_point.x),
            Compact(root_point.y),
            Compact(root_point.z)
        )));
    }
    let (fx, fy) = spec.size();
    if fx * fy > MAX_MAP_CELLS as f64 {
        return Err(MeshStabilityError::Parameter(format!(
            "a map of {} x {} cells exceeds the limit of {MAX_MAP_CELLS} cells; use a larger step or a smaller area",
            Compact(fx),
            Compact(fy)
        )));
    }
    let (nx, ny) = (fx as usize, fy as usize);
    let at = |i: usize, j: usize| {
        (
            spec.x.0 + i as f64 * spec.step,
            spec.y.0 + j as f64 * spec.step,
        )
    };
    let snap = |v: f64, lo: f64| ((v - lo) / spec.step).round();
    let (si, sj) = (snap(spec.start[0], spec.x.0), snap(spec.start[1], spec.y.0));
    if !(si >= 0.0 && sj >= 0.0 && si < nx as f64 && sj < ny as f64) {
        return Err(MeshStabilityError::Parameter(
            "the start is outside the map".into(),
        ));
    }
    let (si, sj) = (si as usize, sj as usize);
    // The first condition of `stop` that fired; once set, every later check says stop.
    let stop = stop.started();
    let stopped: OnceLock<StopReason> = OnceLock::new();
    let halt = || {
        stopped.get().is_some()
            || stop.poll().is_some_and(|r| {
                let _ = stopped.set(r);
                true
            })
    };
    // Settle every cell (`None`: not computed, the map stopped).
    let poses: Vec<Option<Result<R::Pose, String>>> = (0..nx * ny)
        .into_par_iter()
        .map(|c| {
            let (x, y) = at(c % nx, c / nx);
            (!halt()).then(|| robot.settle(distances, x, y, spec.yaw_deg))
        })
        .inspect(|_| tick())
        .collect();
    let mut histories: Vec<Option<Result<AnchorHistory, String>>> = vec![None; nx * ny];
    let start = si + sj * nx;
    histories[start] = match &poses[start] {
        Some(Ok(_)) => Some(Ok(root.clone())),
        Some(Err(e)) => {
            let (x, y) = at(si, sj);
            return Err(MeshStabilityError::Settle {
                x,
                y,
                why: e.clone(),
            });
        }
        None => None,
    };
    tick();
    // Clear-ball skipping on exact distances (the same anchors, fewer queries).
    let params = distances.predict_params();
    let ring = |i: usize, j: usize| i.abs_diff(si).max(j.abs_diff(sj));
    let rings = (si.max(nx - 1 - si)).max(sj.max(ny - 1 - sj));
    // The cells of each ring, bucketed in one pass (a filter of all cells per ring would cost
    // cells x rings: 5e8 steps on a 1000 x 1000 map).
    let mut by_ring: Vec<Vec<usize>> = vec![Vec::new(); rings + 1];
    for c in 0..nx * ny {
        by_ring[ring(c % nx, c / nx)].push(c);
    }
    // Ring by ring outward (at most max(nx, ny) rings, each cell once).
    for (r, cells) in by_ring.iter().enumerate().skip(1) {
        let done: Vec<(usize, Option<Result<AnchorHistory, String>>)> = cells
            .par_iter()
            .map(|&c| {
                let (i, j) = (c % nx, c / nx);
                let pose = match &poses[c] {
                    Some(Ok(p)) => p,
                    Some(Err(e)) => return (c, Some(Err(format!("not settled: {e}")))),
                    None => return (c, None),
                };
                if halt() {
                    return (c, None);
                }
                // The preferred parent one step toward the start, then the other inner
                // neighbours in a fixed order.
                let toward = |v: usize, s: usize| match v.cmp(&s) {
                    std::cmp::Ordering::Less => v + 1,
                    std::cmp::Ordering::Greater => v - 1,
                    std::cmp::Ordering::Equal => v,
                };
                let mut parents = vec![(toward(i, si), toward(j, sj))];
                for dj in [-1i64, 0, 1] {
                    for di in [-1i64, 0, 1] {
                        let (pi, pj) = (i as i64 + di, j as i64 + dj);
                        if pi >= 0 && pj >= 0 && (pi as usize) < nx && (pj as usize) < ny {
                            let p = (pi as usize, pj as usize);
                            if ring(p.0, p.1) + 1 == r && !parents.contains(&p) {
                                parents.push(p);
                            }
                        }
                    }
                }
                let mut why = String::from("no cell toward the start has an anchor history");
                let mut tried = false;
                // The inner neighbours first; when none has a history (a ring of cells that did
                // not settle, e.g. a rigid rover straddling a crest), the nearest cell with one
                // on the diagonal-first line toward the start (at most `r - 1` more steps).
                let (mut ci, mut cj) = parents[0];
                let inward = std::iter::from_fn(|| {
                    (ring(ci, cj) > 0).then(|| {
                        (ci, cj) = (toward(ci, si), toward(cj, sj));
                        (ci, cj)
                    })
                });
                for (pi, pj) in parents.into_iter().chain(inward) {
                    let pc = pi + pj * nx;
                    if tried && ring(pi, pj) + 1 < r {
                        break;
                    }
                    if let (Some(Ok(h)), Some(Ok(pp))) = (&histories[pc], &poses[pc]) {
                        tried = true;
                        match predict(
                            distance,
                            &params,
                            h,
                            &robot.tether_end(pp),
                            &robot.tether_end(pose),
                        ) {
                            Ok(step) => return (c, Some(Ok(step.history))),
                            Err(e) => why = format!("anchor prediction: {e}"),
                        }
                    }
                }
                (c, Some(Err(why)))
            })
            .inspect(|_| tick())
            .collect();
        for (c, h) in done {
            histories[c] = h;
        }
    }
    let cells: Vec<MapCell> = (0..nx * ny)
        .into_par_iter()
        .map(|c| {
            let (x, y) = at(c % nx, c / nx);
            let not_computed = |r: &StopReason| MapCell {
                ground: [x, y],
                pose: None,
                failure: Some(format!("not computed: the map stopped at {r}")),
            };
            match (&poses[c], &histories[c]) {
                (Some(Ok(p)), Some(Ok(h))) => match halt() {
                    true => not_computed(stopped.get().expect("set by halt")),
                    false => MapCell {
                        ground: [x, y],
                        pose: Some(robot.stability(&IndexedGround { mesh: ground, bvh }, p, h)),
                        failure: None,
                    },
                },
                (Some(Err(e)), _) => MapCell {
                    ground: [x, y],
                    pose: None,
                    failure: Some(format!("not settled: {e}")),
                },
                (_, Some(Err(e))) => MapCell {
                    ground: [x, y],
                    pose: None,
                    failure: Some(e.clone()),
                },
                (None, _) | (_, None) => match stopped.get() {
                    Some(r) => not_computed(r),
                    None => MapCell {
                        ground: [x, y],
                        pose: None,
                        failure: Some("not reached".into()),
                    },
                },
            }
        })
        .inspect(|_| tick())
        .collect();
    let stable = cells
        .iter()
        .filter(|c| c.pose.as_ref().is_some_and(|p| p.stable))
        .count();
    let failed = cells.iter().filter(|c| c.pose.is_none()).count();
    let r = root.root().point;
    Ok(StabilityMap {
        robot: robot.robot(),
        spec: *spec,
        nx,
        ny,
        unstable: cells.len() - stable - failed,
        failed,
        stable,
        cells,
        root: [r.x, r.y, r.z],
        distance_source: distances.report(),
        stopped_by: stopped.get().copied(),
    })
}
