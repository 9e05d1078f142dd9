//! Crossing sequences (thesis §2.2.3): the ordered, directed list of BTM diagonals a path crosses,
//! and its reduction by cancelling immediate back-and-forth crossings.
//!
//! # Crossings as half-edges
//! A crossing is the half-edge `h` of the triangle the path leaves; the path enters the triangle
//! of `twin(h)`. Crossing the same diagonal the other way is `twin(h)`, so reduction cancels `h`
//! immediately followed by `twin(h)` (thesis: "remove each pair of adjacent identical letters";
//! with directed letters this is free-group reduction). Map edges are never crossed: a path
//! that would cross one leaves free space, which is a [`PathError`].
//!
//! # The reduced sequence is canonical
//! A crossing sequence is a walk in the dual graph of the BTM, from the path's start triangle to
//! its end triangle. Lifted to the universal cover (thesis §2.2.2, Fig. 2.6) the dual graph is a
//! tree, and the reduced sequence is the unique tree path between the two lifts. Two paths with
//! the same endpoints are therefore homotopic exactly when their reduced sequences are equal, and
//! a loop is contractible exactly when its reduced sequence is empty (Hershberger and Snoeyink).
//! The reduced sequence's triangles form the [`crate::sleeve::Sleeve`].
//!
//! # Symbolic perturbation: paths through vertices and along edges
//! Paths may touch the triangulation's skeleton: a taut tether passes through obstacle vertices
//! and runs along obstacle edges. rappel reads every path `pi` as an infinitesimally perturbed
//! path `pi_eps` that meets edges only transversally at interior points, built by these rules:
//!
//! 1. **Lazy crossing.** The perturbed path stays in its current closed triangle as long as the
//!    real path does; it crosses an edge only when the real path moves strictly to the other
//!    side. A path running along an edge, or touching it, does not cross it.
//! 2. **Arcs around vertices.** Where the real path reaches a vertex `v` and continues (straight
//!    or turning) in a direction outside its current triangle's corner at `v`, the perturbed path
//!    follows a tiny arc around `v` through free space to the nearest triangle of `v`'s fan whose
//!    closed corner contains the outgoing direction. Every vertex of a BTM is a map vertex, so its
//!    free triangles form one fan from one map edge to the other, and the arc is unique: it
//!    rotates away from the obstacle (or the outside), never across it.
//! 3. **Canonical endpoints.** An endpoint strictly inside a triangle starts (ends) there. An
//!    endpoint on the interior of a diagonal belongs to the triangle of the diagonal's half-edge
//!    with the smaller id; an endpoint at a vertex belongs to the first triangle of its fan (the
//!    one on the map edge leaving the vertex with free space on its left, see
//!    `Dcel::edges_around_vertex`). The perturbed path starts with a tiny move from that
//!    triangle in the path's first direction, and ends with a tiny move into it (rules 1-2).
//!
//! Each rule moves the path by less than any epsilon through free space, so `pi_eps` is homotopic
//! to `pi` with endpoints fixed up to these canonical moves; rule 3 makes the start and end
//! triangles depend on the endpoints alone, so homotopic paths get equal reduced sequences.
//! Every decision (which side, through an edge or a vertex, inside a corner) is an exact
//! orientation sign or an exact coordinate comparison.

use crate::geom::{InTriangle, ahead, classify, cone_contains, in_closed_triangle};
use crate::path::{Blocker, Path, PathError};
use nalgebra::Point2;
use rappel_geometry::btm::{Btm, Location};
use rappel_geometry::dcel::{Dcel, EdgeKind, HalfEdgeId, TriangleId, VertexId};
use rappel_geometry::predicates::orient2d;
use serde::{Deserialize, Serialize};

