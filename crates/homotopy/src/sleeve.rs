//! Sleeves (thesis §2.2.3): the chain of triangles whose shared edges are the reduced crossing
//! sequence of a path. A sleeve is a triangulated simple polygon whose dual tree is a path (Lee and
//! Preparata); every path inside it is homotopic to every other with the same endpoints, and the
//! shortest path in the sleeve is the shortest homotopic path (SHP) of the class.
//!
//! In the plane a sleeve may visit a triangle more than once (a tether wound around an obstacle
//! twice crosses the same diagonals twice in the same direction); its lift to the universal cover
//! is always a simple triangle chain, and all the algorithms here work on that lift: they only
//! ever look at consecutive triangles.
//!
//! The sleeve stores its triangles `T_0 .. T_n` and its **portals** `d_1 .. d_n` (the thesis'
//! diagonals): portal `i` is the half-edge of `T_i` whose twin is in `T_{i+1}`. Seen by a
//! traveller crossing it, a portal's left endpoint is its destination and its right endpoint its
//! origin.

use crate::crossing::CrossingSequence;
use nalgebra::Point2;
use rappel_geometry::btm::Btm;
use rappel_geometry::dcel::{HalfEdgeId, TriangleId, VertexId};
use serde::{Deserialize, Serialize};

/// Why a sleeve or a query on it is invalid.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SleeveError {
    /// The start triangle is not a live free triangle of the BTM.
    #[error("triangle {0} is not a free triangle of this BTM")]
    NotFree(TriangleId),
    /// Portal `index` is not an edge of the triangle the chain has reached.
    #[error(
        "portal {index} (half-edge {portal}) is not an edge of the sleeve's triangle {triangle}"
    )]
    NotAChain {
        /// Index of the portal.
        index: usize,
        /// The portal.
        portal: HalfEdgeId,
        /// The triangle reached before it.
        triangle: TriangleId,
    },
    /// Portal `index` is a map edge (boundary or obstacle): nothing lies across it.
    #[error("portal {index} (half-edge {portal}) is a map edge: the sleeve cannot cross it")]
    MapEdge {
        /// Index of the portal.
        index: usize,
        /// The portal.
        portal: HalfEdgeId,
    },
    /// Portal `index` goes straight back through portal `index - 1`: reduce the crossing
    /// sequence first.
    #[error(
        "portal {index} (half-edge {portal}) cancels the portal before it: the sequence is not reduced"
    )]
    NotReduced {
        /// Index of the portal.
        index: usize,
        /// The portal.
        portal: HalfEdgeId,
    },
    /// A query point is not finite.
    #[error("the {which} point ({}, {}) is not finite", point.x, point.y)]
    NonFinite {
        /// `"start"` or `"goal"`.
        which: &'static str,
        /// The point.
        point: Point2<f64>,
    },
    /// A query point is not in the sleeve's first (start) or last (goal) closed triangle.
    #[error("the {which} point ({}, {}) is not in the sleeve's {which} triangle {triangle}", point.x, point.y)]
    PointNotInTriangle {
        /// `"start"` or `"goal"`.
        which: &'static str,
        /// The point.
        point: Point2<f64>,
        /// The triangle it should lie in.
        triangle: TriangleId,
    },
}

/// A sleeve: a chain of BTM triangles joined by portals (thesis §2.2.3).
///
/// ```
/// use nalgebra::Point2;
/// use rappel_geometry::{btm::Btm, map::Map, polygon::Polygon};
/// use rappel_homotopy::{crossing::CrossingSequence, path::Path, sleeve::Sleeve};
/// let p = |x, y| Point2::new(x, y);
/// let map = Map::new(
///     Polygon::new(vec![p(0., 0.), p(10., 0.), p(10., 10.), p(0., 10.)]),
///     vec![Polygon::new(vec![p(4., 4.), p(6., 4.), p(6., 6.), p(4., 6.)])],
/// );
/// let btm = Btm::from_map(&map).unwrap();
/// let path = Path::new(vec![p(5., 9.), p(1., 5.), p(5., 1.)]).unwrap();
/// let chi = CrossingSequence::reduced_of_path(&btm, &path).unwrap();
/// let sleeve = Sleeve::from_crossing_sequence(&btm, &chi).unwrap();
/// assert_eq!(sleeve.triangles().len(), chi.len() + 1);
/// assert_eq!(sleeve.start_triangle(), chi.start_triangle());
/// ```
#[derive(Debug, Clone, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Sleeve {
    triangles: Vec<TriangleId>,
    portals: Vec<HalfEdgeId>,
}

