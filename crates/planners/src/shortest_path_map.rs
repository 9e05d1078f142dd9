//! The shortest path map from one start (Mitchell's continuous Dijkstra; Lee and Preparata's
//! funnels; Polyanya's root-level pruning): a complete, goal-less expansion of the shortest path
//! tree over the BTM, computed once, after which the geodesic (shortest free-space path) length and
//! the **last anchor** of any point are answered by a lookup.
//!
//! # Construction
//! The expansion uses the funnels of the SPT search ([`crate::spt`], thesis Alg. 2 and 4) on the
//! universal cover, without a goal: from the start's canonical triangle every funnel is split at
//! the vertex beyond its mouth and both children are queued, in Dijkstra order of the key
//! `g(apex) + dist(apex, mouth)` (made monotone by a `max` with the parent's key), a lower bound
//! of the length of every path through the funnel's mouth. For every funnel expanded the map
//! records the funnel under the triangle beyond its mouth: that triangle is convex and lies beyond
//! the mouth, so every point in it is reached through the funnel along the tree path to the
//! funnel node whose sector holds it ([`FunnelState::predecessor`]).
//!
//! **Root pruning.** A funnel is dropped when its apex is a lift of a map vertex `v` reached with
//! `g` while some other lift of `v` is known strictly shorter (the `K = 1` dominance of
//! [`crate::spt`]): every path through the funnel passes through the apex, and the same suffix
//! after the shorter lift is a strictly shorter free-space path to the same point. The funnels
//! that hold a shortest path have apexes reached optimally, which nothing strictly beats, so they
//! are never dropped; in Dijkstra order every vertex's optimal lift is recorded before any funnel
//! keyed above its distance is expanded, so each vertex is the apex of funnels from (up to ties)
//! one lift only, as in Polyanya, and the expansion ends without a goal: funnels with a fixed apex
//! do not wind (their chains turn by less than pi).
//!
//! **Mouth cover.** Root pruning alone lets every vertex's funnels sweep its whole visibility
//! wedge. A funnel is also dropped when its mouth `ab` is *covered*: every point `x` of the mouth
//! is reached by the path to the mouth's endpoint `a` (or `b`) best known so far followed by the
//! mouth itself, more cheaply than the lower bound `g(apex) + |apex - x|` of any path through the
//! funnel (one point decides). Every path through the funnel to a point
//! beyond crosses the mouth at some `x`, where something strictly shorter already arrives, so the
//! funnel reaches nothing first. A shortest path's funnel is never covered (at its crossing the
//! bound is at most the geodesic distance, which no known path beats), and the test keeps a
//! [`mouth_cover::COVER_MARGIN`] against rounding. The middle of a long mouth is also covered by
//! the edge's *arrival*, the apex of an expanded funnel that sees the whole mouth directly
//! ([`crate::mouth_cover`], "A third cover"): on the 10,000-obstacle strip the map then takes
//! 793,826 expansions instead of 1,471,178.
//!
//! # Query
//! The geodesic length of `p` is the minimum, over the funnels recorded for `p`'s canonical
//! triangle (the triangle a path ending at `p` is assigned to, [`canonical_triangle`], as for the
//! SPT search's goal), of `g(t) + |t - p|` with `t` the funnel node whose sector holds `p`; in the
//! start's own triangle the straight segment from the start. The node `t` is the last anchor:
//! the start, or the last map vertex the taut tether wraps. Each triangle's funnels are kept in
//! ascending order of a lower bound of their lengths to any point of the triangle (`g(apex)` plus
//! the apex's distance to the triangle); a query stops at the first bound not below the best
//! length found, and skips a funnel whose `g(apex) + |apex - p|` (also a lower bound: every path
//! through the funnel runs from its apex to `p`) is not below it. Equal lengths keep the funnel
//! met first.
//!
//! # Bounds
//! The expansion stops with [`SearchError::BudgetExhausted`] after
//! [`ShortestPathMap::build_with_budget`]'s budget of expansions (by default
//! [`ShortestPathMap::default_budget`]: the automatic budget of [`crate::budget`] for one class,
//! at least [`DEFAULT_MAX_EXPANSIONS`]); [`ShortestPathMap::build_until`] also stops at a
//! [`StopCondition`]'s time limit or cancel flag ([`SearchError::Stopped`], read every
//! [`crate::stop::CHECK_INTERVAL`] expansions). Each expansion adds at most one tree node (48 bytes), one record (20 bytes, 16 once
//! packed per triangle, plus an 8-byte bound) and two queue entries (24 bytes each), so the map
//! holds at most about 130 bytes per expansion: [`DEFAULT_MAX_EXPANSIONS`] bounds it near 1 GB,
//! [`crate::budget::AUTO_MAX_EXPANSIONS`] near 13 GB. A query costs
//! `O(f log n)` for the `f` funnels recorded in its triangle (each sector search is logarithmic in
//! the chain length, funnel module docs).

