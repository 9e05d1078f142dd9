//! Scenario files: a map, a start and a goal, the robot's parameters and the terrain planes, in
//! RON or JSON with one schema (chosen by file extension; see `docs/scenario-format.md`). Loading
//! checks everything a planner relies on and reports the first problem with its location: the
//! line and column for syntax and schema errors, the ring and coordinates for geometric ones.

use nalgebra::Point2;
use rappel_geometry::compact::Compact;
use rappel_geometry::domain::{DOMAIN_TEXT, in_domain};
use rappel_geometry::map::{Map, MapError, ValidMap};
use rappel_terrain::plane_series::{PlaneSeriesError, TerrainPlane, validate_planes};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// A planning scenario.
///
/// ```
/// use rappel::scenario::Scenario;
/// let text = r#"(
///     name: "tiny",
///     map: (
///         boundary: [(0.0, 0.0), (10.0, 0.0), (10.0, 20.0), (0.0, 20.0)],
///         obstacles: [[(4.0, 8.0), (6.0, 8.0), (5.0, 10.0)]],
///     ),
///     start: (5.0, 19.0),
///     goal: (5.0, 1.0),
/// )"#;
/// let s = Scenario::from_ron_str(text).unwrap();
/// s.validate().unwrap();
/// assert_eq!(s.map.obstacles.len(), 1);
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// A short name.
    #[serde(default)]
    pub name: String,
    /// Free text: where the scenario comes from.
    #[serde(default)]
    pub description: String,
    /// The planning map in the unfolded frame (x across the slope, y up the slope).
    #[schemars(with = "MapSchema")]
    pub map: Map,
    /// Where the tether is anchored and the descent starts (near the top).
    #[schemars(with = "[f64; 2]")]
    pub start: Point2<f64>,
    /// The science target (lower down).
    #[schemars(with = "[f64; 2]")]
    pub goal: Point2<f64>,
    /// The robot.
    #[serde(default)]
    pub robot: RobotParams,
    /// The terrain: planes down the fall line.
    #[serde(default)]
    pub terrain: Terrain,
    /// Frictional planning: PTFOs and the tension model (`docs/friction.md`); `None` plans every
    /// obstacle as geometric.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction: Option<crate::ptfo_spec::FrictionSpec>,
    /// Where the planning frame lies in a DEM's coordinates, for scenarios made from DEMs
    /// (`rappel dem`); exports use it to write DEM coordinates.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub georeference: Option<crate::georeference::Georeference>,
}

/// The shape of [`Map`] in a scenario file, for its JSON Schema: rings of `[x, y]` points.
#[derive(schemars::JsonSchema)]
#[schemars(deny_unknown_fields)]
#[allow(dead_code)] // only its schema is used
struct MapSchema {
    /// The outer boundary of the planning region.
    boundary: Vec<[f64; 2]>,
    /// Tether obstacles: holes in the free space.
    #[serde(default)]
    obstacles: Vec<Vec<[f64; 2]>>,
}

/// Which robot model the scenario uses.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
pub enum RobotModel {
    /// A point robot (thesis Ch. 2).
    #[default]
    Point,
    /// JPL's Axel: two wheels, a body and a boom carrying the tether.
    Axel,
    /// A generic four-wheeled rover.
    FourWheel,
}

/// The robot's parameters. Every field has a documented default.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct RobotParams {
    /// The model. Default: `Point`.
    pub model: RobotModel,
    /// Total mass, kg. Default: 35 (Kumar's robots; Axel is about 35-45 kg).
    pub mass_kg: f64,
    /// Tether length, m; `None` for unlimited. Default: `None`.
    pub tether_length_m: Option<f64>,
    /// Clearance kept around obstacles by ascent and descent paths, m. Default: 0.5.
    pub clearance_m: f64,
}

