//! Boundary-triangulated 2-manifolds (thesis §2.2.2; online paper §II-A, Definition 1): the free
//! space of a map triangulated with no Steiner points, so every vertex is a map vertex and every
//! obstacle is a hole. rappel builds the **constrained Delaunay** BTM: among all BTMs it maximises
//! the smallest angle, avoiding the long skinny triangles of the thesis' y-monotone triangulation
//! (§2.5.3, Fig. 2.28), which keeps sleeves short and funnels well conditioned.
//!
//! Invariants (checked by [`Btm::check_invariants`] and by property tests on random maps):
//! - triangle count = n + 2h - 2 for n map vertices and h holes;
//! - triangle areas sum to the free-space area;
//! - every map edge borders exactly one free triangle, every other edge two;
//! - no unconstrained edge fails the empty-circumcircle test (exact `incircle`).
//!
//! Local updates ([`Btm::insert_obstacle`], [`Btm::remove_obstacle`]; thesis §3.5.2,
//! Lemma 3.5.1) retriangulate only the affected region and report the triangles they removed and
//! added; every other triangle keeps its id and geometry, and the invariants hold afterwards.

mod build;
mod invariants;
mod locate;
mod locator;
mod ops;
mod update;

pub use invariants::{InvariantReport, InvariantViolation};
pub use locate::Location;
pub use update::UpdateReport;

use crate::dcel::{Dcel, FaceKind, ObstacleId, TriangleId, VertexId};
use crate::map::{Map, MapError};
use crate::polygon::Polygon;
use nalgebra::Point2;

/// A boundary-triangulated 2-manifold of a map's free space, with its scaffold DCEL.
#[derive(Debug, Clone)]
pub struct Btm {
    pub(crate) dcel: Dcel,
    /// Boundary vertex ids, counter-clockwise.
    pub(crate) boundary: Vec<u32>,
    /// Obstacles by id (`None` once removed).
    pub(crate) obstacles: Vec<Option<ObstacleRecord>>,
    pub(crate) locator: locator::Locator,
}

/// An obstacle's vertices, clockwise (free space on the left of each edge): the ids
/// `first..first + len`, since a ring's vertices are numbered consecutively when it is added
/// ([`build::add_ring`]) and vertex ids never change after. Two words instead of a list: on a
/// 1,000,000-obstacle strip a list each was about 60 bytes per obstacle.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ObstacleRecord {
    first: u32,
    len: u32,
}

impl ObstacleRecord {
    /// The record of the ring added as `ids`.
    pub(crate) fn of(ids: std::ops::Range<u32>) -> Self {
        ObstacleRecord {
            first: ids.start,
            len: ids.end - ids.start,
        }
    }

    /// The obstacle's vertex ids, clockwise.
    pub(crate) fn vertices(&self) -> std::ops::Range<u32> {
        self.first..self.first + self.len
    }
}

/// Why a BTM could not be built or updated. Map defects come from validation; the rest name the
/// coordinates involved.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BtmError {
    /// The map (or the new obstacle) is invalid.
    #[error(transparent)]
    Map(#[from] MapError),
    /// Two vertices coincide.
    #[error("vertex ({}, {}) coincides with an existing vertex ({}, {})", at.x, at.y, existing.x, existing.y)]
    DuplicateVertex {
        /// The new vertex.
        at: Point2<f64>,
        /// The vertex already there.
        existing: Point2<f64>,
    },
    /// A vertex lies on a map edge.
    #[error("vertex ({}, {}) lies on a map edge", at.x, at.y)]
    VertexOnMapEdge {
        /// The vertex.
        at: Point2<f64>,
    },
    /// A map edge passes through a vertex.
    #[error("edge ({}, {})-({}, {}) passes through vertex ({}, {})", from.x, from.y, to.x, to.y, vertex.x, vertex.y)]
    EdgeThroughVertex {
        /// Edge start.
        from: Point2<f64>,
        /// Edge end.
        to: Point2<f64>,
        /// The vertex on it.
        vertex: Point2<f64>,
    },
    /// Two map edges cross.
    #[error("edge ({}, {})-({}, {}) crosses edge ({}, {})-({}, {})", first.0.x, first.0.y, first.1.x, first.1.y, second.0.x, second.0.y, second.1.x, second.1.y)]
    EdgesCross {
        /// One edge.
        first: (Point2<f64>, Point2<f64>),
        /// The other.
        second: (Point2<f64>, Point2<f64>),
    },
    /// No obstacle has this id (never existed or already removed).
    #[error("no obstacle with id {0}")]
    UnknownObstacle(ObstacleId),
    /// An internal consistency failure: a bug, reported instead of a panic.
    #[error("internal error: {0}")]
    Internal(String),
}

