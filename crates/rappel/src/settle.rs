//! Settling a rover on 3D ground (Paton §IV-A) from files: the ground is a Paton scene (`.ron`,
//! [`rappel_terrain::paton_scene::PatonScene`]) or an elevation model (`.asc`, `.tif`) meshed cell
//! centre to cell centre; the robot is Axel or the four-wheel rover ([`SettleRobot`]); the answer
//! is a serialisable [`SettleReport`], optionally with the stability QP's verdict for a tether to
//! a given last anchor (Axel: both boom configurations; the four-wheel rover: its tether exit on
//! the body, [`four_wheel_report_with`]).
//!
//! Distances are parry's exact mesh distances through its BVH, or with [`settle_report_with`]
//! any [`crate::distance_source`] (the sparse distance field: `rappel settle --field RES`).

use std::path::Path;

use nalgebra::Point3;

use rappel_mechanics::axel::AxelParams;
use rappel_mechanics::boom_contact::{IndexedGround, place_boom_in_contact, place_boom_inline};
use rappel_mechanics::four_wheel::{FourWheelParams, FourWheelRover};
use rappel_mechanics::four_wheel_settle::FourWheelPose;
use rappel_mechanics::settle::SettledPose;
use rappel_mechanics::stability_qp::StabilityQp;
use rappel_planners::anchor_prediction::{AnchorHistory, is_detached};
use rappel_terrain::mesh::TriMesh;
use rappel_terrain::paton_scene::PatonScene;
use serde::{Deserialize, Serialize};

use crate::distance_source::{DistanceReport, DistanceSource, GroundDistances};

/// Wheel-ground friction used for the stability verdict (the scenes carry none; Paton's
/// simulations do not state one). Assumed.
pub const SCENE_FRICTION: f64 = 0.6;

/// Why a settle request failed (all are the user's input; the CLI exits 2).
#[derive(Debug, thiserror::Error)]
pub enum SettleFileError {
    /// The file could not be read or parsed.
    #[error("{path}: {why}")]
    Read {
        /// The file.
        path: String,
        /// What went wrong.
        why: String,
    },
}

/// A Paton scene file (`.ron`, unknown fields refused).
pub fn load_scene(path: &Path) -> Result<PatonScene, SettleFileError> {
    let err = |why: String| SettleFileError::Read {
        path: path.display().to_string(),
        why,
    };
    let text = std::fs::read_to_string(path).map_err(|e| err(e.to_string()))?;
    ron::from_str(&text).map_err(|e| err(e.to_string()))
}

/// The ground of a file: a Paton scene, an elevation model or a mesh file (OBJ, STL).
pub fn load_ground(path: &Path) -> Result<TriMesh, SettleFileError> {
    let err = |why: String| SettleFileError::Read {
        path: path.display().to_string(),
        why,
    };
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("ron") => load_scene(path)?.mesh().map_err(|e| err(e.to_string())),
        Some("asc" | "tif" | "tiff") => {
            let dem = rappel_terrain::dem::read_dem(path).map_err(|e| err(e.to_string()))?;
            TriMesh::from_height_grid(&dem).map_err(|e| err(e.to_string()))
        }
        Some("obj" | "ply" | "stl") => {
            rappel_terrain::mesh_file::read_mesh(path).map_err(|e| SettleFileError::Read {
                path: path.display().to_string(),
                why: e.to_string(),
            })
        }
        _ => Err(err(
            "unknown ground format: use a Paton scene (.ron), an elevation model (.asc, .tif) or a mesh (.obj, .ply, .stl)"
                .into(),
        )),
    }
}

/// The stability verdict of one boom configuration.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct BoomVerdict {
    /// `inline` or `in-contact` (Axel), `none` (a robot without a boom).
    pub boom: String,
    /// A static equilibrium exists (`None`: not checked, `error` says why).
    pub stable: Option<bool>,
    /// The error that prevented the check, if one did.
    pub error: Option<String>,
    /// Paton's normalised eq. 9 margin (0 when not stable).
    pub margin: f64,
}

