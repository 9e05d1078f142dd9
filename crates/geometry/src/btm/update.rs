//! Local updates of a BTM when obstacles appear or disappear during a descent (thesis §3.5.2,
//! Lemma 3.5.1; online paper §III-A). Only the affected region is retriangulated:
//!
//! - **insert**: the new obstacle's vertices are inserted with Lawson's flips, its edges with
//!   Anglada's cavity retriangulation, and the triangles inside it leave the BTM;
//! - **remove**: the obstacle's triangles rejoin free space, its edges stop being map edges, and
//!   each of its vertices is removed by ear-clipping the polygon of its neighbours; Lawson's flips
//!   then restore the empty-circumcircle property, which may reach a little beyond the star of the
//!   removed vertices (those triangles are reported too).
//!
//! Every input is checked before anything changes, so a refused update leaves the BTM untouched.
//! During an update the DCEL never rewrites a live triangle: it retires the id and allocates a new
//! one. The [`UpdateReport`] lists the free triangles that existed before and are gone (`removed`)
//! and the free triangles that exist now and did not before (`added`); every other triangle keeps
//! its id and its geometry.

use super::build::{insert_constraint, insert_vertex};
use super::locate::WalkRng;
use super::{Btm, BtmError, Location, ObstacleRecord};
use crate::dcel::{EdgeKind, FaceKind, HalfEdgeId, NONE, ObstacleId, TriangleId};
use crate::map::{Map, MapError, RingId};
use crate::polygon::{PointInPolygon, Polygon};
use crate::predicates::{SegmentContact, incircle, orient2d, segment_contact};
use serde::Serialize;

/// What a local update changed.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize)]
pub struct UpdateReport {
    /// Free triangles that existed before the update and no longer do.
    pub removed: Vec<TriangleId>,
    /// Free triangles created by the update.
    pub added: Vec<TriangleId>,
}

impl Btm {
    /// Adds an obstacle (a simple polygon strictly inside free space, touching nothing) and
    /// retriangulates around it. Returns its id and what changed.
    ///
    /// ```
    /// use nalgebra::Point2;
    /// use rappel_geometry::btm::Btm;
    /// use rappel_geometry::{map::Map, polygon::Polygon};
    /// let p = |x, y| Point2::new(x, y);
    /// let map = Map::new(Polygon::new(vec![p(0., 0.), p(20., 0.), p(20., 20.), p(0., 20.)]), vec![]);
    /// let mut btm = Btm::from_map(&map).unwrap();
    /// let before: Vec<_> = btm.triangles().collect();
    /// let (id, report) = btm.insert_obstacle(&Polygon::new(vec![p(5., 5.), p(8., 5.), p(6., 8.)])).unwrap();
    /// btm.check_invariants().unwrap();
    /// assert_eq!(btm.triangle_count(), 7 + 2 - 2);
    /// // Every triangle not reported removed is still there.
    /// assert!(before.iter().filter(|t| !report.removed.contains(t)).all(|t| btm.is_free_triangle(*t)));
    /// let report = btm.remove_obstacle(id).unwrap();
    /// assert_eq!(btm.triangle_count(), 2);
    /// # let _ = report;
    /// ```
    pub fn insert_obstacle(
        &mut self,
        polygon: &Polygon,
    ) -> Result<(ObstacleId, UpdateReport), BtmError> {
        let id = ObstacleId(self.obstacles.len() as u32);
        self.check_new_obstacle(polygon, id.index())?;

        let mark = self.begin_update();
        let kind = EdgeKind::Obstacle(id);
        let ids = super::build::add_ring(&mut self.dcel, polygon, false, kind);
        let vertices: Vec<u32> = ids.clone().collect();
        let mut rng = WalkRng::new();
        let mut stack = Vec::new();
        let result = (|| {
            for &v in &vertices {
                let p = self.dcel.points[v as usize];
                let hint = self.locator.hint(&self.dcel, &p).unwrap_or(0);
                insert_vertex(&mut self.dcel, v, hint, &mut rng, &mut stack)?;
            }
            for i in 0..vertices.len() {
                insert_constraint(
                    &mut self.dcel,
                    vertices[i],
                    vertices[(i + 1) % vertices.len()],
                )?;
            }
            Ok::<(), BtmError>(())
        })();
        if let Err(e) = result {
            self.dcel.fresh_slots = false;
            return Err(BtmError::Internal(format!(
                "insertion failed after its checks passed: {e}"
            )));
        }
        let inside = self.region_of_ring(&vertices, false);
        for t in inside {
            self.dcel.set_face(t, FaceKind::Obstacle(id));
        }
        self.obstacles.push(Some(ObstacleRecord::of(ids)));
        Ok((id, self.end_update(mark)))
    }