impl Btm {
    /// The underlying DCEL, for navigation.
    pub fn dcel(&self) -> &Dcel {
        &self.dcel
    }

    /// The free triangles (the BTM proper), in id order.
    pub fn triangles(&self) -> impl Iterator<Item = TriangleId> + '_ {
        self.dcel
            .face
            .iter()
            .enumerate()
            .filter(|(_, f)| **f == FaceKind::Free)
            .map(|(t, _)| TriangleId(t as u32))
    }

    /// `true` when `t` is a live free triangle.
    pub fn is_free_triangle(&self, t: TriangleId) -> bool {
        self.dcel.face.get(t.index()) == Some(&FaceKind::Free)
    }

    /// Number of free triangles.
    pub fn triangle_count(&self) -> usize {
        self.dcel
            .face
            .iter()
            .filter(|f| **f == FaceKind::Free)
            .count()
    }

    /// The map vertices (boundary and obstacles), in id order.
    pub fn vertices(&self) -> impl Iterator<Item = VertexId> + '_ {
        (self.dcel.scaffold..self.dcel.points.len() as u32)
            .map(VertexId)
            .filter(|v| self.dcel.is_map_vertex(*v))
    }

    /// Number of map vertices.
    pub fn vertex_count(&self) -> usize {
        self.vertices().count()
    }

    /// Ids of the current obstacles (holes).
    pub fn obstacle_ids(&self) -> impl Iterator<Item = ObstacleId> + '_ {
        self.obstacles
            .iter()
            .enumerate()
            .filter(|(_, o)| o.is_some())
            .map(|(i, _)| ObstacleId(i as u32))
    }

    /// Number of holes.
    pub fn hole_count(&self) -> usize {
        self.obstacles.iter().filter(|o| o.is_some()).count()
    }

    /// An obstacle's vertex ids, clockwise.
    pub fn obstacle_vertices(&self, id: ObstacleId) -> Option<Vec<VertexId>> {
        let rec = self.obstacles.get(id.index())?.as_ref()?;
        Some(rec.vertices().map(VertexId).collect())
    }

    /// An obstacle's polygon (clockwise).
    pub fn obstacle_polygon(&self, id: ObstacleId) -> Option<Polygon> {
        let rec = self.obstacles.get(id.index())?.as_ref()?;
        Some(Polygon::new(
            rec.vertices()
                .map(|v| self.dcel.points[v as usize])
                .collect(),
        ))
    }

    /// The boundary's vertex ids, counter-clockwise.
    pub fn boundary_vertices(&self) -> Vec<VertexId> {
        self.boundary.iter().map(|&v| VertexId(v)).collect()
    }

    /// The current map: boundary and live obstacles (in obstacle-id order).
    pub fn map(&self) -> Map {
        let boundary = Polygon::new(
            self.boundary
                .iter()
                .map(|&v| self.dcel.points[v as usize])
                .collect(),
        );
        let obstacles = self
            .obstacle_ids()
            .filter_map(|id| self.obstacle_polygon(id))
            .collect();
        Map::new(boundary, obstacles)
    }

    /// The obstacle a map vertex belongs to (`None` for boundary vertices and non-map vertices).
    pub fn obstacle_of_vertex(&self, v: VertexId) -> Option<ObstacleId> {
        match self.dcel.ring.get(v.index())?.as_ref()?.kind {
            crate::dcel::EdgeKind::Obstacle(o) => Some(o),
            _ => None,
        }
    }

    /// `true` when every unconstrained edge between free triangles passes the exact
    /// empty-circumcircle test.
    pub fn is_constrained_delaunay(&self) -> bool {
        self.first_non_delaunay_edge().is_none()
    }
}