/// Which robot a settle request places (`rappel settle --robot`).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum SettleRobot {
    /// Axel (default `AxelParams`): two wheels of 12 contact points, the body along the axle,
    /// the boom.
    #[default]
    Axel,
    /// The rigid four-wheel rover (default `FourWheelParams`, `mechanics::four_wheel`): four
    /// point wheels, no body geometry, the tether fixed to the body.
    FourWheel,
}

/// The boom label of the one verdict of a robot without a boom ([`BoomVerdict::boom`]).
pub const NO_BOOM: &str = "none";

/// A settled pose, for printing.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct SettleReport {
    /// The robot settled.
    pub robot: SettleRobot,
    /// Robot origin (ground under the axle centre, or the wheelbase centre), world.
    pub origin: [f64; 3],
    /// Roll, degrees.
    pub roll_deg: f64,
    /// Pitch, degrees.
    pub pitch_deg: f64,
    /// The settled ground contacts: Axel's lowest contact of each wheel (right, left); the
    /// four-wheel rover's supporting wheels' ground points (in `support`'s order).
    pub contacts: Vec<[f64; 3]>,
    /// The four-wheel rover's supporting wheels (0 front left, 1 front right, 2 rear left, 3 rear
    /// right; three or four); `None` for Axel.
    pub support: Option<Vec<usize>>,
    /// Smallest body clearance along the axle, metres (Axel; `None` for the four-wheel rover,
    /// which has no body geometry).
    #[serde(rename = "body_clearance_m")]
    pub body_clearance: Option<f64>,
    /// The verdict per boom configuration when an anchor was given (Axel: `inline` and
    /// `in-contact`; the four-wheel rover: one, boom [`NO_BOOM`]).
    pub stability: Vec<BoomVerdict>,
    /// Where settling read its distances.
    pub distance_source: DistanceReport,
}

/// The stability QP's verdict for `pose` with the tether from the anchor history `history`, in
/// both boom configurations of Axel `params`, with [`SCENE_FRICTION`]:
/// * **inline**: the boom along the line from the pivot to the last anchor, refused where it
///   would pass through the mesh ([`place_boom_inline`]);
/// * **in contact**: the boom swept toward the last anchor until it touches the mesh
///   ([`place_boom_in_contact`]: on its tip or its shaft, e.g. resting on a ledge's lip). The
///   tether leaves from the boom's tip, which is not the pivot the history was predicted for:
///   while the tip lies above the last anchor's `F_d` plane (Paton's detach test,
///   [`rappel_planners::anchor_prediction::is_detached`]) that anchor is popped and the boom swept again toward the one before
///   (at most once per anchor). Attaching anchors between the pivot and the tip is not
///   searched (the boom is at most `L_c` long).
pub fn boom_verdicts<G: rappel_mechanics::boom_contact::BoomGround + ?Sized>(
    ground: &G,
    pose: &SettledPose,
    params: &AxelParams,
    history: &AnchorHistory,
) -> Vec<BoomVerdict> {
    BOOM_CONFIGURATIONS
        .into_iter()
        .map(|boom| boom_verdict(ground, pose, params, history, boom))
        .collect()
}

/// Axel's two boom configurations, in the order [`boom_verdicts`] reports them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BoomConfiguration {
    /// The boom along the line from the pivot to the last anchor.
    Inline,
    /// The boom swept toward the last anchor until it touches the mesh.
    InContact,
}

/// Both configurations, inline first.
pub const BOOM_CONFIGURATIONS: [BoomConfiguration; 2] =
    [BoomConfiguration::Inline, BoomConfiguration::InContact];

/// Whether `pose` is stable with the tether from `history` in some boom configuration: the
/// `stable` of [`boom_verdicts`] (any configuration stable), found without the second
/// configuration's placement and QP when the inline boom is already stable (the planner's motion
/// checks need the verdict, not the margins).
pub fn pose_is_stable<G: rappel_mechanics::boom_contact::BoomGround + ?Sized>(
    ground: &G,
    pose: &SettledPose,
    params: &AxelParams,
    history: &AnchorHistory,
) -> bool {
    BOOM_CONFIGURATIONS
        .into_iter()
        .any(|boom| boom_verdict(ground, pose, params, history, boom).stable == Some(true))
}

