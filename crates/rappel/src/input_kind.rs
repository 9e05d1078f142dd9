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
        let keys = ron_top_level_keys(&text);
        return if keys.contains(&"length") {
            InputKind::PatonScene
        } else if keys.contains(&"surfaces") {
            InputKind::TrackingTerrain
        } else {
            InputKind::Scenario
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

/// The field names of a RON text's top-level struct or map: the identifiers and strings followed
/// by `:` at nesting depth one, found by a scan that skips nested values, strings, characters
/// and comments without parsing them (a 1,000,000-obstacle scenario is 300 MB of numbers; parsing
/// it whole only to read its top-level keys took two thirds of `rappel validate`'s time). Linear
/// in the text, one pass. Malformed text gives whatever keys precede the fault: the kind is a
/// guess that the kind's loader then confirms or rejects with its own message.
fn ron_top_level_keys(text: &str) -> Vec<&str> {
    let bytes = text.as_bytes();
    let mut keys = Vec::new();
    let mut depth = 0usize;
    // The last token at depth one that may be a key (an identifier or a string's contents),
    // kept until the next token decides whether a `:` follows it.
    let mut candidate: Option<&str> = None;
    let mut i = 0;
    while i < bytes.len() {
        let b = bytes[i];
        match b {
            b'/' if bytes.get(i + 1) == Some(&b'/') => {
                i = text[i..].find('\n').map_or(bytes.len(), |k| i + k);
                continue;
            }
            b'/' if bytes.get(i + 1) == Some(&b'*') => {
                // Block comments nest in RON.
                let mut level = 0usize;
                while i < bytes.len() {
                    if bytes[i..].starts_with(b"/*") {
                        level += 1;
                        i += 2;
                    } else if bytes[i..].starts_with(b"*/") {
                        level -= 1;
                        i += 2;
                        if level == 0 {
                            break;
                        }
                    } else {
                        i += 1;
                    }
                }
                continue;
            }
            b' ' | b'\t' | b'\n' | b'\r' => {
                i += 1;
                continue;
            }
            b':' => {
                if depth == 1
                    && let Some(key) = candidate
                {
                    keys.push(key);
                }
                candidate = None;
                i += 1;
                continue;
            }
            b'(' | b'[' | b'{' => depth += 1,
            b')' | b']' | b'}' => depth = depth.saturating_sub(1),
            b'"' => {
                // Only a closed string is a key (its quotes are single bytes, so the slice is on
                // character boundaries).
                let end = skip_quoted(bytes, i, b'"');
                candidate = end.filter(|_| depth == 1).map(|end| &text[i + 1..end - 1]);
                i = end.unwrap_or(bytes.len());
                continue;
            }
            b'\'' => {
                i = skip_quoted(bytes, i, b'\'').unwrap_or(bytes.len());
                candidate = None;
                continue;
            }
            b'r' if matches!(bytes.get(i + 1), Some(b'#' | b'"')) => {
                // A raw string: r"..." or r#"..."# with any number of hashes.
                let hashes = bytes[i + 1..].iter().take_while(|&&c| c == b'#').count();
                let open = i + 1 + hashes;
                if bytes.get(open) == Some(&b'"') {
                    let close: Vec<u8> = std::iter::once(b'"')
                        .chain(std::iter::repeat_n(b'#', hashes))
                        .collect();
                    let end = bytes[open + 1..]
                        .windows(close.len())
                        .position(|w| w == close.as_slice())
                        .map_or(bytes.len(), |k| open + 1 + k + close.len());
                    candidate = None;
                    i = end;
                    continue;
                }
            }
            _ => {}
        }
        if b.is_ascii_alphabetic() || b == b'_' {
            let start = i;
            while i < bytes.len() && (bytes[i].is_ascii_alphanumeric() || bytes[i] == b'_') {
                i += 1;
            }
            candidate = (depth == 1).then(|| &text[start..i]);
            continue;
        }
        candidate = None;
        i += 1;
    }
    keys
}

/// The index just past the quoted literal opening at `start` with `quote`, backslash escapes
/// skipped; `None` when the text ends before it closes.
fn skip_quoted(bytes: &[u8], start: usize, quote: u8) -> Option<usize> {
    let mut i = start + 1;
    while i < bytes.len() {
        match bytes[i] {
            b'\\' => i += 2,
            c if c == quote => return Some(i + 1),
            _ => i += 1,
        }
    }
    None
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

#[cfg(test)]
mod tests {
    use super::ron_top_level_keys;

    /// The scan's keys against `ron::Value`'s (an independent parser) on every RON fixture of
    /// the repository: the same top-level keys, in the same order.
    #[test]
    fn top_level_keys_agree_with_rons_own_parse_on_every_fixture() {
        let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures");
        let mut stack = vec![std::path::PathBuf::from(root)];
        let mut checked = 0;
        while let Some(dir) = stack.pop() {
            for entry in std::fs::read_dir(&dir).expect("fixtures readable") {
                let path = entry.expect("entry").path();
                if path.is_dir() {
                    stack.push(path);
                    continue;
                }
                if path.extension().and_then(|e| e.to_str()) != Some("ron") {
                    continue;
                }
                let text = std::fs::read_to_string(&path).expect("fixture readable");
                let Ok(ron::Value::Map(m)) = ron::from_str::<ron::Value>(&text) else {
                    continue;
                };
                let expected: Vec<String> = m
                    .keys()
                    .filter_map(|k| match k {
                        ron::Value::String(s) => Some(s.clone()),
                        _ => None,
                    })
                    .collect();
                let mut got: Vec<String> = ron_top_level_keys(&text)
                    .into_iter()
                    .map(str::to_string)
                    .collect();
                let mut want = expected.clone();
                got.sort();
                want.sort();
                assert_eq!(got, want, "{}", path.display());
                checked += 1;
            }
        }
        assert!(checked >= 10, "only {checked} RON fixtures found");
    }

    #[test]
    fn nested_keys_strings_and_comments_are_skipped() {
        let text = r##"
            // length: 1.0 in a line comment
            /* surfaces: [ /* nested */ ] */
            Scene(
                name: "a (tricky): \"string\" with [brackets]",
                note: r#"raw "length": inside"#,
                c: ':',
                map: (boundary: [(0.0, 0.0)], length: 3.0),
                "quoted": 1,
                last: Some(x),
            )
        "##;
        assert_eq!(
            ron_top_level_keys(text),
            ["name", "note", "c", "map", "quoted", "last"]
        );
        assert!(ron_top_level_keys("(length: 1.0)").contains(&"length"));
        assert!(ron_top_level_keys("").is_empty());
        assert!(ron_top_level_keys("((((").is_empty());
        assert!(ron_top_level_keys("(\"unterminated: 1").is_empty());
        assert!(ron_top_level_keys("(\"é").is_empty());
        assert_eq!(ron_top_level_keys("(a: \"\\"), ["a"]);
        assert_eq!(ron_top_level_keys("(\"\\\": 1)"), Vec::<&str>::new());
    }
}