/// The crossing sequence `chi(pi)` of a path (thesis §2.2.3): the start triangle, the directed
/// crossings (half-edges of the triangles left) and the end triangle. Compare sequences only
/// within one BTM.
///
/// ```
/// use nalgebra::Point2;
/// use rappel_geometry::{btm::Btm, map::Map, polygon::Polygon};
/// use rappel_homotopy::{crossing::CrossingSequence, path::Path};
/// let p = |x, y| Point2::new(x, y);
/// let map = Map::new(
///     Polygon::new(vec![p(0., 0.), p(10., 0.), p(10., 10.), p(0., 10.)]),
///     vec![Polygon::new(vec![p(4., 4.), p(6., 4.), p(6., 6.), p(4., 6.)])],
/// );
/// let btm = Btm::from_map(&map).unwrap();
/// // A loop beside the obstacle: it crosses diagonals, but reduces to nothing.
/// let there_and_back = Path::new(vec![p(7., 1.), p(9., 1.), p(9., 9.), p(7., 9.), p(7., 1.)]).unwrap();
/// let chi = CrossingSequence::of_path(&btm, &there_and_back).unwrap();
/// assert!(!chi.is_empty());
/// assert!(chi.reduced(&btm).is_empty());
/// ```
#[derive(Debug, Clone, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct CrossingSequence {
    start: TriangleId,
    end: TriangleId,
    crossings: Vec<HalfEdgeId>,
}

// `Path::validate` lives here, beside the walk it runs, so that `path` (below this module)
// imports nothing from it.
impl Path {
    /// Checks that the path stays in the closed free space of `btm`.
    ///
    /// ```
    /// use nalgebra::Point2;
    /// use rappel_geometry::{btm::Btm, map::Map, polygon::Polygon};
    /// use rappel_homotopy::path::{Path, PathError};
    /// let p = |x, y| Point2::new(x, y);
    /// let map = Map::new(
    ///     Polygon::new(vec![p(0., 0.), p(10., 0.), p(10., 10.), p(0., 10.)]),
    ///     vec![Polygon::new(vec![p(4., 4.), p(6., 4.), p(6., 6.), p(4., 6.)])],
    /// );
    /// let btm = Btm::from_map(&map).unwrap();
    /// assert!(Path::new(vec![p(1., 1.), p(9., 1.), p(9., 9.)]).unwrap().validate(&btm).is_ok());
    /// // Along the obstacle's bottom edge: touching is allowed.
    /// assert!(Path::new(vec![p(1., 4.), p(9., 4.)]).unwrap().validate(&btm).is_ok());
    /// let through = Path::new(vec![p(1., 5.), p(9., 5.)]).unwrap();
    /// assert!(matches!(through.validate(&btm), Err(PathError::LeavesFreeSpace { segment: 0, .. })));
    /// ```
    pub fn validate(&self, btm: &Btm) -> Result<(), PathError> {
        CrossingSequence::of_path(btm, self).map(|_| ())
    }
}

impl CrossingSequence {
    /// The raw crossing sequence of a path (validated against free space on the way).
    pub fn of_path(btm: &Btm, path: &Path) -> Result<CrossingSequence, PathError> {
        let mut tracer = Tracer::new(btm, path.start())?;
        for q in &path.points()[1..] {
            tracer.push(*q)?;
        }
        Ok(tracer.finish())
    }

    /// The reduced crossing sequence `chi-bar(pi)` of a path: the canonical word of its homotopy
    /// class (with its endpoints).
    pub fn reduced_of_path(btm: &Btm, path: &Path) -> Result<CrossingSequence, PathError> {
        Ok(Self::of_path(btm, path)?.reduced(btm))
    }

    /// A sequence from its parts, unchecked (for sequences built by a search;
    /// [`crate::sleeve::Sleeve::from_crossing_sequence`] checks it is a chain).
    pub fn from_parts(
        start: TriangleId,
        end: TriangleId,
        crossings: Vec<HalfEdgeId>,
    ) -> CrossingSequence {
        CrossingSequence {
            start,
            end,
            crossings,
        }
    }

    /// The triangle the (perturbed) path starts in.
    pub fn start_triangle(&self) -> TriangleId {
        self.start
    }

    /// The triangle the (perturbed) path ends in.
    pub fn end_triangle(&self) -> TriangleId {
        self.end
    }

    /// The directed crossings, in path order.
    pub fn crossings(&self) -> &[HalfEdgeId] {
        &self.crossings
    }

    /// Number of crossings.
    pub fn len(&self) -> usize {
        self.crossings.len()
    }

