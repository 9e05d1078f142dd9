//! The mouth-cover test: a funnel whose mouth is reached more cheaply, at every point, along the
//! mouth from one of its two endpoints than through the funnel itself holds no shortest path
//! (used by the goal-less shortest path map, [`crate::shortest_path_map`], and by the single-class
//! SPT search, [`crate::spt`], module docs "Dominance pruning with a class count").
//!
//! # The test
//! A funnel with apex `p` reached with length `g(p)` and mouth `ab` (a triangulation edge between
//! two map vertices, free space) is *covered* when for every point `x` of `ab`
//!
//! `g(p) + |p - x| > min(best(a) + |x - a|, best(b) + |x - b|)`
//!
//! where `best(v)` is the length of some free-space path to `v` already known (any path, in any
//! homotopy class). The left side is a lower bound of every path through the funnel to `x`
//! (every such path runs from the apex to `x`); the right side is the length of a real path to
//! `x` (to an endpoint, then along the free edge). Every path through the funnel to a point
//! beyond crosses the mouth at some `x`, where something strictly shorter already arrives: the
//! funnel holds no globally shortest path. A shortest path's funnel is never covered: at its
//! crossing `x*` the left side is at most the geodesic distance of `x*`, which no real path beats.
//!
//! The left side minus either term of the minimum is monotone along the mouth (the slope of
//! `|p - x|` is at most the mouth's own), one nonincreasing and one nondecreasing from `a` to `b`,
//! so the smallest excess over the minimum sits where the two terms cross (clamped to the
//! mouth): one point decides.
//!
//! # A third cover: an arrival that sees the whole mouth
//! The endpoints cover the ends of a long mouth well and its middle badly. A funnel expanded
//! through a mouth whose apex sees the whole mouth directly (both chains are the apex and a tip)
//! leaves an *arrival*: its apex `s` with length `g(s)`, reaching every mouth point `x` with
//! `g(s) + |s - x|` along a free straight segment. [`is_covered_with`] also accepts a funnel when
//! the part of the mouth the endpoints leave uncovered (one interval, by the monotonicity above)
//! is covered by an arrival. The boundary `g(p) + |p - x| = g(s) + |s - x| + delta` is a branch
//! of a hyperbola with foci `p` and `s`; squaring twice turns it into a quadratic in the mouth's
//! parameter whose roots include every point where the arrival's excess changes sign, so when
//! none lies in the interval (widened by [`PARAMETER_SLACK`]) the excess has one sign there and
//! the middle decides. Every numerically doubtful case (a vanishing leading coefficient, a
//! non-finite value) keeps the funnel. The arrival store (`ArrivalStore`) keeps one arrival per
//! edge per query, the one reaching the mouth's middle first.
//!
//! Because the covering path may lie in another homotopy class, the test is valid only where one
//! class is wanted: the globally shortest path (the goal-less map, or the SPT search with a class
//! count of one).

use nalgebra::Point2;
use rappel_geometry::dcel::{Dcel, VertexId};
use rappel_homotopy::funnel_state::{FunnelState, FunnelTree};

/// Relative margin of the mouth-cover test: a funnel is dropped only when its bound exceeds the
/// cover by more than this fraction of the cover, far above the rounding of lengths (about 1e-15
/// relative, a few operations per length), so rounding never drops the funnel of a shortest path.
pub const COVER_MARGIN: f64 = 1e-9;

/// One end of a funnel's mouth: its point and the shortest known length of a path to it
/// (`f64::INFINITY` when none is known yet).
#[derive(Debug, Clone, Copy)]
pub struct MouthEnd {
    /// The map vertex's point.
    pub point: Point2<f64>,
    /// The shortest known length to it.
    pub best: f64,
}

/// The smallest left side of the test: `g(apex) + dist(apex, mouth)`, a lower bound of every
/// path through the funnel `f` to its mouth, with `apex_length` the apex's `g` (the tips lie on
/// the mouth's endpoints, so the mouth is read from the tree). The shortest path map keys its
/// funnels by it; the single-class search's wave order sorts within a band by it
/// ([`crate::spt`], "The wave order").
#[inline]
pub(crate) fn reach_bound(tree: &FunnelTree, f: &FunnelState, apex_length: f64) -> f64 {
    let (a, b, p) = (
        tree.point(f.right()),
        tree.point(f.left()),
        tree.point(f.apex()),
    );
    apex_length + crate::feasibility::distance_to_segment(&p, &a, &b)
}

