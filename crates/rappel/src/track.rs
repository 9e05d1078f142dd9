//! Two robots on one tether on multi-slope 3D terrain (Kumar Problem 1; the work of
//! `rappel track`): the track-scenario schema (surfaces, prism obstacles, the holding robot), path
//! files, the per-waypoint report and its picture of the unfolded frame.
//!
//! A track scenario is JSON (or RON) with unknown fields refused:
//! ```json
//! { "name": "kumar", "gravity": 9.81,
//!   "holding": { "max_pull": 0.0, "friction": 0.4, "mass": 35.0 },
//!   "surfaces": [ { "vertices": [[x, y, z], ...], "friction": 0.4 }, ... ],
//!   "obstacles": [ { "surface": 0, "base": [[x, y, z], ...], "height": 1.0, "friction": 0.4 } ] }
//! ```
//! An optional `"model"` chooses how Kumar's text is read where rappel's default departs from it
//! ([`TrackModel`]; unknown fields refused): `{"ground_anchors": "crests" | "valleys",
//! "robot2": "wheels" | "body", "friction_pyramid": "circumscribed" | "inscribed"}`, each field
//! optional (defaults: crests, wheels, circumscribed; [`TrackModel::kumar`] is valleys, body,
//! circumscribed).
//!
//! Surfaces are convex planar polygons in the world, each sharing an edge with the one before.
//! Paths are JSON arrays of `[x, y]` points in the **frame** (surface 0 laid flat: origin at its
//! first vertex, `x` along its first edge).

use nalgebra::Point2;
use rappel_mechanics::four_wheel::FourWheelRover;
use rappel_mechanics::robot::RobotModel;
use rappel_mechanics::tension_limit::HoldingRobot;
pub use rappel_planners::tether_tracking::GroundAnchorEdges;
pub use rappel_planners::tether_tracking::two_robots::{PyramidChoice, Robot2Contact, TrackModel};
use rappel_planners::tether_tracking::two_robots::{TwoRobotError, TwoRobots, WaypointReport};
use rappel_terrain::multi_slope::{MultiSlopeError, MultiSlopeTerrain, ObstacleSpec, SurfaceSpec};
use rappel_terrain::surface::Terrain;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Most waypoints accepted in one path file (each is one tracked step and one LP).
pub const MAX_WAYPOINTS: usize = 100_000;

/// The holding robot (Kumar eq. 1).
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HoldingParams {
    /// Extra pull of its wheels `F_0`, N.
    pub max_pull: f64,
    /// Its ground friction `mu_s0`.
    pub friction: f64,
    /// Its mass `m_1`, kg.
    pub mass: f64,
}

/// A track scenario (see the module docs).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrackScenario {
    /// A name for reports.
    #[serde(default)]
    pub name: String,
    /// Gravity, m/s^2.
    pub gravity: f64,
    /// Robot 1.
    pub holding: HoldingParams,
    /// The surfaces, in chain order.
    pub surfaces: Vec<SurfaceSpec>,
    /// The obstacles.
    #[serde(default)]
    pub obstacles: Vec<ObstacleSpec>,
    /// How Kumar's text is read where rappel departs from it (default: rappel's model).
    #[serde(default)]
    pub model: TrackModel,
}

