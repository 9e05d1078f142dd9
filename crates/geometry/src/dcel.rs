//! The half-edge DCEL (doubly-connected edge list) behind every BTM, in the compact triangle
//! layout: triangle `t` owns half-edges `3t`, `3t + 1`, `3t + 2` in counter-clockwise order, so
//! `next`, `prev` and the incident face are arithmetic and only `origin` and `twin` are stored.
//!
//! The DCEL triangulates a large scaffold triangle around the whole map, so every half-edge inside
//! it has a twin and walks never fall off a hole. Each face carries a [`FaceKind`]: free space (the
//! BTM proper), inside an obstacle, or outside the map boundary. Public navigation hides the
//! scaffold: [`Dcel::twin`] answers `None` across a map edge, and iterators list free faces only.
//!
//! Ids are stable: a triangle id names the same triangle, with the same vertices, for as long as it
//! is alive. Local updates never rewrite a live triangle in place; they retire it and allocate a
//! new id (see [`crate::btm::Btm::insert_obstacle`]).

use nalgebra::Point2;
use serde::{Deserialize, Serialize};
use std::fmt;

/// Marker for "no such element" in the compact arrays.
pub(crate) const NONE: u32 = u32::MAX;

macro_rules! id_type {
    ($(#[$doc:meta])* $name:ident) => {
        $(#[$doc])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
        #[serde(transparent)]
        pub struct $name(pub u32);

        impl $name {
            /// The id as an index into per-element arrays.
            #[inline]
            pub fn index(self) -> usize {
                self.0 as usize
            }
        }

        impl fmt::Display for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                write!(f, "{}", self.0)
            }
        }
    };
}

id_type!(
    /// A vertex of the DCEL; stable for the vertex's lifetime.
    VertexId
);
id_type!(
    /// A half-edge; `HalfEdgeId(3t + i)` is the `i`-th edge of triangle `t`.
    HalfEdgeId
);
id_type!(
    /// A triangle (face) of the DCEL; stable for the triangle's lifetime.
    TriangleId
);
id_type!(
    /// An obstacle (hole) of a BTM; stable across local updates.
    ObstacleId
);

impl HalfEdgeId {
    /// The triangle this half-edge bounds (its incident face).
    #[inline]
    pub fn triangle(self) -> TriangleId {
        TriangleId(self.0 / 3)
    }

    /// The next half-edge counter-clockwise around the same triangle.
    #[inline]
    pub fn next(self) -> HalfEdgeId {
        HalfEdgeId(if self.0 % 3 == 2 {
            self.0 - 2
        } else {
            self.0 + 1
        })
    }

    /// The previous half-edge around the same triangle.
    #[inline]
    pub fn prev(self) -> HalfEdgeId {
        HalfEdgeId(if self.0.is_multiple_of(3) {
            self.0 + 2
        } else {
            self.0 - 1
        })
    }
}

impl TriangleId {
    /// The triangle's three half-edges, counter-clockwise.
    #[inline]
    pub fn half_edges(self) -> [HalfEdgeId; 3] {
        [
            HalfEdgeId(3 * self.0),
            HalfEdgeId(3 * self.0 + 1),
            HalfEdgeId(3 * self.0 + 2),
        ]
    }
}

/// What lies in a face.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum FaceKind {
    /// Free space: a triangle of the BTM.
    Free,
    /// Inside an obstacle.
    Obstacle(ObstacleId),
    /// Outside the map boundary (including the scaffold around it).
    Exterior,
    /// A retired triangle id, no longer part of the DCEL.
    Dead,
}

/// What a half-edge is part of, beyond the triangulation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum EdgeKind {
    /// An edge added by the triangulation (a diagonal), free on both sides.
    Diagonal,
    /// An edge of the map boundary.
    Boundary,
    /// An edge of the given obstacle.
    Obstacle(ObstacleId),
}

/// Per-vertex membership in the map: which ring and the next vertex along it, oriented so that
/// free space lies to the left of `vertex -> ring_next`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct RingLink {
    pub kind: EdgeKind,
    pub next: u32,
}