/// `true` when every point of the mouth `a`-`b` is reached more cheaply along the mouth from an
/// endpoint than any path through the funnel with apex `apex` (reached with `apex_length`) can
/// reach it, by more than [`COVER_MARGIN`] (module docs). `false` when either end has no known
/// length, or the mouth is degenerate.
///
/// ```
/// use nalgebra::Point2;
/// use rappel_planners::mouth_cover::{MouthEnd, is_covered};
/// let a = MouthEnd { point: Point2::new(0.0, 0.0), best: 0.0 };
/// let b = MouthEnd { point: Point2::new(1.0, 0.0), best: 1.0 };
/// // An apex far away with a long path: the mouth is reached from `a` more cheaply everywhere.
/// assert!(is_covered(&Point2::new(0.5, -10.0), 50.0, a, b));
/// // The apex at `a` itself with `a`'s length: not covered (it is the covering path).
/// assert!(!is_covered(&Point2::new(0.0, 0.0), 0.0, a, b));
/// ```
#[inline]
pub fn is_covered(apex: &Point2<f64>, apex_length: f64, a: MouthEnd, b: MouthEnd) -> bool {
    if !(a.best.is_finite() && b.best.is_finite()) {
        return false;
    }
    let ab = b.point - a.point;
    let len = ab.norm();
    if len == 0.0 {
        return false;
    }
    let t = ((b.best - a.best + len) / (2.0 * len)).clamp(0.0, 1.0);
    let x = a.point + ab * t;
    let cover = (a.best + (x - a.point).norm()).min(b.best + (b.point - x).norm());
    apex_length + (x - apex).norm() > cover * (1.0 + COVER_MARGIN)
}

/// A point that sees the whole mouth directly, with the length of a path to it: every mouth point
/// `x` is reached with `length + |point - x|`.
#[derive(Debug, Clone, Copy)]
pub struct Arrival {
    /// The point (an apex of a funnel expanded through the mouth).
    pub point: Point2<f64>,
    /// The length of a path to it.
    pub length: f64,
}

/// Relative width by which the computed interval ends are widened before the arrival's part of the
/// test, and below which a quadratic's leading coefficient counts as vanishing (the test then
/// answers `false`).
pub const PARAMETER_SLACK: f64 = 1e-9;

/// [`is_covered`] with a third cover: a point that sees the whole mouth (module docs). `true`
/// only when every point of the mouth is covered by one of the three with the margin; every
/// numerically doubtful case answers `false` (the funnel is kept).
pub fn is_covered_with(
    apex: &Point2<f64>,
    apex_length: f64,
    a: MouthEnd,
    b: MouthEnd,
    arrival: Option<Arrival>,
) -> bool {
    if is_covered(apex, apex_length, a, b) {
        return true;
    }
    let Some(s) = arrival else {
        return false;
    };
    let w = b.point - a.point;
    let len = w.norm();
    if !(len > 0.0 && s.length.is_finite() && apex_length.is_finite()) {
        return false;
    }
    let scale = apex_length.max(s.length).max(len);
    let delta = COVER_MARGIN * scale;
    let at = |t: f64| a.point + w * t;
    let lb = |t: f64| apex_length + (at(t) - apex).norm();
    // The part reached more cheaply from `a`: [0, ta] (lb - A is nonincreasing), and from `b`:
    // [tb, 1] (lb - B is nondecreasing); each end checked at the point itself.
    let from_a = |t: f64| lb(t) - (a.best + t * len) > delta;
    let from_b = |t: f64| lb(t) - (b.best + (1.0 - t) * len) > delta;
    let ta = if a.best.is_finite() && from_a(0.0) {
        // lb(t) = a.best + delta + t len: |q - t w| = c + t len, linear after squaring.
        let q = apex - a.point;
        let c = a.best + delta - apex_length;
        let den = 2.0 * (q.dot(&w) + c * len);
        let t = ((q.norm_squared() - c * c) / den - PARAMETER_SLACK).clamp(0.0, 1.0);
        if t.is_finite() && from_a(t) { t } else { 0.0 }
    } else {
        0.0
    };
    let tb = if b.best.is_finite() && from_b(1.0) {
        let q = apex - b.point;
        let wb = -w;
        let c = b.best + delta - apex_length;
        let den = 2.0 * (q.dot(&wb) + c * len);
        let u = ((q.norm_squared() - c * c) / den - PARAMETER_SLACK).clamp(0.0, 1.0);
        let t = 1.0 - u;
        if t.is_finite() && from_b(t) { t } else { 1.0 }
    } else {
        1.0
    };
    if ta >= tb {
        return true;
    }
    // On [ta, tb] the arrival must cover: D(t) = lb(t) - (s.length + |s - x(t)|) - delta > 0.
    // Its zeros solve |p - x| = |s - x| + k (k = s.length - apex_length + delta); squaring twice
    // gives a quadratic whose roots include every zero. No root in the (widened) interval: D has
    // one sign there, read at the middle.
    let (lo, hi) = (ta - PARAMETER_SLACK, tb + PARAMETER_SLACK);
    let k = s.length - apex_length + delta;
    let qp = apex - a.point;
    let qs = s.point - a.point;
    let alpha = qp.norm_squared() - qs.norm_squared() - k * k;
    let beta = -2.0 * (qp - qs).dot(&w);
    let qa = beta * beta - 4.0 * k * k * len * len;
    let qb = 2.0 * alpha * beta + 8.0 * k * k * qs.dot(&w);
    let qc = alpha * alpha - 4.0 * k * k * qs.norm_squared();
    let size = qa.abs().max(qb.abs()).max(qc.abs());
    if !(size.is_finite()) || qa.abs() <= PARAMETER_SLACK * size {
        return false;
    }
    let disc = qb * qb - 4.0 * qa * qc;
    if disc >= -PARAMETER_SLACK * qb * qb {
        let r = disc.max(0.0).sqrt();
        for t in [(-qb - r) / (2.0 * qa), (-qb + r) / (2.0 * qa)] {
            if !t.is_finite() || (lo..=hi).contains(&t) {
                return false;
            }
        }
    }
    let mid = 0.5 * (ta + tb);
    lb(mid) - (s.length + (at(mid) - s.point).norm()) > delta
}

