//! The planning map (thesis §2.1.2, Fig. 2.7): an outer boundary polygon and obstacle polygons
//! (holes) in the planar, unfolded frame of a tether-demand plane, and its validation. A valid map
//! is exactly what a boundary-triangulated 2-manifold can be built from: simple rings of positive
//! area, every obstacle strictly inside the boundary, no two obstacles sharing a point.
//!
//! Validation is exact (it uses [`crate::predicates`]) and reports the first defect it finds as a
//! [`MapError`] that names the ring and the coordinates involved. Overlapping obstacles, the normal
//! output of obstacle detection, are merged by [`crate::normalize`] rather than refused.

use crate::compact::Compact;
use crate::domain::{DOMAIN_TEXT, in_domain};
use crate::polygon::{Aabb, PointInPolygon, Polygon};
use crate::predicates::{SegmentContact, orient2d, segment_contact};
use crate::spatial_grid::SpatialGrid;
use nalgebra::Point2;
use serde::{Deserialize, Serialize};
use std::fmt;

/// A map: the outer boundary and the obstacles inside it.
///
/// ```
/// use nalgebra::Point2;
/// use rappel_geometry::map::Map;
/// use rappel_geometry::polygon::Polygon;
/// let p = |x, y| Point2::new(x, y);
/// let map = Map::new(
///     Polygon::new(vec![p(0., 0.), p(10., 0.), p(10., 10.), p(0., 10.)]),
///     vec![Polygon::new(vec![p(4., 4.), p(6., 4.), p(5., 6.)])],
/// );
/// map.validate().unwrap();
/// assert_eq!(map.free_area(), 98.0);
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Map {
    /// The outer boundary of the planning region.
    pub boundary: Polygon,
    /// Tether obstacles: holes in the free space.
    #[serde(default)]
    pub obstacles: Vec<Polygon>,
}

/// A map that passed [`Map::validate`]: the proof that every condition for building a BTM holds,
/// so that whoever holds one (e.g. [`crate::btm::Btm::build`]) need not validate again. Only
/// [`Map::validate`] makes one (the field is private), and it borrows the map, which therefore
/// cannot change while the proof lives.
///
/// ```
/// use nalgebra::Point2;
/// use rappel_geometry::map::Map;
/// use rappel_geometry::polygon::Polygon;
/// let p = |x, y| Point2::new(x, y);
/// let map = Map::new(
///     Polygon::new(vec![p(0., 0.), p(10., 0.), p(10., 10.), p(0., 10.)]),
///     vec![Polygon::new(vec![p(4., 4.), p(6., 4.), p(5., 6.)])],
/// );
/// let valid = map.validate().unwrap();
/// assert_eq!(valid.map().obstacles.len(), 1);
/// assert_eq!(valid.vertex_count(), 7); // it dereferences to the map
/// // A map with a defect gives no proof.
/// let bad = Map::new(map.boundary.clone(), vec![Polygon::new(vec![p(4., 4.), p(6., 6.), p(6., 4.), p(4., 6.)])]);
/// assert!(bad.validate().is_err());
/// ```
///
/// Nothing outside validation can make one (the field is private):
///
/// ```compile_fail
/// use rappel_geometry::map::{Map, ValidMap};
/// use rappel_geometry::polygon::Polygon;
/// let map = Map::new(Polygon::new(vec![]), vec![]);
/// let forged = ValidMap { map: &map };
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ValidMap<'a> {
    map: &'a Map,
}

impl<'a> ValidMap<'a> {
    /// The validated map.
    pub fn map(self) -> &'a Map {
        self.map
    }
}

impl std::ops::Deref for ValidMap<'_> {
    type Target = Map;

    fn deref(&self) -> &Map {
        self.map
    }
}

/// A contact found by [`Map::edge_contacts`]: the key `(ring, edge, ring, edge)` (rings numbered
/// boundary first) and the defect it is.
pub(crate) type EdgeContact = ((u32, u32, u32, u32), MapError);

/// Which ring of a map something refers to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum RingId {
    /// The outer boundary.
    Boundary,
    /// Obstacle number `i` (0-based, in map order).
    Obstacle(usize),
}

impl fmt::Display for RingId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RingId::Boundary => write!(f, "the boundary"),
            RingId::Obstacle(i) => write!(f, "obstacle {i}"),
        }
    }
}

/// Formats a point as `(x, y)` for error messages.
pub(crate) struct At(pub Point2<f64>);

impl fmt::Display for At {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "({}, {})", Compact(self.0.x), Compact(self.0.y))
    }
}

/// Why a point is not in free space.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FreeSpaceViolation {
    /// Outside the outer boundary.
    OutsideBoundary,
    /// On the outer boundary.
    OnBoundary,
    /// Inside obstacle `i`.
    InsideObstacle(usize),
    /// On the boundary of obstacle `i`.
    OnObstacle(usize),
}

impl fmt::Display for FreeSpaceViolation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FreeSpaceViolation::OutsideBoundary => write!(f, "outside the map boundary"),
            FreeSpaceViolation::OnBoundary => write!(f, "on the map boundary"),
            FreeSpaceViolation::InsideObstacle(i) => write!(f, "inside obstacle {i}"),
            FreeSpaceViolation::OnObstacle(i) => write!(f, "on the edge of obstacle {i}"),
        }
    }
}

