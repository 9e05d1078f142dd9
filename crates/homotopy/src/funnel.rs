//! The Funnel Algorithm (thesis §2.3.1, Alg. 1; Chazelle, Lee and Preparata): the shortest path
//! between two points of a sleeve, in time linear in the sleeve's length.
//!
//! # The funnel
//! After the portals `d_1 .. d_i`, the shortest paths from the start `v_s` to the two endpoints
//! `alpha_i` (left) and `beta_i` (right) of `d_i` share a prefix up to the **apex** (cusp) `c`
//! and then split into two inward-convex chains: the left chain turns left at every vertex, the
//! right chain turns right. The funnel is kept in a double-ended queue
//! `[alpha_i, .., c, .., beta_i]`. Extending every chain edge to a ray cuts the region beyond the
//! mouth `d_i` into sectors (Fig. 2.14); a new vertex `v` (opposite `d_i` in the next triangle)
//! sees exactly the funnel vertex of its sector, its predecessor `pred(v)`.
//!
//! Adding `v` on the left: pop left-chain vertices `x` (with inner neighbour `y`) while `v` is not
//! strictly left of the ray `y -> x`; if the left chain empties, the apex walks out along the right
//! chain while `v` is strictly right of the ray `c -> r_1`, each apex passed joining the final
//! path. Then push `v`. Adding on the right is the mirror image. Each vertex is pushed and popped
//! at most once: linear time. Finally the goal is added like a vertex, and the path is the apex
//! history followed by the chain from the apex to the goal.
//!
//! All tests are exact orientation signs on input points (map vertices, start, goal): no point
//! is ever constructed. Collinear ties pop, so the path never keeps a vertex it passes straight
//! through; every interior vertex of the result is a strict turn.
//!
//! # Anchors
//! Each interior vertex of the taut path is an [`Anchor`] (thesis §2.4): the map vertex, its
//! obstacle, the side the tether wraps it on (the obstacle lies on that side of the path, which
//! turns towards it) and the turning angle, the wrap angle later used for capstan friction.

use crate::geom::{in_closed_triangle, is_finite};
use crate::sleeve::{Sleeve, SleeveError};
use nalgebra::Point2;
use rappel_geometry::btm::Btm;
use rappel_geometry::dcel::{ObstacleId, VertexId};
use rappel_geometry::predicates::orient2d;
use serde::{Deserialize, Serialize};
use std::collections::VecDeque;

/// The side of the path an obstacle lies on, looking along the path.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Side {
    /// On the left: the path turns left (counter-clockwise) around it.
    Left,
    /// On the right: the path turns right (clockwise) around it.
    Right,
}

/// An interior vertex of a taut tether (thesis §2.4): where it wraps a map vertex.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Anchor {
    /// The map vertex.
    pub vertex: VertexId,
    /// Its position.
    pub point: Point2<f64>,
    /// The obstacle it belongs to; `None` for a (reflex) vertex of the map boundary.
    pub obstacle: Option<ObstacleId>,
    /// The side of the path the obstacle lies on.
    pub side: Side,
    /// The tether's turning angle at the anchor, in radians, in `(0, pi)`: the angle between the
    /// incoming and outgoing directions (the wrap angle of the capstan equation).
    pub turning_angle: f64,
}

impl Anchor {
    /// The turning angle with a sign: positive for a left (counter-clockwise) turn.
    pub fn signed_turning_angle(&self) -> f64 {
        match self.side {
            Side::Left => self.turning_angle,
            Side::Right => -self.turning_angle,
        }
    }
}

/// A taut path: the shortest path in a sleeve, as a polyline with its anchors.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TautPath {
    /// The polyline, from start to goal; consecutive points are distinct (a single point when
    /// start and goal coincide and the path is trivial).
    pub points: Vec<Point2<f64>>,
    /// The map vertex at each point (`None` at the start and goal unless they sit on one).
    pub vertices: Vec<Option<VertexId>>,
    /// The interior vertices, in path order.
    pub anchors: Vec<Anchor>,
    /// Euclidean length.
    pub length: f64,
}

