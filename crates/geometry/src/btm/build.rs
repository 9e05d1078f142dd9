//! Building the BTM as a constrained Delaunay triangulation of the map's free space, with no
//! Steiner points (every vertex is a map vertex), in four steps:
//!
//! 1. **Scaffold**: one large triangle around the map, so that walks and flips never meet a border.
//! 2. **Delaunay insertion**: every map vertex, in Hilbert-curve order (each point lands near the
//!    previous one, so the walk is short), by splitting the triangle or edge it falls in and
//!    restoring the Delaunay property with Lawson's flips.
//! 3. **Constraints**: every map edge. Most are already Delaunay edges and are only marked; the
//!    others are inserted with Anglada's algorithm: remove the triangles the segment crosses and
//!    retriangulate the two pseudo-polygons on either side, each by recursively picking the chain
//!    vertex whose circle through the segment's ends is empty. The result is the constrained
//!    Delaunay triangulation (Anglada 1997).
//! 4. **Faces**: a flood fill from the map edges labels each triangle free, obstacle or exterior
//!    (free space lies to the left of every ring, oriented boundary counter-clockwise and
//!    obstacles clockwise).
//!
//! **Vertex order.** Steps 2-4 run with the map vertices numbered in Hilbert order (after the
//! three scaffold vertices), and the finished triangulation is numbered back in map order (ring
//! after ring, as [`Btm`]'s users see it): one pass over the half-edges' origins and the vertex
//! arrays. Maps number their obstacles in any order (the generated strips in none), so in map
//! order the vertices of neighbouring triangles lie far apart in the point and ring arrays and the
//! insertion walks, the incircle tests, the constraint pass (one fan search per map edge) and the
//! face seeds were bound by cache misses on large maps. The triangles made are the same in either
//! numbering (every decision is a geometric predicate on the points, the walk's random choices
//! are seeded, and the Hilbert order breaks ties by map id); the constraints are inserted and the
//! faces seeded in Hilbert order too.

use super::{Btm, BtmError, ObstacleRecord};
use crate::btm::locate::{RawLocation, WalkRng};
use crate::btm::locator::Locator;
use crate::dcel::{Dcel, EdgeKind, FaceKind, HalfEdgeId, NONE, ObstacleId, RingLink};
use crate::map::{Map, ValidMap};
use crate::polygon::{Aabb, Polygon};
use crate::predicates::{incircle, orient2d};
use nalgebra::Point2;

/// How far the scaffold triangle reaches beyond the map, in multiples of the map's size. Any
/// value works with exact predicates; a large one keeps scaffold triangles from crowding the map.
const SCAFFOLD_SCALE: f64 = 64.0;

impl Btm {
    /// Builds the BTM of a validated map ([`Map::validate`] makes the [`ValidMap`] proof;
    /// [`Btm::from_map`] validates and builds in one call).
    ///
    /// ```
    /// use nalgebra::Point2;
    /// use rappel_geometry::btm::Btm;
    /// use rappel_geometry::{map::Map, polygon::Polygon};
    /// let p = |x, y| Point2::new(x, y);
    /// let map = Map::new(
    ///     Polygon::new(vec![p(0., 0.), p(10., 0.), p(10., 10.), p(0., 10.)]),
    ///     vec![Polygon::new(vec![p(4., 4.), p(6., 4.), p(5., 6.)])],
    /// );
    /// let btm = Btm::build(map.validate().unwrap()).unwrap();
    /// // n + 2h - 2 triangles: 7 vertices, 1 hole.
    /// assert_eq!(btm.triangle_count(), 7);
    /// assert!(btm.is_constrained_delaunay());
    /// ```
    pub fn build(map: ValidMap<'_>) -> Result<Btm, BtmError> {
        Btm::build_valid(map.map())
    }