impl Default for RobotParams {
    fn default() -> Self {
        RobotParams {
            model: RobotModel::Point,
            mass_kg: 35.0,
            tether_length_m: None,
            clearance_m: 0.5,
        }
    }
}

/// The terrain of a scenario.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct Terrain {
    /// Planes from the top of the wall down, meeting edge to edge (may be empty). Read with
    /// unknown fields refused.
    #[serde(deserialize_with = "deserialize_planes")]
    #[schemars(with = "Vec<PlaneFields>")]
    pub planes: Vec<TerrainPlane>,
}

/// The fields of a terrain plane as a scenario file gives them: the same as [`TerrainPlane`], with
/// unknown fields refused (a misspelt `frictoin:` must not silently fall back to nothing).
#[derive(Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
struct PlaneFields {
    /// Band top, m (planning frame, y up the slope).
    y_top: f64,
    /// Band bottom, m.
    y_bottom: f64,
    /// Slope, degrees.
    slope_deg: f64,
    /// Wheel-terrain friction coefficient.
    friction: f64,
}

fn deserialize_planes<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> Result<Vec<TerrainPlane>, D::Error> {
    let fields: Vec<PlaneFields> = Vec::deserialize(d)?;
    Ok(fields
        .into_iter()
        // `+ 0.0` turns a written `-0.0` into 0 (the same number), so that no message shows `-0`.
        .map(|p| {
            TerrainPlane::new(
                p.y_top + 0.0,
                p.y_bottom + 0.0,
                p.slope_deg + 0.0,
                p.friction + 0.0,
            )
        })
        .collect())
}

/// The steepest plane a scenario may hold, degrees: the limit of the robot models
/// ([`rappel_mechanics::robot::MAX_SLOPE`]; a vertical wall has no up-slope frame for a wheeled
/// robot), checked at validation so that `validate` accepts exactly what `plan` and `stability`
/// can use.
pub const MAX_SLOPE_DEG: f64 = 89.0;

/// The RON options of scenario files: optional numbers written plainly (`tether_length_m: 20.0`;
/// `Some(20.0)` is read too).
fn ron_options() -> ron::Options {
    ron::Options::default().with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME)
}

/// Longest parser message printed, characters (a message may quote a long stretch of input).
const MAX_MESSAGE_CHARS: usize = 240;

/// A parser's message made safe to print: library internals translated, control characters and
/// other unprintable bytes of the input escaped, long quotes shortened.
pub(crate) fn readable_message(message: &str) -> String {
    if message.contains("recursion_limit") || message.contains("recursion limit") {
        return "nested too deeply (more than 128 levels of brackets)".to_string();
    }
    let mut out = String::new();
    for (count, c) in message.chars().enumerate() {
        if count >= MAX_MESSAGE_CHARS {
            out.push_str("...");
            break;
        }
        if c.is_control() || c == '\u{fffd}' {
            out.extend(c.escape_default());
        } else {
            out.push(c);
        }
    }
    out
}