/// The verdict of one boom configuration (see [`boom_verdicts`]).
pub fn boom_verdict<G: rappel_mechanics::boom_contact::BoomGround + ?Sized>(
    ground: &G,
    pose: &SettledPose,
    params: &AxelParams,
    history: &AnchorHistory,
    boom: BoomConfiguration,
) -> BoomVerdict {
    let anchors = history.anchors();
    let in_contact = || {
        let mut n = anchors.len() - 1;
        // Each pass pops one anchor (n decreases) or returns: at most one pass per anchor.
        loop {
            let placed = place_boom_in_contact(
                pose,
                params,
                ground,
                SCENE_FRICTION,
                (&anchors[n].point, None),
            )
            .map_err(|e| e.to_string())?;
            let popped = n > 0 && is_detached(&anchors[n - 1], &anchors[n], &placed.1.tip);
            if !popped {
                return Ok(placed.0);
            }
            n -= 1;
        }
    };
    let (name, placed) = match boom {
        BoomConfiguration::Inline => (
            "inline",
            place_boom_inline(
                pose,
                params,
                ground,
                SCENE_FRICTION,
                (&history.last().point, None),
            )
            .map_err(|e| e.to_string()),
        ),
        BoomConfiguration::InContact => ("in-contact", in_contact()),
    };
    qp_verdict(name, placed)
}

impl crate::report::Report for SettleReport {
    const KIND: &'static str = "settle";
}

/// Settle Axel (default parameters) at `(x, y)` with yaw `yaw_deg` (degrees from `+x`,
/// counter-clockwise); with `anchor`, check stability for both boom configurations. Settling
/// through parry's exact BVH distances ([`settle_report_with`] and [`DistanceSource::Exact`]).
pub fn settle_report(
    ground: &TriMesh,
    x: f64,
    y: f64,
    yaw_deg: f64,
    anchor: Option<[f64; 3]>,
) -> Result<(SettledPose, SettleReport), rappel_mechanics::settle::SettleError> {
    let distances = GroundDistances::new(ground, DistanceSource::Exact).map_err(|_| {
        rappel_mechanics::settle::SettleError::Parameter(
            "parry's BVH refused the mesh (more vertices than u32 indices)",
        )
    })?;
    settle_report_with(ground, &distances, x, y, yaw_deg, anchor)
}

/// [`settle_report`] with settling (the footprint, the drop, the body points along the axle)
/// through `distances` (built from `ground`: exact or through the sparse field); the boom sweep
/// and the stability placement read the mesh's triangles through its BVH. The report states the
/// distance source.
pub fn settle_report_with(
    ground: &TriMesh,
    distances: &GroundDistances,
    x: f64,
    y: f64,
    yaw_deg: f64,
    anchor: Option<[f64; 3]>,
) -> Result<(SettledPose, SettleReport), rappel_mechanics::settle::SettleError> {
    let params = AxelParams::default();
    let bvh = &**distances.bvh();
    let pose = distances.settle(x, y, yaw_deg)?;
    let stability = match anchor.map(|a| AnchorHistory::new(Point3::new(a[0], a[1], a[2]))) {
        Some(Ok(history)) => boom_verdicts(
            &IndexedGround { mesh: ground, bvh },
            &pose,
            &params,
            &history,
        ),
        Some(Err(e)) => ["inline", "in-contact"]
            .map(|boom| BoomVerdict {
                boom: boom.to_string(),
                stable: None,
                error: Some(e.to_string()),
                margin: 0.0,
            })
            .to_vec(),
        None => Vec::new(),
    };
    let p = |q: &Point3<f64>| [q.x, q.y, q.z];
    let report = SettleReport {
        robot: SettleRobot::Axel,
        origin: p(&pose.origin),
        roll_deg: crate::report::deg(pose.roll()),
        pitch_deg: crate::report::deg(pose.pitch()),
        contacts: pose.contacts.iter().map(p).collect(),
        support: None,
        body_clearance: Some(pose.body_clearance),
        stability,
        distance_source: distances.report(),
    };
    Ok((pose, report))
}