/// The DCEL storage. Crate-internal mutation; public read-only navigation.
#[derive(Debug, Clone)]
pub struct Dcel {
    pub(crate) points: Vec<Point2<f64>>,
    /// Some half-edge leaving each vertex (`NONE` for removed vertices).
    pub(crate) vertex_edge: Vec<u32>,
    /// Ring membership per vertex (`None` for scaffold vertices and removed vertices).
    pub(crate) ring: Vec<Option<RingLink>>,
    /// Origin vertex per half-edge.
    pub(crate) origin: Vec<u32>,
    /// Twin half-edge per half-edge (`NONE` on the scaffold's outer edges).
    pub(crate) twin: Vec<u32>,
    /// `true` for half-edges on a map edge (boundary or obstacle).
    pub(crate) constrained: Vec<bool>,
    /// Face kind per triangle.
    pub(crate) face: Vec<FaceKind>,
    /// Number of scaffold vertices (ids `0..scaffold`).
    pub(crate) scaffold: u32,
    /// Update mode: never rewrite a live triangle slot; retire it and allocate a new one.
    pub(crate) fresh_slots: bool,
    /// Slots retired in update mode, with the face kind they had.
    pub(crate) retired: Vec<(u32, FaceKind)>,
}

impl Dcel {
    pub(crate) fn with_capacity(vertices: usize) -> Self {
        let tris = 2 * vertices + 8;
        Dcel {
            points: Vec::with_capacity(vertices + 3),
            vertex_edge: Vec::with_capacity(vertices + 3),
            ring: Vec::with_capacity(vertices + 3),
            origin: Vec::with_capacity(3 * tris),
            twin: Vec::with_capacity(3 * tris),
            constrained: Vec::with_capacity(3 * tris),
            face: Vec::with_capacity(tris),
            scaffold: 0,
            fresh_slots: false,
            retired: Vec::new(),
        }
    }

    /// Reserves room for `vertices` more vertices and `triangles` more triangle slots.
    pub(crate) fn reserve(&mut self, vertices: usize, triangles: usize) {
        self.points.reserve(vertices);
        self.vertex_edge.reserve(vertices);
        self.ring.reserve(vertices);
        self.origin.reserve(3 * triangles);
        self.twin.reserve(3 * triangles);
        self.constrained.reserve(3 * triangles);
        self.face.reserve(triangles);
        self.retired.reserve(triangles);
    }

    // ----- public navigation -------------------------------------------------------------

    /// Coordinates of a vertex.
    ///
    /// ```
    /// # use rappel_geometry::btm::Btm;
    /// # use rappel_geometry::{map::Map, polygon::Polygon};
    /// # use nalgebra::Point2;
    /// # let sq = Polygon::new(vec![Point2::new(0.,0.), Point2::new(4.,0.), Point2::new(4.,4.), Point2::new(0.,4.)]);
    /// let btm = Btm::from_map(&Map::new(sq, vec![])).unwrap();
    /// let t = btm.triangles().next().unwrap();
    /// let [a, b, c] = btm.dcel().triangle_vertices(t);
    /// assert!(btm.dcel().point(a).x >= 0.0);
    /// ```
    #[inline]
    pub fn point(&self, v: VertexId) -> Point2<f64> {
        self.points[v.index()]
    }

    /// The vertex a half-edge leaves from.
    #[inline]
    pub fn origin(&self, h: HalfEdgeId) -> VertexId {
        VertexId(self.origin[h.index()])
    }

    /// The vertex a half-edge arrives at.
    #[inline]
    pub fn destination(&self, h: HalfEdgeId) -> VertexId {
        VertexId(self.origin[h.next().index()])
    }

    /// The opposite half-edge, when the face across it is free space; `None` across a map edge.
    #[inline]
    pub fn twin(&self, h: HalfEdgeId) -> Option<HalfEdgeId> {
        let t = self.twin[h.index()];
        (t != NONE && self.face[(t / 3) as usize] == FaceKind::Free).then_some(HalfEdgeId(t))
    }