    /// Validates `map` ([`Map::validate`]) and builds its BTM: [`Btm::build`] for a map not
    /// validated before.
    ///
    /// ```
    /// use nalgebra::Point2;
    /// use rappel_geometry::btm::{Btm, BtmError};
    /// use rappel_geometry::{map::Map, polygon::Polygon};
    /// let p = |x, y| Point2::new(x, y);
    /// let square = |x: f64, y: f64| Polygon::new(vec![p(x, y), p(x + 2., y), p(x + 2., y + 2.), p(x, y + 2.)]);
    /// let boundary = Polygon::new(vec![p(0., 0.), p(10., 0.), p(10., 10.), p(0., 10.)]);
    /// assert!(Btm::from_map(&Map::new(boundary.clone(), vec![square(2., 2.)])).is_ok());
    /// // Overlapping obstacles: refused by validation.
    /// let bad = Map::new(boundary, vec![square(2., 2.), square(3., 3.)]);
    /// assert!(matches!(Btm::from_map(&bad), Err(BtmError::Map(_))));
    /// ```
    pub fn from_map(map: &Map) -> Result<Btm, BtmError> {
        Btm::build(map.validate()?)
    }

    /// [`Btm::build`] on the map inside the proof.
    fn build_valid(map: &Map) -> Result<Btm, BtmError> {
        let n = map.vertex_count();
        let mut dcel = Dcel::with_capacity(n);
        add_scaffold(&mut dcel, &map.aabb());

        // Vertices, rings oriented so free space lies on the left.
        let mut rings: Vec<std::ops::Range<u32>> = Vec::with_capacity(map.obstacles.len() + 1);
        rings.push(add_ring(&mut dcel, &map.boundary, true, EdgeKind::Boundary));
        for (i, o) in map.obstacles.iter().enumerate() {
            let kind = EdgeKind::Obstacle(ObstacleId(i as u32));
            rings.push(add_ring(&mut dcel, o, false, kind));
        }

        // The triangulation is made with the map vertices numbered in Hilbert order (module
        // docs, "Vertex order"), and numbered back in map order at the end.
        let order = hilbert_order(&dcel, dcel.scaffold, dcel.points.len() as u32);
        let renumbered = Renumbering::new(dcel.scaffold, order);
        renumbered.apply(&mut dcel);

        // Delaunay insertion in Hilbert order.
        let mut rng = WalkRng::new();
        let mut last = 0u32;
        let mut stack = Vec::with_capacity(64);
        for v in dcel.scaffold..dcel.points.len() as u32 {
            last = insert_vertex(&mut dcel, v, last, &mut rng, &mut stack)?;
        }

        // Constraints: the map edge leaving each vertex, in the same order; each one's half-edge
        // as found, a hint for the face seeds (a later insertion may have replaced it).
        let mut found = vec![NONE; dcel.points.len()];
        for v in dcel.scaffold..dcel.points.len() as u32 {
            if let Some(link) = dcel.ring[v as usize] {
                found[v as usize] = insert_constraint(&mut dcel, v, link.next)?.unwrap_or(NONE);
            }
        }

        classify_faces(&mut dcel, &found)?;
        renumbered.undo(&mut dcel);
        let mut rings = rings.into_iter();
        let boundary = rings.next().unwrap_or_default().collect();
        let obstacles = rings.map(|ids| Some(ObstacleRecord::of(ids))).collect();
        let locator = Locator::new(&dcel);
        Ok(Btm {
            dcel,
            boundary,
            obstacles,
            locator,
        })
    }
}

/// Adds the three scaffold vertices and their triangle.
pub(crate) fn add_scaffold(dcel: &mut Dcel, b: &Aabb) {
    let (w, h) = b.size();
    let s = w.max(h).max(1.0) * SCAFFOLD_SCALE;
    let c = Point2::new((b.min.x + b.max.x) / 2.0, (b.min.y + b.max.y) / 2.0);
    let a = dcel.add_vertex(Point2::new(c.x - s, c.y - s), None);
    let bb = dcel.add_vertex(Point2::new(c.x + s, c.y - s), None);
    let cc = dcel.add_vertex(Point2::new(c.x, c.y + s), None);
    dcel.scaffold = 3;
    dcel.push_triangle(a, bb, cc, FaceKind::Exterior);
}