/// One arrival per triangulation edge for one query (module docs, "A third cover"): slots indexed
/// by half-edge, each the arrival's map vertex (`u32::MAX` for a start that is no map vertex) and
/// length, invalidated by a generation stamp rather than cleared, so a query costs what it
/// touches. An edge's arrival is written to the slots of both its half-edges, so that a lookup
/// (at every expansion) reads one slot and not the twin table and the face kinds first: on the
/// 100,000-obstacle strip those two reads were two of the cover test's three cache misses. The
/// slots are allocated zeroed (the pages a query never touches are never written), 16 bytes per
/// half-edge. Of two arrivals at one edge the one reaching the mouth's middle first is kept.
#[derive(Debug, Clone, Default)]
pub(crate) struct ArrivalStore {
    generation: u32,
    /// `[stamp << 32 | vertex, length bits]` per half-edge slot.
    slots: Vec<[u64; 2]>,
}

/// The vertex id stored for an apex that is no map vertex (the start).
const NO_VERTEX: u32 = u32::MAX;

impl ArrivalStore {
    /// Starts a query on `dcel`.
    pub(crate) fn reset(&mut self, dcel: &Dcel) {
        let half_edges = 3 * dcel.triangle_capacity();
        if self.slots.len() < half_edges {
            // Zeroed allocation: stamp 0 is never current (the generation skips it).
            self.slots = vec![[0u64; 2]; half_edges];
            self.generation = 0;
        }
        self.generation = self.generation.wrapping_add(1);
        if self.generation == 0 {
            self.slots.iter_mut().for_each(|s| s[0] = 0);
            self.generation = 1;
        }
    }

    /// This query's arrival at the funnel's mouth, with the tree's root as the point of an apex
    /// that is no map vertex.
    #[inline]
    pub(crate) fn arrival(
        &self,
        dcel: &Dcel,
        tree: &FunnelTree,
        f: &FunnelState,
    ) -> Option<Arrival> {
        let [tag, bits] = *self.slots.get(f.mouth().index())?;
        if (tag >> 32) as u32 != self.generation {
            return None;
        }
        let vertex = tag as u32;
        Some(Arrival {
            point: if vertex == NO_VERTEX {
                tree.point(tree.root())
            } else {
                dcel.point(VertexId(vertex))
            },
            length: f64::from_bits(bits),
        })
    }

    /// Records the funnel about to be expanded as its mouth's arrival when its apex sees the
    /// whole mouth (both tips hang off the apex) and it reaches the mouth's middle before the
    /// arrival kept so far.
    pub(crate) fn record(&mut self, dcel: &Dcel, tree: &FunnelTree, f: &FunnelState) {
        if tree.node(f.right()).parent() != Some(f.apex())
            || tree.node(f.left()).parent() != Some(f.apex())
        {
            return;
        }
        let mid = nalgebra::center(&tree.point(f.right()), &tree.point(f.left()));
        let length = tree.length(f.apex());
        let reach = length + (tree.point(f.apex()) - mid).norm();
        if let Some(kept) = self.arrival(dcel, tree, f)
            && kept.length + (kept.point - mid).norm() <= reach
        {
            return;
        }
        let vertex = tree.vertex(f.apex()).map_or(NO_VERTEX, |v| v.0);
        let entry = [
            (u64::from(self.generation) << 32) | u64::from(vertex),
            length.to_bits(),
        ];
        let twin = dcel.twin(f.mouth());
        for h in std::iter::once(f.mouth()).chain(twin) {
            if let Some(slot) = self.slots.get_mut(h.index()) {
                *slot = entry;
            }
        }
    }

    /// Bytes held.
    pub(crate) fn held_bytes(&self) -> usize {
        self.slots.capacity() * 16
    }
}
