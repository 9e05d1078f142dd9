//! Settling a rover on 3D ground (Paton §IV-A) from files: the ground is a Paton scene (`.ron`,
//! [`rappel_terrain::paton_scene::PatonScene`]) or an elevation model (`.asc`, `.tif`) meshed cell
//! centre to cell centre; the robot is Axel or the four-wheel rover ([`SettleRobot`]); the answer
//! is a serialisable [`SettleReport`], optionally with the stability QP's verdict for a tether to
//! a given last anchor (Axel: both boom configurations; the four-wheel rover: its tether exit on
//! the body, [`four_wheel_report_with`]).
//!
//! Distances are parry's exact mesh distances through its BVH, or with [`settle_report_with`]
//! any [`rappel_planners::rover::ground`] (the sparse distance field: `rappel settle --field RES`).

use std::path::Path;

use nalgebra::Point3;

use rappel_mechanics::axel::AxelParams;
use rappel_mechanics::boom_contact::IndexedGround;
use rappel_mechanics::four_wheel_settle::FourWheelPose;
use rappel_mechanics::settle::SettledPose;
use rappel_planners::anchor_prediction::AnchorHistory;
use rappel_terrain::mesh::TriMesh;
use rappel_terrain::paton_scene::PatonScene;
use serde::{Deserialize, Serialize};

pub use rappel_planners::rover::ground::{DistanceReport, DistanceSource, GroundDistances};
pub use rappel_planners::rover::verdict::{
    BoomVerdict, NO_BOOM, SCENE_FRICTION, SettleRobot, boom_verdicts, four_wheel_verdict,
};

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
    /// The file was not read: not a regular file, over the input size cap, not text
    /// ([`rappel_terrain::input`]).
    #[error(transparent)]
    Input(#[from] rappel_terrain::input::InputError),
    /// An elevation model that could not be read.
    #[error(transparent)]
    Dem(#[from] rappel_terrain::dem::DemError),
    /// A mesh file that could not be read.
    #[error(transparent)]
    Mesh(#[from] rappel_terrain::mesh_file::MeshFileError),
}

/// A Paton scene file (`.ron`, unknown fields refused).
pub fn load_scene(path: &Path) -> Result<PatonScene, SettleFileError> {
    let err = |why: String| SettleFileError::Read {
        path: path.display().to_string(),
        why,
    };
    let text = rappel_terrain::input::read_text(path)?;
    ron::from_str(&text).map_err(|e| err(crate::scenario::readable_message(&e.to_string())))
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
            let dem = rappel_terrain::dem::read_dem(path)?;
            TriMesh::from_height_grid(&dem).map_err(|e| err(e.to_string()))
        }
        Some("obj" | "ply" | "stl") => Ok(rappel_terrain::mesh_file::read_mesh(path)?),
        _ => Err(err(
            "unknown ground format: use a Paton scene (.ron), an elevation model (.asc, .tif) or a mesh (.obj, .ply, .stl)"
                .into(),
        )),
    }
}

/// `Err` with the ground's extent when the ground point `(x, y)` lies outside the ground's
/// bounding box (a request to settle there is bad input, not a pose that does not settle).
///
/// ```
/// let ground = rappel::terrain::paton_scene::PatonScene::paper(false).mesh().unwrap();
/// assert!(rappel::settle::within_ground(&ground, 0.0, 0.0).is_ok());
/// let e = rappel::settle::within_ground(&ground, 500.0, 0.0).unwrap_err();
/// assert_eq!(e, "outside the ground, which spans x -20.000 to 17.801 and y -20.000 to 20.000");
/// ```
pub fn within_ground(ground: &TriMesh, x: f64, y: f64) -> Result<(), String> {
    use rappel_geometry::compact::Rounded;
    let (lo, hi) = ground.bounds();
    if (lo.x..=hi.x).contains(&x) && (lo.y..=hi.y).contains(&y) {
        return Ok(());
    }
    Err(format!(
        "outside the ground, which spans x {} to {} and y {} to {}",
        Rounded(lo.x, 3),
        Rounded(hi.x, 3),
        Rounded(lo.y, 3),
        Rounded(hi.y, 3)
    ))
}

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
    pub body_clearance_m: Option<f64>,
    /// The verdict per boom configuration when an anchor was given (Axel: `inline` and
    /// `in-contact`; the four-wheel rover: one, boom [`NO_BOOM`]).
    pub stability: Vec<BoomVerdict>,
    /// Where settling read its distances.
    pub distance_source: DistanceReport,
}

crate::report::report!(SettleReport, "settle");

/// The JSON form of a pose that does not settle (`rappel settle --json`, exit code 1): the
/// request and the reason, so that `--json` means JSON on stdout in every outcome.
///
/// ```
/// use rappel::settle::{NotSettledReport, SettleRobot};
/// let r = NotSettledReport {
///     robot: SettleRobot::Axel,
///     at: [1.0, 2.0],
///     yaw_deg: 0.0,
///     reason: "no ground under the footprint".into(),
/// };
/// assert!(r.to_json().contains("\"report\": \"settle_not_settled\""));
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct NotSettledReport {
    /// The robot asked for.
    pub robot: SettleRobot,
    /// The ground point asked for, `[x, y]` metres.
    pub at: [f64; 2],
    /// The heading asked for, degrees.
    pub yaw_deg: f64,
    /// Why the pose does not settle.
    pub reason: String,
}

crate::report::report!(NotSettledReport, "settle_not_settled");

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
        body_clearance_m: Some(pose.body_clearance),
        stability,
        distance_source: distances.report(),
    };
    Ok((pose, report))
}

/// The four-wheel rover (default `FourWheelParams`) settled at `(x, y)` with yaw `yaw_deg`
/// (degrees from `+x`, counter-clockwise) through `distances` (built from the ground); with the
/// last anchor `anchor`, the stability QP's verdict ([`NO_BOOM`]: the tether from the anchor to
/// the rover's tether exit on the body, the supporting wheels' contacts with frames from the
/// mesh's exact distance gradient, [`SCENE_FRICTION`]). The rover has no body geometry: no body
/// collision is checked.
///
/// ```
/// use rappel::planners::rover::ground::{DistanceSource, GroundDistances};
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
        body_clearance_m: None,
        stability,
        distance_source: distances.report(),
    };
    Ok((pose, report))
}