use crate::budget::ExpansionBudget;
use crate::feasibility::distance_to_segment;
use crate::min_heap::{MinEntry, Rank};
use crate::mouth_cover::{self, ArrivalStore, MouthEnd};
use crate::spt::{SearchError, canonical_triangle};
use crate::stop::{StopCondition, StopReason};
use nalgebra::Point2;
use rappel_geometry::btm::{Btm, Location};
use rappel_geometry::dcel::{TriangleId, VertexId};
use rappel_geometry::predicates::orient2d;
use rappel_homotopy::funnel_state::{FunnelState, FunnelTree, NodeId};
use std::collections::BinaryHeap;

/// Smallest default budget of funnel expansions of one map (about 130 bytes each, module docs
/// "Bounds"); larger maps get the automatic budget ([`ShortestPathMap::default_budget`]).
pub const DEFAULT_MAX_EXPANSIONS: usize = 8_000_000;

/// The answer for one point: its geodesic distance from the start and the last anchor of the
/// shortest path (the point before it on the taut path).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Geodesic {
    /// Length of the shortest free-space path from the start, m.
    pub length: f64,
    /// The last anchor: the start, or the last map vertex the shortest path wraps.
    pub last_anchor: Point2<f64>,
    /// The map vertex of the last anchor (`None`: the start).
    pub anchor_vertex: Option<VertexId>,
}

/// Counters of a map's construction.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct MapStats {
    /// Funnels expanded (one record each).
    pub expansions: usize,
    /// Funnels dropped by root pruning.
    pub pruned_dominated: usize,
    /// Nodes of the shortest path tree.
    pub tree_nodes: usize,
    /// Largest number of queued funnels.
    pub queue_peak: usize,
}

/// The shortest path map of one start over a BTM (module docs).
///
/// ```
/// use nalgebra::Point2;
/// use rappel_geometry::{btm::Btm, map::Map, polygon::Polygon};
/// use rappel_planners::shortest_path_map::ShortestPathMap;
/// let p = |x, y| Point2::new(x, y);
/// let map = Map::new(
///     Polygon::new(vec![p(0., 0.), p(10., 0.), p(10., 10.), p(0., 10.)]),
///     vec![Polygon::new(vec![p(4., 4.), p(6., 4.), p(6., 6.), p(4., 6.)])],
/// );
/// let btm = Btm::from_map(&map).unwrap();
/// let spm = ShortestPathMap::build(&btm, p(5., 9.)).unwrap();
/// // Behind the box: around one of its top corners, then straight down.
/// let g = spm.query(p(5., 1.)).unwrap().unwrap();
/// assert!((g.length - (2.0 * 10f64.sqrt() + 2.0)).abs() < 1e-12);
/// assert!(g.last_anchor == p(4., 4.) || g.last_anchor == p(6., 4.));
/// // In plain view: the start itself.
/// assert_eq!(spm.query(p(1., 9.)).unwrap().unwrap().last_anchor, p(5., 9.));
/// ```
#[derive(Debug, Clone)]
pub struct ShortestPathMap<'b> {
    btm: &'b Btm,
    start: Point2<f64>,
    start_triangle: TriangleId,
    tree: FunnelTree,
    /// `funnels[offsets[t]..offsets[t + 1]]` entered triangle `t`.
    offsets: Vec<u32>,
    funnels: Vec<FunnelState>,
    /// `bounds[i]`: a lower bound of the length through `funnels[i]` to any point of its
    /// triangle; ascending within a triangle.
    bounds: Vec<f64>,
    stats: MapStats,
}