/// Adds a ring's vertices and their ring links, oriented counter-clockwise when
/// `counter_clockwise` (the boundary) and clockwise otherwise (obstacles), so that free space
/// lies on the left; the ring itself is read in whichever direction gives that orientation.
/// Returns the ring's vertex ids, consecutive in ring order.
pub(crate) fn add_ring(
    dcel: &mut Dcel,
    ring: &Polygon,
    counter_clockwise: bool,
    kind: EdgeKind,
) -> std::ops::Range<u32> {
    let first = dcel.points.len() as u32;
    let n = ring.len() as u32;
    let forward = ring.is_counter_clockwise() == counter_clockwise;
    for i in 0..ring.len() {
        let p = if forward {
            ring.vertices[i]
        } else {
            ring.vertices[ring.len() - 1 - i]
        };
        let next = first + (i as u32 + 1) % n;
        dcel.add_vertex(p, Some(RingLink { kind, next }));
    }
    first..first + n
}

/// The vertex numbering the triangulation is made in (module docs, "Vertex order"): the map
/// vertices in Hilbert order after the scaffold's, so that vertices near each other in the plane
/// are near each other in the vertex arrays.
struct Renumbering {
    /// The map-order id of each build id.
    map_id: Vec<u32>,
}

impl Renumbering {
    /// Build ids: the scaffold's `0..scaffold` unchanged, then `order`.
    fn new(scaffold: u32, order: Vec<u32>) -> Self {
        let mut map_id: Vec<u32> = (0..scaffold).collect();
        map_id.extend(order);
        Renumbering { map_id }
    }

    /// Renumbers `dcel`'s vertices into build order (no triangle may refer to a map vertex
    /// yet), in place.
    fn apply(&self, dcel: &mut Dcel) {
        let mut build_id = vec![NONE; self.map_id.len()];
        for (b, &m) in self.map_id.iter().enumerate() {
            build_id[m as usize] = b as u32;
        }
        renumber_vertices(dcel, &build_id);
    }

    /// Numbers `dcel`'s vertices back in map order, in place.
    fn undo(&self, dcel: &mut Dcel) {
        for o in dcel.origin.iter_mut() {
            if let Some(&m) = self.map_id.get(*o as usize) {
                *o = m;
            }
        }
        renumber_vertices(dcel, &self.map_id);
    }
}

/// Gives vertex `v` the id `to[v]` in the vertex arrays and the ring links (a permutation of
/// `0..to.len()`), in place: the arrays are permuted along the permutation's cycles, so that the
/// build never holds two copies of them (on a 1,000,000-obstacle strip a copy of the points and
/// ring links was 150 MB at the build's peak). The three arrays move in one walk of the cycles:
/// the walk is a chain of dependent random reads (each step reads `to` where the last one led),
/// which on that strip's 4.7 million vertices missed the cache and the TLB at every step, three
/// walks (one per array) took about 5 % of a whole `rappel plan`. Triangles are renumbered by the
/// caller.
fn renumber_vertices(dcel: &mut Dcel, to: &[u32]) {
    for link in dcel.ring.iter_mut().flatten() {
        link.next = to[link.next as usize];
    }
    let mut seen = vec![false; to.len()];
    let (points, ring, edges) = (&mut dcel.points, &mut dcel.ring, &mut dcel.vertex_edge);
    let (mut point, mut link, mut edge) = (Point2::origin(), None, NONE);
    walk_cycles(to, &mut seen, |step| match step {
        CycleStep::Take(i) => (point, link, edge) = (points[i], ring[i], edges[i]),
        CycleStep::SwapWith(d) => {
            std::mem::swap(&mut point, &mut points[d]);
            std::mem::swap(&mut link, &mut ring[d]);
            std::mem::swap(&mut edge, &mut edges[d]);
        }
    });
}

/// One step of [`walk_cycles`].
#[derive(Debug, Clone, Copy)]
enum CycleStep {
    /// A cycle starts at index `i`: carry the element there.
    Take(usize),
    /// Swap the carried element with the one at index `d` (the carried one belongs there).
    SwapWith(usize),
}