/// The stability verdict of the settled four-wheel rover `pose` (default `FourWheelParams`) with
/// the tether from `anchor` to its tether exit ([`NO_BOOM`]): the supporting wheels' contacts
/// with frames from `ground`'s distance gradient, [`SCENE_FRICTION`], the stability QP.
pub fn four_wheel_verdict<D: rappel_terrain::surface::SignedDistance + ?Sized>(
    pose: &FourWheelPose,
    ground: &D,
    anchor: &Point3<f64>,
) -> BoomVerdict {
    let placed = FourWheelRover::new(FourWheelParams::default())
        .and_then(|rover| pose.place(&rover, ground, SCENE_FRICTION, Some((anchor, None))))
        .map_err(|e| e.to_string());
    qp_verdict(NO_BOOM, placed)
}

/// The stability QP's verdict on a placed robot (or the placement's error), labelled `boom`.
fn qp_verdict(
    boom: &str,
    placed: Result<rappel_mechanics::robot::PlacedRobot, String>,
) -> BoomVerdict {
    match placed.and_then(|placed| {
        StabilityQp::default()
            .check(&placed)
            .map_err(|e| e.to_string())
    }) {
        Ok(r) => BoomVerdict {
            boom: boom.to_string(),
            stable: Some(r.stable),
            error: None,
            margin: r.margin,
        },
        Err(e) => BoomVerdict {
            boom: boom.to_string(),
            stable: None,
            error: Some(e),
            margin: 0.0,
        },
    }
}

/// The four-wheel rover (default `FourWheelParams`) settled at `(x, y)` with yaw `yaw_deg`
/// (degrees from `+x`, counter-clockwise) through `distances` (built from the ground); with the
/// last anchor `anchor`, the stability QP's verdict ([`NO_BOOM`]: the tether from the anchor to
/// the rover's tether exit on the body, the supporting wheels' contacts with frames from the
/// mesh's exact distance gradient, [`SCENE_FRICTION`]). The rover has no body geometry: no body
/// collision is checked.
///
/// ```
/// use rappel::distance_source::{DistanceSource, GroundDistances};
/// use rappel::settle::four_wheel_report_with;
/// use rappel::terrain::mesh::TriMesh;
/// use nalgebra::Point3;
/// // The plane z = 0.1 y.
/// let ground = TriMesh::new(
///     vec![
///         Point3::new(-5.0, -5.0, -0.5),
///         Point3::new(5.0, -5.0, -0.5),
///         Point3::new(5.0, 5.0, 0.5),
///         Point3::new(-5.0, 5.0, 0.5),
///     ],
///     vec![[0, 1, 2], [0, 2, 3]],
/// )
/// .unwrap();
/// let d = GroundDistances::new(&ground, DistanceSource::Exact).unwrap();
/// let (pose, report) = four_wheel_report_with(&d, 0.0, 0.0, 90.0, None).unwrap();
/// assert_eq!(report.support, Some(vec![0, 1, 2, 3]));
/// assert!((pose.pitch() - 0.1f64.atan()).abs() < 1e-9);
/// ```
pub fn four_wheel_report_with(
    distances: &GroundDistances,
    x: f64,
    y: f64,
    yaw_deg: f64,
    anchor: Option<[f64; 3]>,
) -> Result<(FourWheelPose, SettleReport), rappel_mechanics::settle::SettleError> {
    let pose = distances.settle_four_wheel(x, y, yaw_deg)?;
    let stability = match anchor {
        Some(a) => vec![four_wheel_verdict(
            &pose,
            &**distances.bvh(),
            &Point3::new(a[0], a[1], a[2]),
        )],
        None => Vec::new(),
    };
    let p = |q: &Point3<f64>| [q.x, q.y, q.z];
    let report = SettleReport {
        robot: SettleRobot::FourWheel,
        origin: p(&pose.origin),
        roll_deg: crate::report::deg(pose.roll()),
        pitch_deg: crate::report::deg(pose.pitch()),
        contacts: pose
            .support
            .iter()
            .map(|&w| p(&pose.ground_points[w]))
            .collect(),
        support: Some(pose.support.clone()),
        body_clearance: None,
        stability,
        distance_source: distances.report(),
    };
    Ok((pose, report))
}
