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
//! Surfaces are convex planar polygons in the world, each sharing an edge with the one before.
//! Paths are JSON arrays of `[x, y]` points in the **frame** (surface 0 laid flat: origin at its
//! first vertex, `x` along its first edge).

use nalgebra::Point2;
use rappel_mechanics::four_wheel::FourWheelRover;
use rappel_mechanics::robot::RobotModel;
use rappel_mechanics::tension_limit::HoldingRobot;
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
}

/// Why a track run failed.
#[derive(Debug, thiserror::Error)]
pub enum TrackRunError {
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
    std::fs::read_to_string(path).map_err(|source| TrackRunError::Io {
        path: path.display().to_string(),
        source,
    })
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
        message,
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
    let pts: Vec<[f64; 2]> = parse(path, &read(path)?)?;
    let bad = |message: String| TrackRunError::Path {
        path: path.display().to_string(),
        message,
    };
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
    /// Robot 2 at each waypoint.
    pub waypoints: Vec<WaypointReport>,
    /// The first waypoint where Robot 2 is not stable, if any.
    pub first_unstable: Option<usize>,
    /// Why: the least tension it needs against the limit, in words.
    pub verdict: String,
}

impl crate::report::Report for TrackReport {
    const KIND: &'static str = "track";
}

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
        robot2: &rover as &dyn RobotModel,
        tether_height: rover.params().tether_exit.z,
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
                w.t2max,
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
        waypoints,
        first_unstable,
        verdict,
    })
}

/// The drawing box of a picture: the points' bounds scaled to 800 px on the longer side.
struct Frame {
    x0: f64,
    y1: f64,
    w: f64,
    h: f64,
    scale: f64,
}

impl Frame {
    fn of<'p>(points: impl Iterator<Item = &'p Point2<f64>>) -> Frame {
        let (mut x0, mut y0, mut x1, mut y1) = (f64::MAX, f64::MAX, f64::MIN, f64::MIN);
        for p in points {
            x0 = x0.min(p.x);
            y0 = y0.min(p.y);
            x1 = x1.max(p.x);
            y1 = y1.max(p.y);
        }
        let (w, h) = ((x1 - x0).max(1e-9), (y1 - y0).max(1e-9));
        Frame {
            x0,
            y1,
            w,
            h,
            scale: 800.0 / w.max(h),
        }
    }
}

/// An SVG of the unfolded frame: surfaces, obstacles, the paths and the final tether.
pub fn track_picture(
    terrain: &MultiSlopeTerrain,
    path1: &[Point2<f64>],
    path2: &[Point2<f64>],
    report: &TrackReport,
) -> String {
    let polys = terrain.frame_polygons();
    let Frame {
        x0,
        y1,
        w,
        h,
        scale,
    } = Frame::of(polys.iter().flat_map(|p| p.vertices.iter()));
    let tx = |p: &Point2<f64>| {
        format!(
            "{:.2},{:.2}",
            (p.x - x0) * scale + 20.0,
            (y1 - p.y) * scale + 20.0
        )
    };
    let poly = |pts: &[Point2<f64>], style: &str| {
        let s: Vec<String> = pts.iter().map(tx).collect();
        format!("<polygon points=\"{}\" {style}/>\n", s.join(" "))
    };
    let line = |pts: &[Point2<f64>], style: &str| {
        let s: Vec<String> = pts.iter().map(tx).collect();
        format!(
            "<polyline points=\"{}\" fill=\"none\" {style}/>\n",
            s.join(" ")
        )
    };
    let mut out = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{:.0}\" height=\"{:.0}\">\n<title>rappel track {}</title>\n",
        w * scale + 40.0,
        h * scale + 40.0,
        report.name
    );
    for (i, p) in polys.iter().enumerate() {
        let shade = 235 - (terrain.slope_rad(i).to_degrees() as i64).clamp(0, 90);
        out += &poly(
            &p.vertices,
            &format!("fill=\"rgb({shade},{shade},{shade})\" stroke=\"#888\""),
        );
    }
    for o in terrain.obstacles() {
        out += &poly(&o.base.vertices, "fill=\"#555\"");
    }
    out += &line(path1, "stroke=\"#1f77b4\" stroke-width=\"2\"");
    out += &line(path2, "stroke=\"#2ca02c\" stroke-width=\"2\"");
    if let Some(last) = report.waypoints.last() {
        let pts: Vec<Point2<f64>> = last.configuration.iter().map(|a| a.point).collect();
        out += &line(
            &pts,
            "stroke=\"#d62728\" stroke-width=\"1.5\" stroke-dasharray=\"4 2\"",
        );
    }
    for w in &report.waypoints {
        let color = if w.stable { "#2ca02c" } else { "#d62728" };
        out += &format!(
            "<circle cx=\"{}\" cy=\"{}\" r=\"3\" fill=\"{color}\"/>\n",
            (w.position.x - x0) * scale + 20.0,
            (y1 - w.position.y) * scale + 20.0
        );
    }
    out += "</svg>\n";
    out
}