/// Walks the cycles of the permutation `to` (of `0..to.len()`) once each, telling `step` how to
/// move every element at index `i` to index `to[i]` with one carried element; `seen` is scratch of
/// the same length. A cycle of length `m` is one `Take` and `m` swaps, the last of which puts the
/// carried element back where the cycle started.
fn walk_cycles(to: &[u32], seen: &mut [bool], mut step: impl FnMut(CycleStep)) {
    seen.fill(false);
    for start in 0..to.len() {
        if seen[start] {
            continue;
        }
        // The carried element is the one that came from index `i`; it goes to `to[i]`, whose
        // element is carried on. The cycle closes when the element is written back at `start`.
        step(CycleStep::Take(start));
        let mut i = start;
        loop {
            seen[i] = true;
            let d = to[i] as usize;
            step(CycleStep::SwapWith(d));
            if d == start {
                break;
            }
            i = d;
        }
    }
}

/// Vertex ids `from..to` sorted along a Hilbert curve over their bounding box.
fn hilbert_order(dcel: &Dcel, from: u32, to: u32) -> Vec<u32> {
    let b = Aabb::of_points(dcel.points[from as usize..to as usize].iter());
    let (w, h) = b.size();
    let scale = 65535.0 / w.max(h).max(f64::MIN_POSITIVE);
    let mut keyed: Vec<(u64, u32)> = (from..to)
        .map(|v| {
            let p = dcel.points[v as usize];
            let x = ((p.x - b.min.x) * scale) as u32;
            let y = ((p.y - b.min.y) * scale) as u32;
            (hilbert_index(x.min(65535), y.min(65535)), v)
        })
        .collect();
    keyed.sort_unstable();
    keyed.into_iter().map(|(_, v)| v).collect()
}

/// Position of `(x, y)` (16-bit each) along the Hilbert curve of order 16.
fn hilbert_index(mut x: u32, mut y: u32) -> u64 {
    let mut d: u64 = 0;
    let mut s: u32 = 1 << 15;
    while s > 0 {
        let rx = u32::from(x & s > 0);
        let ry = u32::from(y & s > 0);
        d += u64::from(s) * u64::from(s) * u64::from((3 * rx) ^ ry);
        if ry == 0 {
            if rx == 1 {
                x = 0xFFFF - x;
                y = 0xFFFF - y;
            }
            std::mem::swap(&mut x, &mut y);
        }
        s >>= 1;
    }
    d
}

/// Inserts vertex `v` (already in `dcel.points`) into the triangulation, walking from triangle
/// `hint`; returns a triangle incident to `v`, a good hint for the next insertion.
pub(crate) fn insert_vertex(
    dcel: &mut Dcel,
    v: u32,
    hint: u32,
    rng: &mut WalkRng,
    stack: &mut Vec<u32>,
) -> Result<u32, BtmError> {
    let p = dcel.points[v as usize];
    let hint = if dcel
        .face
        .get(hint as usize)
        .is_some_and(|f| *f != FaceKind::Dead)
    {
        hint
    } else {
        (0..dcel.face.len() as u32)
            .rev()
            .find(|&t| dcel.face[t as usize] != FaceKind::Dead)
            .unwrap_or(0)
    };
    stack.clear();
    match dcel.walk(&p, hint, rng) {
        None => {
            return Err(BtmError::Internal(format!(
                "vertex at ({}, {}) fell outside the scaffold",
                p.x, p.y
            )));
        }
        Some(RawLocation::OnVertex(u)) => {
            return Err(BtmError::DuplicateVertex {
                at: p,
                existing: dcel.points[u as usize],
            });
        }
        Some(RawLocation::Inside(t)) => stack.extend_from_slice(&dcel.split_triangle(t, v)),
        Some(RawLocation::OnEdge(h)) => {
            if dcel.constrained[h as usize] {
                return Err(BtmError::VertexOnMapEdge { at: p });
            }
            stack.extend(dcel.split_edge(h, v));
        }
    }
    dcel.legalize_around_new_vertex(stack);
    Ok(dcel.vertex_edge[v as usize] / 3)
}