/// A defect that makes a map unusable for triangulation. Each names the ring and where; the doc of
/// each variant says how to fix the input.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MapError {
    /// A coordinate is NaN or infinite. Fix: replace the vertex.
    #[error("{ring} vertex {vertex} has a non-finite coordinate ({}, {})", Compact(*.x), Compact(*.y))]
    NonFinite {
        /// The ring.
        ring: RingId,
        /// The vertex index in the ring.
        vertex: usize,
        /// Its x coordinate as given.
        x: f64,
        /// Its y coordinate as given.
        y: f64,
    },
    /// A coordinate lies outside the supported domain ([`crate::domain`]). Fix: express the map
    /// in a unit that brings it into the domain, or correct the vertex.
    #[error("{ring} vertex {vertex} at {} is outside the coordinate domain: {DOMAIN_TEXT}", At(*.at))]
    OutOfDomain {
        /// The ring.
        ring: RingId,
        /// The vertex index in the ring.
        vertex: usize,
        /// The vertex.
        at: Point2<f64>,
    },
    /// The polygon-overlay dependency refused its input (see [`crate::overlay`]).
    #[error(transparent)]
    Overlay(#[from] crate::overlay::OverlayError),
    /// A named point (start, goal) lies outside the supported domain ([`crate::domain`]).
    #[error("the {what} point {} is outside the coordinate domain: {DOMAIN_TEXT}", At(*.at))]
    PointOutOfDomain {
        /// `"start"`, `"goal"`, ...
        what: &'static str,
        /// The point.
        at: Point2<f64>,
    },
    /// Fewer than three distinct vertices. Fix: drop the ring or give it a real shape.
    #[error("{ring} has {distinct} distinct vertices; a polygon needs at least 3 (first vertex at {})", At(*.at))]
    TooFewVertices {
        /// The ring.
        ring: RingId,
        /// How many distinct vertices it has.
        distinct: usize,
        /// Its first vertex, to find it.
        at: Point2<f64>,
    },
    /// The same vertex twice in a row. Fix: remove the repeat (normalisation does).
    #[error("{ring} repeats vertex {vertex} at {}", At(*.at))]
    RepeatedVertex {
        /// The ring.
        ring: RingId,
        /// Index of the repeat.
        vertex: usize,
        /// The repeated point.
        at: Point2<f64>,
    },
    /// All vertices on one line. Fix: drop the ring.
    #[error("{ring} has zero area: all its vertices lie on one line (first vertex at {})", At(*.at))]
    ZeroArea {
        /// The ring.
        ring: RingId,
        /// Its first vertex.
        at: Point2<f64>,
    },
    /// Two edges of one ring cross or touch. Fix: redraw the ring as a simple polygon, or take its
    /// convex hull (normalisation can).
    #[error("{ring} intersects itself: edges {first_edge} and {second_edge} meet near {}", At(*.at))]
    SelfIntersecting {
        /// The ring.
        ring: RingId,
        /// The first edge (edge `i` runs from vertex `i` to vertex `i + 1`).
        first_edge: usize,
        /// The second edge.
        second_edge: usize,
        /// A point of the contact.
        at: Point2<f64>,
    },
    /// An obstacle lies entirely outside the boundary. Fix: drop it (normalisation does).
    #[error("obstacle {obstacle} lies outside the boundary (vertex at {})", At(*.at))]
    ObstacleOutsideBoundary {
        /// The obstacle.
        obstacle: usize,
        /// One of its vertices.
        at: Point2<f64>,
    },
    /// An obstacle crosses or touches the boundary. Fix: move the boundary inwards or clip the
    /// obstacle; the tether cannot pass between an obstacle and the boundary it touches anyway.
    #[error("obstacle {obstacle} crosses or touches the boundary near {}", At(*.at))]
    ObstacleCrossesBoundary {
        /// The obstacle.
        obstacle: usize,
        /// A point of the contact.
        at: Point2<f64>,
    },
    /// Two obstacles overlap (crossing edges or one inside the other). Fix: merge them with
    /// [`crate::normalize::normalize`].
    #[error("obstacles {first} and {second} overlap near {}", At(*.at))]
    ObstaclesOverlap {
        /// The lower-numbered obstacle.
        first: usize,
        /// The other obstacle.
        second: usize,
        /// A point of the overlap.
        at: Point2<f64>,
    },
    /// Two obstacles share a point without overlapping. Fix: merge them with
    /// [`crate::normalize::normalize`] (a tether cannot pass between them).
    #[error("obstacles {first} and {second} touch at {}", At(*.at))]
    ObstaclesTouch {
        /// The lower-numbered obstacle.
        first: usize,
        /// The other obstacle.
        second: usize,
        /// The contact point.
        at: Point2<f64>,
    },
    /// A named point (start, goal, ...) is not in free space. Fix: move it.
    #[error("the {what} point {} is {violation}", At(*.at))]
    PointNotFree {
        /// What the point is, e.g. `start` or `goal`.
        what: &'static str,
        /// The point.
        at: Point2<f64>,
        /// Why it is not free.
        violation: FreeSpaceViolation,
    },
}