    /// Removes an obstacle and retriangulates the region it leaves. Returns what changed.
    pub fn remove_obstacle(&mut self, id: ObstacleId) -> Result<UpdateReport, BtmError> {
        let record = self
            .obstacles
            .get_mut(id.index())
            .and_then(Option::take)
            .ok_or(BtmError::UnknownObstacle(id))?;
        let vs: Vec<u32> = record.vertices().collect();
        let mark = self.begin_update();
        let inside = self.region_of_ring(&vs, false);
        for t in inside {
            self.dcel.set_face(t, FaceKind::Free);
        }
        for i in 0..vs.len() {
            if let Some(h) = self.dcel.find_edge(vs[i], vs[(i + 1) % vs.len()]) {
                self.dcel.set_constrained(h, false);
            }
        }
        for &v in &vs {
            self.dcel.ring[v as usize] = None;
        }
        let mut suspects = Vec::new();
        for &v in &vs {
            match self.remove_vertex(v) {
                Ok(slots) => {
                    suspects.extend(slots.iter().flat_map(|&t| [3 * t, 3 * t + 1, 3 * t + 2]))
                }
                Err(e) => {
                    self.dcel.fresh_slots = false;
                    return Err(e);
                }
            }
        }
        self.dcel.legalize_edges(&mut suspects);
        Ok(self.end_update(mark))
    }

    fn begin_update(&mut self) -> usize {
        self.dcel.fresh_slots = true;
        self.dcel.retired.clear();
        self.dcel.face.len()
    }

    fn end_update(&mut self, mark: usize) -> UpdateReport {
        self.dcel.fresh_slots = false;
        let mut removed: Vec<TriangleId> = self
            .dcel
            .retired
            .drain(..)
            .filter(|&(t, kind)| (t as usize) < mark && kind == FaceKind::Free)
            .map(|(t, _)| TriangleId(t))
            .collect();
        removed.sort_unstable();
        let added = (mark..self.dcel.face.len())
            .filter(|&t| self.dcel.face[t] == FaceKind::Free)
            .map(|t| TriangleId(t as u32))
            .collect();
        UpdateReport { removed, added }
    }

    /// Triangles enclosed by a ring given clockwise (free side on the left): the faces on the
    /// right of its edges and everything reachable from them without crossing a map edge.
    /// (`left = true` gives the free side instead.)
    fn region_of_ring(&self, ring: &[u32], left: bool) -> Vec<u32> {
        let d = &self.dcel;
        let mut seen = std::collections::HashSet::new();
        let mut stack = Vec::new();
        for i in 0..ring.len() {
            if let Some(h) = d.find_edge(ring[i], ring[(i + 1) % ring.len()]) {
                let t = if left { h / 3 } else { d.twin[h as usize] / 3 };
                stack.push(t);
            }
        }
        while let Some(t) = stack.pop() {
            if !seen.insert(t) {
                continue;
            }
            for i in 0..3 {
                let h = 3 * t + i;
                let g = d.twin[h as usize];
                if !d.constrained[h as usize] && g != NONE && !seen.contains(&(g / 3)) {
                    stack.push(g / 3);
                }
            }
        }
        let mut out: Vec<u32> = seen.into_iter().collect();
        out.sort_unstable();
        out
    }