/// An axonometric (isometric) SVG of the folded terrain: surfaces shaded by slope, obstacles as
/// prisms, both paths on the ground and the final tether in 3D.
pub fn track_picture_3d(
    terrain: &MultiSlopeTerrain,
    path1: &[Point2<f64>],
    path2: &[Point2<f64>],
    report: &TrackReport,
) -> String {
    use nalgebra::Point3;
    let (c30, s30) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
    let project = |q: &Point3<f64>| Point2::new((q.x - q.y) * c30, (q.x + q.y) * s30 + q.z);
    let fold_all = |pts: &[Point2<f64>]| -> Vec<Point3<f64>> {
        pts.iter().filter_map(|p| terrain.world(p)).collect()
    };
    let mut faces: Vec<(Vec<Point3<f64>>, String)> = Vec::new();
    for (i, poly) in terrain.frame_polygons().iter().enumerate() {
        let shade = 235 - (terrain.slope_rad(i).to_degrees() as i64).clamp(0, 90);
        let pts = poly.vertices.iter().map(|p| terrain.fold(i, p)).collect();
        faces.push((
            pts,
            format!("fill=\"rgb({shade},{shade},{shade})\" stroke=\"#888\""),
        ));
    }
    for o in terrain.obstacles() {
        let n = terrain.normal(o.surface) * o.height;
        let base: Vec<Point3<f64>> = o
            .base
            .vertices
            .iter()
            .map(|p| terrain.fold(o.surface, p))
            .collect();
        for k in 0..base.len() {
            let (a, b) = (base[k], base[(k + 1) % base.len()]);
            faces.push((
                vec![a, b, b + n, a + n],
                "fill=\"#777\" stroke=\"#333\"".into(),
            ));
        }
        faces.push((
            base.iter().map(|p| p + n).collect(),
            "fill=\"#555\" stroke=\"#333\"".into(),
        ));
    }
    let lines: Vec<(Vec<Point3<f64>>, &str)> = vec![
        (fold_all(path1), "stroke=\"#1f77b4\" stroke-width=\"2\""),
        (fold_all(path2), "stroke=\"#2ca02c\" stroke-width=\"2\""),
        (
            report
                .waypoints
                .last()
                .map(|w| w.configuration.iter().map(|a| a.world).collect())
                .unwrap_or_default(),
            "stroke=\"#d62728\" stroke-width=\"1.5\" stroke-dasharray=\"4 2\"",
        ),
    ];
    let all: Vec<Point2<f64>> = faces
        .iter()
        .flat_map(|f| f.0.iter())
        .chain(lines.iter().flat_map(|l| l.0.iter()))
        .map(project)
        .collect();
    let Frame {
        x0,
        y1,
        w,
        h,
        scale,
    } = Frame::of(all.iter());
    let tx = |q: &Point3<f64>| {
        let p = project(q);
        format!(
            "{:.2},{:.2}",
            (p.x - x0) * scale + 20.0,
            (y1 - p.y) * scale + 20.0
        )
    };
    let mut out = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{:.0}\" height=\"{:.0}\">\n<title>rappel track {} (3D)</title>\n",
        w * scale + 40.0,
        h * scale + 40.0,
        report.name
    );
    for (pts, style) in &faces {
        let s: Vec<String> = pts.iter().map(tx).collect();
        out += &format!("<polygon points=\"{}\" {style}/>\n", s.join(" "));
    }
    for (pts, style) in &lines {
        let s: Vec<String> = pts.iter().map(tx).collect();
        out += &format!(
            "<polyline points=\"{}\" fill=\"none\" {style}/>\n",
            s.join(" ")
        );
    }
    out += "</svg>\n";
    out
}