impl MapError {
    /// The same single-ring defect attributed to `ring` (for a ring validated on its own, e.g. an
    /// obstacle checked as if it were a boundary); defects between rings are returned unchanged.
    pub fn for_ring(self, ring: RingId) -> MapError {
        match self {
            MapError::NonFinite { vertex, x, y, .. } => MapError::NonFinite { ring, vertex, x, y },
            MapError::TooFewVertices { distinct, at, .. } => {
                MapError::TooFewVertices { ring, distinct, at }
            }
            MapError::RepeatedVertex { vertex, at, .. } => {
                MapError::RepeatedVertex { ring, vertex, at }
            }
            MapError::ZeroArea { at, .. } => MapError::ZeroArea { ring, at },
            MapError::SelfIntersecting {
                first_edge,
                second_edge,
                at,
                ..
            } => MapError::SelfIntersecting {
                ring,
                first_edge,
                second_edge,
                at,
            },
            other => other,
        }
    }
}

impl Map {
    /// A map from its boundary and obstacles (not validated).
    pub fn new(boundary: Polygon, obstacles: Vec<Polygon>) -> Self {
        Map {
            boundary,
            obstacles,
        }
    }

    /// A map holding `obstacles` inside a square-cornered frame padded by their extent (at least
    /// 1 m) on every side: for working on a set of polygons (merging, checking they are apart)
    /// without a real boundary.
    ///
    /// ```
    /// use nalgebra::Point2;
    /// use rappel_geometry::{map::Map, polygon::Polygon};
    /// let tri = Polygon::new(vec![Point2::new(0., 0.), Point2::new(2., 0.), Point2::new(1., 1.)]);
    /// Map::framing(vec![tri]).validate().unwrap();
    /// ```
    pub fn framing(obstacles: Vec<Polygon>) -> Map {
        let b = if obstacles.is_empty() {
            Aabb {
                min: Point2::origin(),
                max: Point2::new(1.0, 1.0),
            }
        } else {
            Aabb::of_points(obstacles.iter().flat_map(|p| p.vertices.iter()))
        };
        let (w, h) = b.size();
        let pad = w.max(h).max(1.0);
        let frame = Polygon::new(vec![
            Point2::new(b.min.x - pad, b.min.y - pad),
            Point2::new(b.max.x + pad, b.min.y - pad),
            Point2::new(b.max.x + pad, b.max.y + pad),
            Point2::new(b.min.x - pad, b.max.y + pad),
        ]);
        Map::new(frame, obstacles)
    }

    /// The ring with the given id (`None` for an obstacle index out of range).
    pub fn ring(&self, id: RingId) -> Option<&Polygon> {
        match id {
            RingId::Boundary => Some(&self.boundary),
            RingId::Obstacle(i) => self.obstacles.get(i),
        }
    }