/// Makes `a - b` a map edge of the triangulation (see the module docs); the half-edge `a -> b`
/// when the edge was there already (`None` when it was inserted).
pub(crate) fn insert_constraint(dcel: &mut Dcel, a: u32, b: u32) -> Result<Option<u32>, BtmError> {
    if let Some(h) = dcel.find_edge(a, b) {
        dcel.set_constrained(h, true);
        return Ok(Some(h));
    }
    let (pa, pb) = (dcel.points[a as usize], dcel.points[b as usize]);
    let through = |v: u32| BtmError::EdgeThroughVertex {
        from: pa,
        to: pb,
        vertex: dcel.points[v as usize],
    };
    // The triangle of a's fan that the segment leaves through.
    let start = dcel.vertex_edge[a as usize];
    let mut h = start;
    let mut first = NONE;
    for _ in 0..dcel.origin.len() {
        let (u, w) = (dcel.dest(h), dcel.apex(h));
        let ou = orient2d(&pa, dcel.pt(u), &pb);
        let ow = orient2d(&pa, dcel.pt(w), &pb);
        if ou == 0.0 && (dcel.pt(u) - pa).dot(&(pb - pa)) > 0.0 {
            return Err(through(u));
        }
        if ou > 0.0 && ow < 0.0 {
            first = h;
            break;
        }
        let t = dcel.twin[HalfEdgeId(h).prev().index()];
        if t == NONE || t == start {
            break;
        }
        h = t;
    }
    if first == NONE {
        return Err(BtmError::Internal(format!(
            "no triangle around ({}, {}) faces ({}, {})",
            pa.x, pa.y, pb.x, pb.y
        )));
    }
    let face = dcel.face[(first / 3) as usize];
    let mut dead = vec![first / 3];
    let mut left: Vec<u32> = vec![dcel.apex(first)];
    let mut right: Vec<u32> = vec![dcel.dest(first)];
    let mut e = HalfEdgeId(first).next().0; // u -> w, crossed by the segment
    loop {
        if dcel.constrained[e as usize] {
            let (u, w) = (
                dcel.points[dcel.origin[e as usize] as usize],
                dcel.points[dcel.dest(e) as usize],
            );
            return Err(BtmError::EdgesCross {
                first: (pa, pb),
                second: (u, w),
            });
        }
        let g = dcel.twin[e as usize];
        if g == NONE {
            return Err(BtmError::Internal(
                "constraint walk left the scaffold".into(),
            ));
        }
        dead.push(g / 3);
        let x = dcel.apex(g);
        if x == b {
            break;
        }
        let o = orient2d(&pa, &pb, dcel.pt(x));
        if o > 0.0 {
            left.push(x);
            e = HalfEdgeId(g).next().0;
        } else if o < 0.0 {
            right.push(x);
            e = HalfEdgeId(g).prev().0;
        } else {
            return Err(through(x));
        }
    }
    let mut tris = Vec::with_capacity(dead.len());
    triangulate_pseudo_polygon(dcel, a, b, &left, &mut tris);
    right.reverse();
    triangulate_pseudo_polygon(dcel, b, a, &right, &mut tris);
    dcel.replace_cavity(&dead, &tris, face, Some((a, b)));
    Ok(None)
}

/// Constrained Delaunay triangulation of the pseudo-polygon with base edge `s -> e` and the chain
/// of vertices to its left ordered from `s`'s side to `e`'s side; appends CCW triangles.
fn triangulate_pseudo_polygon(dcel: &Dcel, s: u32, e: u32, chain: &[u32], out: &mut Vec<[u32; 3]>) {
    // Explicit stack of (base start, base end, chain range) to survive very long chains.
    let mut work: Vec<(u32, u32, usize, usize)> = vec![(s, e, 0, chain.len())];
    while let Some((s, e, lo, hi)) = work.pop() {
        if lo >= hi {
            continue;
        }
        let mut c = lo;
        for i in lo + 1..hi {
            if incircle(dcel.pt(s), dcel.pt(e), dcel.pt(chain[c]), dcel.pt(chain[i])) > 0.0 {
                c = i;
            }
        }
        out.push([s, e, chain[c]]);
        work.push((s, chain[c], lo, c));
        work.push((chain[c], e, c + 1, hi));
    }
}

