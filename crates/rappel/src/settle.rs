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

/// Half-width of the square of ground drawn around a settled pose by [`settled_pose_picture`],
/// in multiples of the rover's track.
pub const PICTURE_PATCH_TRACKS: f64 = 2.5;

/// Most ground triangles [`ground_patch`] clips (the nearest to the centre first): bounds the
/// picture on a fine mesh.
pub const PICTURE_MAX_TRIANGLES: usize = 20_000;

/// The part of `ground` over the square of half-width `half` (plan view) centred on `centre`:
/// each triangle whose plan bounding box meets the square, clipped to it (Sutherland-Hodgman on
/// the square's four sides, heights interpolated along the clipped edges, so every point stays on
/// its triangle); at most [`PICTURE_MAX_TRIANGLES`] triangles, nearest first. On a height-field
/// mesh covering the square the pieces tile it.
///
/// ```
/// use rappel::settle::ground_patch;
/// use rappel::terrain::mesh::TriMesh;
/// use nalgebra::{Point2, Point3};
/// let ground = TriMesh::new(
///     vec![
///         Point3::new(-5.0, -5.0, 0.0),
///         Point3::new(5.0, -5.0, 1.0),
///         Point3::new(5.0, 5.0, 1.0),
///         Point3::new(-5.0, 5.0, 0.0),
///     ],
///     vec![[0, 1, 2], [0, 2, 3]],
/// )
/// .unwrap();
/// let patch = ground_patch(&ground, Point2::new(0.0, 0.0), 1.0);
/// assert_eq!(patch.len(), 2);
/// ```
pub fn ground_patch(
    ground: &TriMesh,
    centre: nalgebra::Point2<f64>,
    half: f64,
) -> Vec<Vec<Point3<f64>>> {
    let (lo, hi) = (centre.x - half, centre.x + half);
    let (blo, bhi) = (centre.y - half, centre.y + half);
    let vertices = ground.vertices();
    let mut near: Vec<(f64, [Point3<f64>; 3])> = ground
        .triangles()
        .iter()
        .map(|t| t.map(|i| vertices[i]))
        .filter(|t| {
            let (x0, x1) = (
                t.iter().map(|p| p.x).fold(f64::INFINITY, f64::min),
                t.iter().map(|p| p.x).fold(f64::NEG_INFINITY, f64::max),
            );
            let (y0, y1) = (
                t.iter().map(|p| p.y).fold(f64::INFINITY, f64::min),
                t.iter().map(|p| p.y).fold(f64::NEG_INFINITY, f64::max),
            );
            x1 >= lo && x0 <= hi && y1 >= blo && y0 <= bhi
        })
        .map(|t| {
            let c = (t[0].coords + t[1].coords + t[2].coords) / 3.0;
            ((c.xy() - centre.coords).norm(), t)
        })
        .collect();
    near.sort_by(|a, b| a.0.total_cmp(&b.0));
    near.truncate(PICTURE_MAX_TRIANGLES);
    // The square's sides as (axis, bound, keep below): x <= hi, x >= lo, y <= bhi, y >= blo.
    let sides = [
        (0usize, hi, true),
        (0, lo, false),
        (1, bhi, true),
        (1, blo, false),
    ];
    near.into_iter()
        .filter_map(|(_, t)| {
            let mut poly: Vec<Point3<f64>> = t.to_vec();
            for (axis, bound, below) in sides {
                let inside = |p: &Point3<f64>| {
                    if below {
                        p[axis] <= bound
                    } else {
                        p[axis] >= bound
                    }
                };
                let mut out = Vec::with_capacity(poly.len() + 1);
                for (k, p) in poly.iter().enumerate() {
                    let q = &poly[(k + 1) % poly.len()];
                    if inside(p) {
                        out.push(*p);
                    }
                    if inside(p) != inside(q) {
                        let s = (bound - p[axis]) / (q[axis] - p[axis]);
                        let mut m = p + (q - p) * s;
                        m[axis] = bound;
                        out.push(m);
                    }
                }
                poly = out;
                if poly.is_empty() {
                    return None;
                }
            }
            (poly.len() >= 3).then_some(poly)
        })
        .collect()
}

/// Points on each drawn wheel rim.
const RIM_POINTS: usize = 32;

