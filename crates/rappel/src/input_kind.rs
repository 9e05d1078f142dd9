//! The kinds of input file rappel reads, told apart by extension and top-level shape, and
//! checked by the loader each command uses (`rappel validate`): a scenario (also an online prior
//! or truth), a Paton scene, a tracking terrain, a path file, a pairs file, a mesh or an
//! elevation model. A check runs the same loader, with the same caps and the same messages, as
//! the command that reads the file; so "valid" here means the command will accept it.

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::scenario::Scenario;

/// A kind of input file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum InputKind {
    /// A planning scenario (`.ron`/`.json`): `plan`, `btm`, `stability`, `online` (prior and
    /// truth), `query`.
    Scenario,
    /// A Paton scene (`.ron`, `fixtures/paton/`): `settle`, `settle-map`, `navigate`.
    PatonScene,
    /// A multi-slope tracking terrain (`.json`/`.ron`, `fixtures/tracking/`): `track`.
    TrackingTerrain,
    /// A path: a JSON array of `[x, y]` points (`shp --path`, `track --robot1/--robot2`).
    Path,
    /// A pairs file: a JSON array of `{"start": [x, y], "goal": [x, y]}` (`query --pairs`).
    Pairs,
    /// A triangle mesh (`.obj`, `.ply`, `.stl`): `settle`, `settle-map`.
    Mesh,
    /// An elevation model (`.asc`, `.tif`): `dem`, `settle`, `settle-map`.
    Dem,
    /// A lidar point cloud (`.las`, `.laz`): `dem --cell`.
    PointCloud,
}

impl InputKind {
    /// Every kind, in the order of the docs.
    pub const ALL: [InputKind; 8] = [
        InputKind::Scenario,
        InputKind::PatonScene,
        InputKind::TrackingTerrain,
        InputKind::Path,
        InputKind::Pairs,
        InputKind::Mesh,
        InputKind::Dem,
        InputKind::PointCloud,
    ];

    /// The kind's name on the command line and in reports (`paton-scene`, ...).
    ///
    /// ```
    /// use rappel::input_kind::InputKind;
    /// assert_eq!(InputKind::PatonScene.name(), "paton-scene");
    /// assert_eq!(InputKind::parse("pairs"), Some(InputKind::Pairs));
    /// ```
    pub fn name(self) -> &'static str {
        match self {
            InputKind::Scenario => "scenario",
            InputKind::PatonScene => "paton-scene",
            InputKind::TrackingTerrain => "tracking-terrain",
            InputKind::Path => "path",
            InputKind::Pairs => "pairs",
            InputKind::Mesh => "mesh",
            InputKind::Dem => "dem",
            InputKind::PointCloud => "point-cloud",
        }
    }

    /// The kind named `name` ([`InputKind::name`]).
    pub fn parse(name: &str) -> Option<InputKind> {
        InputKind::ALL.into_iter().find(|k| k.name() == name)
    }
}

/// The JSON form of `rappel validate`: the kind checked and a summary of a valid file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct ValidateReport {
    /// The file checked.
    pub file: String,
    /// The kind it was checked as (detected, or given with `--kind`).
    pub kind: InputKind,
    /// Always `true` (an invalid file is an error, exit code 2).
    pub valid: bool,
    /// The contents in one line.
    pub summary: String,
    /// Obstacles (scenarios only; `null` for other kinds).
    pub obstacles: Option<usize>,
    /// Map vertices (scenarios only).
    pub vertices: Option<usize>,
    /// Terrain planes (scenarios only).
    pub terrain_planes: Option<usize>,
    /// Free-space area, m² (scenarios only).
    pub free_area_m2: Option<f64>,
    /// PTFOs of the friction section (scenarios only).
    pub ptfos: Option<usize>,
    /// The scenario carries a georeference (made from a DEM; scenarios only).
    pub georeferenced: Option<bool>,
}

crate::report::report!(ValidateReport, "validate");

