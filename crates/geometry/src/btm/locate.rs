//! Point location (thesis §2.2.3 needs it to start every crossing sequence): a stochastic visibility
//! walk from a hint triangle with exact orientation tests, and a coarse grid of vertices for cold
//! queries. Points on edges and vertices are reported as such, never rounded to a neighbour.
//!
//! The walk runs over the whole scaffold triangulation, so it crosses obstacles and the outside of
//! the map freely and always terminates (Devillers, Pion and Teillaud's remembering stochastic walk
//! terminates with probability one in any triangulation; the random choices come from a fixed-seed
//! generator, so results are reproducible).

use super::Btm;
use crate::dcel::{Dcel, FaceKind, HalfEdgeId, NONE, ObstacleId, TriangleId, VertexId};
use crate::predicates::orient2d;
use nalgebra::Point2;

/// Where a point lies in a BTM.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Location {
    /// Strictly inside a free triangle.
    Triangle(TriangleId),
    /// On the interior of an edge of free space. The half-edge's face is free; when both sides
    /// are free it is the half-edge with the smaller id.
    Edge(HalfEdgeId),
    /// Exactly on a map vertex.
    Vertex(VertexId),
    /// Strictly inside an obstacle.
    Obstacle(ObstacleId),
    /// Outside the map boundary (strictly).
    Outside,
}

/// Raw result of a walk in the scaffold triangulation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum RawLocation {
    Inside(u32),
    OnEdge(u32),
    OnVertex(u32),
}

/// A tiny deterministic generator for the walk's coin flips (xorshift64*).
#[derive(Debug, Clone)]
pub(crate) struct WalkRng(u64);

impl WalkRng {
    pub(crate) fn new() -> Self {
        WalkRng(0x9E37_79B9_7F4A_7C15)
    }

    #[inline]
    pub(crate) fn next3(&mut self) -> u32 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 33) as u32 % 3
    }
}

impl Dcel {
    /// Walks from triangle `start` to the point `p`. `None` when `p` is outside the scaffold or
    /// `start` is not alive.
    pub(crate) fn walk(
        &self,
        p: &Point2<f64>,
        start: u32,
        rng: &mut WalkRng,
    ) -> Option<RawLocation> {
        let mut t = start;
        if self
            .face
            .get(t as usize)
            .is_none_or(|f| *f == FaceKind::Dead)
        {
            return None;
        }
        let mut came_from = NONE;
        // A walk visits each triangle at most a few times; this bound only guards against
        // corrupted structures.
        for _ in 0..(4 * self.face.len() + 16) {
            let r = rng.next3();
            let mut moved = false;
            for k in 0..3 {
                let h = 3 * t + (r + k) % 3;
                if h == came_from {
                    continue;
                }
                let (a, b) = (self.origin[h as usize], self.dest(h));
                if orient2d(self.pt(a), self.pt(b), p) < 0.0 {
                    let g = self.twin[h as usize];
                    if g == NONE {
                        return None;
                    }
                    came_from = g;
                    t = g / 3;
                    moved = true;
                    break;
                }
            }
            if !moved {
                return Some(self.classify_in_triangle(t, p));
            }
        }
        None
    }

    /// Where `p`, known to lie in the closed triangle `t`, sits: interior, edge or vertex.
    fn classify_in_triangle(&self, t: u32, p: &Point2<f64>) -> RawLocation {
        let mut zero_edges = [NONE; 3];
        let mut zeros = 0;
        for i in 0..3 {
            let h = 3 * t + i;
            let (a, b) = (self.origin[h as usize], self.dest(h));
            if orient2d(self.pt(a), self.pt(b), p) == 0.0 {
                zero_edges[zeros] = h;
                zeros += 1;
            }
        }
        match zeros {
            0 => RawLocation::Inside(t),
            1 => RawLocation::OnEdge(zero_edges[0]),
            _ => {
                // On two edge lines: the vertex they share.
                let (h1, h2) = (zero_edges[0], zero_edges[1]);
                let v = if self.dest(h1) == self.origin[h2 as usize] {
                    self.dest(h1)
                } else {
                    self.origin[h1 as usize]
                };
                RawLocation::OnVertex(v)
            }
        }
    }
}

impl Btm {
    /// The free-space location of `p`, starting a walk from the coarse index.
    ///
    /// ```
    /// use nalgebra::Point2;
    /// use rappel_geometry::btm::{Btm, Location};
    /// use rappel_geometry::{map::Map, polygon::Polygon};
    /// let p = |x, y| Point2::new(x, y);
    /// let map = Map::new(
    ///     Polygon::new(vec![p(0., 0.), p(10., 0.), p(10., 10.), p(0., 10.)]),
    ///     vec![Polygon::new(vec![p(4., 4.), p(6., 4.), p(5., 6.)])],
    /// );
    /// let btm = Btm::from_map(&map).unwrap();
    /// assert!(matches!(btm.locate(&p(1., 2.)), Location::Triangle(_) | Location::Edge(_)));
    /// assert!(matches!(btm.locate(&p(5., 5.)), Location::Obstacle(_)));
    /// assert!(matches!(btm.locate(&p(0., 0.)), Location::Vertex(_)));
    /// assert_eq!(btm.locate(&p(11., 5.)), Location::Outside);
    /// ```
    pub fn locate(&self, p: &Point2<f64>) -> Location {
        let hint = self.locator.hint(&self.dcel, p).map(TriangleId);
        self.locate_from(p, hint)
    }

    /// The free-space location of `p`, walking from `hint` (any live triangle id, free or not);
    /// falls back to the coarse index when the hint is missing or retired.
    pub fn locate_from(&self, p: &Point2<f64>, hint: Option<TriangleId>) -> Location {
        if !(p.x.is_finite() && p.y.is_finite()) {
            return Location::Outside;
        }
        let mut rng = WalkRng::new();
        let start = hint
            .filter(|t| {
                self.dcel
                    .face
                    .get(t.index())
                    .is_some_and(|f| *f != FaceKind::Dead)
            })
            .map(|t| t.0)
            .or_else(|| self.locator.hint(&self.dcel, p));
        let Some(start) = start else {
            return Location::Outside;
        };
        match self.dcel.walk(p, start, &mut rng) {
            None => Location::Outside,
            Some(raw) => self.to_location(raw),
        }
    }

    pub(crate) fn to_location(&self, raw: RawLocation) -> Location {
        let d = &self.dcel;
        match raw {
            RawLocation::Inside(t) => match d.face[t as usize] {
                FaceKind::Free => Location::Triangle(TriangleId(t)),
                FaceKind::Obstacle(o) => Location::Obstacle(o),
                _ => Location::Outside,
            },
            RawLocation::OnVertex(v) => {
                if d.is_map_vertex(VertexId(v)) {
                    Location::Vertex(VertexId(v))
                } else {
                    Location::Outside
                }
            }
            RawLocation::OnEdge(h) => {
                let g = d.twin[h as usize];
                let free = |e: u32| e != NONE && d.face[(e / 3) as usize] == FaceKind::Free;
                match (free(h), free(g)) {
                    (true, true) => Location::Edge(HalfEdgeId(h.min(g))),
                    (true, false) => Location::Edge(HalfEdgeId(h)),
                    (false, true) => Location::Edge(HalfEdgeId(g)),
                    (false, false) => match d.face[(h / 3) as usize] {
                        FaceKind::Obstacle(o) => Location::Obstacle(o),
                        _ => Location::Outside,
                    },
                }
            }
        }
    }
}
