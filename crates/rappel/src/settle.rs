//! Settling Axel on 3D ground (Paton §IV-A) from files: the ground is a Paton scene (`.ron`,
//! [`rappel_terrain::paton_scene::PatonScene`]) or an elevation model (`.asc`, `.tif`) meshed cell
//! centre to cell centre; the answer is a serialisable [`SettleReport`], optionally with the
//! stability QP's verdict for a tether to a given last anchor (both boom configurations).
//!
//! Distances are exact mesh distances (`O(triangles)` per query; the scene meshes have a few
//! hundred triangles, an elevation model two per cell).

use std::path::Path;

use nalgebra::Point3;

use rappel_mechanics::axel::{Axel, AxelParams, BoomMode};
use rappel_mechanics::settle::{SettleParams, SettledPose, settle_axel};
use rappel_mechanics::stability_qp::StabilityQp;
use rappel_terrain::mesh::TriMesh;
use rappel_terrain::paton_scene::PatonScene;
use serde::Serialize;

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
        Some("obj" | "stl") => {
            rappel_terrain::mesh_file::read_mesh(path).map_err(|e| SettleFileError::Read {
                path: path.display().to_string(),
                why: e.to_string(),
            })
        }
        _ => Err(err(
            "unknown ground format: use a Paton scene (.ron), an elevation model (.asc, .tif) or a mesh (.obj, .stl)"
                .into(),
        )),
    }
}

/// The stability verdict of one boom configuration.
#[derive(Debug, Clone, Serialize)]
pub struct BoomVerdict {
    /// `inline` or `in-contact`.
    pub boom: &'static str,
    /// A static equilibrium exists (or the error that prevented the check).
    pub stable: Result<bool, String>,
    /// Paton's normalised eq. 9 margin (0 when not stable).
    pub margin: f64,
}

/// A settled pose, for printing.
#[derive(Debug, Clone, Serialize)]
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
    pub body_clearance: f64,
    /// The verdict per boom configuration when an anchor was given.
    pub stability: Vec<BoomVerdict>,
}

/// The stability QP's verdict for `pose` with the tether toward the last anchor `anchor`, in
/// both boom configurations (inline, in contact) of Axel `params`, with [`SCENE_FRICTION`].
pub fn boom_verdicts<D: rappel_terrain::surface::SignedDistance + ?Sized>(
    ground: &D,
    pose: &SettledPose,
    params: &AxelParams,
    anchor: &Point3<f64>,
) -> Vec<BoomVerdict> {
    [
        ("inline", BoomMode::Inline),
        ("in-contact", BoomMode::InContact),
    ]
    .into_iter()
    .map(|(name, boom)| {
        let verdict = Axel::new(AxelParams { boom, ..*params })
            .and_then(|axel| pose.place(&axel, ground, SCENE_FRICTION, Some((anchor, None))))
            .map_err(|e| e.to_string())
            .and_then(|placed| {
                StabilityQp::default()
                    .check(&placed)
                    .map_err(|e| e.to_string())
            });
        match verdict {
            Ok(r) => BoomVerdict {
                boom: name,
                stable: Ok(r.stable),
                margin: r.margin,
            },
            Err(e) => BoomVerdict {
                boom: name,
                stable: Err(e),
                margin: 0.0,
            },
        }
    })
    .collect()
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
    let stability = match anchor {
        Some(a) => boom_verdicts(ground, &pose, &params, &Point3::new(a[0], a[1], a[2])),
        None => Vec::new(),
    };
    let p = |q: &Point3<f64>| [q.x, q.y, q.z];
    let report = SettleReport {
        origin: p(&pose.origin),
        roll_deg: pose.roll().to_degrees(),
        pitch_deg: pose.pitch().to_degrees(),
        contacts: [p(&pose.contacts[0]), p(&pose.contacts[1])],
        body_clearance: pose.body_clearance,
        stability,
    };
    Ok((pose, report))
}