    /// `true` when the path crosses no diagonal.
    pub fn is_empty(&self) -> bool {
        self.crossings.is_empty()
    }

    /// The reduced sequence: every crossing immediately followed by its reverse is cancelled,
    /// repeatedly (one stack pass, linear time).
    pub fn reduced(&self, btm: &Btm) -> CrossingSequence {
        let d = btm.dcel();
        let mut stack: Vec<HalfEdgeId> = Vec::with_capacity(self.crossings.len());
        for &h in &self.crossings {
            if stack.last().is_some_and(|&top| cancels(d, top, h)) {
                stack.pop();
            } else {
                stack.push(h);
            }
        }
        CrossingSequence {
            start: self.start,
            end: self.end,
            crossings: stack,
        }
    }

    /// `true` when no crossing is immediately followed by its reverse.
    pub fn is_reduced(&self, btm: &Btm) -> bool {
        let d = btm.dcel();
        self.crossings.windows(2).all(|w| !cancels(d, w[0], w[1]))
    }

    /// The crossings, handed over (for the reductions built on this one).
    pub(crate) fn into_crossings(self) -> Vec<HalfEdgeId> {
        self.crossings
    }

    /// The sequence of the reversed path: crossings reversed and each replaced by its twin.
    /// Crossings must be diagonals of `btm` (they are, for sequences computed from paths).
    pub fn reversed(&self, btm: &Btm) -> CrossingSequence {
        let d = btm.dcel();
        CrossingSequence {
            start: self.end,
            end: self.start,
            crossings: self
                .crossings
                .iter()
                .rev()
                .map(|&h| d.twin(h).unwrap_or(h))
                .collect(),
        }
    }

    /// The triangles visited, in order: the start triangle and the triangle entered at each
    /// crossing.
    pub fn triangles<'a>(&'a self, btm: &'a Btm) -> impl Iterator<Item = TriangleId> + 'a {
        let d = btm.dcel();
        std::iter::once(self.start).chain(
            self.crossings
                .iter()
                .map(move |&h| d.twin(h).map_or(h.triangle(), |g| g.triangle())),
        )
    }
}

/// `true` when crossing `then` right after `first` cancels it: `then` crosses the same diagonal
/// back (the reduction's rule).
pub(crate) fn cancels(d: &Dcel, first: HalfEdgeId, then: HalfEdgeId) -> bool {
    d.twin(first) == Some(then)
}

/// Where the tracer's current point sits in its current triangle.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Pos {
    /// Strictly inside.
    Interior,
    /// On the interior of this half-edge of the triangle.
    Edge(HalfEdgeId),
    /// On this corner.
    Vertex(VertexId),
    /// Just entered the triangle transversally through an edge's interior (mid-segment, at a
    /// point that is not representable and not needed).
    Crossed,
}

impl From<InTriangle> for Pos {
    fn from(c: InTriangle) -> Pos {
        match c {
            InTriangle::Edge(h) => Pos::Edge(h),
            InTriangle::Vertex(v) => Pos::Vertex(v),
            InTriangle::Interior | InTriangle::Outside => Pos::Interior,
        }
    }
}

/// How a segment failed to stay in free space (converted to a [`PathError`] by the tracer).
enum Leave {
    Edge(HalfEdgeId),
    Vertex(VertexId),
    Internal(&'static str),
}

/// Walks a path through a BTM one segment at a time, recording its crossing sequence under the
/// module's perturbation rules and checking that it stays in free space. A failed
/// [`Tracer::push`] leaves the tracer unchanged, so random walks can try a step and retry.
///
/// ```
/// use nalgebra::Point2;
/// use rappel_geometry::{btm::Btm, map::Map, polygon::Polygon};
/// use rappel_homotopy::crossing::Tracer;
/// let p = |x, y| Point2::new(x, y);
/// let map = Map::new(
///     Polygon::new(vec![p(0., 0.), p(10., 0.), p(10., 10.), p(0., 10.)]),
///     vec![Polygon::new(vec![p(4., 4.), p(6., 4.), p(6., 6.), p(4., 6.)])],
/// );
/// let btm = Btm::from_map(&map).unwrap();
/// let mut tracer = Tracer::new(&btm, p(1., 5.)).unwrap();
/// assert!(tracer.push(p(9., 5.)).is_err()); // through the obstacle: refused, nothing changes
/// tracer.push(p(1., 9.)).unwrap();
/// tracer.push(p(9., 9.)).unwrap();
/// assert_eq!(tracer.point(), p(9., 9.));
/// let chi = tracer.finish();
/// assert!(!chi.is_empty());
/// ```
#[derive(Debug, Clone)]
pub struct Tracer<'a> {
    btm: &'a Btm,
    start: TriangleId,
    tri: TriangleId,
    pos: Pos,
    point: Point2<f64>,
    segments: usize,
    crossings: Vec<HalfEdgeId>,
    fan: Vec<HalfEdgeId>,
}