impl Sleeve {
    /// The sleeve of a crossing sequence, reduced first if it is not.
    pub fn from_crossing_sequence(
        btm: &Btm,
        sequence: &CrossingSequence,
    ) -> Result<Sleeve, SleeveError> {
        if sequence.is_reduced(btm) {
            Sleeve::from_portals(
                btm,
                sequence.start_triangle(),
                sequence.crossings().to_vec(),
            )
        } else {
            let reduced = sequence.reduced(btm);
            Sleeve::from_portals(btm, reduced.start_triangle(), reduced.crossings().to_vec())
        }
    }

    /// The sleeve starting in `start` and crossing `portals` in order; checks that they form a
    /// reduced chain of free triangles.
    pub fn from_portals(
        btm: &Btm,
        start: TriangleId,
        portals: Vec<HalfEdgeId>,
    ) -> Result<Sleeve, SleeveError> {
        if !btm.is_free_triangle(start) {
            return Err(SleeveError::NotFree(start));
        }
        let d = btm.dcel();
        let mut triangles = Vec::with_capacity(portals.len() + 1);
        triangles.push(start);
        let mut current = start;
        for (index, &portal) in portals.iter().enumerate() {
            if portal.triangle() != current {
                return Err(SleeveError::NotAChain {
                    index,
                    portal,
                    triangle: current,
                });
            }
            if index > 0 && d.twin(portals[index - 1]) == Some(portal) {
                return Err(SleeveError::NotReduced { index, portal });
            }
            let g = d
                .twin(portal)
                .ok_or(SleeveError::MapEdge { index, portal })?;
            current = g.triangle();
            triangles.push(current);
        }
        Ok(Sleeve { triangles, portals })
    }

    /// The triangles `T_0 .. T_n`, in order (repeats possible in the plane, see the module docs).
    pub fn triangles(&self) -> &[TriangleId] {
        &self.triangles
    }

    /// The portals `d_1 .. d_n`: portal `i` is the half-edge of `T_i` crossed into `T_{i+1}`.
    pub fn portals(&self) -> &[HalfEdgeId] {
        &self.portals
    }

    /// Number of triangles.
    pub fn len(&self) -> usize {
        self.triangles.len()
    }

    /// Always `false`: a sleeve has at least its start triangle.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// The first triangle, holding the start point.
    pub fn start_triangle(&self) -> TriangleId {
        self.triangles[0]
    }

    /// The last triangle, holding the goal point.
    pub fn goal_triangle(&self) -> TriangleId {
        self.triangles[self.triangles.len() - 1]
    }

    /// The left and right endpoints of portal `i`, as seen crossing it.
    pub fn portal_ends(&self, btm: &Btm, i: usize) -> (VertexId, VertexId) {
        let d = btm.dcel();
        let h = self.portals[i];
        (d.destination(h), d.origin(h))
    }

    /// The first `n` triangles (at least one) as a sleeve of their own.
    pub fn prefix(&self, n: usize) -> Sleeve {
        let n = n.clamp(1, self.triangles.len());
        Sleeve {
            triangles: self.triangles[..n].to_vec(),
            portals: self.portals[..n - 1].to_vec(),
        }
    }

    /// The same sleeve walked from its goal triangle to its start triangle.
    pub fn reversed(&self, btm: &Btm) -> Sleeve {
        let d = btm.dcel();
        Sleeve {
            triangles: self.triangles.iter().rev().copied().collect(),
            portals: self
                .portals
                .iter()
                .rev()
                .map(|&h| d.twin(h).unwrap_or(h))
                .collect(),
        }
    }

    /// The crossing sequence of the sleeve (reduced by construction).
    pub fn crossing_sequence(&self) -> CrossingSequence {
        CrossingSequence::from_parts(
            self.start_triangle(),
            self.goal_triangle(),
            self.portals.clone(),
        )
    }
}