/// What a check found: the kind checked and a one-line description of the contents.
#[derive(Debug, Clone, PartialEq)]
pub struct InputSummary {
    /// The kind checked.
    pub kind: InputKind,
    /// The contents in one line (`"3 obstacles, 17 vertices, ..."`).
    pub summary: String,
    /// The scenario itself, when the file is one.
    pub scenario: Option<Box<Scenario>>,
}

/// Why a file is not a valid input of its kind: the loader's own message (which names the file)
/// and the kind it was checked as.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{message} (checked as a {} file)", .kind.name())]
pub struct InputKindError {
    /// The kind the file was checked as.
    pub kind: InputKind,
    /// The loader's message.
    pub message: String,
}

/// The kind of `path`: by extension for meshes and elevation models, else by the top-level
/// shape of the text (a `.ron` with a `length` field is a Paton scene; a JSON object with
/// `surfaces` a tracking terrain; a JSON array of objects a pairs file, of arrays a path; else a
/// scenario, whose loader then says what is wrong). An unreadable file is a scenario too: its
/// check reports the read error.
///
/// ```
/// use rappel::input_kind::{InputKind, detect};
/// let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/");
/// let kind = |f: &str| detect(std::path::Path::new(&format!("{dir}{f}")));
/// assert_eq!(kind("thesis-fig-2-7.ron"), InputKind::Scenario);
/// assert_eq!(kind("paton/ledge.ron"), InputKind::PatonScene);
/// assert_eq!(kind("tracking/kumar.json"), InputKind::TrackingTerrain);
/// assert_eq!(kind("paths/fig-2-7-east.json"), InputKind::Path);
/// assert_eq!(kind("queries/fig-2-7-pairs.json"), InputKind::Pairs);
/// assert_eq!(kind("terrain/mars_hirise_dteec_010228_1490_crop.tif"), InputKind::Dem);
/// ```
pub fn detect(path: &Path) -> InputKind {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("obj" | "ply" | "stl") => return InputKind::Mesh,
        Some("asc" | "tif" | "tiff") => return InputKind::Dem,
        Some("las" | "laz") => return InputKind::PointCloud,
        _ => {}
    }
    let Ok(text) = rappel_terrain::input::read_text(path) else {
        return InputKind::Scenario;
    };
    if ext.as_deref() == Some("ron") {
        return match ron::from_str::<ron::Value>(&text) {
            Ok(ron::Value::Map(m)) if m.keys().any(|k| k == &ron::Value::from("length")) => {
                InputKind::PatonScene
            }
            Ok(ron::Value::Map(m)) if m.keys().any(|k| k == &ron::Value::from("surfaces")) => {
                InputKind::TrackingTerrain
            }
            _ => InputKind::Scenario,
        };
    }
    match serde_json::from_str::<serde_json::Value>(&text) {
        Ok(serde_json::Value::Object(o)) if o.contains_key("surfaces") => {
            InputKind::TrackingTerrain
        }
        Ok(serde_json::Value::Array(a)) => match a.first() {
            Some(serde_json::Value::Object(_)) => InputKind::Pairs,
            _ => InputKind::Path,
        },
        _ => InputKind::Scenario,
    }
}

/// The cell, metres, of the grid a point cloud is read into when it is only checked: 1,000 km,
/// so that any survey grids to a handful of cells whatever its extent (`rappel dem --cell`
/// checks the user's own cell against the grid limits).
#[cfg(feature = "mesh")]
const VALIDATE_CELL_M: f64 = 1.0e6;