    /// All rings with their ids, boundary first.
    pub fn rings(&self) -> impl Iterator<Item = (RingId, &Polygon)> + '_ {
        std::iter::once((RingId::Boundary, &self.boundary)).chain(
            self.obstacles
                .iter()
                .enumerate()
                .map(|(i, o)| (RingId::Obstacle(i), o)),
        )
    }

    /// Total number of vertices over all rings.
    pub fn vertex_count(&self) -> usize {
        self.rings().map(|(_, r)| r.len()).sum()
    }

    /// Area of the free space: the boundary's area minus the obstacles' (valid maps only).
    pub fn free_area(&self) -> f64 {
        self.boundary.area() - self.obstacles.iter().map(Polygon::area).sum::<f64>()
    }

    /// The boundary's bounding box.
    pub fn aabb(&self) -> Aabb {
        self.boundary.aabb()
    }

    /// Checks every condition for building a BTM; returns the first defect found, or the map's
    /// [`ValidMap`] proof, which [`crate::btm::Btm::build`] takes so that it need not check
    /// again. Every coordinate must lie in the domain of [`crate::domain`] (checked first,
    /// before any predicate could overflow).
    pub fn validate(&self) -> Result<ValidMap<'_>, MapError> {
        for (id, ring) in self.rings() {
            for (vertex, p) in ring.vertices.iter().enumerate() {
                if p.x.is_finite() && p.y.is_finite() && !(in_domain(p.x) && in_domain(p.y)) {
                    return Err(MapError::OutOfDomain {
                        ring: id,
                        vertex,
                        at: *p,
                    });
                }
            }
        }
        for (id, ring) in self.rings() {
            validate_ring_alone(id, ring)?;
        }
        self.check_edge_contacts()?;
        self.check_containment()?;
        Ok(ValidMap { map: self })
    }

    /// Where `p` lies with respect to free space (the map must be valid).
    ///
    /// ```
    /// use nalgebra::Point2;
    /// use rappel_geometry::map::{Map, FreeSpaceViolation};
    /// use rappel_geometry::polygon::Polygon;
    /// let p = |x, y| Point2::new(x, y);
    /// let map = Map::new(
    ///     Polygon::new(vec![p(0., 0.), p(10., 0.), p(10., 10.), p(0., 10.)]),
    ///     vec![Polygon::new(vec![p(4., 4.), p(6., 4.), p(5., 6.)])],
    /// );
    /// assert_eq!(map.free_space_violation(&p(1., 1.)), None);
    /// assert_eq!(map.free_space_violation(&p(5., 5.)), Some(FreeSpaceViolation::InsideObstacle(0)));
    /// ```
    pub fn free_space_violation(&self, p: &Point2<f64>) -> Option<FreeSpaceViolation> {
        match self.boundary.locate(p) {
            PointInPolygon::Outside => return Some(FreeSpaceViolation::OutsideBoundary),
            PointInPolygon::OnBoundary => return Some(FreeSpaceViolation::OnBoundary),
            PointInPolygon::Inside => {}
        }
        for (i, o) in self.obstacles.iter().enumerate() {
            if !o.aabb().contains(p) {
                continue;
            }
            match o.locate(p) {
                PointInPolygon::Inside => return Some(FreeSpaceViolation::InsideObstacle(i)),
                PointInPolygon::OnBoundary => return Some(FreeSpaceViolation::OnObstacle(i)),
                PointInPolygon::Outside => {}
            }
        }
        None
    }

    /// Checks that the point called `what` (e.g. `"start"`) lies in free space.
    pub fn validate_point(&self, what: &'static str, p: &Point2<f64>) -> Result<(), MapError> {
        if p.x.is_finite() && p.y.is_finite() && !(in_domain(p.x) && in_domain(p.y)) {
            return Err(MapError::PointOutOfDomain { what, at: *p });
        }
        if !(p.x.is_finite() && p.y.is_finite()) {
            return Err(MapError::PointNotFree {
                what,
                at: *p,
                violation: FreeSpaceViolation::OutsideBoundary,
            });
        }
        match self.free_space_violation(p) {
            None => Ok(()),
            Some(violation) => Err(MapError::PointNotFree {
                what,
                at: *p,
                violation,
            }),
        }
    }

    /// Every pair of edges (within a ring or across rings) that meet where they must not, as
    /// errors keyed by `(ring, edge, ring, edge)` with rings numbered boundary first, sorted.
    pub(crate) fn edge_contacts(&self) -> Vec<EdgeContact> {
        self.edge_contacts_by(ContactForm::Auto)
    }

    /// [`Map::edge_contacts`] in the form `form` picks (both find the same contacts).
    fn edge_contacts_by(&self, form: ContactForm) -> Vec<EdgeContact> {
        // Segment table: (ring, edge index). Ring 0 is the boundary, ring k + 1 obstacle k.
        let rings: Vec<&Polygon> = std::iter::once(&self.boundary)
            .chain(&self.obstacles)
            .collect();
        let mut bounds = self.boundary.aabb();
        for o in &self.obstacles {
            let b = o.aabb();
            bounds = Aabb::of_points([&bounds.min, &bounds.max, &b.min, &b.max]);
        }
        let frame = SpatialGrid::new(bounds, self.vertex_count());
        // Rings taken in the order of the cell of their first vertex, so that the segments of
        // neighbouring cells are neighbours in memory (on large maps the pass over the cells is
        // bound by memory traffic otherwise: obstacles are numbered in no spatial order).
        let firsts: Vec<Point2<f64>> = rings
            .iter()
            .map(|r| r.vertices.first().copied().unwrap_or(bounds.min))
            .collect();
        let mut segs: Vec<(u32, u32)> = Vec::with_capacity(self.vertex_count());
        let mut ends: Vec<(Point2<f64>, Point2<f64>)> = Vec::with_capacity(self.vertex_count());
        let mut boxes: Vec<Aabb> = Vec::with_capacity(self.vertex_count());
        let lens: Vec<u32> = rings.iter().map(|r| r.len() as u32).collect();
        for r in frame.order_by_cell(&firsts) {
            let ring = rings[r as usize];
            let n = ring.len();
            for e in 0..n {
                let (a, b) = (
                    ring.vertices[e],
                    ring.vertices[if e + 1 == n { 0 } else { e + 1 }],
                );
                segs.push((r, e as u32));
                ends.push((a, b));
                boxes.push(Aabb::of_points([&a, &b]));
            }
        }
        let grid = frame.clone().pack(&boxes);
        let pairs_listed: usize = grid
            .buckets()
            .map(|b| b.len() * b.len().saturating_sub(1) / 2)
            .sum();
        let form = match form {
            ContactForm::Auto if pairs_listed > SEGMENT_FORM_PAIRS_PER_EDGE * boxes.len() => {
                ContactForm::Segments
            }
            ContactForm::Auto => ContactForm::Boxes,
            chosen => chosen,
        };
        let mut found: Vec<EdgeContact> = Vec::new();
        // The exact contact test of edges `i` and `j`, whose boxes meet (disjoint boxes, by exact
        // coordinate comparisons, mean disjoint edges: each form rejects those first).
        let mut test = |i: usize, j: usize| {
            let ring_len = lens[segs[i].0 as usize];
            if let Some(contact) =
                segment_pair_contact(ring_len, (segs[i], ends[i]), (segs[j], ends[j]))
            {
                found.push(contact);
            }
        };
        if form == ContactForm::Boxes {
            // A pair of edges shares every cell that both boxes cover. It is tested only in the
            // cell holding the lower-left corner of the intersection of their boxes, which both
            // boxes cover (cells are monotone in the coordinates), so each pair is tested once,
            // without a set of pairs seen.
            for (cell, bucket) in grid.buckets().enumerate() {
                for (k, &i) in bucket.iter().enumerate() {
                    for &j in &bucket[k + 1..] {
                        let (bi, bj) = (&boxes[i as usize], &boxes[j as usize]);
                        let corner = Point2::new(bi.min.x.max(bj.min.x), bi.min.y.max(bj.min.y));
                        if corner.x <= bi.max.x.min(bj.max.x)
                            && corner.y <= bi.max.y.min(bj.max.y)
                            && grid.cell_of(&corner) == cell
                        {
                            test(i as usize, j as usize);
                        }
                    }
                }
            }
        } else {
            // Each edge is listed in the cells its segment meets, not in every cell of its box.
            // Edge `i` finds every edge that touches it among the edges listed in its own cells
            // (they share the cell of a common point), and tests each partner `j > i` once:
            // `tested_by[j]` remembers the last `i` that tested `j` (no set of pairs).
            let segments: Vec<[Point2<f64>; 2]> = ends.iter().map(|&(a, b)| [a, b]).collect();
            let grid = frame.pack_segments(&segments);
            let mut tested_by = vec![u32::MAX; segments.len()];
            for (i, segment) in segments.iter().enumerate() {
                grid.visit_near_convex(segment, 0.0, |j| {
                    let j = j as usize;
                    if j <= i || tested_by[j] == i as u32 {
                        return;
                    }
                    tested_by[j] = i as u32;
                    let (bi, bj) = (&boxes[i], &boxes[j]);
                    if bi.min.x.max(bj.min.x) <= bi.max.x.min(bj.max.x)
                        && bi.min.y.max(bj.min.y) <= bi.max.y.min(bj.max.y)
                    {
                        test(i, j);
                    }
                });
            }
        }
        found.sort_by_key(|(k, _)| *k);
        found
    }

    /// The first edge contact in input order, as an error.
    fn check_edge_contacts(&self) -> Result<(), MapError> {
        match self.edge_contacts().into_iter().next() {
            Some((_, e)) => Err(e),
            None => Ok(()),
        }
    }

    /// Pairs of obstacles `(i, j)`, `i < j`, one of which holds a vertex of the other (checked
    /// for one vertex each: with no edge contacts that decides nesting).
    pub(crate) fn nested_obstacles(&self) -> Vec<(usize, usize, Point2<f64>)> {
        let boxes: Vec<Aabb> = self.obstacles.iter().map(Polygon::aabb).collect();
        let grid = SpatialGrid::packed(self.boundary.aabb(), boxes.len(), &boxes);
        let firsts: Vec<Point2<f64>> = self.obstacles.iter().map(|o| o.vertices[0]).collect();
        let mut out = Vec::new();
        // Obstacles in the order of their first vertex's cell: neighbouring lookups touch
        // neighbouring memory. The result is sorted below by pair and then by the obstacle whose
        // vertex was found, so the visiting order does not show.
        for i in grid.order_by_cell(&firsts) {
            let i = i as usize;
            let v = firsts[i];
            for &j in grid.at(&v) {
                let j = j as usize;
                if j != i
                    && boxes[j].contains(&v)
                    && self.obstacles[j].locate(&v) != PointInPolygon::Outside
                {
                    out.push((i.min(j), i.max(j), i, v));
                }
            }
        }
        out.sort_by_key(|&(i, j, visitor, _)| (i, j, visitor));
        out.dedup_by_key(|&mut (i, j, _, _)| (i, j));
        out.into_iter().map(|(i, j, _, v)| (i, j, v)).collect()
    }

    /// With no edge contacts, rings are nested or disjoint: check each obstacle is inside the
    /// boundary and inside no other obstacle.
    fn check_containment(&self) -> Result<(), MapError> {
        for (i, o) in self.obstacles.iter().enumerate() {
            let v = o.vertices[0];
            if self.boundary.locate(&v) != PointInPolygon::Inside {
                return Err(MapError::ObstacleOutsideBoundary { obstacle: i, at: v });
            }
        }
        match self.nested_obstacles().first() {
            Some(&(first, second, at)) => Err(MapError::ObstaclesOverlap { first, second, at }),
            None => Ok(()),
        }
    }
}