/// A queued funnel: equal keys in any order.
impl Rank for FunnelState {
    fn rank(&self) -> usize {
        0
    }
}

impl<'b> ShortestPathMap<'b> {
    /// The map of `start` (a finite point of the closed free space) with the default budget
    /// ([`ShortestPathMap::default_budget`]).
    pub fn build(btm: &'b Btm, start: Point2<f64>) -> Result<Self, SearchError> {
        Self::build_with_budget(btm, start, Self::default_budget(btm))
    }

    /// The default budget of a map on `btm`: the automatic budget of one class
    /// ([`crate::budget::ExpansionBudget::Auto`]), at least [`DEFAULT_MAX_EXPANSIONS`].
    pub fn default_budget(btm: &Btm) -> usize {
        crate::budget::ExpansionBudget::Auto
            .limit(btm.triangle_count(), 1)
            .max(DEFAULT_MAX_EXPANSIONS)
    }

    /// The map of `start` expanding at most `max_expansions` funnels (at least 1); a map that
    /// needs more is [`SearchError::BudgetExhausted`].
    pub fn build_with_budget(
        btm: &'b Btm,
        start: Point2<f64>,
        max_expansions: usize,
    ) -> Result<Self, SearchError> {
        Self::build_until(btm, start, &StopCondition::expansions(max_expansions))
    }