/// Why a scenario could not be loaded or used.
#[derive(Debug, thiserror::Error)]
pub enum ScenarioError {
    /// The file was not read: not a regular file, over the input size cap, not text
    /// ([`rappel_terrain::input`]).
    #[error(transparent)]
    Input(#[from] rappel_terrain::input::InputError),
    /// The file could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// The extension names no known format.
    #[error("{}: unknown scenario format; use a .ron or .json file", path.display())]
    UnknownFormat {
        /// The file.
        path: PathBuf,
    },
    /// Syntax or schema error at a position.
    #[error("{}:{line}:{column}: {message}", path.display())]
    Parse {
        /// The file (empty for strings).
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What is wrong.
        message: String,
    },
    /// The map, start or goal is unusable.
    #[error("{}: {source}", path.display())]
    Map {
        /// The file.
        path: PathBuf,
        /// The defect.
        source: MapError,
    },
    /// The terrain planes are unusable.
    #[error("{}: terrain: {source}", path.display())]
    Planes {
        /// The file.
        path: PathBuf,
        /// The defect.
        source: PlaneSeriesError,
    },
    /// A terrain plane is outside what the planners accept.
    #[error("{}: terrain: plane {plane}: {message}", path.display())]
    Plane {
        /// The file.
        path: PathBuf,
        /// The plane's index, 0 at the top.
        plane: usize,
        /// What is wrong.
        message: String,
    },
    /// The `georeference` section is unusable.
    #[error("{}: georeference: {message}", path.display())]
    Georeference {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// The `friction` section is unusable (`docs/friction.md`).
    #[error("{}: {message}", path.display())]
    Friction {
        /// The file.
        path: PathBuf,
        /// What is wrong, naming the entry.
        message: String,
    },
    /// A [`crate::builder::ScenarioBuilder`] was not given a required part.
    #[error("scenario builder: no {missing} given (call .{missing}(...))")]
    Incomplete {
        /// The missing part: `boundary`, `start` or `goal`.
        missing: &'static str,
    },
    /// A robot parameter is out of range.
    #[error("{}: robot: {message}", path.display())]
    Robot {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
}

/// The two file formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Rusty Object Notation (`.ron`).
    Ron,
    /// JSON (`.json`).
    Json,
}

impl Format {
    /// The format named by a path's extension.
    pub fn of_path(path: &Path) -> Option<Format> {
        match path.extension()?.to_str()?.to_ascii_lowercase().as_str() {
            "ron" => Some(Format::Ron),
            "json" => Some(Format::Json),
            _ => None,
        }
    }
}

/// A scenario that passed [`Scenario::validate`], with its map's [`ValidMap`] proof: what the
/// planners that build a BTM take, so that the map is validated once. Only
/// [`Scenario::validate`] makes one (the fields are private); it borrows the scenario, which
/// therefore cannot change while the proof lives.
///
/// ```
/// use rappel::scenario::Scenario;
/// let s = rappel::generated::star_scenario(6).unwrap();
/// let valid = s.validate().unwrap();
/// assert_eq!(valid.name, "star-6"); // it dereferences to the scenario
/// assert_eq!(valid.map().obstacles[0].len(), 6);
/// ```
///
/// Nothing outside validation can make one (the fields are private):
///
/// ```compile_fail
/// use rappel::scenario::ValidScenario;
/// let s = rappel::generated::star_scenario(6).unwrap();
/// let valid = s.validate().unwrap();
/// let forged = ValidScenario { scenario: &s, map: valid.map() };
/// ```
#[derive(Debug, Clone, Copy)]
pub struct ValidScenario<'a> {
    scenario: &'a Scenario,
    map: ValidMap<'a>,
}

impl<'a> ValidScenario<'a> {
    /// The validated scenario.
    pub fn scenario(&self) -> &'a Scenario {
        self.scenario
    }

    /// Its validated map.
    pub fn map(&self) -> ValidMap<'a> {
        self.map
    }
}

impl std::ops::Deref for ValidScenario<'_> {
    type Target = Scenario;

    fn deref(&self) -> &Scenario {
        self.scenario
    }
}

impl Scenario {
    /// Parses RON text (not validated).
    pub fn from_ron_str(text: &str) -> Result<Scenario, ScenarioError> {
        ron_options()
            .from_str(text)
            .map_err(|e| ScenarioError::Parse {
                path: PathBuf::new(),
                line: e.span.start.line,
                column: e.span.start.col,
                message: readable_message(&e.code.to_string()),
            })
    }

    /// Parses JSON text (not validated).
    pub fn from_json_str(text: &str) -> Result<Scenario, ScenarioError> {
        serde_json::from_str(text).map_err(|e| ScenarioError::Parse {
            path: PathBuf::new(),
            line: e.line(),
            column: e.column(),
            message: readable_message(&strip_json_position(&e.to_string())),
        })
    }