/// Why a track run failed.
#[derive(Debug, thiserror::Error)]
pub enum TrackRunError {
    /// The file was not read: not a regular file, over the input size cap, not text
    /// ([`rappel_terrain::input`]).
    #[error(transparent)]
    Input(#[from] rappel_terrain::input::InputError),
    /// A file could not be read.
    #[error("{path}: cannot read: {source}")]
    Io {
        /// The file.
        path: String,
        /// The cause.
        source: std::io::Error,
    },
    /// A file does not parse.
    #[error("{path}: {message}")]
    Parse {
        /// The file.
        path: String,
        /// The parser's message (with line and column).
        message: String,
    },
    /// The terrain is refused.
    #[error("{path}: {source}")]
    Terrain {
        /// The file.
        path: String,
        /// The cause.
        source: MultiSlopeError,
    },
    /// A path is empty, too long or has a non-finite point.
    #[error("{path}: {message}")]
    Path {
        /// The file.
        path: String,
        /// What is wrong.
        message: String,
    },
    /// Tracking or stability failed.
    #[error(transparent)]
    Run(#[from] TwoRobotError),
}

fn read(path: &Path) -> Result<String, TrackRunError> {
    Ok(rappel_terrain::input::read_text(path)?)
}

fn parse<T: serde::de::DeserializeOwned>(path: &Path, text: &str) -> Result<T, TrackRunError> {
    let ron = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("ron"));
    let r = if ron {
        ron::from_str(text).map_err(|e| e.to_string())
    } else {
        serde_json::from_str(text).map_err(|e| e.to_string())
    };
    r.map_err(|message| TrackRunError::Parse {
        path: path.display().to_string(),
        message: crate::scenario::readable_message(&message),
    })
}

/// Loads a track scenario and builds its terrain.
pub fn load_terrain(path: &Path) -> Result<(TrackScenario, MultiSlopeTerrain), TrackRunError> {
    let s: TrackScenario = parse(path, &read(path)?)?;
    let t = MultiSlopeTerrain::new(s.surfaces.clone(), s.obstacles.clone()).map_err(|source| {
        TrackRunError::Terrain {
            path: path.display().to_string(),
            source,
        }
    })?;
    Ok((s, t))
}

/// Loads a path file: a JSON array of `[x, y]` frame points (1 to [`MAX_WAYPOINTS`]).
pub fn load_path(path: &Path) -> Result<Vec<Point2<f64>>, TrackRunError> {
    // Read as lists of numbers first, so that a point of 3 numbers is named as such (a
    // fixed-length array would report "trailing characters" or "invalid length").
    let pts: Vec<Vec<f64>> = parse(path, &read(path)?)?;
    let bad = |message: String| TrackRunError::Path {
        path: path.display().to_string(),
        message,
    };
    if let Some(i) = pts.iter().position(|p| p.len() != 2) {
        return Err(bad(format!(
            "point {i} has {} numbers; a waypoint is [x, y]",
            pts[i].len()
        )));
    }
    if pts.is_empty() || pts.len() > MAX_WAYPOINTS {
        return Err(bad(format!(
            "a path needs 1 to {MAX_WAYPOINTS} points, got {}",
            pts.len()
        )));
    }
    if let Some(i) = pts.iter().position(|p| !p.iter().all(|c| c.is_finite())) {
        return Err(bad(format!("point {i} is not finite")));
    }
    Ok(pts.iter().map(|p| Point2::new(p[0], p[1])).collect())
}

/// The result of `rappel track`.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
pub struct TrackReport {
    /// The scenario's name.
    pub name: String,
    /// The model the verdicts were computed in (the scenario's `model`).
    pub model: TrackModel,
    /// Robot 2 at each waypoint.
    pub waypoints: Vec<WaypointReport>,
    /// The first waypoint where Robot 2 is not stable, if any.
    pub first_unstable: Option<usize>,
    /// Why: the least tension it needs against the limit, in words.
    pub verdict: String,
}

crate::report::report!(TrackReport, "track");

/// Runs Kumar Problem 1: Robot 1 along `path1` (a single point for the one-robot form: a fixed
/// anchor), Robot 2 along `path2`; Robot 2 is the default four-wheel rover of `m_2` = 35 kg.
pub fn track(
    scenario: &TrackScenario,
    terrain: &MultiSlopeTerrain,
    path1: &[Point2<f64>],
    path2: &[Point2<f64>],
) -> Result<TrackReport, TrackRunError> {
    let rover = FourWheelRover::default();
    let two = TwoRobots {
        terrain,
        holding: HoldingRobot {
            max_pull: scenario.holding.max_pull,
            friction: scenario.holding.friction,
            mass: scenario.holding.mass,
        },
        gravity: scenario.gravity,
        robot2: &rover as &(dyn RobotModel + Sync),
        tether_height: rover.params().tether_exit.z,
        model: scenario.model,
    };
    let waypoints = two.run(path1, path2)?;
    let first_unstable = waypoints.iter().position(|w| !w.stable);
    let verdict = match first_unstable {
        None => format!("Robot 2 is stable at all {} waypoints", waypoints.len()),
        Some(i) => {
            let w = &waypoints[i];
            format!(
                "Robot 2 is not stable at waypoint {i} ({:.3}, {:.3}) on surface {} ({:.1} deg): \
                 no equilibrium with T2 <= T2max = {:.1} N (total winding {:.1} deg{})",
                w.position.x,
                w.position.y,
                w.surface,
                terrain.slope_rad(w.surface).to_degrees(),
                w.t2max_n,
                w.total_winding.to_degrees(),
                if w.ground_anchored {
                    ", last anchor on the ground"
                } else {
                    ""
                }
            )
        }
    };
    Ok(TrackReport {
        name: scenario.name.clone(),
        model: scenario.model,
        waypoints,
        first_unstable,
        verdict,
    })
}