    /// The opposite half-edge whatever lies across (obstacle and exterior faces included).
    #[inline]
    pub fn twin_any(&self, h: HalfEdgeId) -> Option<HalfEdgeId> {
        let t = self.twin[h.index()];
        (t != NONE).then_some(HalfEdgeId(t))
    }

    /// The next half-edge around the same face.
    #[inline]
    pub fn next(&self, h: HalfEdgeId) -> HalfEdgeId {
        h.next()
    }

    /// The previous half-edge around the same face.
    #[inline]
    pub fn prev(&self, h: HalfEdgeId) -> HalfEdgeId {
        h.prev()
    }

    /// The face a half-edge bounds.
    #[inline]
    pub fn incident_face(&self, h: HalfEdgeId) -> TriangleId {
        h.triangle()
    }

    /// What lies in a face.
    #[inline]
    pub fn face_kind(&self, t: TriangleId) -> FaceKind {
        self.face[t.index()]
    }

    /// What a half-edge is part of.
    pub fn edge_kind(&self, h: HalfEdgeId) -> EdgeKind {
        if !self.constrained[h.index()] {
            return EdgeKind::Diagonal;
        }
        let (a, b) = (self.origin[h.index()], self.origin[h.next().index()]);
        for (u, w) in [(a, b), (b, a)] {
            if let Some(link) = self.ring[u as usize]
                && link.next == w
            {
                return link.kind;
            }
        }
        EdgeKind::Diagonal
    }

    /// `true` when the half-edge lies on a map edge (boundary or obstacle).
    #[inline]
    pub fn is_map_edge(&self, h: HalfEdgeId) -> bool {
        self.constrained[h.index()]
    }

    /// The three vertices of a triangle, counter-clockwise.
    #[inline]
    pub fn triangle_vertices(&self, t: TriangleId) -> [VertexId; 3] {
        let b = 3 * t.index();
        [
            VertexId(self.origin[b]),
            VertexId(self.origin[b + 1]),
            VertexId(self.origin[b + 2]),
        ]
    }

    /// The three corner points of a triangle, counter-clockwise.
    #[inline]
    pub fn triangle_points(&self, t: TriangleId) -> [Point2<f64>; 3] {
        self.triangle_vertices(t).map(|v| self.point(v))
    }

    /// Some half-edge leaving `v` whose face is free space (`None` for removed vertices).
    pub fn vertex_half_edge(&self, v: VertexId) -> Option<HalfEdgeId> {
        self.edges_around_vertex(v).next()
    }