    /// Reads, parses and validates a scenario file.
    pub fn load(path: impl AsRef<Path>) -> Result<Scenario, ScenarioError> {
        let path = path.as_ref();
        let scenario = Scenario::read(path)?;
        scenario.validate_at(path)?;
        Ok(scenario)
    }

    /// Reads and parses a scenario file, not validated: for a caller that keeps the
    /// [`ValidScenario`] of [`Scenario::validate_at`] ([`Scenario::load`] is the two, the proof
    /// dropped).
    ///
    /// ```
    /// use rappel::scenario::Scenario;
    /// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/thesis-fig-2-7.ron");
    /// let s = Scenario::read(path).unwrap();
    /// let valid = s.validate_at(path).unwrap();
    /// assert_eq!(valid.map().obstacles.len(), s.map.obstacles.len());
    /// ```
    pub fn read(path: impl AsRef<Path>) -> Result<Scenario, ScenarioError> {
        let path = path.as_ref();
        let format = Format::of_path(path).ok_or_else(|| ScenarioError::UnknownFormat {
            path: path.to_path_buf(),
        })?;
        let text = rappel_terrain::input::read_text(path)?;
        let parsed = match format {
            Format::Ron => Scenario::from_ron_str(&text),
            Format::Json => Scenario::from_json_str(&text),
        };
        parsed.map_err(|e| e.at(path))
    }

    /// [`Scenario::validate`], its error located in the file `path` that the scenario was read
    /// from.
    pub fn validate_at(&self, path: impl AsRef<Path>) -> Result<ValidScenario<'_>, ScenarioError> {
        self.validate().map_err(|e| e.at(path.as_ref()))
    }

    /// Checks the map, the start and goal, the planes and the robot; returns the
    /// [`ValidScenario`] proof, which carries the map's [`ValidMap`] (so that a BTM is built
    /// without validating the map again).
    pub fn validate(&self) -> Result<ValidScenario<'_>, ScenarioError> {
        let path = PathBuf::new();
        let map_err = |source| ScenarioError::Map {
            path: PathBuf::new(),
            source,
        };
        let map = self.map.validate().map_err(map_err)?;
        self.map
            .validate_point("start", &self.start)
            .map_err(map_err)?;
        self.map
            .validate_point("goal", &self.goal)
            .map_err(map_err)?;
        for (plane, p) in self.terrain.planes.iter().enumerate() {
            let bad_plane = |message: String| {
                Err(ScenarioError::Plane {
                    path: PathBuf::new(),
                    plane,
                    message,
                })
            };
            // Ranges checked here with compact numbers in the message; the series' own checks
            // (bands meeting edge to edge) follow.
            if !(0.0..=MAX_SLOPE_DEG).contains(&p.slope_deg) {
                return bad_plane(format!(
                    "slope {} degrees: it must be between 0 and {MAX_SLOPE_DEG}, the steepest the robot models accept",
                    Compact(p.slope_deg)
                ));
            }
            if !(p.friction.is_finite() && p.friction >= 0.0) {
                return bad_plane(format!(
                    "friction {}: it must be a number >= 0",
                    Compact(p.friction)
                ));
            }
            for (name, v) in [("y_top", p.y_top), ("y_bottom", p.y_bottom)] {
                if !in_domain(v) {
                    return bad_plane(format!("{name} = {}: {DOMAIN_TEXT}", Compact(v)));
                }
            }
            if p.y_top <= p.y_bottom {
                return bad_plane(format!(
                    "y_top {} is not above y_bottom {}",
                    Compact(p.y_top),
                    Compact(p.y_bottom)
                ));
            }
        }
        validate_planes(&self.terrain.planes).map_err(|source| ScenarioError::Planes {
            path: path.clone(),
            source,
        })?;
        let r = &self.robot;
        let bad = |message: String| {
            Err(ScenarioError::Robot {
                path: PathBuf::new(),
                message,
            })
        };
        if !(r.mass_kg.is_finite() && r.mass_kg > 0.0) {
            return bad(format!(
                "mass_kg must be a positive number, got {}",
                Compact(r.mass_kg)
            ));
        }
        if !(r.clearance_m.is_finite() && r.clearance_m >= 0.0) {
            return bad(format!(
                "clearance_m must be >= 0, got {}",
                Compact(r.clearance_m)
            ));
        }
        if let Some(l) = r.tether_length_m
            && !(l.is_finite() && l > 0.0)
        {
            return bad(format!(
                "tether_length_m must be positive, got {}",
                Compact(l)
            ));
        }
        if let Some(f) = &self.friction {
            f.resolve(
                self.robot.mass_kg,
                &self.terrain.planes,
                self.map.obstacles.len(),
            )
            .map_err(|message| ScenarioError::Friction {
                path: PathBuf::new(),
                message,
            })?;
        }
        if let Some(g) = &self.georeference {
            g.validate()
                .map_err(|message| ScenarioError::Georeference {
                    path: PathBuf::new(),
                    message,
                })?;
        }
        Ok(ValidScenario {
            scenario: self,
            map,
        })
    }

    /// The scenario as text in `format`.
    pub fn to_text(&self, format: Format) -> String {
        match format {
            Format::Ron => {
                let config = ron::ser::PrettyConfig::new()
                    .depth_limit(4)
                    .indentor("    ".to_string());
                ron_options()
                    .to_string_pretty(self, config)
                    .unwrap_or_default()
                    + "\n"
            }
            Format::Json => serde_json::to_string_pretty(self).unwrap_or_default() + "\n",
        }
    }

    /// Writes the scenario to `path` (format by extension), atomically.
    pub fn save(&self, path: impl AsRef<Path>) -> Result<(), ScenarioError> {
        let path = path.as_ref();
        let format = Format::of_path(path).ok_or_else(|| ScenarioError::UnknownFormat {
            path: path.to_path_buf(),
        })?;
        crate::io::write_atomically(path, self.to_text(format).as_bytes()).map_err(|source| {
            ScenarioError::Io {
                path: path.to_path_buf(),
                source,
            }
        })
    }
}