/// Checks on one ring that need no other ring: finiteness, vertex count, repeats, area.
fn validate_ring_alone(ring: RingId, poly: &Polygon) -> Result<(), MapError> {
    for (vertex, p) in poly.vertices.iter().enumerate() {
        if !(p.x.is_finite() && p.y.is_finite()) {
            return Err(MapError::NonFinite {
                ring,
                vertex,
                x: p.x,
                y: p.y,
            });
        }
        if !(in_domain(p.x) && in_domain(p.y)) {
            return Err(MapError::OutOfDomain {
                ring,
                vertex,
                at: *p,
            });
        }
    }
    let first = poly.vertices.first().copied().unwrap_or(Point2::origin());
    // Three distinct vertices (by bits, as `distinct_vertex_count` counts them) are found in one
    // pass; the exact count (a sort) only for the error.
    let key = |p: &Point2<f64>| (p.x.to_bits(), p.y.to_bits());
    let keys = || poly.vertices.iter().map(key);
    let three_distinct = keys().next().is_some_and(|a| {
        keys()
            .find(|&p| p != a)
            .is_some_and(|b| keys().any(|p| p != a && p != b))
    });
    if !three_distinct {
        return Err(MapError::TooFewVertices {
            ring,
            distinct: poly.distinct_vertex_count(),
            at: first,
        });
    }
    let n = poly.len();
    for i in 0..n {
        if poly.vertices[i] == poly.vertices[(i + 1) % n] {
            return Err(MapError::RepeatedVertex {
                ring,
                vertex: (i + 1) % n,
                at: poly.vertices[i],
            });
        }
    }
    if poly.is_degenerate() {
        return Err(MapError::ZeroArea { ring, at: first });
    }
    Ok(())
}