impl TautPath {
    /// Builds a taut path from its corner points, dropping repeated points and vertices passed
    /// straight through, and computing the anchors.
    pub(crate) fn from_corners(
        btm: &Btm,
        corners: impl IntoIterator<Item = (Point2<f64>, Option<VertexId>)>,
    ) -> TautPath {
        let corners = corners.into_iter();
        let mut points: Vec<Point2<f64>> = Vec::with_capacity(corners.size_hint().0);
        let mut vertices: Vec<Option<VertexId>> = Vec::with_capacity(corners.size_hint().0);
        for (p, v) in corners {
            if let Some(last) = points.last()
                && *last == p
            {
                // Keep the vertex identity of a point that sits on a map vertex.
                let lv = vertices.last_mut().expect("parallel vectors");
                if lv.is_none() {
                    *lv = v;
                }
                continue;
            }
            // Drop the last point when the path goes straight on through it.
            if points.len() >= 2 {
                let (a, b) = (points[points.len() - 2], points[points.len() - 1]);
                if orient2d(&a, &b, &p) == 0.0 && (b - a).dot(&(p - b)) > 0.0 {
                    points.pop();
                    vertices.pop();
                }
            }
            points.push(p);
            vertices.push(v);
        }
        let anchors = (1..points.len().saturating_sub(1))
            .filter_map(|i| {
                let vertex = vertices[i]?;
                let (a, b, c) = (points[i - 1], points[i], points[i + 1]);
                let (u, w) = (b - a, c - b);
                let cross = u.x * w.y - u.y * w.x;
                Some(Anchor {
                    vertex,
                    point: b,
                    obstacle: btm.obstacle_of_vertex(vertex),
                    side: if orient2d(&a, &b, &c) > 0.0 {
                        Side::Left
                    } else {
                        Side::Right
                    },
                    turning_angle: cross.abs().atan2(u.dot(&w)),
                })
            })
            .collect();
        // `+ 0.0`: an empty sum of f64 is -0.0; a length is never negative.
        let length = points.windows(2).map(|w| (w[1] - w[0]).norm()).sum::<f64>() + 0.0;
        TautPath {
            points,
            vertices,
            anchors,
            length,
        }
    }

    /// The start point.
    pub fn start(&self) -> Point2<f64> {
        self.points[0]
    }

    /// The goal point.
    pub fn goal(&self) -> Point2<f64> {
        self.points[self.points.len() - 1]
    }

    /// The polyline as a [`crate::path::Path`].
    pub fn to_path(&self) -> crate::path::Path {
        // Points of a taut path are finite and non-empty by construction.
        crate::path::Path::new(self.points.clone()).expect("taut paths are valid paths")
    }

    /// Total turning (sum of the anchors' turning angles), radians.
    pub fn total_turning(&self) -> f64 {
        self.anchors.iter().map(|a| a.turning_angle).sum()
    }
}

/// A corner candidate in the funnel: a point and the map vertex it is (if any).
#[derive(Debug, Clone, Copy)]
struct Slot {
    p: Point2<f64>,
    v: Option<VertexId>,
}

/// The funnel deque of Alg. 1: `[alpha .. apex .. beta]` plus the apex history.
struct Deque {
    q: VecDeque<Slot>,
    apex: usize,
    history: Vec<Slot>,
}

impl Deque {
    fn new(start: Slot, capacity: usize) -> Self {
        let mut q = VecDeque::with_capacity(capacity);
        q.push_back(start);
        Deque {
            q,
            apex: 0,
            history: Vec::with_capacity(capacity),
        }
    }

    /// Adds `s` at the left end (Alg. 1 lines 9-16, side L).
    fn push_left(&mut self, s: Slot) {
        if self.q[0].p == s.p {
            return;
        }
        while self.apex > 0 && !crate::geom::strictly_left(&self.q[1].p, &self.q[0].p, &s.p) {
            self.q.pop_front();
            self.apex -= 1;
        }
        if self.apex == 0 {
            while self.q.len() > 1 && crate::geom::strictly_right(&self.q[0].p, &self.q[1].p, &s.p)
            {
                if let Some(old) = self.q.pop_front() {
                    self.history.push(old);
                }
            }
        }
        self.q.push_front(s);
        self.apex += 1;
    }

    /// Adds `s` at the right end (the mirror image of [`Deque::push_left`]).
    fn push_right(&mut self, s: Slot) {
        let n = self.q.len();
        if self.q[n - 1].p == s.p {
            return;
        }
        while self.apex + 1 < self.q.len() {
            let n = self.q.len();
            if crate::geom::strictly_right(&self.q[n - 2].p, &self.q[n - 1].p, &s.p) {
                break;
            }
            self.q.pop_back();
        }
        if self.apex + 1 == self.q.len() {
            while self.q.len() > 1 {
                let n = self.q.len();
                if !crate::geom::strictly_left(&self.q[n - 1].p, &self.q[n - 2].p, &s.p) {
                    break;
                }
                if let Some(old) = self.q.pop_back() {
                    self.history.push(old);
                }
                self.apex = self.q.len() - 1;
            }
        }
        self.q.push_back(s);
    }