impl ScenarioError {
    /// The same error, attributed to `path`.
    fn at(self, p: &Path) -> ScenarioError {
        let p = p.to_path_buf();
        match self {
            ScenarioError::Parse {
                line,
                column,
                message,
                ..
            } => ScenarioError::Parse {
                path: p,
                line,
                column,
                message,
            },
            ScenarioError::Map { source, .. } => ScenarioError::Map { path: p, source },
            ScenarioError::Planes { source, .. } => ScenarioError::Planes { path: p, source },
            ScenarioError::Robot { message, .. } => ScenarioError::Robot { path: p, message },
            ScenarioError::Plane { plane, message, .. } => ScenarioError::Plane {
                path: p,
                plane,
                message,
            },
            ScenarioError::Friction { message, .. } => ScenarioError::Friction { path: p, message },
            ScenarioError::Georeference { message, .. } => {
                ScenarioError::Georeference { path: p, message }
            }
            other => other,
        }
    }
}

/// serde_json appends " at line L column C" to its messages; we print the position up front.
pub(crate) fn strip_json_position(message: &str) -> String {
    match message.rfind(" at line ") {
        Some(i) => message[..i].to_string(),
        None => message.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parser_messages_are_translated_and_printable() {
        let m = readable_message(
            "Exceeded recursion limit, try increasing `ron::Options::recursion_limit` and using `serde_stacker` to protect against a stack overflow",
        );
        assert!(
            m.contains("nested too deeply") && !m.contains("ron::"),
            "{m}"
        );
        let m = readable_message("Unexpected `\u{0}\u{1b}[31m`");
        assert!(!m.chars().any(char::is_control), "{m:?}");
        assert!(readable_message(&"x".repeat(10_000)).len() < 300);
    }
}