    /// The map of `start` stopped by `stop`: its fixed budget (at least 1), or the default
    /// budget ([`ShortestPathMap::default_budget`]) when it has the automatic one, is
    /// [`SearchError::BudgetExhausted`]; its time limit (from the build's start unless `stop`
    /// was [started](StopCondition::started)) and cancel flags are [`SearchError::Stopped`].
    ///
    /// ```
    /// use nalgebra::Point2;
    /// use rappel_geometry::{btm::Btm, map::Map, polygon::Polygon};
    /// use rappel_planners::shortest_path_map::ShortestPathMap;
    /// use rappel_planners::spt::SearchError;
    /// use rappel_planners::stop::{CancelFlag, StopCondition, StopReason};
    /// let p = |x, y| Point2::new(x, y);
    /// let map = Map::new(
    ///     Polygon::new(vec![p(0., 0.), p(10., 0.), p(10., 10.), p(0., 10.)]),
    ///     vec![Polygon::new(vec![p(4., 4.), p(6., 4.), p(6., 6.), p(4., 6.)])],
    /// );
    /// let btm = Btm::from_map(&map).unwrap();
    /// let flag = CancelFlag::new();
    /// flag.cancel();
    /// let e = ShortestPathMap::build_until(&btm, p(5., 9.), &StopCondition::cancel(flag));
    /// assert!(matches!(e, Err(SearchError::Stopped { reason: StopReason::Cancelled, .. })));
    /// ```
    pub fn build_until(
        btm: &'b Btm,
        start: Point2<f64>,
        stop: &StopCondition,
    ) -> Result<Self, SearchError> {
        let max_expansions = match stop.budget() {
            ExpansionBudget::Fixed(0) => {
                return Err(SearchError::Option("max_expansions must be at least 1"));
            }
            ExpansionBudget::Fixed(n) => n,
            ExpansionBudget::Auto => Self::default_budget(btm),
        };
        let mut watch = stop.watch(max_expansions);
        let start_triangle =
            canonical_triangle(btm, start).map_err(|source| SearchError::Endpoint {
                which: "start",
                point: start,
                source,
            })?;
        let d = btm.dcel();
        let mut tree = FunnelTree::new(start);
        // The shortest known lift of every map vertex, for root pruning.
        let mut best = vec![f64::INFINITY; d.vertex_capacity()];
        if let Location::Vertex(v) = btm.locate(&start) {
            best[v.index()] = 0.0;
        }
        let mut queue = BinaryHeap::new();
        let mut stats = MapStats::default();
        let initial = FunnelState::initial(&mut tree, btm, start_triangle)?;
        for f in &initial {
            for tip in [f.left(), f.right()] {
                let n = tree.node(tip);
                if let Some(v) = n.vertex() {
                    best[v.index()] = best[v.index()].min(n.length);
                }
            }
        }
        for f in initial {
            let key = lower_bound(&tree, &f);
            queue.push(MinEntry { key, item: f });
        }
        // One arrival per edge for the mouth-cover test ([`crate::mouth_cover`]).
        let mut arrivals = ArrivalStore::default();
        arrivals.reset(d);
        let dominated =
            |tree: &FunnelTree, best: &[f64], arrivals: &ArrivalStore, f: &FunnelState| {
                let apex = tree.node(f.apex());
                apex.vertex().is_some_and(|v| best[v.index()] < apex.length)
                    || mouth_is_covered(btm, tree, best, arrivals, f)
            };
        let mut records: Vec<(u32, FunnelState)> = Vec::new();
        while let Some(MinEntry { key, item: funnel }) = queue.pop() {
            if dominated(&tree, &best, &arrivals, &funnel) {
                stats.pruned_dominated += 1;
                continue;
            }
            match watch.check(stats.expansions) {
                None => {}
                Some(StopReason::Expansions { .. } | StopReason::Iterations { .. }) => {
                    return Err(SearchError::BudgetExhausted {
                        expansions: stats.expansions,
                    });
                }
                Some(reason) => {
                    return Err(SearchError::Stopped {
                        reason,
                        expansions: stats.expansions,
                    });
                }
            }
            stats.expansions += 1;
            let next = funnel.next_triangle(btm).ok_or_else(|| {
                SearchError::Internal("a queued funnel has a closed mouth".into())
            })?;
            records.push((next.0, funnel));
            arrivals.record(d, &tree, &funnel);
            let split = funnel.split(&mut tree, btm)?;
            let g = tree.node(split.node).length;
            let b = &mut best[split.vertex.index()];
            *b = b.min(g);
            for child in [split.left, split.right].into_iter().flatten() {
                if dominated(&tree, &best, &arrivals, &child) {
                    stats.pruned_dominated += 1;
                    continue;
                }
                let child_key = lower_bound(&tree, &child).max(key);
                queue.push(MinEntry {
                    key: child_key,
                    item: child,
                });
            }
            stats.queue_peak = stats.queue_peak.max(queue.len());
        }
        stats.tree_nodes = tree.len();
        // Pack the records per triangle, each triangle's by ascending bound (module docs, "Query").
        let mut keyed: Vec<(u32, f64, FunnelState)> = records
            .into_iter()
            .map(|(t, f)| (t, triangle_bound(btm, &tree, TriangleId(t), &f), f))
            .collect();
        keyed.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
        let mut offsets = vec![0u32; d.triangle_capacity() + 1];
        for (t, _, _) in &keyed {
            offsets[*t as usize + 1] += 1;
        }
        for i in 1..offsets.len() {
            offsets[i] += offsets[i - 1];
        }
        let bounds: Vec<f64> = keyed.iter().map(|r| r.1).collect();
        let funnels: Vec<FunnelState> = keyed.into_iter().map(|r| r.2).collect();
        Ok(ShortestPathMap {
            btm,
            start,
            start_triangle,
            tree,
            offsets,
            funnels,
            bounds,
            stats,
        })
    }

    /// The start.
    pub fn start(&self) -> Point2<f64> {
        self.start
    }