    /// The half-edges leaving `v` that bound free faces, counter-clockwise. At a map vertex the
    /// free faces form one fan from one map edge to the other; the iteration starts at the half-edge
    /// along the map edge on whose left free space lies, so consecutive items share a face edge.
    pub fn edges_around_vertex(&self, v: VertexId) -> impl Iterator<Item = HalfEdgeId> + '_ {
        let start = self.fan_start(v);
        let mut current = start;
        std::iter::from_fn(move || {
            loop {
                let h = current?;
                // Next counter-clockwise out-edge: the twin of the previous edge of this face.
                let t = self.twin[h.prev().index()];
                let next = (t != NONE).then_some(HalfEdgeId(t));
                current = if next == start { None } else { next };
                if self.face[h.triangle().index()] == FaceKind::Free {
                    return Some(h);
                }
            }
        })
    }

    /// The out-edge to start a counter-clockwise fan at: for a map vertex, the out-edge along its
    /// ring (free space on its left); otherwise any out-edge.
    fn fan_start(&self, v: VertexId) -> Option<HalfEdgeId> {
        let e = *self.vertex_edge.get(v.index())?;
        if e == NONE {
            return None;
        }
        let Some(link) = self.ring[v.index()] else {
            return Some(HalfEdgeId(e));
        };
        let mut h = HalfEdgeId(e);
        for _ in 0..self.origin.len() {
            if self.origin[h.next().index()] == link.next {
                return Some(h);
            }
            let t = self.twin[h.prev().index()];
            if t == NONE {
                break;
            }
            h = HalfEdgeId(t);
            if h.0 == e {
                break;
            }
        }
        Some(HalfEdgeId(e))
    }

    /// Number of vertex slots (alive or removed), for dense per-vertex arrays.
    pub fn vertex_capacity(&self) -> usize {
        self.points.len()
    }

    /// Number of triangle slots (alive or retired), for dense per-triangle arrays.
    pub fn triangle_capacity(&self) -> usize {
        self.face.len()
    }

    /// Number of live triangles of any kind (free, obstacle, exterior scaffold).
    pub fn face_count_alive(&self) -> usize {
        self.face.iter().filter(|f| **f != FaceKind::Dead).count()
    }

    /// `true` for a vertex of the map (not scaffold, not removed).
    pub fn is_map_vertex(&self, v: VertexId) -> bool {
        self.ring.get(v.index()).is_some_and(|r| r.is_some())
    }

    // ----- crate-internal primitives ---------------------------------------------------

    #[inline]
    pub(crate) fn dest(&self, h: u32) -> u32 {
        self.origin[HalfEdgeId(h).next().index()]
    }

    #[inline]
    pub(crate) fn pt(&self, v: u32) -> &Point2<f64> {
        &self.points[v as usize]
    }

    pub(crate) fn add_vertex(&mut self, p: Point2<f64>, ring: Option<RingLink>) -> u32 {
        self.points.push(p);
        self.vertex_edge.push(NONE);
        self.ring.push(ring);
        (self.points.len() - 1) as u32
    }

    /// Appends a triangle `(a, b, c)` (counter-clockwise) with no twins yet.
    pub(crate) fn push_triangle(&mut self, a: u32, b: u32, c: u32, face: FaceKind) -> u32 {
        let t = self.face.len() as u32;
        self.origin.extend_from_slice(&[a, b, c]);
        self.twin.extend_from_slice(&[NONE, NONE, NONE]);
        self.constrained.extend_from_slice(&[false, false, false]);
        self.face.push(face);
        self.vertex_edge[a as usize] = 3 * t;
        self.vertex_edge[b as usize] = 3 * t + 1;
        self.vertex_edge[c as usize] = 3 * t + 2;
        t
    }

    /// Writes triangle `(a, b, c)` into slot `t` (twins to be linked by the caller).
    pub(crate) fn write_triangle(&mut self, t: u32, a: u32, b: u32, c: u32, face: FaceKind) {
        let base = 3 * t as usize;
        self.origin[base] = a;
        self.origin[base + 1] = b;
        self.origin[base + 2] = c;
        self.face[t as usize] = face;
        self.vertex_edge[a as usize] = 3 * t;
        self.vertex_edge[b as usize] = 3 * t + 1;
        self.vertex_edge[c as usize] = 3 * t + 2;
    }

    /// Makes `h` and `g` twins (`g` may be `NONE`).
    #[inline]
    pub(crate) fn link(&mut self, h: u32, g: u32) {
        self.twin[h as usize] = g;
        if g != NONE {
            self.twin[g as usize] = h;
        }
    }

    /// Marks both halves of the edge of `h` as a map edge (or not).
    pub(crate) fn set_constrained(&mut self, h: u32, value: bool) {
        self.constrained[h as usize] = value;
        let g = self.twin[h as usize];
        if g != NONE {
            self.constrained[g as usize] = value;
        }
    }

    /// The half-edge `a -> b`, if the edge exists (searches `a`'s fan).
    pub(crate) fn find_edge(&self, a: u32, b: u32) -> Option<u32> {
        let start = self.vertex_edge[a as usize];
        if start == NONE {
            return None;
        }
        // Rotate counter-clockwise; if the fan is open (scaffold hull), rotate clockwise too.
        let mut h = start;
        loop {
            if self.dest(h) == b {
                return Some(h);
            }
            let t = self.twin[HalfEdgeId(h).prev().index()];
            if t == NONE {
                break;
            }
            h = t;
            if h == start {
                return None;
            }
        }
        let mut h = start;
        loop {
            let t = self.twin[h as usize];
            if t == NONE {
                return None;
            }
            h = HalfEdgeId(t).next().0;
            if h == start {
                return None;
            }
            if self.dest(h) == b {
                return Some(h);
            }
        }
    }
}