    /// Removes vertex `v` (an interior vertex of the triangulation): ear-clips the polygon of its
    /// neighbours and returns the new triangle slots.
    fn remove_vertex(&mut self, v: u32) -> Result<Vec<u32>, BtmError> {
        let d = &self.dcel;
        let start = d.vertex_edge[v as usize];
        if start == NONE {
            return Err(BtmError::Internal(format!(
                "vertex {v} is not in the triangulation"
            )));
        }
        let mut fan = Vec::new();
        let mut h = start;
        loop {
            fan.push(h);
            let t = d.twin[HalfEdgeId(h).prev().index()];
            if t == NONE {
                return Err(BtmError::Internal(format!(
                    "vertex {v} is on the scaffold hull"
                )));
            }
            h = t;
            if h == start {
                break;
            }
            if fan.len() > d.origin.len() {
                return Err(BtmError::Internal(format!(
                    "fan of vertex {v} does not close"
                )));
            }
        }
        let link: Vec<u32> = fan.iter().map(|&h| d.dest(h)).collect();
        let dead: Vec<u32> = fan.iter().map(|&h| h / 3).collect();
        let face = d.face[(start / 3) as usize];
        let tris = self
            .ear_clip(&link)
            .ok_or_else(|| BtmError::Internal(format!("no ear in the link of vertex {v}")))?;
        let slots = self.dcel.replace_cavity(&dead, &tris, face, None);
        self.dcel.vertex_edge[v as usize] = NONE;
        Ok(slots)
    }

    /// Triangulates a simple counter-clockwise polygon of vertex ids by ear clipping, preferring
    /// ears whose circumcircle holds no other polygon vertex (fewer flips afterwards).
    fn ear_clip(&self, polygon: &[u32]) -> Option<Vec<[u32; 3]>> {
        let d = &self.dcel;
        let mut poly = polygon.to_vec();
        let mut out = Vec::with_capacity(poly.len().saturating_sub(2));
        while poly.len() > 3 {
            let m = poly.len();
            let mut chosen = None;
            for i in 0..m {
                let (a, b, c) = (poly[(i + m - 1) % m], poly[i], poly[(i + 1) % m]);
                if orient2d(d.pt(a), d.pt(b), d.pt(c)) <= 0.0 {
                    continue;
                }
                let others = poly.iter().filter(|&&x| x != a && x != b && x != c);
                let mut blocked = false;
                let mut delaunay = true;
                for &x in others {
                    let px = d.pt(x);
                    if orient2d(d.pt(a), d.pt(b), px) >= 0.0
                        && orient2d(d.pt(b), d.pt(c), px) >= 0.0
                        && orient2d(d.pt(c), d.pt(a), px) >= 0.0
                    {
                        blocked = true;
                        break;
                    }
                    if incircle(d.pt(a), d.pt(b), d.pt(c), px) > 0.0 {
                        delaunay = false;
                    }
                }
                if blocked {
                    continue;
                }
                if delaunay {
                    chosen = Some(i);
                    break;
                }
                chosen.get_or_insert(i);
            }
            let i = chosen?;
            let m = poly.len();
            out.push([poly[(i + m - 1) % m], poly[i], poly[(i + 1) % m]]);
            poly.remove(i);
        }
        if poly.len() == 3 {
            if orient2d(d.pt(poly[0]), d.pt(poly[1]), d.pt(poly[2])) <= 0.0 {
                return None;
            }
            out.push([poly[0], poly[1], poly[2]]);
        }
        Some(out)
    }