/// Checks `path` as a file of `kind` with the loader of the commands that read it.
///
/// ```
/// use rappel::input_kind::{InputKind, check};
/// let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/");
/// let ok = check(std::path::Path::new(&format!("{dir}paths/fig-2-7-east.json")), InputKind::Path).unwrap();
/// assert_eq!(ok.summary, "5 waypoints");
/// let e = check(std::path::Path::new(&format!("{dir}paths/fig-2-7-east.json")), InputKind::Scenario);
/// assert!(e.unwrap_err().to_string().ends_with("(checked as a scenario file)"));
/// ```
pub fn check(path: &Path, kind: InputKind) -> Result<InputSummary, InputKindError> {
    let fail = |message: String| InputKindError { kind, message };
    let done = |summary: String| InputSummary {
        kind,
        summary,
        scenario: None,
    };
    match kind {
        InputKind::Scenario => {
            let s = Scenario::load(path).map_err(|e| fail(e.to_string()))?;
            Ok(InputSummary {
                kind,
                summary: format!(
                    "{} obstacles, {} vertices, {} terrain planes",
                    s.map.obstacles.len(),
                    s.map.vertex_count(),
                    s.terrain.planes.len()
                ),
                scenario: Some(Box::new(s)),
            })
        }
        InputKind::TrackingTerrain => {
            let (s, _) = crate::track::load_terrain(path).map_err(|e| fail(e.to_string()))?;
            Ok(done(format!(
                "{} surfaces, {} obstacles",
                s.surfaces.len(),
                s.obstacles.len()
            )))
        }
        InputKind::Path => {
            let p = crate::track::load_path(path).map_err(|e| fail(e.to_string()))?;
            Ok(done(format!("{} waypoints", p.len())))
        }
        InputKind::Pairs => {
            let p = crate::query::load_pairs(path).map_err(|e| fail(e.to_string()))?;
            Ok(done(format!("{} start/goal pairs", p.len())))
        }
        InputKind::Dem => {
            let g = rappel_terrain::dem::read_dem(path).map_err(|e| fail(e.to_string()))?;
            let geo = g.geometry();
            Ok(done(format!(
                "{} x {} cells of {} m, {} with a height",
                geo.nrows,
                geo.ncols,
                rappel_geometry::compact::Compact(geo.cell_x),
                geo.len() - g.unknown_count()
            )))
        }
        #[cfg(feature = "mesh")]
        InputKind::Mesh => {
            let m = rappel_terrain::mesh_file::read_mesh(path).map_err(|e| fail(e.to_string()))?;
            Ok(done(format!(
                "{} vertices, {} triangles",
                m.vertices().len(),
                m.triangles().len()
            )))
        }
        #[cfg(feature = "mesh")]
        InputKind::PatonScene => {
            let scene = crate::settle::load_scene(path).map_err(|e| fail(e.to_string()))?;
            let mesh = scene
                .mesh()
                .map_err(|e| fail(format!("{}: {e}", path.display())))?;
            Ok(done(format!(
                "ledge {} x {} x {} m, slope {}°, {} root anchors, {}; {} triangles",
                scene.length,
                scene.width,
                scene.height,
                scene.slope_deg,
                scene.anchors.len(),
                if scene.pole.is_some() {
                    "a pole"
                } else {
                    "no pole"
                },
                mesh.triangles().len()
            )))
        }
        #[cfg(feature = "mesh")]
        InputKind::PointCloud => {
            // `rappel dem`'s reader, every point decoded and checked; the cell only sizes the
            // throw-away grid (one cell per VALIDATE_CELL_M square), since the cell a user
            // grids with is theirs to choose.
            use rappel_terrain::point_cloud::{Statistic, read_point_cloud};
            let pc = read_point_cloud(
                path,
                VALIDATE_CELL_M,
                Statistic::Max,
                &rappel_terrain::grid::DemLimits::default(),
            )
            .map_err(|e| fail(e.to_string()))?;
            Ok(done(format!(
                "{} points, CRS {}{}",
                pc.points,
                pc.crs.as_deref().unwrap_or("none (local coordinates)"),
                match pc.ignored.len() {
                    0 => String::new(),
                    n => format!(", {n} GeoKeys not used"),
                }
            )))
        }
        #[cfg(not(feature = "mesh"))]
        InputKind::Mesh | InputKind::PatonScene | InputKind::PointCloud => Err(fail(format!(
            "{}: this build has no mesh support (the `mesh` feature is off)",
            path.display()
        ))),
    }
}
