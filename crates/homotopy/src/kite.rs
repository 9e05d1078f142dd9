//! What lies across each edge of a BTM, packed for the shortest-path-tree search: thesis Alg. 3
//! line 11 and Alg. 4 ("Expand Kite") "find `v`, `d_alpha`, `d_beta`" for the funnel's mouth `d`.
//!
//! Across a mouth `d` (a half-edge of the funnel's last triangle) lies the triangle
//! `(alpha, beta, v)`; splitting the funnel there (Alg. 2) needs the vertex `v`, its point, and
//! the two exits `d_alpha = v alpha` and `d_beta = beta v`, each unless it is a map edge. Read from
//! the DCEL that is eight scattered loads (the twin of `d`, the face across, the origin of the
//! vertex, its point, the twins of both exits and the faces across them), and on a map of
//! hundreds of thousands of obstacles, whose DCEL is far larger than the cache and whose vertex
//! points are numbered in the map's order (the obstacles in any order), most of them miss. A
//! [`KiteTable`] stores the answer of every half-edge in one 32-byte record aligned to 32 bytes
//! (two to a cache line, none across two), indexed by the half-edge's id: one load per
//! expansion. Half-edges come in triangle order, which the BTM build makes follow the Hilbert
//! order of the vertices, so a funnel's next mouths usually lie on the same or a nearby line.
//!
//! The table is a copy: [`Kite::across`] computes the same record from the DCEL, and both give
//! bit-identical splits ([`crate::funnel_state::FunnelState::split_across`]).
//!
//! ```
//! use nalgebra::Point2;
//! use rappel_geometry::{btm::Btm, map::Map, polygon::Polygon};
//! use rappel_homotopy::kite::{Kite, KiteTable};
//! let p = |x, y| Point2::new(x, y);
//! let map = Map::new(
//!     Polygon::new(vec![p(0., 0.), p(10., 0.), p(10., 10.), p(0., 10.)]),
//!     vec![Polygon::new(vec![p(4., 4.), p(6., 4.), p(6., 6.), p(4., 6.)])],
//! );
//! let btm = Btm::from_map(&map).unwrap();
//! let kites = KiteTable::new(&btm);
//! for t in btm.triangles() {
//!     for h in t.half_edges() {
//!         assert_eq!(kites.get(h), Kite::across(&btm, h));
//!         // Across a map edge lies no free triangle.
//!         assert_eq!(kites.get(h).beyond().is_none(), btm.dcel().is_map_edge(h));
//!     }
//! }
//! ```

use nalgebra::Point2;
use rappel_geometry::btm::Btm;
use rappel_geometry::dcel::{HalfEdgeId, TriangleId, VertexId};

/// Marks a closed mouth (`beyond`) or an exit along a map edge.
const CLOSED: u32 = u32::MAX;

/// What lies across one half-edge `d` (module docs): 32 bytes, aligned to 32.
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(C, align(32))]
pub struct Kite {
    /// The point of the vertex `v` opposite `d` across it.
    point: Point2<f64>,
    /// The vertex `v`.
    vertex: u32,
    /// The free triangle across `d` ([`CLOSED`] across a map edge).
    beyond: u32,
    /// The exit `d_alpha = v -> alpha`, [`CLOSED`] when it is a map edge.
    left: u32,
    /// The exit `d_beta = beta -> v`, [`CLOSED`] when it is a map edge.
    right: u32,
}

impl Kite {
    /// The record of half-edge `mouth` computed from the DCEL (what [`KiteTable::get`] returns).
    pub fn across(btm: &Btm, mouth: HalfEdgeId) -> Kite {
        let d = btm.dcel();
        let Some(g) = d.twin(mouth) else {
            return Kite {
                point: Point2::origin(),
                vertex: CLOSED,
                beyond: CLOSED,
                left: CLOSED,
                right: CLOSED,
            };
        };
        // g runs alpha -> beta in the triangle (alpha, beta, v) across the mouth.
        let vertex = d.origin(g.prev());
        let exit = |h: HalfEdgeId| d.twin(h).map_or(CLOSED, |_| h.0);
        Kite {
            point: d.point(vertex),
            vertex: vertex.0,
            beyond: g.triangle().0,
            left: exit(g.prev()),
            right: exit(g.next()),
        }
    }

    /// The free triangle across the mouth (`None` across a map edge).
    #[inline]
    pub fn beyond(&self) -> Option<TriangleId> {
        (self.beyond != CLOSED).then_some(TriangleId(self.beyond))
    }

    /// The vertex `v` opposite the mouth, and its point (`None` across a map edge).
    #[inline]
    pub fn vertex(&self) -> Option<(VertexId, Point2<f64>)> {
        (self.beyond != CLOSED).then_some((VertexId(self.vertex), self.point))
    }

    /// The exit `d_alpha` (from `v` to the mouth's left end `alpha`), unless it is a map edge.
    #[inline]
    pub fn left_exit(&self) -> Option<HalfEdgeId> {
        (self.left != CLOSED).then_some(HalfEdgeId(self.left))
    }

    /// The exit `d_beta` (from the mouth's right end `beta` to `v`), unless it is a map edge.
    #[inline]
    pub fn right_exit(&self) -> Option<HalfEdgeId> {
        (self.right != CLOSED).then_some(HalfEdgeId(self.right))
    }
}

/// The [`Kite`] of every half-edge of a BTM, by half-edge id (module docs). Memory: 32 bytes per
/// half-edge slot of the DCEL (scaffold and obstacle triangles included, whose records are
/// closed): the scaffolded triangulation of `n` vertices has `2n + 1` triangles, so about 192
/// bytes per map vertex.
#[derive(Debug, Clone, Default)]
pub struct KiteTable {
    kites: Vec<Kite>,
}

impl KiteTable {
    /// The table of `btm`, in one pass over its half-edges.
    pub fn new(btm: &Btm) -> KiteTable {
        let slots = 3 * btm.dcel().triangle_capacity();
        KiteTable {
            kites: (0..slots as u32)
                .map(|h| Kite::across(btm, HalfEdgeId(h)))
                .collect(),
        }
    }

    /// The record of half-edge `mouth`.
    ///
    /// # Panics
    /// When `mouth` is not a half-edge of the BTM the table was made from.
    #[inline]
    pub fn get(&self, mouth: HalfEdgeId) -> Kite {
        self.kites[mouth.index()]
    }

    /// Bytes held.
    pub fn held_bytes(&self) -> usize {
        self.kites.capacity() * std::mem::size_of::<Kite>()
    }
}