    /// Checks a new obstacle before anything changes: a valid ring, strictly inside free space,
    /// touching and enclosing nothing.
    fn check_new_obstacle(&self, polygon: &Polygon, index: usize) -> Result<(), BtmError> {
        Map::new(polygon.clone(), Vec::new())
            .validate()
            .map_err(|e| e.for_ring(RingId::Obstacle(index)))?;

        let d = &self.dcel;
        let contact = |kind: EdgeKind, at, overlap: bool| contact_error(kind, index, at, overlap);
        let ring_kind = |v: u32| {
            d.ring[v as usize]
                .map(|r| r.kind)
                .unwrap_or(EdgeKind::Boundary)
        };
        let mut seeds = Vec::new();
        for p in &polygon.vertices {
            match self.locate(p) {
                Location::Triangle(t) => seeds.push(t.0),
                Location::Edge(h) => {
                    if d.constrained[h.index()] {
                        return Err(contact(d.edge_kind(h), *p, false));
                    }
                    seeds.push(h.0 / 3);
                    seeds.push(d.twin[h.index()] / 3);
                }
                Location::Vertex(v) => return Err(contact(ring_kind(v.0), *p, false)),
                Location::Obstacle(o) => return Err(contact(EdgeKind::Obstacle(o), *p, true)),
                Location::Outside => {
                    return Err(MapError::ObstacleOutsideBoundary {
                        obstacle: index,
                        at: *p,
                    }
                    .into());
                }
            }
        }
        // Every map edge and vertex the new obstacle could meet is reachable from its vertices'
        // triangles through free triangles that meet its bounding box.
        let bbox = polygon.aabb();
        let mut seen = std::collections::HashSet::new();
        while let Some(t) = seeds.pop() {
            if !seen.insert(t) {
                continue;
            }
            let pts = d.triangle_points(TriangleId(t));
            if !crate::polygon::Aabb::of_points(&pts).intersects(&bbox) {
                continue;
            }
            for i in 0..3 {
                let h = 3 * t + i;
                let (a, b) = (d.origin[h as usize], d.dest(h));
                if d.constrained[h as usize] {
                    for (p, q) in polygon.edges() {
                        let c = segment_contact(p, q, d.pt(a), d.pt(b));
                        if c != SegmentContact::Disjoint {
                            let kind = d.edge_kind(HalfEdgeId(h));
                            return Err(contact(kind, *p, c == SegmentContact::Crossing));
                        }
                    }
                } else {
                    let g = d.twin[h as usize];
                    if g != NONE && d.face[(g / 3) as usize] == FaceKind::Free {
                        seeds.push(g / 3);
                    }
                }
                if d.ring[a as usize].is_some()
                    && polygon.locate(d.pt(a)) != PointInPolygon::Outside
                {
                    return Err(contact(ring_kind(a), *d.pt(a), true));
                }
            }
        }
        Ok(())
    }
}

/// The error for new obstacle `index` meeting a map edge or vertex of `kind` at `at`: overlapping
/// or touching another obstacle, or reaching the boundary.
fn contact_error(
    kind: EdgeKind,
    index: usize,
    at: nalgebra::Point2<f64>,
    overlap: bool,
) -> BtmError {
    match kind {
        EdgeKind::Obstacle(o) => {
            let (first, second) = (o.index().min(index), o.index().max(index));
            if overlap {
                MapError::ObstaclesOverlap { first, second, at }.into()
            } else {
                MapError::ObstaclesTouch { first, second, at }.into()
            }
        }
        _ => MapError::ObstacleCrossesBoundary {
            obstacle: index,
            at,
        }
        .into(),
    }
}

/// Triangle slots a local update may allocate per obstacle vertex it inserts, for
/// [`Btm::reserve_for_updates`]: each new vertex adds two triangles net, and in update mode every
/// triangle of the retriangulated cavity (and of the Delaunay flips after it) takes a fresh slot;
/// eight per vertex covers typical cavities without reserving absurd amounts.
pub const RESERVED_TRIANGLES_PER_VERTEX: usize = 8;

