//! Paths in the map frame (thesis §2.2): a robot path or a tether configuration is a polyline
//! `pi : [0, 1] -> free space`, given by its points. A [`Path`] only checks what it can on its own
//! (at least one point, all finite); whether it stays in free space is checked against a BTM by
//! [`Path::validate`], which walks it through the triangulation with exact predicates (the same
//! walk that computes its crossing sequence, [`crate::crossing`]).
//!
//! Free space is closed: a path may touch obstacle boundaries, run along obstacle edges and pass
//! through obstacle vertices (a taut tether does all three). It may not enter an obstacle's
//! interior or leave the map; such a path is a [`PathError::LeavesFreeSpace`] naming the segment.

use nalgebra::Point2;
use rappel_geometry::dcel::ObstacleId;
use serde::{Deserialize, Serialize};
use std::fmt;

/// What a path ran into.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Blocker {
    /// An obstacle (a hole of the BTM).
    Obstacle(ObstacleId),
    /// The map boundary.
    Boundary,
}

impl fmt::Display for Blocker {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Blocker::Obstacle(o) => write!(f, "obstacle {o}"),
            Blocker::Boundary => write!(f, "the map boundary"),
        }
    }
}

/// Why a path is not a valid path in free space. Every variant says where, so the input can be
/// fixed: move the named point, or split the named segment around the obstacle.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PathError {
    /// The path has no points; give at least one `[x, y]` point.
    #[error("the path has no points: give at least one [x, y] point")]
    Empty,
    /// A coordinate is NaN or infinite.
    #[error("point {index} ({}, {}) is not finite", point.x, point.y)]
    NonFinite {
        /// Index of the point in the path.
        index: usize,
        /// The point.
        point: Point2<f64>,
    },
    /// A point lies inside an obstacle or outside the map.
    #[error("point {index} ({}, {}) is not in free space: it lies {}", point.x, point.y, inside_or_outside(blocker))]
    PointNotFree {
        /// Index of the point in the path.
        index: usize,
        /// The point.
        point: Point2<f64>,
        /// The obstacle it is inside, or the boundary it is outside of.
        blocker: Blocker,
    },
    /// A segment enters an obstacle or leaves the map.
    #[error("segment {segment} from ({}, {}) to ({}, {}) leaves free space into {blocker} near ({}, {})", from.x, from.y, to.x, to.y, near.x, near.y)]
    LeavesFreeSpace {
        /// Index of the segment (segment `i` joins points `i` and `i + 1`).
        segment: usize,
        /// The segment's first point.
        from: Point2<f64>,
        /// The segment's last point.
        to: Point2<f64>,
        /// Where it leaves free space: the map vertex it turns into the obstacle at, or
        /// (approximately, for the message only) where it crosses the map edge.
        near: Point2<f64>,
        /// What it enters.
        blocker: Blocker,
    },
    /// The walk through the triangulation lost its way: a bug in rappel, reported instead of a
    /// panic. Please report it with the map and path.
    #[error("internal error while walking segment {segment}: {message}")]
    Internal {
        /// Index of the segment.
        segment: usize,
        /// What went wrong.
        message: String,
    },
}

fn inside_or_outside(b: &Blocker) -> String {
    match b {
        Blocker::Obstacle(o) => format!("inside obstacle {o}"),
        Blocker::Boundary => "outside the map boundary".to_string(),
    }
}

/// A polyline path in the map frame: at least one point, every coordinate finite. Consecutive
/// equal points are allowed (they make empty segments, which change nothing).
///
/// Serialises as a JSON array of `[x, y]` points, the path-file format of `rappel shp`.
///
/// ```
/// use nalgebra::Point2;
/// use rappel_homotopy::path::Path;
/// let path = Path::new(vec![Point2::new(0.0, 0.0), Point2::new(3.0, 4.0)]).unwrap();
/// assert_eq!(path.length(), 5.0);
/// let json = serde_json::to_string(&path).unwrap();
/// assert_eq!(json, "[[0.0,0.0],[3.0,4.0]]");
/// assert!(Path::new(vec![]).is_err());
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "Vec<Point2<f64>>", into = "Vec<Point2<f64>>")]
pub struct Path {
    points: Vec<Point2<f64>>,
}

impl Path {
    /// A path through `points`; fails on an empty list or a non-finite coordinate.
    pub fn new(points: Vec<Point2<f64>>) -> Result<Path, PathError> {
        if points.is_empty() {
            return Err(PathError::Empty);
        }
        if let Some((index, point)) = points
            .iter()
            .enumerate()
            .find(|(_, p)| !crate::geom::is_finite(p))
        {
            return Err(PathError::NonFinite {
                index,
                point: *point,
            });
        }
        Ok(Path { points })
    }

    /// The points, in order.
    pub fn points(&self) -> &[Point2<f64>] {
        &self.points
    }

    /// The first point.
    pub fn start(&self) -> Point2<f64> {
        self.points[0]
    }

    /// The last point.
    pub fn end(&self) -> Point2<f64> {
        self.points[self.points.len() - 1]
    }

    /// Number of segments (points minus one).
    pub fn segment_count(&self) -> usize {
        self.points.len() - 1
    }

    /// Euclidean length: the sum of the segment lengths.
    pub fn length(&self) -> f64 {
        // `+ 0.0`: an empty sum of f64 is -0.0; a length is never negative.
        self.points
            .windows(2)
            .map(|w| (w[1] - w[0]).norm())
            .sum::<f64>()
            + 0.0
    }

    /// The same path travelled backwards (thesis §2.2: the reversal `pi(1 - t)`).
    pub fn reversed(&self) -> Path {
        let mut points = self.points.clone();
        points.reverse();
        Path { points }
    }

    /// `true` when the path ends where it starts (a loop, thesis §2.2.1).
    pub fn is_closed(&self) -> bool {
        self.start() == self.end()
    }
}

impl TryFrom<Vec<Point2<f64>>> for Path {
    type Error = PathError;
    fn try_from(points: Vec<Point2<f64>>) -> Result<Self, Self::Error> {
        Path::new(points)
    }
}

impl From<Path> for Vec<Point2<f64>> {
    fn from(path: Path) -> Self {
        path.points
    }
}