/// The contact of two edges `(ring, edge)` of `rings`, looked up there (the tests' brute force).
#[cfg(test)]
fn pair_contact(rings: &[&Polygon], x: (u32, u32), y: (u32, u32)) -> Option<EdgeContact> {
    let seg_points = |s: (u32, u32)| {
        let ring = rings[s.0 as usize];
        let n = ring.len();
        (
            ring.vertices[s.1 as usize],
            ring.vertices[(s.1 as usize + 1) % n],
        )
    };
    let ring_len = rings[x.0 as usize].len() as u32;
    segment_pair_contact(ring_len, (x, seg_points(x)), (y, seg_points(y)))
}

/// The contact of two edges `(ring, edge)` (rings numbered boundary first) where they must not
/// meet, as an error keyed by the ordered pair, or `None` when they are disjoint or merely share
/// the vertex of two consecutive edges of a ring. Each edge comes with its endpoints `(from, to)`;
/// `ring_len` is the vertex count of the first one's ring (used when both lie on one ring).
fn segment_pair_contact(
    ring_len: u32,
    x: ((u32, u32), (Point2<f64>, Point2<f64>)),
    y: ((u32, u32), (Point2<f64>, Point2<f64>)),
) -> Option<EdgeContact> {
    let ring_id = |r: u32| {
        if r == 0 {
            RingId::Boundary
        } else {
            RingId::Obstacle(r as usize - 1)
        }
    };
    let ((si, (a, b)), (sj, (c, d))) = if x.0 < y.0 { (x, y) } else { (y, x) };
    let key = (si.0, si.1, sj.0, sj.1);
    // Consecutive edges of a ring share their common vertex, so they always meet; they meet where
    // they must not exactly when they overlap beyond it. Deciding that first spares the general
    // contact test for most pairs of a ring (every consecutive pair shares a grid cell).
    let adjacent = si.0 == sj.0 && {
        let n = ring_len;
        (si.1 + 1) % n == sj.1 || (sj.1 + 1) % n == si.1
    };
    if adjacent && !adjacent_edges_overlap(&a, &b, &c, &d) {
        return None;
    }
    let contact = segment_contact(&a, &b, &c, &d);
    if contact == SegmentContact::Disjoint {
        return None;
    }
    let at = contact_point(&a, &b, &c, &d);
    let error = if si.0 == sj.0 {
        MapError::SelfIntersecting {
            ring: ring_id(si.0),
            first_edge: si.1 as usize,
            second_edge: sj.1 as usize,
            at,
        }
    } else if si.0 == 0 {
        MapError::ObstacleCrossesBoundary {
            obstacle: sj.0 as usize - 1,
            at,
        }
    } else if contact == SegmentContact::Crossing {
        MapError::ObstaclesOverlap {
            first: si.0 as usize - 1,
            second: sj.0 as usize - 1,
            at,
        }
    } else {
        MapError::ObstaclesTouch {
            first: si.0 as usize - 1,
            second: sj.0 as usize - 1,
            at,
        }
    };
    Some((key, error))
}

/// Adjacent edges `ab` and `cd` of a ring share one endpoint; they also meet beyond it exactly when
/// the ring doubles back on itself there (a spike): collinear, with both far ends on the same side.
fn adjacent_edges_overlap(
    a: &Point2<f64>,
    b: &Point2<f64>,
    c: &Point2<f64>,
    d: &Point2<f64>,
) -> bool {
    let (shared, p, q) = if b == c {
        (b, a, d)
    } else if d == a {
        (a, b, c)
    } else {
        // Adjacent by index yet no common endpoint: impossible for a ring, so treat it as a defect.
        return true;
    };
    // Collinear with both far ends on one side of the shared vertex. The dot product of two
    // vectors along one line is positive exactly when they point the same way.
    orient2d(p, shared, q) == 0.0 && (p - shared).dot(&(q - shared)) > 0.0
}

