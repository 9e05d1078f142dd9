//! Settling Axel on 3D ground (Paton §IV-A) from files: the ground is a Paton scene (`.ron`,
//! [`rappel_terrain::paton_scene::PatonScene`]) or an elevation model (`.asc`, `.tif`) meshed cell
//! centre to cell centre; the answer is a serialisable [`SettleReport`], optionally with the
//! stability QP's verdict for a tether to a given last anchor (both boom configurations).
//!
//! Distances are exact mesh distances (`O(triangles)` per query; the scene meshes have a few
//! hundred triangles, an elevation model two per cell).

use std::path::Path;

use nalgebra::Point3;

use rappel_mechanics::axel::AxelParams;
use rappel_mechanics::boom_contact::{place_boom_in_contact, place_boom_inline};
use rappel_mechanics::settle::{SettleParams, SettledPose, settle_axel};
use rappel_mechanics::stability_qp::StabilityQp;
use rappel_planners::anchor_prediction::{AnchorHistory, detach_height};
use rappel_terrain::mesh::TriMesh;
use rappel_terrain::paton_scene::PatonScene;
use serde::{Deserialize, Serialize};

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
    /// `inline` or `in-contact`.
    pub boom: String,
    /// A static equilibrium exists (`None`: not checked, `error` says why).
    pub stable: Option<bool>,
    /// The error that prevented the check, if one did.
    pub error: Option<String>,
    /// Paton's normalised eq. 9 margin (0 when not stable).
    pub margin: f64,
}

/// A settled pose, for printing.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct SettleReport {
    /// Robot origin (ground under the axle centre), world.
    pub origin: [f64; 3],
    /// Roll, degrees.
    pub roll_deg: f64,
    /// Pitch, degrees.
    pub pitch_deg: f64,
    /// The lowest contact of each wheel (right, left).
    pub contacts: [[f64; 3]; 2],
    /// Smallest body clearance along the axle, metres.
    #[serde(rename = "body_clearance_m")]
    pub body_clearance: f64,
    /// The verdict per boom configuration when an anchor was given.
    pub stability: Vec<BoomVerdict>,
}

/// The stability QP's verdict for `pose` with the tether from the anchor history `history`, in
/// both boom configurations of Axel `params`, with [`SCENE_FRICTION`]:
/// * **inline**: the boom along the line from the pivot to the last anchor, refused where it
///   would pass through the mesh ([`place_boom_inline`]);
/// * **in contact**: the boom swept toward the last anchor until it touches the mesh
///   ([`place_boom_in_contact`]: on its tip or its shaft, e.g. resting on a ledge's lip). The
///   tether leaves from the boom's tip, which is not the pivot the history was predicted for:
///   while the tip lies above the last anchor's `F_d` plane (Paton's detach test,
///   [`detach_height`]) that anchor is popped and the boom swept again toward the one before
///   (at most once per anchor). Attaching anchors between the pivot and the tip is not
///   searched (the boom is at most `L_c` long).
pub fn boom_verdicts(
    ground: &TriMesh,
    pose: &SettledPose,
    params: &AxelParams,
    history: &AnchorHistory,
) -> Vec<BoomVerdict> {
    let anchors = history.anchors();
    let last = history.last().point;
    let in_contact = || {
        let mut n = anchors.len() - 1;
        loop {
            let placed = place_boom_in_contact(
                pose,
                params,
                ground,
                SCENE_FRICTION,
                (&anchors[n].point, None),
            )
            .map_err(|e| e.to_string())?;
            let popped = n > 0
                && detach_height(&anchors[n - 1], &anchors[n], &placed.1.tip)
                    .is_some_and(|h| h > 0.0);
            if !popped {
                return Ok(placed.0);
            }
            n -= 1;
        }
    };
    [("inline", true), ("in-contact", false)]
        .into_iter()
        .map(|(name, inline)| {
            let placed = if inline {
                place_boom_inline(pose, params, ground, SCENE_FRICTION, (&last, None))
                    .map_err(|e| e.to_string())
            } else {
                in_contact()
            };
            let verdict = placed.and_then(|placed| {
                StabilityQp::default()
                    .check(&placed)
                    .map_err(|e| e.to_string())
            });
            match verdict {
                Ok(r) => BoomVerdict {
                    boom: name.to_string(),
                    stable: Some(r.stable),
                    error: None,
                    margin: r.margin,
                },
                Err(e) => BoomVerdict {
                    boom: name.to_string(),
                    stable: None,
                    error: Some(e),
                    margin: 0.0,
                },
            }
        })
        .collect()
}

impl crate::report::Report for SettleReport {
    const KIND: &'static str = "settle";
}

/// Settle Axel (default parameters) at `(x, y)` with yaw `yaw_deg` (degrees from `+x`,
/// counter-clockwise); with `anchor`, check stability for both boom configurations.
pub fn settle_report(
    ground: &TriMesh,
    x: f64,
    y: f64,
    yaw_deg: f64,
    anchor: Option<[f64; 3]>,
) -> Result<(SettledPose, SettleReport), rappel_mechanics::settle::SettleError> {
    let (_, hi) = ground.bounds();
    let params = AxelParams::default();
    let pose = settle_axel(
        ground,
        &params,
        x,
        y,
        hi.z + 1.0,
        yaw_deg.to_radians(),
        &SettleParams::default(),
    )?;
    let stability = match anchor.map(|a| AnchorHistory::new(Point3::new(a[0], a[1], a[2]))) {
        Some(Ok(history)) => boom_verdicts(ground, &pose, &params, &history),
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
        origin: p(&pose.origin),
        roll_deg: crate::report::deg(pose.roll()),
        pitch_deg: crate::report::deg(pose.pitch()),
        contacts: [p(&pose.contacts[0]), p(&pose.contacts[1])],
        body_clearance: pose.body_clearance,
        stability,
    };
    Ok((pose, report))
}