    /// The apex history, then the left chain from the apex out to its tip.
    fn into_left_path(self) -> impl Iterator<Item = Slot> {
        let Deque { q, apex, history } = self;
        history.into_iter().chain(
            q.into_iter()
                .take(apex + 1)
                .collect::<Vec<_>>()
                .into_iter()
                .rev(),
        )
    }
}

/// The shortest path from `start` to `goal` inside `sleeve` (Alg. 1), with its anchors. `start`
/// must lie in the closed start triangle and `goal` in the closed goal triangle. Linear in the
/// sleeve's length.
///
/// Around one square obstacle, the path from above to below wraps two corners:
/// ```
/// use nalgebra::Point2;
/// use rappel_geometry::{btm::Btm, map::Map, polygon::Polygon};
/// use rappel_homotopy::{crossing::CrossingSequence, path::Path, sleeve::Sleeve};
/// use rappel_homotopy::funnel::{shortest_path_in_sleeve, Side};
/// let p = |x, y| Point2::new(x, y);
/// let map = Map::new(
///     Polygon::new(vec![p(0., 0.), p(10., 0.), p(10., 10.), p(0., 10.)]),
///     vec![Polygon::new(vec![p(4., 4.), p(6., 4.), p(6., 6.), p(4., 6.)])],
/// );
/// let btm = Btm::from_map(&map).unwrap();
/// let (s, g) = (p(5., 9.), p(5., 1.));
/// let walk = Path::new(vec![s, p(1., 5.), g]).unwrap(); // passes left of the obstacle
/// let chi = CrossingSequence::reduced_of_path(&btm, &walk).unwrap();
/// let sleeve = Sleeve::from_crossing_sequence(&btm, &chi).unwrap();
/// let taut = shortest_path_in_sleeve(&btm, &sleeve, s, g).unwrap();
/// assert_eq!(taut.points, vec![s, p(4., 6.), p(4., 4.), g]);
/// assert!((taut.length - (2.0 * 10f64.sqrt() + 2.0)).abs() < 1e-12);
/// // Going down on the obstacle's west side, the obstacle is on the left.
/// assert!(taut.anchors.iter().all(|a| a.side == Side::Left));
/// ```
pub fn shortest_path_in_sleeve(
    btm: &Btm,
    sleeve: &Sleeve,
    start: Point2<f64>,
    goal: Point2<f64>,
) -> Result<TautPath, SleeveError> {
    check_endpoints(btm, sleeve, &start, &goal)?;
    let d = btm.dcel();
    let slot = |v: VertexId| Slot {
        p: d.point(v),
        v: Some(v),
    };
    let portals = sleeve.portals();
    let mut f = Deque::new(Slot { p: start, v: None }, portals.len() + 4);
    if let Some(&first) = portals.first() {
        f.push_left(slot(d.destination(first)));
        f.push_right(slot(d.origin(first)));
        for (index, w) in portals.windows(2).enumerate() {
            // The entry edge of the next triangle runs left -> right; the exit portal is its
            // `prev` (new vertex on the right) or its `next` (new vertex on the left).
            let entry = d.twin(w[0]).ok_or(SleeveError::MapEdge {
                index,
                portal: w[0],
            })?;
            if w[1] == entry.prev() {
                f.push_right(slot(d.origin(w[1])));
            } else {
                f.push_left(slot(d.destination(w[1])));
            }
        }
    }
    f.push_left(Slot { p: goal, v: None });
    Ok(TautPath::from_corners(
        btm,
        f.into_left_path().map(|s| (s.p, s.v)),
    ))
}

/// Checks that `start` and `goal` are finite and lie in the sleeve's end triangles.
pub(crate) fn check_endpoints(
    btm: &Btm,
    sleeve: &Sleeve,
    start: &Point2<f64>,
    goal: &Point2<f64>,
) -> Result<(), SleeveError> {
    let d = btm.dcel();
    for (which, p, t) in [
        ("start", start, sleeve.start_triangle()),
        ("goal", goal, sleeve.goal_triangle()),
    ] {
        if !is_finite(p) {
            return Err(SleeveError::NonFinite { which, point: *p });
        }
        if !btm.is_free_triangle(t) || !in_closed_triangle(d, t, p) {
            return Err(SleeveError::PointNotInTriangle {
                which,
                point: *p,
                triangle: t,
            });
        }
    }
    Ok(())
}