/// A representative point of the contact between two meeting segments.
fn contact_point(
    a: &Point2<f64>,
    b: &Point2<f64>,
    c: &Point2<f64>,
    d: &Point2<f64>,
) -> Point2<f64> {
    use crate::predicates::point_on_segment;
    for (p, s0, s1) in [(c, a, b), (d, a, b), (a, c, d), (b, c, d)] {
        if point_on_segment(s0, s1, p) {
            return *p;
        }
    }
    // A proper crossing: the floating-point intersection, for the message only.
    let r = b - a;
    let s = d - c;
    let denom = r.x * s.y - r.y * s.x;
    if denom == 0.0 {
        return *a;
    }
    let t = ((c - a).x * s.y - (c - a).y * s.x) / denom;
    a + r * t
}

/// How [`Map::edge_contacts`] lists the edges in its grid before testing the pairs that share a
/// cell. Both forms find exactly the contacts of testing every pair of edges (the module's tests
/// run both against that oracle).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum ContactForm {
    /// [`ContactForm::Boxes`] unless the box grid lists more than
    /// [`SEGMENT_FORM_PAIRS_PER_EDGE`] pairs per edge, then [`ContactForm::Segments`].
    Auto,
    /// Each edge in every cell of its bounding box, each pair tested in the cell holding the
    /// lower-left corner of the intersection of their boxes: the fastest on maps of many small
    /// obstacles (each edge in one to four cells).
    Boxes,
    /// Each edge in the cells its segment meets, each edge testing the edges listed in its own
    /// cells, each pair once (a stamp per edge): on long diagonal edges packed close together
    /// (the 10,000-vertex star's spikes) the boxes pile up in every cell whatever its size, and
    /// this form lists and tests less than half as much.
    Segments,
}

/// Pairs listed per edge in the box grid (pairs of edges sharing a cell, most of them rejected
/// by the corner rule before any exact test) above which [`ContactForm::Auto`] takes the segment
/// form: the generated crater strips of 1,000 to 100,000 obstacles list 2.4-2.5 pairs per edge
/// (Boxes), the thesis's Fig. 2.7 map 2.0, the 10,000-vertex star 667 (Segments).
const SEGMENT_FORM_PAIRS_PER_EDGE: usize = 16;

#[cfg(test)]
mod tests {
    use super::*;

    fn poly(pts: &[(f64, f64)]) -> Polygon {
        Polygon::new(pts.iter().map(|&(x, y)| Point2::new(x, y)).collect())
    }

    fn square(x: f64, y: f64, s: f64) -> Polygon {
        poly(&[(x, y), (x + s, y), (x + s, y + s), (x, y + s)])
    }

    fn map(obstacles: Vec<Polygon>) -> Map {
        Map::new(square(0.0, 0.0, 100.0), obstacles)
    }

    /// One `check`: the map's validation result, as the error variant's name.
    fn check(m: &Map, expected: &str) {
        let got = match m.validate() {
            Ok(_) => "ok".to_string(),
            Err(e) => format!("{e:?}")
                .split([' ', '{', '('])
                .next()
                .unwrap_or("")
                .to_string(),
        };
        assert_eq!(got, expected, "{:?}", m.validate());
    }

    #[test]
    fn each_defect_has_its_own_error() {
        check(&map(vec![square(10., 10., 5.)]), "ok");
        check(
            &map(vec![poly(&[(1., 1.), (f64::NAN, 2.), (3., 1.)])]),
            "NonFinite",
        );
        check(
            &map(vec![poly(&[(1., 1.), (2., 2.), (1., 1.)])]),
            "TooFewVertices",
        );
        check(
            &map(vec![poly(&[(1., 1.), (2., 2.), (2., 2.), (3., 1.)])]),
            "RepeatedVertex",
        );
        check(
            &map(vec![poly(&[(1., 1.), (2., 2.), (3., 3.)])]),
            "ZeroArea",
        );
        check(
            &map(vec![poly(&[
                (10., 10.),
                (20., 20.),
                (20., 10.),
                (10., 20.),
            ])]),
            "SelfIntersecting",
        );
        check(
            &map(vec![square(200., 200., 5.)]),
            "ObstacleOutsideBoundary",
        );
        check(&map(vec![square(95., 50., 10.)]), "ObstacleCrossesBoundary");
        check(&map(vec![square(0., 50., 10.)]), "ObstacleCrossesBoundary");
        check(
            &map(vec![square(10., 10., 5.), square(12., 12., 5.)]),
            "ObstaclesOverlap",
        );
        check(
            &map(vec![square(10., 10., 10.), square(12., 12., 2.)]),
            "ObstaclesOverlap",
        );
        check(
            &map(vec![square(10., 10., 5.), square(15., 10., 5.)]),
            "ObstaclesTouch",
        );
        check(
            &map(vec![square(10., 10., 5.), square(15., 15., 5.)]),
            "ObstaclesTouch",
        );
    }