    /// The BTM the map lies on.
    pub fn btm(&self) -> &'b Btm {
        self.btm
    }

    /// The construction's counters.
    pub fn stats(&self) -> MapStats {
        self.stats
    }

    /// Bytes held by the map (tree nodes, records, offsets).
    pub fn held_bytes(&self) -> usize {
        self.tree.capacity_bytes()
            + self.funnels.capacity() * std::mem::size_of::<FunnelState>()
            + self.bounds.capacity() * 8
            + self.offsets.capacity() * 4
    }

    /// The geodesic length and last anchor of `p` (module docs, "Query"); `None` when no
    /// free-space path reaches it. A point that is not a finite point of the closed free space is
    /// [`SearchError::Endpoint`].
    pub fn query(&self, p: Point2<f64>) -> Result<Option<Geodesic>, SearchError> {
        let t = canonical_triangle(self.btm, p).map_err(|source| SearchError::Endpoint {
            which: "query",
            point: p,
            source,
        })?;
        let mut best: Option<Geodesic> = None;
        let offer = |best: &mut Option<Geodesic>, node: NodeId| {
            let mut n = self.tree.node(node);
            // A point on a tree node: the anchor is the node's own predecessor.
            let length = n.length + (p - n.point).norm();
            if n.point == p
                && let Some(parent) = n.parent()
            {
                n = self.tree.node(parent);
            }
            if best.is_none_or(|b| length < b.length) {
                *best = Some(Geodesic {
                    length,
                    last_anchor: n.point,
                    anchor_vertex: n.vertex(),
                });
            }
        };
        if t == self.start_triangle {
            // The start's triangle is convex: the straight segment.
            offer(&mut best, self.tree.root());
        }
        let (a, b) = (
            self.offsets[t.index()] as usize,
            self.offsets[t.index() + 1] as usize,
        );
        for (f, bound) in self.funnels[a..b].iter().zip(&self.bounds[a..b]) {
            let known = best.map_or(f64::INFINITY, |b| b.length);
            if *bound >= known {
                // Every later funnel's bound is at least this one's.
                break;
            }
            let apex = self.tree.node(f.apex());
            if apex.length + (p - apex.point).norm() >= known {
                continue;
            }
            offer(&mut best, f.predecessor(&self.tree, &p));
        }
        Ok(best)
    }
}

/// A lower bound of the length of every path through the funnel's mouth: `g(apex)` plus the
/// distance from the apex to the mouth segment ([`mouth_cover::reach_bound`]).
fn lower_bound(tree: &FunnelTree, f: &FunnelState) -> f64 {
    mouth_cover::reach_bound(tree, f, tree.length(f.apex()))
}

/// `true` when the funnel's mouth is covered from its endpoints' best known lengths or its edge's
/// arrival ([`crate::mouth_cover`]).
fn mouth_is_covered(
    btm: &Btm,
    tree: &FunnelTree,
    best: &[f64],
    arrivals: &ArrivalStore,
    f: &FunnelState,
) -> bool {
    let d = btm.dcel();
    let m = f.mouth();
    let end = |v: VertexId| MouthEnd {
        point: d.point(v),
        best: best[v.index()],
    };
    let apex = tree.node(f.apex());
    mouth_cover::is_covered_with(
        &apex.point,
        apex.length,
        end(d.origin(m)),
        end(d.destination(m)),
        arrivals.arrival(d, tree, f),
    )
}

/// A lower bound of the length of every path through `f` to a point of triangle `t` (beyond
/// its mouth): `g(apex)` plus the distance from the apex to the triangle (every such path runs
/// from the apex to the point).
fn triangle_bound(btm: &Btm, tree: &FunnelTree, t: TriangleId, f: &FunnelState) -> f64 {
    let apex = tree.node(f.apex());
    let [a, b, c] = btm.dcel().triangle_points(t);
    let q = &apex.point;
    let (ab, bc, ca) = (
        orient2d(&a, &b, q),
        orient2d(&b, &c, q),
        orient2d(&c, &a, q),
    );
    let inside = (ab >= 0.0 && bc >= 0.0 && ca >= 0.0) || (ab <= 0.0 && bc <= 0.0 && ca <= 0.0);
    let distance = if inside {
        0.0
    } else {
        distance_to_segment(q, &a, &b)
            .min(distance_to_segment(q, &b, &c))
            .min(distance_to_segment(q, &c, &a))
    };
    apex.length + distance
}