/// An axonometric SVG of Axel `params` settled at `pose` on `ground` ([`crate::axonometric`]):
/// the ground within [`PICTURE_PATCH_TRACKS`] tracks of the axle ([`ground_patch`]), shaded by
/// slope and drawn back to front; the axle (body) between the two wheels, each wheel a rim of the wheel radius in its
/// plane with its settled contact marked; and, with the tether's last `anchor`, the boom in the
/// configuration that holds, labelled in its `data-boom` attribute: **inline** toward the anchor
/// (`boom inline toward the anchor`) when the inline boom clears the ground, else swept down to
/// its ground contact (`boom in contact with the ground`), and the tether from the boom's tip to
/// the anchor.
///
/// ```
/// use rappel::settle::{settle_report, settled_pose_picture};
/// use rappel::mechanics::axel::AxelParams;
/// use rappel::terrain::mesh::TriMesh;
/// use nalgebra::Point3;
/// let ground = TriMesh::new(
///     vec![
///         Point3::new(-5.0, -5.0, 0.0),
///         Point3::new(5.0, -5.0, 0.0),
///         Point3::new(5.0, 5.0, 0.0),
///         Point3::new(-5.0, 5.0, 0.0),
///     ],
///     vec![[0, 1, 2], [0, 2, 3]],
/// )
/// .unwrap();
/// let (pose, _) = settle_report(&ground, 0.0, 0.0, 0.0, None).unwrap();
/// let svg = settled_pose_picture(
///     &ground,
///     &pose,
///     &AxelParams::default(),
///     Some([-4.0, 0.0, 2.0]),
///     "flat",
/// );
/// assert!(svg.contains("<g id=\"wheels\">") && svg.contains("<g id=\"tether\">"));
/// ```
pub fn settled_pose_picture(
    ground: &TriMesh,
    pose: &SettledPose,
    params: &AxelParams,
    anchor: Option<[f64; 3]>,
    title: &str,
) -> String {
    use crate::axonometric::Axonometric;
    use nalgebra::Vector3;
    let pivot = crate::mesh_stability::tether_end(pose, params);
    let mut faces: Vec<(f64, Vec<Point3<f64>>, f64)> =
        ground_patch(ground, pivot.xy(), PICTURE_PATCH_TRACKS * params.track)
            .into_iter()
            .map(|f| {
                let n = (f[1] - f[0]).cross(&(f[2] - f[0]));
                let cos_slope = (n.z.abs() / n.norm().max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
                let c = f.iter().fold(Vector3::zeros(), |a, p| a + p.coords) / f.len() as f64;
                (Axonometric::depth(&Point3::from(c)), f, cos_slope)
            })
            .collect();
    faces.sort_by(|a, b| b.0.total_cmp(&a.0));
    let mut view = Axonometric::default();
    view.group("ground");
    for (_, f, cos_slope) in &faces {
        view.shaded_polygon(f, *cos_slope);
    }
    let frame = |v: Vector3<f64>| pose.rotation * v;
    let half = 0.5 * params.track;
    let hubs = [-half, half].map(|y| pivot + frame(Vector3::new(0.0, y, 0.0)));
    view.group("body");
    view.polyline(&hubs, "stroke=\"#1f77b4\" stroke-width=\"5\"");
    view.group("wheels");
    for hub in &hubs {
        let rim: Vec<Point3<f64>> = (0..RIM_POINTS)
            .map(|k| {
                let t = std::f64::consts::TAU * k as f64 / RIM_POINTS as f64;
                hub + frame(Vector3::new(t.cos(), 0.0, t.sin()) * params.wheel_radius)
            })
            .collect();
        view.polygon(
            &rim,
            "fill=\"#1f77b4\" fill-opacity=\"0.35\" stroke=\"#1f77b4\" stroke-width=\"2\"",
        );
    }
    for c in &pose.contacts {
        view.polyline(
            &[*c, *c + frame(Vector3::z()) * 0.25 * params.wheel_radius],
            "class=\"contact\" stroke=\"#ff7f0e\" stroke-width=\"3\"",
        );
    }
    if let Some(anchor) = anchor.map(Point3::from) {
        // The configuration that holds: inline toward the anchor when the inline boom clears the
        // ground, else swept down to its contact (Paton §IV-A; `boom_contact`).
        let inline = rappel_mechanics::boom_contact::place_boom_inline(
            pose,
            params,
            ground,
            SCENE_FRICTION,
            (&anchor, None),
        );
        let contact = rappel_mechanics::boom_contact::place_boom_in_contact(
            pose,
            params,
            ground,
            SCENE_FRICTION,
            (&anchor, None),
        );
        let (tip, label) = match (inline, contact) {
            (Ok(placed), _) => (
                placed.tether.map_or(pivot, |t| t.exit),
                "boom inline toward the anchor",
            ),
            (Err(_), Ok((_, c))) => (c.tip, "boom in contact with the ground"),
            (Err(_), Err(_)) => (pivot, "no boom configuration holds"),
        };
        view.group("boom");
        view.polyline(
            &[pivot, tip],
            &format!("stroke=\"#333\" stroke-width=\"3\" data-boom=\"{label}\""),
        );
        view.group("tether");
        view.polyline(&[tip, anchor], "stroke=\"#d62728\" stroke-width=\"2\"");
        return view.render(&format!("{title}: {label}"));
    }
    view.render(title)
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