impl Btm {
    /// Reserves room in the mesh's arrays for local updates that insert up to `vertices` obstacle
    /// vertices in all, so that a time-critical update does not reallocate (and copy) the whole
    /// mesh when an array reaches its capacity. Growth is amortised anyway; this removes the
    /// occasional latency spike, and restores headroom after a `clone` (which allocates exactly).
    ///
    /// ```
    /// use nalgebra::Point2;
    /// use rappel_geometry::btm::Btm;
    /// use rappel_geometry::{map::Map, polygon::Polygon};
    /// let p = |x, y| Point2::new(x, y);
    /// let map = Map::new(Polygon::new(vec![p(0., 0.), p(20., 0.), p(20., 20.), p(0., 20.)]), vec![]);
    /// let mut btm = Btm::from_map(&map).unwrap();
    /// btm.reserve_for_updates(64);
    /// btm.insert_obstacle(&Polygon::new(vec![p(5., 5.), p(8., 5.), p(6., 8.)])).unwrap();
    /// btm.check_invariants().unwrap();
    /// ```
    pub fn reserve_for_updates(&mut self, vertices: usize) {
        let triangles = vertices.saturating_mul(RESERVED_TRIANGLES_PER_VERTEX);
        self.dcel.reserve(vertices, triangles);
    }

    /// Renumbers the triangles densely, dropping the ids retired by local updates (which are
    /// never reused, so a long online session accumulates them). Returns, for every old triangle
    /// id, its new id (`None` for retired ids). All triangle and half-edge ids change: callers
    /// that keep ids must translate them with the returned table. Vertex and obstacle ids do not
    /// change.
    ///
    /// ```
    /// use nalgebra::Point2;
    /// use rappel_geometry::btm::Btm;
    /// use rappel_geometry::{map::Map, polygon::Polygon};
    /// let p = |x, y| Point2::new(x, y);
    /// let map = Map::new(Polygon::new(vec![p(0., 0.), p(20., 0.), p(20., 20.), p(0., 20.)]), vec![]);
    /// let mut btm = Btm::from_map(&map).unwrap();
    /// let (id, _) = btm.insert_obstacle(&Polygon::new(vec![p(5., 5.), p(8., 5.), p(6., 8.)])).unwrap();
    /// btm.remove_obstacle(id).unwrap();
    /// let renumbered = btm.compact();
    /// assert_eq!(btm.dcel().triangle_capacity(), renumbered.iter().flatten().count());
    /// btm.check_invariants().unwrap();
    /// ```
    pub fn compact(&mut self) -> Vec<Option<TriangleId>> {
        let d = &mut self.dcel;
        let mut renumber = vec![None; d.face.len()];
        let mut next = 0u32;
        for (t, f) in d.face.iter().enumerate() {
            if *f != FaceKind::Dead {
                renumber[t] = Some(TriangleId(next));
                next += 1;
            }
        }
        let half = |h: u32| -> u32 {
            if h == NONE {
                return NONE;
            }
            match renumber[(h / 3) as usize] {
                Some(t) => 3 * t.0 + h % 3,
                None => NONE,
            }
        };
        let live = next as usize;
        let (mut origin, mut twin, mut constrained, mut face) = (
            Vec::with_capacity(3 * live),
            Vec::with_capacity(3 * live),
            Vec::with_capacity(3 * live),
            Vec::with_capacity(live),
        );
        for (t, f) in d.face.iter().enumerate() {
            if *f == FaceKind::Dead {
                continue;
            }
            for i in 0..3 {
                let h = 3 * t + i;
                origin.push(d.origin[h]);
                twin.push(half(d.twin[h]));
                constrained.push(d.constrained[h]);
            }
            face.push(*f);
        }
        for e in d.vertex_edge.iter_mut() {
            *e = half(*e);
        }
        (d.origin, d.twin, d.constrained, d.face) = (origin, twin, constrained, face);
        d.retired.clear();
        renumber
    }
}