    #[test]
    fn edge_contacts_match_all_pairs_on_random_overlapping_maps() {
        // Grid-snapped random quads (many shared vertices, collinear overlaps and crossings):
        // the grid's once-per-pair selection must find exactly the contacts of testing every
        // pair of edges.
        use rand::{RngExt, SeedableRng};
        let mut total = 0;
        for seed in 0..200u64 {
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
            let mut coord = || f64::from(rng.random_range(0..=40u32)) * 0.5;
            let obstacles: Vec<Polygon> = (0..8)
                .map(|_| {
                    let (x, y) = (coord().min(17.0) + 1.0, coord().min(17.0) + 1.0);
                    let (w, h) = (coord() * 0.2 + 0.5, coord() * 0.2 + 0.5);
                    poly(&[(x, y), (x + w, y), (x + w, y + h), (x, y + h)])
                })
                .collect();
            let m = map(obstacles);
            let found = m.edge_contacts();
            assert_eq!(found, brute_contacts(&m), "seed {seed}");
            assert_eq!(
                m.edge_contacts_by(ContactForm::Segments),
                found,
                "seed {seed}"
            );
            total += found.len();
        }
        assert!(
            total > 100,
            "only {total} contacts: the maps do not exercise the check"
        );
    }

    /// Every contact of `m` found by testing every pair of edges, sorted: the oracle.
    fn brute_contacts(m: &Map) -> Vec<EdgeContact> {
        let rings: Vec<&Polygon> = std::iter::once(&m.boundary).chain(&m.obstacles).collect();
        let segs: Vec<(u32, u32)> = rings
            .iter()
            .enumerate()
            .flat_map(|(r, ring)| (0..ring.len()).map(move |e| (r as u32, e as u32)))
            .collect();
        let mut brute: Vec<EdgeContact> = Vec::new();
        for (k, &x) in segs.iter().enumerate() {
            for &y in &segs[k + 1..] {
                brute.extend(pair_contact(&rings, x, y));
            }
        }
        brute.sort_by_key(|(k, _)| *k);
        brute
    }

    #[test]
    fn edge_contacts_match_all_pairs_on_random_stars() {
        // Star-shaped obstacles with long spikes in every direction, their points snapped to a
        // coarse grid (shared points, collinear overlaps, crossings, touches at vertices): the
        // cells along each segment must find exactly the contacts of testing every pair.
        use rand::{RngExt, SeedableRng};
        let mut total = 0;
        for seed in 0..200u64 {
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
            let obstacles: Vec<Polygon> = (0..4)
                .map(|_| {
                    let (cx, cy) = (
                        f64::from(rng.random_range(6..=14u32)),
                        f64::from(rng.random_range(6..=14u32)),
                    );
                    let n = 2 * rng.random_range(3..=12u32);
                    let pts: Vec<(f64, f64)> = (0..n)
                        .map(|i| {
                            let a = std::f64::consts::TAU * f64::from(i) / f64::from(n);
                            let r = if i % 2 == 0 {
                                f64::from(rng.random_range(3..=5u32))
                            } else {
                                1.0
                            };
                            let snap = |v: f64| (v * 4.0).round() / 4.0;
                            (snap(cx + r * a.cos()), snap(cy + r * a.sin()))
                        })
                        .collect();
                    poly(&pts)
                })
                .collect();
            // A small map, so that the grid's cells are shorter than the spikes.
            let m = Map::new(square(0.0, 0.0, 20.0), obstacles);
            let brute = brute_contacts(&m);
            for form in [ContactForm::Boxes, ContactForm::Segments] {
                assert_eq!(m.edge_contacts_by(form), brute, "seed {seed}, {form:?}");
            }
            total += brute.len();
        }
        assert!(
            total > 100,
            "only {total} contacts: the maps do not exercise the check"
        );
    }

    #[test]
    fn a_spike_is_a_self_intersection() {
        // Edge (2,2)->(4,4) doubles back along (4,4)->(3,3).
        check(
            &map(vec![poly(&[
                (2., 1.),
                (2., 2.),
                (4., 4.),
                (3., 3.),
                (5., 1.),
            ])]),
            "SelfIntersecting",
        );
    }

    #[test]
    fn messages_name_the_ring_and_place() {
        let e = map(vec![square(10., 10., 5.), square(12., 12., 5.)])
            .validate()
            .unwrap_err();
        let msg = e.to_string();
        assert!(msg.contains("obstacles 0 and 1 overlap near"), "{msg}");
    }

    #[test]
    fn start_and_goal_must_be_free() {
        let m = map(vec![square(10., 10., 5.)]);
        assert!(m.validate_point("start", &Point2::new(50., 50.)).is_ok());
        let e = m
            .validate_point("goal", &Point2::new(12., 12.))
            .unwrap_err();
        assert_eq!(
            e.to_string(),
            "the goal point (12, 12) is inside obstacle 0"
        );
        assert!(m.validate_point("start", &Point2::new(0., 50.)).is_err());
        assert!(
            m.validate_point("start", &Point2::new(f64::NAN, 50.))
                .is_err()
        );
    }
}