impl<'a> Tracer<'a> {
    /// A tracer at `start`, which must lie in the closed free space.
    pub fn new(btm: &'a Btm, start: Point2<f64>) -> Result<Tracer<'a>, PathError> {
        if !crate::geom::is_finite(&start) {
            return Err(PathError::NonFinite {
                index: 0,
                point: start,
            });
        }
        let d = btm.dcel();
        let (tri, pos) = match btm.locate(&start) {
            Location::Triangle(t) => (t, Pos::Interior),
            // `locate` reports the half-edge with the smaller id when both sides are free: the
            // canonical triangle of rule 3.
            Location::Edge(h) => (h.triangle(), Pos::Edge(h)),
            Location::Vertex(v) => match d.edges_around_vertex(v).next() {
                Some(h) => (h.triangle(), Pos::Vertex(v)),
                None => {
                    return Err(PathError::PointNotFree {
                        index: 0,
                        point: start,
                        blocker: Blocker::Boundary,
                    });
                }
            },
            Location::Obstacle(o) => {
                return Err(PathError::PointNotFree {
                    index: 0,
                    point: start,
                    blocker: Blocker::Obstacle(o),
                });
            }
            Location::Outside => {
                return Err(PathError::PointNotFree {
                    index: 0,
                    point: start,
                    blocker: Blocker::Boundary,
                });
            }
        };
        Ok(Tracer {
            btm,
            start: tri,
            tri,
            pos,
            point: start,
            segments: 0,
            crossings: Vec::new(),
            fan: Vec::new(),
        })
    }

    /// The current point (the last point pushed).
    pub fn point(&self) -> Point2<f64> {
        self.point
    }

    /// The triangle the perturbed path is in now.
    pub fn triangle(&self) -> TriangleId {
        self.tri
    }

    /// Number of segments walked so far.
    pub fn segment_count(&self) -> usize {
        self.segments
    }

    /// The raw crossings so far.
    pub fn crossings(&self) -> &[HalfEdgeId] {
        &self.crossings
    }

    /// Hands over the raw crossings recorded so far and forgets them; the walk goes on from the
    /// same point and triangle, so the crossings of later pushes (and of [`Tracer::finish`])
    /// are the sequence's continuation ([`crate::homotopy::LoopPrefix`]).
    pub(crate) fn take_crossings(&mut self) -> Vec<HalfEdgeId> {
        // The fan is scratch: emptied so that a clone of the tracer allocates nothing.
        self.fan.clear();
        std::mem::take(&mut self.crossings)
    }

    /// Walks the segment from the current point to `q`. On error (the segment leaves free space,
    /// or `q` is not finite) nothing changes.
    pub fn push(&mut self, q: Point2<f64>) -> Result<(), PathError> {
        let segment = self.segments;
        if !crate::geom::is_finite(&q) {
            return Err(PathError::NonFinite {
                index: segment + 1,
                point: q,
            });
        }
        let mark = self.crossings.len();
        match self.walk(&q) {
            Ok((t, pos)) => {
                self.tri = t;
                self.pos = pos;
                self.point = q;
                self.segments += 1;
                Ok(())
            }
            Err(leave) => {
                self.crossings.truncate(mark);
                Err(self.error(segment, q, leave))
            }
        }
    }

    /// Ends the path: moves the perturbed path into the canonical triangle of the last point
    /// (rule 3) and returns the raw crossing sequence.
    pub fn finish(mut self) -> CrossingSequence {
        let d = self.btm.dcel();
        match self.pos {
            Pos::Edge(h) => {
                if let Some(g) = d.twin(h)
                    && g < h
                {
                    self.crossings.push(h);
                    self.tri = g.triangle();
                }
            }
            Pos::Vertex(v) => {
                self.fill_fan(v);
                if let Some(k) = self.fan.iter().position(|h| h.triangle() == self.tri) {
                    // Clockwise down to the first triangle of the fan.
                    self.crossings.extend(self.fan[1..=k].iter().rev());
                    self.tri = self.fan[0].triangle();
                }
            }
            Pos::Interior | Pos::Crossed => {}
        }
        CrossingSequence {
            start: self.start,
            end: self.tri,
            crossings: self.crossings,
        }
    }

    fn fill_fan(&mut self, v: VertexId) {
        self.fan.clear();
        self.fan.extend(self.btm.dcel().edges_around_vertex(v));
    }

    /// Walks the current point to `q`, appending crossings; returns the new triangle and position.
    fn walk(&mut self, q: &Point2<f64>) -> Result<(TriangleId, Pos), Leave> {
        let p = self.point;
        let (mut t, mut pos) = (self.tri, self.pos);
        if *q == p {
            return Ok((t, pos));
        }
        // Each pass moves forward along the segment by at least one edge or vertex; the bound
        // only guards against a corrupted structure.
        let limit = 4 * self.btm.dcel().triangle_capacity() + 16;
        // The half-edge through which the walk has just entered `t` transversally, if it has.
        let mut entered: Option<HalfEdgeId> = None;
        for _ in 0..limit {
            // 0. The straight walk's usual step, after a transversal crossing of edge `g = a b`:
            // `a` is strictly left of the directed line `p q` and `b` strictly right, and `q` is
            // strictly beyond `g` (the segment left the previous, closed triangle through it), so
            // only the two other edges and the third corner `c` need testing. It decides exactly
            // what steps 2-3 below decide, with three orientation tests instead of six.
            if let (Pos::Crossed, Some(g)) = (pos, entered.take()) {
                let d = self.btm.dcel();
                let (a, b) = (d.origin(g), d.destination(g));
                let c = d.origin(d.prev(g));
                let (pa, pb, pc) = (d.point(a), d.point(b), d.point(c));
                if orient2d(&pb, &pc, q) >= 0.0 && orient2d(&pc, &pa, q) >= 0.0 {
                    return Ok((t, classify(d, t, q).into()));
                }
                let sc = orient2d(&p, q, &pc);
                let exit = if sc > 0.0 {
                    d.next(g)
                } else if sc < 0.0 {
                    d.prev(g)
                } else {
                    pos = Pos::Vertex(c);
                    continue;
                };
                let g2 = d.twin(exit).ok_or(Leave::Edge(exit))?;
                self.crossings.push(exit);
                t = g2.triangle();
                entered = Some(g2);
                continue;
            }
            // 1. Turn into the closed triangle that the segment enters (rules 1 and 2).
            match pos {
                Pos::Edge(h) => {
                    let d = self.btm.dcel();
                    let (a, b) = (d.point(d.origin(h)), d.point(d.destination(h)));
                    if orient2d(&a, &b, q) < 0.0 {
                        let g = d.twin(h).ok_or(Leave::Edge(h))?;
                        self.crossings.push(h);
                        t = g.triangle();
                        pos = Pos::Edge(g);
                    }
                }
                Pos::Vertex(v) => {
                    let h =
                        out_edge(self.btm.dcel(), t, v).ok_or(Leave::Internal("lost corner"))?;
                    if !cone_contains(self.btm.dcel(), h, q) {
                        t = self.rotate(t, v, q)?;
                    }
                }
                Pos::Interior | Pos::Crossed => {}
            }
            let d = self.btm.dcel();
            // 2. The segment ends in this closed triangle.
            if in_closed_triangle(d, t, q) {
                return Ok((t, classify(d, t, q).into()));
            }
            // 3. It leaves through an edge's interior or through a vertex ahead.
            let hs = t.half_edges();
            let vs = hs.map(|h| d.origin(h));
            let s = vs.map(|v| orient2d(&p, q, &d.point(v)));
            if let Some(i) = (0..3).find(|&i| s[i] < 0.0 && s[(i + 1) % 3] > 0.0) {
                let g = d.twin(hs[i]).ok_or(Leave::Edge(hs[i]))?;
                self.crossings.push(hs[i]);
                t = g.triangle();
                pos = Pos::Crossed;
                entered = Some(g);
                continue;
            }
            let current = match pos {
                Pos::Vertex(w) => Some(w),
                _ => None,
            };
            let next = (0..3)
                .find(|&i| s[i] == 0.0 && Some(vs[i]) != current && ahead(&p, q, &d.point(vs[i])));
            match next {
                Some(i) => pos = Pos::Vertex(vs[i]),
                None => return Err(Leave::Internal("segment has no exit from its triangle")),
            }
        }
        Err(Leave::Internal("walk did not terminate"))
    }

    /// Rule 2: rotates around `v` from triangle `t` to the nearest fan triangle whose closed corner
    /// contains the direction towards `q`, recording the diagonals crossed.
    fn rotate(&mut self, t: TriangleId, v: VertexId, q: &Point2<f64>) -> Result<TriangleId, Leave> {
        self.fill_fan(v);
        let d = self.btm.dcel();
        let fan = &self.fan;
        let k = fan
            .iter()
            .position(|h| h.triangle() == t)
            .ok_or(Leave::Internal("triangle not in its vertex's fan"))?;
        let target = (1..fan.len()).find_map(|dist| {
            [k.checked_add(dist), k.checked_sub(dist)]
                .into_iter()
                .flatten()
                .find(|&j| j < fan.len() && cone_contains(d, fan[j], q))
        });
        let j = target.ok_or(Leave::Vertex(v))?;
        if j > k {
            // Counter-clockwise: leave each triangle through its edge entering `v`.
            self.crossings.extend(fan[k..j].iter().map(|h| h.prev()));
        } else {
            // Clockwise: leave each triangle through its edge leaving `v`.
            self.crossings.extend(fan[j + 1..=k].iter().rev());
        }
        Ok(fan[j].triangle())
    }

    fn error(&self, segment: usize, to: Point2<f64>, leave: Leave) -> PathError {
        let d = self.btm.dcel();
        let from = self.point;
        match leave {
            Leave::Edge(h) => {
                let blocker = match d.edge_kind(h) {
                    EdgeKind::Obstacle(o) => Blocker::Obstacle(o),
                    _ => Blocker::Boundary,
                };
                let (a, b) = (d.point(d.origin(h)), d.point(d.destination(h)));
                PathError::LeavesFreeSpace {
                    segment,
                    from,
                    to,
                    near: approximate_intersection(&from, &to, &a, &b),
                    blocker,
                }
            }
            Leave::Vertex(v) => PathError::LeavesFreeSpace {
                segment,
                from,
                to,
                near: d.point(v),
                blocker: self
                    .btm
                    .obstacle_of_vertex(v)
                    .map_or(Blocker::Boundary, Blocker::Obstacle),
            },
            Leave::Internal(message) => PathError::Internal {
                segment,
                message: message.to_string(),
            },
        }
    }
}

/// The half-edge of triangle `t` leaving its corner `v`.
fn out_edge(d: &Dcel, t: TriangleId, v: VertexId) -> Option<HalfEdgeId> {
    t.half_edges().into_iter().find(|&h| d.origin(h) == v)
}

/// Where the lines `pq` and `ab` meet, in floating point: for error messages only, never for a
/// decision.
fn approximate_intersection(
    p: &Point2<f64>,
    q: &Point2<f64>,
    a: &Point2<f64>,
    b: &Point2<f64>,
) -> Point2<f64> {
    let (r, s) = (q - p, b - a);
    let den = r.x * s.y - r.y * s.x;
    if den == 0.0 {
        return *p;
    }
    let u = ((a.x - p.x) * s.y - (a.y - p.y) * s.x) / den;
    p + r * u.clamp(0.0, 1.0)
}