/// Labels every live triangle free, obstacle or exterior by flood fill from the map edges (the
/// edge leaving each map vertex along its ring, vertices in id order: in the build's Hilbert
/// numbering consecutive seeds are near each other). `found[v]` is the half-edge of `v`'s map
/// edge as the constraint pass found it, or `NONE`; it is used when it is still that edge, and the
/// edge is searched in `v`'s fan otherwise.
///
/// A triangle is labelled when it is first queued and queued only then, so each is visited once.
/// The fill never crosses a map edge and every seed of one region carries the same label (free
/// space lies left of every ring), so the first label a triangle gets is its label. Both sides of
/// every map edge are labelled first and the fill runs after: it then only enters the pockets of
/// triangles without a map edge, near their seeds, instead of crossing the whole free space from
/// the first seed in no memory order.
fn classify_faces(dcel: &mut Dcel, found: &[u32]) -> Result<(), BtmError> {
    let mut seen = vec![false; dcel.face.len()];
    let mut queue: Vec<u32> = Vec::new();
    let mut label = |dcel: &mut Dcel, queue: &mut Vec<u32>, t: u32, kind: FaceKind| {
        if !seen[t as usize] {
            seen[t as usize] = true;
            dcel.face[t as usize] = kind;
            queue.push(t);
        }
    };
    for a in dcel.scaffold..dcel.points.len() as u32 {
        let Some(link) = dcel.ring[a as usize] else {
            continue;
        };
        let hint = found.get(a as usize).copied().unwrap_or(NONE);
        let still = hint != NONE
            && dcel.face[(hint / 3) as usize] != FaceKind::Dead
            && dcel.origin[hint as usize] == a
            && dcel.dest(hint) == link.next;
        let h = if still {
            Some(hint)
        } else {
            dcel.find_edge(a, link.next)
        };
        let Some(h) = h else {
            let (p, q) = (dcel.points[a as usize], dcel.points[link.next as usize]);
            return Err(BtmError::Internal(format!(
                "map edge ({}, {}) - ({}, {}) missing after its insertion",
                p.x, p.y, q.x, q.y
            )));
        };
        label(dcel, &mut queue, h / 3, FaceKind::Free);
        let g = dcel.twin[h as usize];
        if g != NONE {
            let across = match link.kind {
                EdgeKind::Obstacle(o) => FaceKind::Obstacle(o),
                _ => FaceKind::Exterior,
            };
            label(dcel, &mut queue, g / 3, across);
        }
    }
    while let Some(t) = queue.pop() {
        let kind = dcel.face[t as usize];
        for i in 0..3 {
            let e = 3 * t + i;
            let g = dcel.twin[e as usize];
            if !dcel.constrained[e as usize] && g != NONE {
                label(dcel, &mut queue, g / 3, kind);
            }
        }
    }
    // Anything unreached (only the scaffold when there are no map edges) is exterior.
    for (t, s) in seen.iter().enumerate() {
        if !*s && dcel.face[t] != FaceKind::Dead {
            dcel.face[t] = FaceKind::Exterior;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The in-place renumbering moves every element where a copy indexed by the inverse would
    /// put it, on seeded random permutations with cycles of every length (fixed points
    /// included).
    #[test]
    fn permuting_in_place_matches_a_copy() {
        let mut state = 0x9E37_79B9_7F4A_7C15u64;
        let mut next = |n: usize| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state % n as u64) as usize
        };
        for n in [1usize, 2, 3, 10, 257, 4096] {
            let mut to: Vec<u32> = (0..n as u32).collect();
            for i in (1..n).rev() {
                to.swap(i, next(i + 1));
            }
            let items: Vec<u64> = (0..n as u64).map(|i| i * 7 + 3).collect();
            let mut expected = vec![0u64; n];
            for (i, &d) in to.iter().enumerate() {
                expected[d as usize] = items[i];
            }
            let mut permuted = items.clone();
            let mut carry = 0;
            walk_cycles(&to, &mut vec![false; n], |step| match step {
                CycleStep::Take(i) => carry = permuted[i],
                CycleStep::SwapWith(d) => std::mem::swap(&mut carry, &mut permuted[d]),
            });
            assert_eq!(permuted, expected, "n = {n}");
        }
    }

    #[test]
    fn hilbert_index_is_a_bijection_on_a_small_grid() {
        let mut seen = std::collections::HashSet::new();
        for x in 0..64u32 {
            for y in 0..64u32 {
                assert!(seen.insert(hilbert_index(x << 10, y << 10) >> 20));
            }
        }
        assert_eq!(seen.len(), 64 * 64);
    }
}
