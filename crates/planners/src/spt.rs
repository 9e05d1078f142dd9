//! A* search of the shortest path tree (thesis §2.3.3, Algorithms 3-4; Guibas et al., Hershberger
//! and Snoeyink): the shortest homotopic paths (SHPs) from a start to a goal, one per homotopy
//! class, lazily and in non-decreasing length.
//!
//! # The search space
//! Lifted to the universal cover of the BTM (thesis §2.2.2, Fig. 2.6) the dual graph of the
//! triangulation is a tree, and the shortest path tree (SPT) from the start is the tree of all
//! shortest paths to all lifts of all points. A search state is a funnel on the cover
//! ([`FunnelState`]: two chains, an apex and a mouth, thesis Fig. 2.12); expanding it (Alg. 4,
//! "Expand Kite") splits it at the vertex beyond its mouth into at most two children (Alg. 2), and
//! the sequence of mouths crossed is a reduced crossing sequence, so every funnel reaches a
//! different lift of its triangle. Whenever a funnel enters a lift of the goal's triangle the
//! goal's lift is reached through that funnel, and its shortest path there is the SHP of one
//! homotopy class (the class whose reduced crossing sequence is the funnel's mouth sequence). Each
//! class is reached exactly once. Start and goal triangles are chosen by the canonical-endpoint
//! rule of [`rappel_homotopy::crossing`] (the triangle [`Tracer::new`] starts in), so a class's
//! sleeve equals the reduced crossing sequence of any path in it.
//!
//! # The key (eq. 2.5, made admissible everywhere)
//! The thesis keys a funnel by `f = g(t_g) + |t_g - v_g|` where `t_g = pred(v_g)` is the funnel
//! node whose sector holds the goal (eq. 2.5). When the goal lies beyond the line of the funnel's
//! mouth `d` this is exactly `min over x in d of (g(x) + |x - v_g|)`, the length of the shortest
//! path through the funnel to the goal with every obstacle beyond `d` ignored: an admissible,
//! consistent A* key. When the goal lies *behind* the mouth's line (a funnel leading away from
//! the goal, to come back around an obstacle) eq. 2.5 can overestimate that minimum. rappel then
//! evaluates eq. 2.5 at the goal's mirror image across the mouth's line, which gives the same
//! minimum (reflection preserves `|x - v_g|` for `x` on the line), so the key is always the exact
//! relaxed distance. Keys are made monotone (`max` with the parent's key), so popped keys never
//! decrease; a goal entry's key is its path length, and SHPs come out in non-decreasing length
//! (up to the rounding of the lengths themselves, about 1e-15 relative).
//!
//! # Termination (the thesis leaves it open: Alg. 3 can run forever)
//! The search stops, whichever comes first ([`Termination`]):
//! - **count**: `max_classes` classes found;
//! - **length**: the next candidate is longer than `max_length_factor` times the first SHP;
//! - **expansions**: `max_expansions` funnels expanded;
//! - **time limit** and **cancel**: the options' [`StopCondition`] ([`SearchOptions::with_stop`]:
//!   a wall-clock limit from the search's start, or a [`crate::stop::CancelFlag`] another thread
//!   sets), read every [`crate::stop::CHECK_INTERVAL`] expansions ([`crate::stop`], "Check
//!   cadence"); which one fired is [`SptSearch::stop_reason`];
//! - **exhausted**: no funnel left (the cover is finite only without obstacles, or when a length
//!   bound or the simple-classes mode cuts it);
//! - **disconnected**: start and goal lie in different connected components of free space. This
//!   is answered before any search from component labels of the dual graph ([`SptPlanner::new`]).
//!
//! # Several classes: a geodesic bound through the apex
//! With the Euclidean key alone, A* expands every funnel whose relaxed distance is below the
//! `K`-th class's length, which on a long strip is nearly every lift of every triangle, `K` times
//! over. When more than one class is wanted the search therefore first runs the single-class
//! search backwards (goal to start, length `L_1`) and keeps, for every map vertex `v`, the
//! shortest lift it recorded, `r(v)`. A vertex with `r(v) + |v - v_s| < L_1` was certainly reached
//! optimally by that A* (the funnel holding its shortest path had a key below `L_1`), so its
//! geodesic distance to the goal is `h(v) = r(v)`; for every other vertex
//! `h(v) >= max(|v - v_g|, L_1 - |v - v_s|)`, since `g*(v) + |v - v_s| >= L_1` there
//! ([`SptPlanner::goal_distances`]). Every SHP below a funnel passes through its apex, so
//! `g(apex) + h(apex)` is a second admissible, monotone key; the search uses the larger of the
//! two. On the 10,000-obstacle strip this cuts the expansions for 10 classes tenfold.
//!
//! # Dominance pruning with a class count
//! When at most `K` classes are wanted, a funnel whose apex is a lift `v'` of a map vertex `v`
//! reached with `g(v')` is pruned as soon as `K` other lifts of `v` are known with strictly
//! smaller `g`. Every SHP found below the funnel passes through `v'` (the apex chain is a prefix of
//! every path in the funnel), so it is `p' . s` for the tree path `p'` to `v'` and some suffix
//! `s`; each shorter lift gives a different class `p_i . s` no longer than `g_i + |s| < g(v') +
//! |s|`: `K` strictly shorter classes, so the pruned one is not among the `K` shortest. This is the
//! homotopy-aware form of Polyanya's root-level pruning and keeps the search near-linear on large
//! maps; without a count (or in the simple-classes mode, whose dominating classes need not be
//! simple) no funnel is pruned this way.
//!
//! **One class: the mouth cover.** With `K = 1` the class wanted is the globally shortest path,
//! so a funnel may also be dropped for a shorter path in *another* class: when every point of its
//! mouth is reached more cheaply from the mouth's endpoints (their shortest known lifts, then
//! along the free edge) or from the edge's *arrival* (the apex of an expanded funnel through the
//! same edge that sees the whole edge directly) than the funnel's bound `g(apex) + |apex - x|`
//! allows ([`crate::mouth_cover`]). Root pruning leaves every vertex reached optimally to sweep
//! its whole visibility wedge (on the 10,000-obstacle strip about 46 expansions per apex, with no
//! apex ever expanded from a suboptimal lift); the cover ends the sweeps where other vertices
//! already arrive first. On the crater strips it cuts the first SHP's expansions from 272,785 to
//! 167,499 (10k obstacles) and from 16.5 to 6.8 million (100k), with the same lengths. The
//! cover's proof needs only that the covering paths are real, so the `K = 1` reverse search of
//! [`SptPlanner::goal_distances`] keeps its guarantee (the funnel holding a vertex's shortest
//! path is never covered).
//!
//! # The wave order (one class)
//! On a long map whose shortest path is nearly straight every funnel's A* key lies within a few
//! metres of the answer's (the crater strips: 2 m in 75 km), so the A* order pops funnels from
//! all along the map at once, and on a map whose search state is gigabytes every pop misses the
//! cache and the TLB. The one-class search ([`QueueOrder::Auto`] with `max_classes` 1) therefore
//! pops in the **wave order**: by the key's *band* first (the key rounded down to
//! [`WAVE_BAND_BITS`] bits of mantissa: keys within a factor `1 + 2^-20` of each other share a
//! band), then within a band by the funnel's **reach bound** `g(apex) + dist(apex, mouth)`, a
//! lower bound of every path through the funnel to its mouth. Within a band the search then
//! sweeps the map from the start outwards like Dijkstra's, touching memory in the order it lies
//! on the ground; the bands keep A*'s focus.
//!
//! *Why the answer is the same.* Take a shortest path of length `L*` and the funnels holding it.
//! A funnel's key and reach are lower bounds of every path through it (key >= reach), and a
//! goal entry's key and reach are both its length. While the goal entry of some path of length
//! `L > L*` waits, some funnel `F` holding the shortest path is queued with key <= `L*` and
//! reach <= `L*`. `F`'s band is no later than the goal's (`key(F) <= L*< L`, and rounding down
//! keeps the order); in the same band `F`'s reach, rounded *down*, is at most `L*`, and the
//! goal's reach `L`, rounded *up*, at least `L*`; on equal words funnels pop first. So `F` pops
//! before that goal entry, and the first goal popped has length `L*`. A child's word is the
//! maximum of its own and its parent's (both lower bounds of the child's paths, in this
//! lexicographic sense), so words never decrease and the radix queue's invariant holds. The
//! pruning rules are the same in every order (root pruning and the mouth cover compare with
//! lengths of real paths, the incumbent with exact keys). The reverse search of
//! [`SptPlanner::goal_distances`] keeps its guarantee too: every funnel keyed below `L_1` pops
//! before the goal in this order as well.
//!
//! *What it costs and gains* (crater strips, one process, `first_shp_interleaved`): a funnel whose
//! key lies in the goal's band but above `L*` may now be expanded (A* would never pop it): at
//! 10,000 obstacles 169,062 expansions against 167,499, at 100,000 6,834,277 against 6,793,154,
//! at 1,000,000 80.6 against 67.1 million. In exchange the search walks its memory in order:
//! the 100,000-obstacle query takes about 0.7 of the A* order's time, the 1,000,000-obstacle one
//! about 0.45; the 10,000-obstacle one, whose state fits in the cache, about 1.1 (measurements
//! in `docs/planner.md`, "The wave order"). [`QueueOrder::AStar`] keeps the A* order, and
//! *One band on long corridors.* One band (the key's binade) makes the order Dijkstra's by the
//! reach bound: a single sweep, the best locality, but no A* focus, so it expands every funnel
//! reaching less than the answer, also outside the A* ellipse. That surplus is small once the
//! ellipse spans the free space across the start-goal line (1.03 times the expansions on the
//! 1,000,000-obstacle strip) and large while it does not (3.6 times on a 15,000-obstacle
//! strip). The automatic order therefore switches to one band at the first popped key `k` with
//! `k^2 >= D^2 + 4 w^2` (`D` the start-goal distance, `w` the largest distance of a boundary
//! vertex from their line): every path is then at least `k` long, and the ellipse of major axis
//! `k` has a semi-minor axis of at least `w`. It never switches when the free space reaches
//! behind the start by more than [`SWEEP_BEHIND_FRACTION`] of `D` (one band would sweep that
//! too). At the switch every queued entry is queued again, in the emptied queue, under its word
//! in the new layout from its own reach bound (a goal's from its length): valid words,
//! as above, and words never decrease from there on, so the proof holds after the switch as
//! before it. In one band a funnel's word is its reach's (the band is the reach's binade), so
//! its A* key orders nothing: a child is then keyed by its reach bound (also a lower bound of
//! its paths) and the A* key, a sector scan of the funnel's chains for the goal, is computed
//! only while an incumbent or a length limit prunes by it (their prunings stay exactly as in
//! the other orders). On the 1,000,000-obstacle strip the first SHP takes about 22 s instead of
//! 34 s with a third less memory; at 100,000 about 2.3 s instead of 3.7 s; the 10,000- and
//! 20,000-obstacle strips never switch (`docs/planner.md`, "One band").
//! [`SearchStats::swept_at`] tells whether, and after how many expansions, a search switched.
//!
//! [`QueueOrder::Wave`] takes another band width (fewer bits: wider bands, closer to Dijkstra's
//! order by the reach bound). With several classes the A* order is kept: goal entries of two
//! classes within a reach unit of each other could otherwise come out of order.
//!
//! # Collecting the tree
//! Root pruning, the mouth cover and the incumbent drop most funnels, and with them the only
//! references to most tree nodes: a node is needed while a queued funnel or goal entry holds it
//! (as a tip, or as an ancestor of one). The search therefore collects its tree
//! ([`FunnelTree::collect`], module [`rappel_homotopy::funnel_state`], "Collection") when the
//! tree has grown to twice the nodes the last collection kept (and at least
//! [`COLLECT_MIN_NODES`]), between two pops, where the queue is the only holder of node ids:
//! it marks the ancestors of every queued entry's nodes, keeps those nodes in their order and
//! renumbers the ids in the queue. Lengths, points and the order of ids are unchanged, and no
//! decision reads a node id's value, so the search makes the same decisions and returns the same
//! answers (a unit test checks this bit for bit with collections every few nodes). Each
//! collection costs a pass over the tree and the queue, once per doubling, so the cost per node
//! added stays constant. Not in the simple-classes mode, whose verdicts are kept per node.
//!
//! The first SHP on the 1,000,000-obstacle strip keeps at most 4-5 million of its nodes at a
//! collection, where it made over 100 million: its search's peak memory falls from 3.3 GB to
//! about 1 GB, and the tree's pages are reused instead of being faulted in and zeroed by the
//! kernel (measurements in `docs/planner.md`, "Collecting the tree"). Below about 10,000
//! obstacles the tree never reaches [`COLLECT_MIN_NODES`].
//!
//! # Pruning and straight-through expansion (Polyanya's rules, on funnels)
//! - **The incumbent.** When `r` classes are still wanted (a class count is set, and every goal
//!   reached is returned: not in the simple-classes mode) and `r` goal entries are queued with keys
//!   at most `b`, every funnel keyed `b` or more is dropped before it enters the queue: its key
//!   and those of everything below it are at least `b`, goals pop before funnels on equal keys,
//!   so the `r` queued goals end the search first. For the single query this is Polyanya's "never
//!   push a node that cannot beat the best path found".
//! - **Straight through.** When an expansion leaves exactly one child and that child's key equals
//!   the funnel's (keys are monotone, so it is then a minimum of the queue), the child is expanded
//!   at once, without a round trip through the heap: Polyanya's expansion of one-successor
//!   nodes, restricted to equal keys so that the expansion order stays an A* order. Every such
//!   expansion counts against the budget.
//!
//! # Per-query cost
//! An [`SptPlanner`] keeps a small pool of search scratch spaces (the tree's nodes, the queue, the
//! trail of mouths, the per-vertex lifts). A search takes one and gives it back when dropped; the
//! per-vertex lifts are invalidated by a generation stamp, not refilled, so a query on a prepared
//! map costs what the search touches, and allocates nothing once the pool is warm (beyond its
//! answer). Searches on several threads each take their own space. [`SptPlanner::shortest_taut_path`]
//! answers with the path alone, without the sleeve, crossings and H-signature of a class. The
//! class answer's simplicity lists and H-signature crossings are buffers of the scratch space too.
//!
//! What lies across a funnel's mouth (Alg. 3 line 11: the vertex `v`, its point and the exits
//! `d_alpha`, `d_beta`) is read from the planner's [`KiteTable`], one 32-byte record per
//! half-edge, instead of eight scattered loads from the DCEL (the twins, faces, origin and
//! vertex point), and the key reads the mouth's ends from the funnel's tips in the tree: on a
//! 100,000-obstacle strip the DCEL is far beyond the cache and its vertex points are in the map's
//! order, so those loads missed. The table costs 32 bytes per half-edge slot of the DCEL (the
//! scaffolded triangulation of `n` vertices has `2n + 1` triangles: about 192 bytes per map
//! vertex), built with the planner.
//!
//! The queue is a radix heap over the keys' bits, with the funnels in an arena beside it
//! (`min_heap::ArenaHeap`): every key pushed is at least the key of the funnel being expanded
//! (the children's and the goal's keys are `max`ed with it, pathmax), hence at least the last key
//! popped, so a push appends 16 bytes to the bucket of its first bit differing from that key
//! instead of sifting through a heap that holds up to 864k funnels on a 100,000-obstacle strip.
//! Funnels of equal key and rank pop in the order of their arena index (a function of the
//! search's operations, so the search stays deterministic).
//!
//! A queued funnel carries its apex's path length and map vertex (copied from the tree when a
//! funnel gets a new apex, at most once per expansion): the dominance test at a push and at a
//! pop, and the apex bound of the key, read them from the item instead of from the tree's two
//! arrays. On the 100,000-obstacle strip 6.2 million funnels are popped only to be dropped as
//! dominated; each then costs the load of its vertex's lifts alone.
//!
//! # H-signatures
//! A class's H-signature is the same in its two forms ([`rappel_homotopy::h_signature`]): the
//! winding form over the SHP's polyline tests every pole in each segment's `y` band; the sleeve
//! form reads the crossed cuts of each sleeve triangle from a per-map [`CutIndex`]. On the crater
//! strips the winding form is the cheaper (a path down a strip crosses the cuts of about half the
//! poles in its band anyway, and the poles lie contiguous in memory, where the sleeve's
//! triangles are scattered); the sleeve form pays on maps wide across the path, where the band
//! holds many poles the path never passes. [`SptPlanner::h_signature`] takes the cheaper by
//! counting (two binary searches per SHP segment), and builds the index only once the winding
//! form's excess over the answered classes has cost as much as building it.
//!
//! # Simple classes
//! A class is **simple** when, in its SHP's list of anchors (the map vertices the taut tether
//! wraps, in order), no map vertex occurs twice and the anchors on each obstacle are consecutive:
//! the tether touches every obstacle in one contiguous stretch and turns there by less than a full
//! turn (around a convex hull, a full turn would repeat a vertex). So no tether winds around any
//! obstacle more than once, and none comes back to an obstacle it has left (which also excludes
//! the commutator classes that H-signatures cannot tell from the trivial class, module
//! [`rappel_homotopy::h_signature`]). The test is combinatorial and exact ([`is_simple_class`]).
//! In the simple-classes mode funnels whose apex chain is already not simple are pruned (the apex
//! chain's anchors are anchors of every SHP below), so only finitely many funnels are ever
//! expanded and the search always ends.

use crate::budget::ExpansionBudget;
use crate::min_heap::{ArenaHeap, Rank, key_of_ordered, ordered_bits};
use crate::mouth_cover::{self, ArrivalStore, MouthEnd};
use crate::stop::{StopCondition, StopReason, StopWatch};
use nalgebra::{Point2, Vector2};
use rappel_geometry::btm::Btm;
use rappel_geometry::compact::Compact;
use rappel_geometry::dcel::{HalfEdgeId, ObstacleId, TriangleId, VertexId};
use rappel_geometry::predicates::orient2d;
use rappel_homotopy::crossing::{CrossingSequence, Tracer};
use rappel_homotopy::funnel::TautPath;
use rappel_homotopy::funnel_state::{FunnelState, FunnelStateError, FunnelTree, NodeId, TreeMarks};
use rappel_homotopy::h_signature::{CutIndex, HSignature, Poles};
use rappel_homotopy::kite::{Kite, KiteTable};
use rappel_homotopy::path::PathError;
use rappel_homotopy::shp::ShortestHomotopicPath;
use rappel_homotopy::sleeve::{Sleeve, SleeveError};
use serde::{Deserialize, Serialize};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, OnceLock};

/// Default number of classes a search returns.
pub const DEFAULT_MAX_CLASSES: usize = 10;
/// The fixed budget of funnel expansions the searches had before budgets followed the map (about
/// 130 bytes of search state each); the automatic budget ([`ExpansionBudget::Auto`], the default)
/// never gives less.
pub const DEFAULT_MAX_EXPANSIONS: usize = crate::budget::AUTO_MIN_EXPANSIONS;

/// Marks "no parent" in the trail of mouths and "no component" in the labels.
const NONE: u32 = u32::MAX;

/// Why a search could not be set up or run.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SearchError {
    /// The start or the goal is not a finite point of free space.
    #[error("the {which} point ({}, {}) is not usable: {source}", Compact(point.x), Compact(point.y))]
    Endpoint {
        /// `"start"` or `"goal"`.
        which: &'static str,
        /// The point.
        point: Point2<f64>,
        /// What is wrong with it.
        source: PathError,
    },
    /// The expansion budget ran out before the search could answer (not a proof that start and
    /// goal are disconnected).
    #[error(
        "the search budget ran out after {expansions} expansions before a path was found (this does not mean start and goal are disconnected; raise the budget)"
    )]
    BudgetExhausted {
        /// Funnel expansions made.
        expansions: usize,
    },
    /// The time limit ran out, or the search was cancelled, before it could answer (the
    /// expansion budget is [`SearchError::BudgetExhausted`]).
    #[error(
        "the search stopped at {reason} after {expansions} expansions before a path was found (this does not mean start and goal are disconnected)"
    )]
    Stopped {
        /// The condition that fired ([`StopReason::TimeLimit`] or [`StopReason::Cancelled`]).
        reason: StopReason,
        /// Funnel expansions made.
        expansions: usize,
    },
    /// A search option is out of range; the message says which and the valid range.
    #[error("invalid search option: {0}")]
    Option(&'static str),
    /// A funnel or sleeve operation failed: a bug, reported instead of a panic.
    #[error("internal search error: {0}")]
    Internal(String),
}

impl From<FunnelStateError> for SearchError {
    fn from(e: FunnelStateError) -> Self {
        SearchError::Internal(e.to_string())
    }
}

impl From<SleeveError> for SearchError {
    fn from(e: SleeveError) -> Self {
        SearchError::Internal(e.to_string())
    }
}

/// Settings of an SPT search (module docs, "Termination"), with validated setters.
///
/// ```
/// use rappel_planners::spt::SearchOptions;
/// let o = SearchOptions::default()
///     .with_max_classes(Some(3)).unwrap()
///     .with_max_length_factor(Some(1.5)).unwrap()
///     .with_simple_only(true);
/// assert_eq!(o.max_classes(), Some(3));
/// assert!(SearchOptions::default().with_max_length_factor(Some(0.5)).is_err());
/// ```
///
/// The expansion budget, a time limit and cancel flags are one [`StopCondition`]
/// ([`SearchOptions::with_stop`]); serialized as `max_expansions` (and `time_limit_s` when set).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SearchOptions {
    max_classes: Option<usize>,
    max_length_factor: Option<f64>,
    #[serde(flatten)]
    stop: StopCondition,
    simple_only: bool,
    #[serde(default = "default_trail_limit")]
    trail_limit: usize,
    /// Programmatic only (not read from or written to scenario files and reports): every order
    /// returns the same classes.
    #[serde(skip)]
    queue_order: QueueOrder,
}

/// The order in which a search pops its funnels (module docs, "The wave order"). Every order
/// returns the same classes with the same lengths; they differ in the funnels expanded on the
/// way and in how their memory is touched.
///
/// ```
/// use nalgebra::Point2;
/// use rappel_geometry::{btm::Btm, map::Map, polygon::Polygon};
/// use rappel_planners::spt::{QueueOrder, SearchOptions, SptPlanner};
///
/// let p = |x, y| Point2::new(x, y);
/// let square = |x: f64, y: f64| {
///     Polygon::new(vec![p(x, y), p(x + 1.0, y), p(x + 1.0, y + 1.0), p(x, y + 1.0)])
/// };
/// let boundary = Polygon::new(vec![p(0., 0.), p(10., 0.), p(10., 10.), p(0., 10.)]);
/// let map = Map::new(boundary, vec![square(2.0, 4.0), square(4.5, 5.0)]);
/// let btm = Btm::from_map(&map).unwrap();
/// let planner = SptPlanner::new(&btm);
/// let (a, b) = (Point2::new(5.0, 9.0), Point2::new(4.0, 1.0));
/// let one = SearchOptions::default().with_max_classes(Some(1)).unwrap();
/// let length = |order| {
///     let options = one.clone().with_queue_order(order);
///     planner.search(a, b, &options).unwrap().next().unwrap().unwrap().length()
/// };
/// let wave = length(QueueOrder::Auto);
/// assert_eq!(wave, length(QueueOrder::AStar));
/// assert_eq!(wave, length(QueueOrder::Wave { band_bits: 0 }));
/// // The wave order is for one class only.
/// let many = SearchOptions::default().with_queue_order(QueueOrder::Wave { band_bits: 4 });
/// assert!(planner.search(a, b, &many).is_err());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum QueueOrder {
    /// The wave order with bands of [`WAVE_BAND_BITS`] bits when one class is wanted
    /// (`max_classes` 1, not the simple-classes mode), switching to one band once the A*
    /// ellipse is proven to span the free space (module docs, "The wave order"); the A* order
    /// otherwise.
    #[default]
    Auto,
    /// The A* order always: by eq. 2.5's key, goals before funnels on equal keys.
    AStar,
    /// The wave order with keys banded to `band_bits` bits of mantissa (at most 52; a band spans
    /// a factor `1 + 2^-band_bits` of key): fewer bits make wider bands, an order closer to
    /// Dijkstra's by the reach bound. One class only: a search asked for it with another class
    /// count, or in the simple-classes mode, is refused ([`SearchError::Option`]).
    ///
    /// `band_bits: 0` (one band per binade of key: a single sweep by the reach bound) from the
    /// start suits long corridors whose A* ellipse spans their width; on maps wider than the
    /// ellipse it expands far more (3.6 times on the 15,000-obstacle strip, `docs/planner.md`,
    /// "One band"). An explicit band width never switches.
    Wave {
        /// Mantissa bits of the key kept in the band (0-52).
        band_bits: u32,
    },
}

fn default_trail_limit() -> usize {
    TRAIL_MAX_ENTRIES
}

impl Default for SearchOptions {
    /// [`DEFAULT_MAX_CLASSES`] classes, no length bound, the automatic expansion budget
    /// ([`ExpansionBudget::Auto`]), every class, a trail of at most [`TRAIL_MAX_ENTRIES`] mouths.
    fn default() -> Self {
        SearchOptions {
            max_classes: Some(DEFAULT_MAX_CLASSES),
            max_length_factor: None,
            stop: StopCondition::none(),
            simple_only: false,
            trail_limit: TRAIL_MAX_ENTRIES,
            queue_order: QueueOrder::Auto,
        }
    }
}

impl SearchOptions {
    /// The order the search pops its funnels in ([`QueueOrder`]; the answer does not depend on
    /// it).
    pub fn with_queue_order(mut self, order: QueueOrder) -> Self {
        self.queue_order = order;
        self
    }

    /// The order the search pops its funnels in.
    pub fn queue_order(&self) -> QueueOrder {
        self.queue_order
    }

    /// Stop after `k` classes (`None`: no count; at least 1).
    pub fn with_max_classes(mut self, k: Option<usize>) -> Result<Self, SearchError> {
        if k == Some(0) {
            return Err(SearchError::Option("max_classes must be at least 1"));
        }
        self.max_classes = k;
        Ok(self)
    }

    /// Stop before the first class longer than `factor` times the shortest (`None`: no bound;
    /// finite and at least 1).
    pub fn with_max_length_factor(mut self, factor: Option<f64>) -> Result<Self, SearchError> {
        if let Some(f) = factor
            && !(f.is_finite() && f >= 1.0)
        {
            return Err(SearchError::Option(
                "max_length_factor must be a finite number >= 1",
            ));
        }
        self.max_length_factor = factor;
        Ok(self)
    }

    /// Stop after `n` funnel expansions (at least 1).
    pub fn with_max_expansions(mut self, n: usize) -> Result<Self, SearchError> {
        if n == 0 {
            return Err(SearchError::Option("max_expansions must be at least 1"));
        }
        self.stop = self.stop.with_budget(ExpansionBudget::Fixed(n));
        Ok(self)
    }

    /// Bound the expansions as `budget` says ([`ExpansionBudget::Fixed`] at least 1), keeping
    /// the time limit and cancel flags.
    pub fn with_budget(self, budget: ExpansionBudget) -> Result<Self, SearchError> {
        match budget {
            ExpansionBudget::Fixed(n) => self.with_max_expansions(n),
            ExpansionBudget::Auto => Ok(SearchOptions {
                stop: self.stop.with_budget(ExpansionBudget::Auto),
                ..self
            }),
        }
    }

    /// Stop as `stop` says (replacing the budget, time limit and cancel flags; a fixed budget
    /// at least 1).
    ///
    /// ```
    /// use std::time::Duration;
    /// use rappel_planners::spt::SearchOptions;
    /// use rappel_planners::stop::{CancelFlag, StopCondition};
    /// let flag = CancelFlag::new();
    /// let o = SearchOptions::default()
    ///     .with_stop(StopCondition::time(Duration::from_secs(2)).or_cancel(flag))
    ///     .unwrap();
    /// assert_eq!(o.stop().time_limit(), Some(Duration::from_secs(2)));
    /// assert!(SearchOptions::default().with_stop(StopCondition::expansions(0)).is_err());
    /// ```
    pub fn with_stop(mut self, stop: StopCondition) -> Result<Self, SearchError> {
        if stop.budget() == ExpansionBudget::Fixed(0) {
            return Err(SearchError::Option("max_expansions must be at least 1"));
        }
        self.stop = stop;
        Ok(self)
    }

    /// The stop condition: expansion budget, time limit, cancel flags.
    pub fn stop(&self) -> &StopCondition {
        &self.stop
    }

    /// Return simple classes only (module docs, "Simple classes").
    pub fn with_simple_only(mut self, simple_only: bool) -> Self {
        self.simple_only = simple_only;
        self
    }

    /// Record at most `n` funnel mouths for building sleeves from the search's trail; beyond
    /// that the trail is dropped and sleeves are traced from the SHPs (the same sleeves: a
    /// memory bound, not an approximation). Default [`TRAIL_MAX_ENTRIES`].
    pub fn with_trail_limit(mut self, n: usize) -> Self {
        self.trail_limit = n;
        self
    }

    /// The trail limit.
    pub fn trail_limit(&self) -> usize {
        self.trail_limit
    }

    /// The class count, if any.
    pub fn max_classes(&self) -> Option<usize> {
        self.max_classes
    }

    /// The length factor, if any.
    pub fn max_length_factor(&self) -> Option<f64> {
        self.max_length_factor
    }

    /// The expansion budget.
    pub fn budget(&self) -> ExpansionBudget {
        self.stop.budget()
    }

    /// The expansions this search may make on `btm` ([`ExpansionBudget::limit`] with the class
    /// count, [`DEFAULT_MAX_CLASSES`] when there is none).
    pub fn expansion_limit(&self, btm: &Btm) -> usize {
        self.stop.expansion_limit(
            btm.triangle_count(),
            self.max_classes.unwrap_or(DEFAULT_MAX_CLASSES),
        )
    }

    /// Whether only simple classes are returned.
    pub fn simple_only(&self) -> bool {
        self.simple_only
    }
}

/// Why a search stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Termination {
    /// `max_classes` classes were found.
    ClassCount,
    /// The next candidate is longer than `max_length_factor` times the shortest.
    LengthFactor,
    /// The expansion budget ran out.
    Expansions,
    /// The time limit of the options' [`StopCondition`] ran out.
    TimeLimit,
    /// A cancel flag of the options' [`StopCondition`] was set.
    Cancelled,
    /// No funnel is left: every class (within the bounds) has been returned.
    Exhausted,
    /// Start and goal lie in different connected components of free space: no path exists.
    Disconnected,
}

impl Termination {
    /// A short phrase for reports.
    pub fn describe(&self) -> &'static str {
        match self {
            Termination::ClassCount => "the requested number of classes was found",
            Termination::LengthFactor => "the next class would exceed the length factor",
            Termination::Expansions => "the search budget ran out (raise it)",
            Termination::TimeLimit => "the time limit ran out",
            Termination::Cancelled => "the search was cancelled",
            Termination::Exhausted => "no further class exists within the bounds",
            Termination::Disconnected => {
                "start and goal lie in different connected components of free space"
            }
        }
    }
}

impl From<StopReason> for Termination {
    /// [`Termination::Expansions`] for an expansion (or iteration) budget,
    /// [`Termination::TimeLimit`], [`Termination::Cancelled`].
    fn from(r: StopReason) -> Self {
        match r {
            StopReason::Expansions { .. } | StopReason::Iterations { .. } => {
                Termination::Expansions
            }
            StopReason::TimeLimit { .. } => Termination::TimeLimit,
            StopReason::Cancelled => Termination::Cancelled,
        }
    }
}

/// Counters of a search, as the search keeps them and as reports write them (`stats` of the
/// plan report, `docs/output-format.md`; its JSON Schema is derived from this type).
#[derive(
    Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema,
)]
pub struct SearchStats {
    /// Funnels expanded (Alg. 4 calls).
    pub expansions: usize,
    /// Funnels dropped by dominance pruning.
    pub pruned_dominated: usize,
    /// Funnels dropped because their mouth is covered from its endpoints (one class wanted:
    /// module docs, "Dominance pruning with a class count").
    #[serde(default)]
    pub pruned_covered: usize,
    /// Funnels dropped by the length bound.
    pub pruned_length: usize,
    /// Funnels never queued because enough queued goals are at least as short (module docs,
    /// "Pruning and straight-through expansion").
    #[serde(default)]
    pub pruned_incumbent: usize,
    /// Funnels dropped because their apex chain is not simple (simple-classes mode).
    pub pruned_simple: usize,
    /// Goal lifts reached whose class was not simple (simple-classes mode).
    pub skipped_not_simple: usize,
    /// Nodes held in the shortest path tree at the end (those kept by any collection, module
    /// docs "Collecting the tree", and made since).
    pub tree_nodes: usize,
    /// Split nodes removed at once because both children were dropped (dead ends and pruned
    /// children: nothing refers to them).
    #[serde(default)]
    pub nodes_discarded: usize,
    /// Nodes no queued entry held any more, dropped by collections of the tree (module docs,
    /// "Collecting the tree"); `tree_nodes` counts the nodes kept.
    #[serde(default)]
    pub nodes_collected: usize,
    /// Largest number of queued entries.
    pub queue_peak: usize,
    /// The expansions made when the automatic wave order switched to one band (module docs,
    /// "The wave order"); `None`, and absent from a report, when it did not.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub swept_at: Option<usize>,
    /// The expansions the search was allowed ([`SearchOptions::expansion_limit`]).
    #[serde(default)]
    pub expansion_limit: usize,
    /// Expansions of the reverse one-class search that bounded the geodesic distances to the goal
    /// before a several-class search ([`SptPlanner::goal_distances`]; not in `expansions`, under
    /// its own budget of the same kind).
    #[serde(default)]
    pub bound_expansions: usize,
    /// Peak bytes held by the search's own structures (tree nodes, queue, trail, pruning lists),
    /// counting allocated capacity where it is visible and live length for the tree.
    pub peak_bytes: usize,
}

/// One class found by the search: its rank, its SHP with crossing sequence and sleeve, and its
/// H-signature.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RankedShp {
    /// 1 for the shortest class, then 2, 3, ...
    pub rank: usize,
    /// The SHP (taut tether: polyline, anchors, length), its reduced crossing sequence and sleeve.
    pub shp: ShortestHomotopicPath,
    /// The H-signature of the SHP (thesis eqs. 2.2-2.3, winding form).
    pub h_signature: HSignature,
    /// Whether the class is simple (module docs).
    pub simple: bool,
    /// Funnels expanded when the class was found.
    pub expansions: usize,
}

impl RankedShp {
    /// The SHP's length, m.
    pub fn length(&self) -> f64 {
        self.shp.taut.length
    }
}

/// What a completed search returns.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SearchOutcome {
    /// The classes, shortest first.
    pub classes: Vec<RankedShp>,
    /// Why the search stopped.
    pub termination: Termination,
    /// Which condition of the options' [`StopCondition`] stopped it (`None`: the search ended
    /// by its own rules, class count, length factor, exhaustion or disconnection).
    #[serde(default)]
    pub stop_reason: Option<StopReason>,
    /// Its counters.
    pub stats: SearchStats,
}

/// Per-BTM preparation shared by searches: connected-component labels of the dual graph (for the
/// quick "not connected" answer) and the H-signature poles.
///
/// ```
/// use nalgebra::Point2;
/// use rappel_geometry::{btm::Btm, map::Map, polygon::Polygon};
/// use rappel_planners::spt::{SearchOptions, SptPlanner, Termination};
/// let p = |x, y| Point2::new(x, y);
/// let map = Map::new(
///     Polygon::new(vec![p(0., 0.), p(10., 0.), p(10., 10.), p(0., 10.)]),
///     vec![Polygon::new(vec![p(4., 4.), p(6., 4.), p(6., 6.), p(4., 6.)])],
/// );
/// let btm = Btm::from_map(&map).unwrap();
/// let planner = SptPlanner::new(&btm);
/// // The classic single query: the globally shortest path.
/// let best = planner.shortest_path(p(5., 9.), p(5., 1.)).unwrap().unwrap();
/// assert!((best.length() - (2.0 * 10f64.sqrt() + 2.0)).abs() < 1e-12);
/// // Lazily, the next classes in non-decreasing length.
/// let options = SearchOptions::default().with_max_classes(Some(3)).unwrap();
/// let mut search = planner.search(p(5., 9.), p(5., 1.), &options).unwrap();
/// let first = search.next_best().unwrap().unwrap();
/// let second = search.next_best().unwrap().unwrap();
/// assert!(first.length() <= second.length());
/// assert_ne!(first.shp.crossings, second.shp.crossings);
/// let third = search.next_best().unwrap().unwrap();
/// assert!(search.next_best().unwrap().is_none());
/// assert_eq!(search.termination(), Some(Termination::ClassCount));
/// assert!(third.length() >= second.length());
/// ```
#[derive(Debug)]
pub struct SptPlanner<'b> {
    btm: &'b Btm,
    component: Vec<u32>,
    /// What lies across every half-edge, one record per expansion (module docs, "Per-query
    /// cost").
    kites: KiteTable,
    poles: Poles,
    /// The cuts meeting each free triangle, for signatures read from sleeves, built when it
    /// pays (module docs, "H-signatures"); `Some(None)` on maps where the index would be too
    /// large (signatures in winding form then).
    cuts: OnceLock<Option<CutIndex>>,
    /// Pole tests the winding form made beyond what the sleeve form would have cost, summed over
    /// the classes answered while there was no index.
    excess: AtomicUsize,
    /// Pole tests the index's build is worth ([`INDEX_BUILD_TESTS_PER_TRIANGLE`] per free
    /// triangle).
    index_cost: usize,
    /// The vertices of the map's outer boundary, for the wave order's switch to one band (module
    /// docs, "The wave order"): the free space's extent along and across a query's line.
    boundary: Vec<Point2<f64>>,
    /// Scratch spaces of finished searches, reused by the next ones (at most [`POOL_SIZE`], each
    /// at most [`POOL_MAX_BYTES`]): a query on a prepared planner allocates nothing once warm.
    pool: Mutex<Vec<Scratch>>,
}

impl Clone for SptPlanner<'_> {
    /// The same preparation with an empty scratch pool.
    fn clone(&self) -> Self {
        SptPlanner {
            btm: self.btm,
            component: self.component.clone(),
            kites: self.kites.clone(),
            poles: self.poles.clone(),
            cuts: self.cuts.clone(),
            excess: AtomicUsize::new(self.excess.load(Ordering::Relaxed)),
            index_cost: self.index_cost,
            boundary: self.boundary.clone(),
            pool: Mutex::new(Vec::new()),
        }
    }
}

impl<'b> SptPlanner<'b> {
    /// Prepares searches on `btm`: labels the connected components of its dual graph and places
    /// the H-signature poles. Linear in the size of the BTM. The cut index of the sleeve-form
    /// signatures is built later, if ever, when it pays (module docs, "H-signatures").
    pub fn new(btm: &'b Btm) -> SptPlanner<'b> {
        let d = btm.dcel();
        let mut component = vec![NONE; d.triangle_capacity()];
        let mut label = 0;
        let mut stack = Vec::new();
        for t in btm.triangles() {
            if component[t.index()] != NONE {
                continue;
            }
            component[t.index()] = label;
            stack.push(t);
            while let Some(u) = stack.pop() {
                for h in u.half_edges() {
                    if let Some(g) = d.twin(h)
                        && component[g.triangle().index()] == NONE
                    {
                        component[g.triangle().index()] = label;
                        stack.push(g.triangle());
                    }
                }
            }
            label += 1;
        }
        SptPlanner {
            btm,
            component,
            kites: KiteTable::new(btm),
            poles: Poles::new(btm),
            cuts: OnceLock::new(),
            excess: AtomicUsize::new(0),
            index_cost: btm
                .triangles()
                .count()
                .saturating_mul(INDEX_BUILD_TESTS_PER_TRIANGLE),
            boundary: btm
                .boundary_vertices()
                .into_iter()
                .map(|v| d.point(v))
                .collect(),
            pool: Mutex::new(Vec::new()),
        }
    }

    /// A scratch space from the pool, or a new one.
    fn take_scratch(&self) -> Scratch {
        self.pool
            .lock()
            .ok()
            .and_then(|mut p| p.pop())
            .unwrap_or_default()
    }

    /// Gives a finished search's scratch space back to the pool (dropped when the pool is full
    /// or the space too large).
    fn return_scratch(&self, scratch: Scratch) {
        if scratch.held_bytes() > POOL_MAX_BYTES {
            return;
        }
        if let Ok(mut p) = self.pool.lock()
            && p.len() < POOL_SIZE
        {
            p.push(scratch);
        }
    }

    /// The BTM searched.
    pub fn btm(&self) -> &'b Btm {
        self.btm
    }

    /// The H-signature poles.
    pub fn poles(&self) -> &Poles {
        &self.poles
    }

    /// The cut index of the sleeve-form signatures, when built (`None` before, and on maps too
    /// unfavourable to index).
    pub fn cut_index(&self) -> Option<&CutIndex> {
        self.cuts.get().and_then(Option::as_ref)
    }

    /// Builds the cut index now (a no-op once built), for callers that know many classes with
    /// long winding-form signatures will follow; `None` when the map is too unfavourable to
    /// index ([`CutIndex::new`]).
    pub fn prepare_cut_index(&self) -> Option<&CutIndex> {
        self.cuts
            .get_or_init(|| CutIndex::new(self.btm, &self.poles))
            .as_ref()
    }

    /// The H-signature of a class from its SHP and sleeve, in whichever of the two equal forms
    /// costs less (module docs, "H-signatures"): the winding form tests every pole in each SHP
    /// segment's `y` band; the sleeve form costs about [`SLEEVE_TESTS_PER_TRIANGLE`] pole tests
    /// per sleeve triangle, once the index exists. Without an index the excess of the winding
    /// form is accumulated, and the index is built once that excess reaches the build's own
    /// cost (the ski-rental rule: never more than twice the cost of the better choice made in
    /// hindsight, up to the constants).
    pub fn h_signature(&self, taut: &TautPath, sleeve: &Sleeve) -> HSignature {
        self.h_signature_reusing(taut, sleeve, &mut Vec::new())
    }

    /// [`SptPlanner::h_signature`] with a search's buffer for the cut crossings.
    fn h_signature_reusing(
        &self,
        taut: &TautPath,
        sleeve: &Sleeve,
        crossings: &mut Vec<u64>,
    ) -> HSignature {
        let from_sleeve = SLEEVE_TESTS_PER_TRIANGLE.saturating_mul(sleeve.len());
        match self.cuts.get() {
            Some(Some(index)) => {
                if self.poles.band_work(&taut.points) > from_sleeve {
                    HSignature::of_sleeve_reusing(
                        self.btm,
                        index,
                        taut.start(),
                        taut.goal(),
                        sleeve,
                        crossings,
                    )
                } else {
                    HSignature::of_taut_path_reusing(&self.poles, taut, crossings).0
                }
            }
            // No index on this map: the winding form, whatever it costs.
            Some(None) => HSignature::of_taut_path_reusing(&self.poles, taut, crossings).0,
            None => {
                // No index yet: the winding form, its pole tests counted on the way (the same
                // count as `band_work`, without its second pass of binary searches); the index
                // is built once the excess has paid for it, and serves the next classes (both
                // forms give the same signature).
                let (h, winding) = HSignature::of_taut_path_reusing(&self.poles, taut, crossings);
                if winding > from_sleeve {
                    let excess = self
                        .excess
                        .fetch_add(winding - from_sleeve, Ordering::Relaxed)
                        .saturating_add(winding - from_sleeve);
                    if excess >= self.index_cost {
                        self.prepare_cut_index();
                    }
                }
                h
            }
        }
    }

    /// `true` when the two free triangles are connected in free space.
    pub fn connected(&self, a: TriangleId, b: TriangleId) -> bool {
        let (ca, cb) = (self.component[a.index()], self.component[b.index()]);
        ca != NONE && ca == cb
    }

    /// A search from `start` to `goal` (Alg. 3 set-up). Both must be finite points of the closed
    /// free space.
    ///
    /// Unless exactly one class is asked for, the search first bounds the geodesic distance from
    /// every map vertex to the goal ([`SptPlanner::goal_distances`]) and uses it to sharpen its
    /// keys (module docs, "Several classes").
    pub fn search(
        &self,
        start: Point2<f64>,
        goal: Point2<f64>,
        options: &SearchOptions,
    ) -> Result<SptSearch<'_>, SearchError> {
        // One clock for the reverse search and the search itself.
        let options = SearchOptions {
            stop: options.stop.started(),
            ..*options
        };
        let (to_goal, bound_expansions) = if options.max_classes == Some(1) {
            (None, 0)
        } else {
            self.goal_distances_within(start, goal, &options.stop)?
        };
        let mut search = SptSearch::new(self, start, goal, options, to_goal)?;
        search.stats.bound_expansions = bound_expansions;
        Ok(search)
    }

    /// Lower bounds `h(v)` of the geodesic (shortest free-space path) distance from every map
    /// vertex `v` to `goal`, indexed by vertex id, exact near the shortest path (module docs,
    /// "Several classes"); `None` when `start` and `goal` are not connected.
    pub fn goal_distances(
        &self,
        start: Point2<f64>,
        goal: Point2<f64>,
    ) -> Result<Option<Vec<f64>>, SearchError> {
        self.goal_distances_within(start, goal, &StopCondition::none())
            .map(|(h, _)| h)
    }

    /// [`SptPlanner::goal_distances`] with the reverse search (one class) stopped by `stop`, and
    /// the expansions it made; a reverse search stopped early gives no bounds (the straight line
    /// serves), never an error.
    fn goal_distances_within(
        &self,
        start: Point2<f64>,
        goal: Point2<f64>,
        stop: &StopCondition,
    ) -> Result<(Option<Vec<f64>>, usize), SearchError> {
        let options = SearchOptions::default()
            .with_max_classes(Some(1))?
            .with_stop(stop.clone())?;
        // The reverse search runs from the goal: name the endpoints as the caller knows them.
        let mut reverse =
            SptSearch::new(self, goal, start, options, None).map_err(|e| match e {
                SearchError::Endpoint {
                    which,
                    point,
                    source,
                } => SearchError::Endpoint {
                    which: if which == "start" { "goal" } else { "start" },
                    point,
                    source,
                },
                other => other,
            })?;
        let Some(best) = reverse.next_best()? else {
            return Ok((None, reverse.stats.expansions));
        };
        let shortest = best.length();
        let d = self.btm.dcel();
        let recorded = |v: usize| reverse.scratch.lifts.shortest(v);
        let h = (0..d.vertex_capacity())
            .map(|v| {
                let p = d.point(VertexId(v as u32));
                let from_start = (p - start).norm();
                match recorded(v) {
                    Some(r) if r + from_start < shortest => r,
                    _ => (p - goal).norm().max(shortest - from_start),
                }
            })
            .collect();
        Ok((Some(h), reverse.stats.expansions))
    }

    /// The globally shortest path from `start` to `goal` as a taut path (its corners, anchors
    /// and length), without the class's sleeve, crossing sequence and H-signature that
    /// [`SptPlanner::shortest_path`] also builds: the answer a navigation-mesh planner such as
    /// Polyanya gives, for batch length queries. `None` when they are not connected; a search
    /// stopped by its expansion budget is [`SearchError::BudgetExhausted`].
    pub fn shortest_taut_path(
        &self,
        start: Point2<f64>,
        goal: Point2<f64>,
    ) -> Result<Option<TautPath>, SearchError> {
        self.shortest_taut_path_within(start, goal, ExpansionBudget::Auto)
    }

    /// [`SptPlanner::shortest_taut_path`] with its expansions bounded by `budget`.
    pub fn shortest_taut_path_within(
        &self,
        start: Point2<f64>,
        goal: Point2<f64>,
        budget: ExpansionBudget,
    ) -> Result<Option<TautPath>, SearchError> {
        self.shortest_taut_path_until(start, goal, &StopCondition::budget_of(budget))
    }

    /// [`SptPlanner::shortest_taut_path`] stopped by `stop`: its expansion budget is
    /// [`SearchError::BudgetExhausted`], its time limit or cancel flags
    /// [`SearchError::Stopped`].
    pub fn shortest_taut_path_until(
        &self,
        start: Point2<f64>,
        goal: Point2<f64>,
        stop: &StopCondition,
    ) -> Result<Option<TautPath>, SearchError> {
        let options = SearchOptions::default()
            .with_max_classes(Some(1))?
            .with_stop(stop.clone())?;
        let mut search = SptSearch::new(self, start, goal, options, None)?;
        match search.next_goal()? {
            Some((node, _)) => Ok(Some(search.scratch.tree.taut_path(self.btm, node))),
            None => match search.stopped_error() {
                Some(e) => Err(e),
                None => Ok(None),
            },
        }
    }

    /// The classic single query: the globally shortest path from `start` to `goal` (the first
    /// class), or `None` when they are not connected. A search stopped by its expansion budget
    /// ([`DEFAULT_MAX_EXPANSIONS`]) is [`SearchError::BudgetExhausted`], not `None`.
    pub fn shortest_path(
        &self,
        start: Point2<f64>,
        goal: Point2<f64>,
    ) -> Result<Option<RankedShp>, SearchError> {
        let options = SearchOptions::default().with_max_classes(Some(1))?;
        let mut search = self.search(start, goal, &options)?;
        let best = search.next_best()?;
        if best.is_none()
            && let Some(e) = search.stopped_error()
        {
            return Err(e);
        }
        Ok(best)
    }
}

/// The SHPs from `start` to `goal` under `options`, collected: a convenience over
/// [`SptPlanner::search`].
pub fn shortest_homotopic_paths(
    btm: &Btm,
    start: Point2<f64>,
    goal: Point2<f64>,
    options: &SearchOptions,
) -> Result<SearchOutcome, SearchError> {
    SptPlanner::new(btm).search(start, goal, options)?.run()
}

/// The triangle a path starting (or ending) at `p` is assigned to: the canonical-endpoint rule of
/// [`rappel_homotopy::crossing`], as used by [`Tracer::new`].
pub fn canonical_triangle(btm: &Btm, p: Point2<f64>) -> Result<TriangleId, PathError> {
    Tracer::new(btm, p).map(|t| t.triangle())
}

/// `true` when the class of `taut` is simple (module docs): no map vertex occurs twice among its
/// anchors and the anchors on each obstacle are consecutive.
///
/// ```
/// use nalgebra::Point2;
/// use rappel_geometry::{btm::Btm, map::Map, polygon::Polygon};
/// use rappel_homotopy::{path::Path, shp::shortest_homotopic_path};
/// use rappel_planners::spt::is_simple_class;
/// let p = |x, y| Point2::new(x, y);
/// let map = Map::new(
///     Polygon::new(vec![p(0., 0.), p(10., 0.), p(10., 10.), p(0., 10.)]),
///     vec![Polygon::new(vec![p(4., 4.), p(6., 4.), p(6., 6.), p(4., 6.)])],
/// );
/// let btm = Btm::from_map(&map).unwrap();
/// let west = Path::new(vec![p(5., 9.), p(1., 5.), p(5., 1.)]).unwrap();
/// assert!(is_simple_class(&shortest_homotopic_path(&btm, &west).unwrap().taut));
/// // Once around the obstacle before going down: the tether wraps it a full turn.
/// let wound = Path::new(vec![p(5., 9.), p(1., 5.), p(5., 1.), p(9., 5.), p(5., 9.), p(1., 5.), p(5., 1.)]).unwrap();
/// assert!(!is_simple_class(&shortest_homotopic_path(&btm, &wound).unwrap().taut));
/// ```
pub fn is_simple_class(taut: &TautPath) -> bool {
    anchors_are_simple(
        taut.anchors.iter().map(|a| (a.vertex, a.obstacle)),
        &mut SimpleBuffers::default(),
    )
}

/// The two lists of the simplicity test, kept by a search across its classes and queries.
#[derive(Debug, Clone, Default)]
struct SimpleBuffers {
    vertices: Vec<VertexId>,
    /// The obstacle of each run of consecutive anchors on one obstacle.
    runs: Vec<ObstacleId>,
}

/// The simplicity test on a sequence of anchors `(vertex, obstacle)`: no vertex twice, and no
/// obstacle in two separate runs of consecutive anchors (an obstacle left behind never comes
/// back). Two sorted lists (`buffers`, cleared first), no hashing: the lists are as short as the
/// tether's anchors.
fn anchors_are_simple(
    anchors: impl Iterator<Item = (VertexId, Option<ObstacleId>)>,
    buffers: &mut SimpleBuffers,
) -> bool {
    let SimpleBuffers { vertices, runs } = buffers;
    vertices.clear();
    runs.clear();
    let mut current: Option<ObstacleId> = None;
    for (v, o) in anchors {
        vertices.push(v);
        if o != current {
            runs.extend(o);
            current = o;
        }
    }
    vertices.sort_unstable();
    runs.sort_unstable();
    vertices.windows(2).all(|w| w[0] != w[1]) && runs.windows(2).all(|w| w[0] != w[1])
}

#[derive(Debug, Clone, Copy)]
enum Kind {
    /// The goal, reached through the funnel whose mouth is `trail`.
    Goal { node: NodeId, trail: u32 },
    /// A funnel to expand; `trail` indexes its mouth in the trail, `apex` is its apex's length and
    /// vertex.
    Funnel {
        funnel: FunnelState,
        trail: u32,
        apex: Apex,
    },
}

/// What the dominance test and the apex bound read of a funnel's apex: its path length `g` and
/// its map vertex ([`NONE`] for the root), copied out of the tree once, when a funnel gets a new
/// apex, and carried in the queued item (module docs, "Per-query cost"). A funnel popped only to
/// be dropped as dominated then costs one load of its vertex's lifts, not two more scattered
/// loads from the tree's arrays.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Apex {
    length: f64,
    vertex: u32,
}

impl Apex {
    /// The apex record of tree node `node`.
    #[inline]
    fn of(tree: &FunnelTree, node: NodeId) -> Apex {
        Apex {
            length: tree.length(node),
            vertex: tree.vertex(node).map_or(NONE, |v| v.0),
        }
    }

    /// The map vertex, `None` for the root.
    #[inline]
    fn vertex(self) -> Option<VertexId> {
        (self.vertex != NONE).then_some(VertexId(self.vertex))
    }
}

impl Rank for Kind {
    /// On equal keys a goal before a funnel.
    fn rank(&self) -> usize {
        matches!(self, Kind::Funnel { .. }) as usize
    }
}

/// The `K` smallest path lengths known per map vertex, for dominance pruning.
///
/// Per-query cost follows the vertices the search touches, not the map: the per-vertex arrays are
/// allocated once per [`Scratch`] and invalidated by bumping a generation stamp, and the lists of
/// `K > 1` lengths are buffers reused from query to query (no allocation per vertex once warm).
/// For `K = 1` the one length lives in the per-vertex array itself.
#[derive(Debug, Clone, Default)]
struct Lifts {
    k: usize,
    /// The current generation; a vertex's entry is valid when its stamp equals it.
    generation: u32,
    /// Per vertex id, its stamp with its `K = 1` length or `K > 1` list index side by side: one
    /// cache line per lookup (on a 100,000-obstacle strip the arrays are far beyond the cache,
    /// and dominance is checked at every push and pop).
    slots: Vec<VertexLifts>,
    /// Sorted lists of at most `k` lengths; the first `used` belong to this query.
    lists: Vec<Vec<f64>>,
    used: usize,
    /// Bytes of the first `used` lists (header and lengths held, not capacities, so that the
    /// count does not depend on what earlier queries left in the buffers).
    list_bytes: usize,
}

/// One vertex's entry in [`Lifts`].
#[derive(Debug, Clone, Copy, Default)]
struct VertexLifts {
    stamp: u32,
    /// `K > 1`: the index of the vertex's list in `lists`.
    slot: u32,
    /// `K = 1`: the shortest length.
    shortest: f64,
}

impl Lifts {
    /// Starts a query keeping `k` lengths per vertex among `vertices` vertex ids.
    fn reset(&mut self, k: usize, vertices: usize) {
        self.k = k;
        if self.slots.len() < vertices {
            self.slots.resize(vertices, VertexLifts::default());
        }
        self.generation = self.generation.wrapping_add(1);
        if self.generation == 0 {
            // After 2^32 queries: clear the stamps once so that no stale entry looks current.
            self.slots.iter_mut().for_each(|s| s.stamp = 0);
            self.generation = 1;
        }
        self.used = 0;
        self.list_bytes = 0;
    }

    fn record(&mut self, v: VertexId, g: f64) {
        let generation = self.generation;
        let Some(entry) = self.slots.get_mut(v.index()) else {
            return;
        };
        let fresh = entry.stamp != generation;
        entry.stamp = generation;
        if self.k == 1 {
            if fresh || g < entry.shortest {
                entry.shortest = g;
            }
            return;
        }
        if fresh {
            entry.slot = self.used as u32;
            if self.used == self.lists.len() {
                self.lists.push(Vec::with_capacity(self.k.min(4)));
            } else {
                self.lists[self.used].clear();
            }
            self.list_bytes += std::mem::size_of::<Vec<f64>>();
            self.used += 1;
        }
        let list = &mut self.lists[entry.slot as usize];
        if list.len() == self.k && list[self.k - 1] <= g {
            return;
        }
        let before = list.len();
        let at = list.partition_point(|&x| x <= g);
        list.insert(at, g);
        list.truncate(self.k);
        self.list_bytes += (list.len() - before) * 8;
    }

    /// This query's entry of vertex index `v`, if it has one.
    #[inline]
    fn current(&self, v: usize) -> Option<&VertexLifts> {
        self.slots.get(v).filter(|s| s.stamp == self.generation)
    }

    /// The shortest length recorded for `v` in this query.
    fn shortest(&self, v: usize) -> Option<f64> {
        let entry = self.current(v)?;
        if self.k == 1 {
            Some(entry.shortest)
        } else {
            self.lists[entry.slot as usize].first().copied()
        }
    }

    /// `true` when `k` lifts of `v` are known strictly shorter than `g`.
    fn dominates(&self, v: VertexId, g: f64) -> bool {
        let Some(entry) = self.current(v.index()) else {
            return false;
        };
        if self.k == 1 {
            entry.shortest < g
        } else {
            let list = &self.lists[entry.slot as usize];
            list.len() == self.k && list[self.k - 1] < g
        }
    }

    /// Bytes held (capacities).
    fn held_bytes(&self) -> usize {
        self.slots.capacity() * std::mem::size_of::<VertexLifts>()
            + self.lists.capacity() * std::mem::size_of::<Vec<f64>>()
            + self.lists.iter().map(|l| l.capacity() * 8).sum::<usize>()
    }

    /// Bytes this query uses: the per-vertex array and its own lists.
    fn live_bytes(&self) -> usize {
        self.slots.len() * std::mem::size_of::<VertexLifts>() + self.list_bytes
    }
}

/// The storage of one search, reused across queries on one BTM ([`SptPlanner`] keeps a pool):
/// the shortest path tree's nodes, the queue, the trail of mouths, the lifts and the
/// simple-prefix verdicts. A query clears them (keeping their capacity) instead of growing new
/// ones from empty.
#[derive(Debug, Clone, Default)]
struct Scratch {
    tree: FunnelTree,
    queue: ArenaHeap<Kind>,
    trail: Vec<(HalfEdgeId, u32)>,
    /// Whether this query's trail outgrew [`TRAIL_MAX_ENTRIES`] and was dropped.
    trail_dropped: bool,
    lifts: Lifts,
    simple_prefix: Vec<u8>,
    /// The simplicity test's lists and the H-signature's cut crossings, reused by every class
    /// answered (no allocation per class beyond the answer's own vectors).
    simple_buffers: SimpleBuffers,
    crossings: Vec<u64>,
    /// Lengths of the queued goal entries, ascending, at most the number of classes still
    /// wanted (module docs, "The incumbent"); kept only when a class count is set and every
    /// goal reached is returned (not in the simple-classes mode).
    pending_goals: Vec<f64>,
    /// One arrival per edge for the mouth-cover test (one class wanted).
    arrivals: ArrivalStore,
    /// The live nodes of a collection of the tree (module docs, "Collecting the tree").
    marks: TreeMarks,
}

impl Scratch {
    /// Drops the tree nodes no queued entry holds and renumbers the nodes the queue holds
    /// (module docs, "Collecting the tree"); returns the number dropped. `peak` (bytes) is raised
    /// to what is held just before the nodes go, when the marks are held with the whole tree.
    fn collect(&mut self, pruning: bool, peak: &mut usize) -> usize {
        let (tree, marks) = (&self.tree, &mut self.marks);
        tree.begin_marking(marks);
        self.queue.for_each_queued_mut(|item| match item {
            Kind::Goal { node, .. } => tree.mark(marks, *node),
            Kind::Funnel { funnel, .. } => funnel.mark(tree, marks),
        });
        *peak = (*peak).max(self.live_bytes(pruning));
        let dropped = self.tree.collect(&mut self.marks);
        let marks = &self.marks;
        self.queue.for_each_queued_mut(|item| match item {
            Kind::Goal { node, .. } => *node = marks.renumbered(*node),
            Kind::Funnel { funnel, .. } => *funnel = funnel.renumbered(marks),
        });
        dropped
    }

    /// Clears everything for a query from `start`.
    fn reset(&mut self, start: Point2<f64>) {
        self.tree.reset(start);
        self.queue.clear();
        self.trail.clear();
        self.trail_dropped = false;
        self.simple_prefix.clear();
        self.pending_goals.clear();
    }

    /// Bytes held (capacities), for the pool's size limit.
    fn held_bytes(&self) -> usize {
        self.tree.capacity_bytes()
            + self.queue.held_bytes()
            + self.trail.capacity() * std::mem::size_of::<(HalfEdgeId, u32)>()
            + self.lifts.held_bytes()
            + self.arrivals.held_bytes()
            + self.simple_prefix.capacity()
            + self.simple_buffers.vertices.capacity() * std::mem::size_of::<VertexId>()
            + self.simple_buffers.runs.capacity() * std::mem::size_of::<ObstacleId>()
            + self.crossings.capacity() * std::mem::size_of::<u64>()
            + self.pending_goals.capacity() * std::mem::size_of::<f64>()
            + self.marks.held_bytes()
    }

    /// Bytes the current query uses (lengths, not capacities: the same for the same query
    /// whatever earlier queries left in the pool).
    fn live_bytes(&self, pruning: bool) -> usize {
        self.tree.len() * FunnelTree::NODE_BYTES
            + self.queue.live_bytes()
            + self.trail.len() * std::mem::size_of::<(HalfEdgeId, u32)>()
            + if pruning { self.lifts.live_bytes() } else { 0 }
            + if pruning && self.lifts.k == 1 {
                // Allocated zeroed: only the slots touched are resident, but all are counted.
                self.arrivals.held_bytes()
            } else {
                0
            }
            + self.simple_prefix.len()
            + self.marks.held_bytes()
    }
}

/// Cost of the sleeve-form signature per sleeve triangle, in winding-form pole tests (measured
/// on the crater strips, `planner_h_signature` bench: 35-75 ns per triangle against about 13 ns
/// per pole test, with margin).
pub const SLEEVE_TESTS_PER_TRIANGLE: usize = 6;

/// Cost of building the cut index per free triangle, in winding-form pole tests (measured: 36 ms
/// for the 67,360 free triangles of the 10,000-obstacle strip, at about 13 ns per pole test).
pub const INDEX_BUILD_TESTS_PER_TRIANGLE: usize = 40;

/// Most funnel mouths a search records for building its classes' sleeves from the trail (8 bytes
/// each: 8 MB); a search that queues more (a first SHP on a 100,000-obstacle strip queues tens of
/// millions) drops the trail and traces each class's sleeve from its SHP instead, in time
/// proportional to the SHP's triangles.
pub const TRAIL_MAX_ENTRIES: usize = 1 << 20;

/// Fewest tree nodes at which a search collects its tree (module docs, "Collecting the tree"):
/// about 36 MB of nodes, so a query on a map of up to some 10,000 obstacles never collects.
pub const COLLECT_MIN_NODES: usize = 1 << 20;

/// Most scratch spaces an [`SptPlanner`] keeps for reuse (one per thread searching at once is
/// enough; more are dropped).
const POOL_SIZE: usize = 8;
/// Largest scratch space kept for reuse, bytes: a search that grew beyond it (a first SHP on a
/// 100,000-obstacle strip) gives its memory back instead of holding it for the planner's life.
const POOL_MAX_BYTES: usize = 64 << 20;

/// A running SPT search (Alg. 3's loop, one SHP per [`SptSearch::next_best`]).
#[derive(Debug, Clone)]
pub struct SptSearch<'a> {
    planner: &'a SptPlanner<'a>,
    goal: Point2<f64>,
    start_triangle: TriangleId,
    goal_triangle: TriangleId,
    /// Geodesic distance from each map vertex to the goal, when known (module docs).
    to_goal: Option<Vec<f64>>,
    options: SearchOptions,
    /// The tree, queue, trail (mouth of every queued funnel and the index of its parent
    /// funnel's mouth), lifts and simple-prefix verdicts (0 unknown, 1 simple, 2 not simple),
    /// taken from the planner's pool and given back when the search is dropped.
    scratch: Scratch,
    /// Whether dominance pruning is on (the lifts are kept).
    pruning: bool,
    /// The wave order's bands, when the queue pops in it (module docs, "The wave order").
    wave: Option<Wave>,
    /// The popped key from which the wave order sweeps in one band (module docs, "The wave
    /// order": the A* ellipse then spans the free space), when the automatic order may switch.
    sweep_from: Option<f64>,
    /// The tree's length at which it is collected next (module docs, "Collecting the tree");
    /// `usize::MAX` in the simple-classes mode, whose verdicts are kept per node.
    collect_at: usize,
    /// The fewest nodes at which the tree is collected: [`COLLECT_MIN_NODES`] (the unit tests
    /// lower it to collect small trees often).
    collect_min: usize,
    emitted: usize,
    shortest: Option<f64>,
    termination: Option<Termination>,
    /// The check of the options' stop condition, its clock started with the search.
    watch: StopWatch,
    /// Which condition of the stop condition ended the search, if one did.
    stop_reason: Option<StopReason>,
    stats: SearchStats,
}

impl<'a> SptSearch<'a> {
    fn new(
        planner: &'a SptPlanner<'a>,
        start: Point2<f64>,
        goal: Point2<f64>,
        options: SearchOptions,
        to_goal: Option<Vec<f64>>,
    ) -> Result<SptSearch<'a>, SearchError> {
        let btm = planner.btm;
        let endpoint = |which, point| {
            canonical_triangle(btm, point).map_err(|source| SearchError::Endpoint {
                which,
                point,
                source,
            })
        };
        let start_triangle = endpoint("start", start)?;
        let goal_triangle = endpoint("goal", goal)?;
        // Dominance pruning, hence the one-class rules, needs a class count outside the
        // simple-classes mode (`pruning` below).
        let one_class = options.max_classes == Some(1) && !options.simple_only;
        let band_bits = match options.queue_order {
            QueueOrder::Auto => one_class.then_some(WAVE_BAND_BITS),
            QueueOrder::AStar => None,
            QueueOrder::Wave { .. } if !one_class => {
                return Err(SearchError::Option(
                    "the wave order is for one class: max_classes 1, not the simple-classes mode",
                ));
            }
            QueueOrder::Wave { band_bits } if band_bits > 52 => {
                return Err(SearchError::Option(
                    "the wave order keeps at most 52 bits of mantissa (band_bits <= 52)",
                ));
            }
            QueueOrder::Wave { band_bits } => Some(band_bits),
        };
        let mut scratch = planner.take_scratch();
        scratch.reset(start);
        let pruning = match options.max_classes {
            Some(k) if !options.simple_only => {
                scratch.lifts.reset(k, btm.dcel().vertex_capacity());
                if k == 1 {
                    scratch.arrivals.reset(btm.dcel());
                }
                true
            }
            _ => false,
        };
        let expansion_limit = options.expansion_limit(btm);
        let watch = options.stop.watch(expansion_limit);
        let wave = band_bits.map(Wave::new);
        let sweep_from = match options.queue_order {
            QueueOrder::Auto if one_class => sweep_key(start, goal, &planner.boundary),
            _ => None,
        };
        // The simple-classes mode keeps its verdicts per node: its tree is never collected.
        let collect_at = if options.simple_only {
            usize::MAX
        } else {
            COLLECT_MIN_NODES
        };
        let mut search = SptSearch {
            planner,
            goal,
            start_triangle,
            goal_triangle,
            to_goal,
            options,
            scratch,
            pruning,
            wave,
            sweep_from,
            collect_at,
            collect_min: COLLECT_MIN_NODES,
            emitted: 0,
            shortest: None,
            termination: None,
            watch,
            stop_reason: None,
            stats: SearchStats {
                expansion_limit,
                ..SearchStats::default()
            },
        };
        if !planner.connected(start_triangle, goal_triangle) {
            search.termination = Some(Termination::Disconnected);
            return Ok(search);
        }
        if goal_triangle == start_triangle {
            // The trivial class: the straight segment inside the (convex) start triangle.
            let root = search.scratch.tree.root();
            let node = search.scratch.tree.extend(root, search.goal, None);
            let key = search.scratch.tree.node(node).length;
            search.push_goal(key, node, NONE, 0);
        }
        let d = btm.dcel();
        if search.pruning {
            // The start triangle's corners are reached straight from the start, which is the
            // shortest lift of a corner it lies on (the canonical triangle of a start on a map
            // vertex has that vertex as a corner, so no second point location is needed).
            for v in d.triangle_vertices(start_triangle) {
                let g = (d.point(v) - start).norm();
                search.scratch.lifts.record(v, g);
            }
        }
        // Alg. 3 lines 5-10, without collecting the (at most three) initial funnels.
        for h in start_triangle.half_edges() {
            if d.twin(h).is_none() {
                continue;
            }
            let f = FunnelState::through(&mut search.scratch.tree, btm, h)?;
            let apex = Apex::of(&search.scratch.tree, f.apex());
            let key = search.lower_bound(&f, apex);
            search.offer(key, f, apex, NONE);
        }
        Ok(search)
    }

    /// Why the search stopped (`None` while it can go on).
    pub fn termination(&self) -> Option<Termination> {
        self.termination
    }

    /// Which condition of the options' [`StopCondition`] stopped the search (`None` while it
    /// runs, and when it ended by its own rules): the expansion budget with its limit, the time
    /// limit, or a cancel flag.
    pub fn stop_reason(&self) -> Option<StopReason> {
        self.stop_reason
    }

    /// The error of a search that the stop condition ended: the expansion budget is
    /// [`SearchError::BudgetExhausted`], the time limit and a cancel flag are
    /// [`SearchError::Stopped`].
    fn stopped_error(&self) -> Option<SearchError> {
        let expansions = self.stats.expansions;
        match self.stop_reason? {
            StopReason::Expansions { .. } | StopReason::Iterations { .. } => {
                Some(SearchError::BudgetExhausted { expansions })
            }
            reason => Some(SearchError::Stopped { reason, expansions }),
        }
    }

    /// The search's counters so far.
    pub fn stats(&self) -> SearchStats {
        let mut s = self.stats;
        s.tree_nodes = self.scratch.tree.len();
        s
    }

    /// The options in force.
    pub fn options(&self) -> &SearchOptions {
        &self.options
    }

    /// The next SHP in non-decreasing length, each in a new homotopy class (Alg. 3 lines 15-20);
    /// `Ok(None)` once the search has stopped ([`SptSearch::termination`] says why).
    pub fn next_best(&mut self) -> Result<Option<RankedShp>, SearchError> {
        while let Some((node, trail)) = self.next_goal()? {
            if let Some(found) = self.emit(node, trail)? {
                if self.options.max_classes == Some(self.emitted) {
                    self.termination = Some(Termination::ClassCount);
                }
                return Ok(Some(found));
            }
        }
        Ok(None)
    }

    /// Runs Alg. 3's loop to the next goal entry popped (its node and trail), or `None` once the
    /// search has stopped.
    fn next_goal(&mut self) -> Result<Option<(NodeId, u32)>, SearchError> {
        if self.termination.is_some() {
            return Ok(None);
        }
        // The clock and the cancel flags are read at every class too, not only every
        // `CHECK_INTERVAL` expansions: once the funnels are built, the next class may take a
        // handful of expansions while its caller spends milliseconds on each class found
        // (feasibility, the path pair), so a Ctrl-C or a time limit would otherwise wait for
        // hundreds of classes.
        if let Some(reason) = self.watch.poll_now() {
            self.termination = Some(reason.into());
            self.stop_reason = Some(reason);
            return Ok(None);
        }
        loop {
            if self.scratch.tree.len() >= self.collect_at {
                self.collect_tree();
            }
            let Some((word, item)) = self.scratch.queue.pop_ordered() else {
                self.termination = Some(Termination::Exhausted);
                return Ok(None);
            };
            let key = self.key_of_word(word);
            if self.sweep_from.is_some_and(|from| key >= from) {
                self.sweep(item);
                continue;
            }
            if self.length_limit().is_some_and(|limit| key > limit) {
                self.termination = Some(Termination::LengthFactor);
                return Ok(None);
            }
            match item {
                Kind::Goal { node, trail } => {
                    if self.still_wanted().is_some() && !self.scratch.pending_goals.is_empty() {
                        // The smallest queued goal is the one popped.
                        self.scratch.pending_goals.remove(0);
                    }
                    return Ok(Some((node, trail)));
                }
                Kind::Funnel {
                    funnel,
                    trail,
                    apex,
                } => {
                    // The kite is read before the pruning tests, which miss the cache on their
                    // own slots (the apex's lifts, the mouth's arrival): the loads are
                    // independent, so the processor overlaps this miss with theirs instead of
                    // taking it after them (an expanded funnel needs its kite first).
                    let kite = std::hint::black_box(self.planner.kites.get(funnel.mouth()));
                    if self.dominated(apex) {
                        self.stats.pruned_dominated += 1;
                        continue;
                    }
                    if self.covered(&funnel, apex) {
                        self.stats.pruned_covered += 1;
                        continue;
                    }
                    if let Some(reason) = self.watch.check(self.stats.expansions) {
                        self.termination = Some(reason.into());
                        self.stop_reason = Some(reason);
                        return Ok(None);
                    }
                    self.expand(key, word, funnel, kite, apex, trail)?;
                }
            }
        }
    }

    /// Runs the search to its end and collects every class.
    pub fn run(mut self) -> Result<SearchOutcome, SearchError> {
        let mut classes = Vec::new();
        while let Some(c) = self.next_best()? {
            classes.push(c);
        }
        Ok(SearchOutcome {
            classes,
            termination: self.termination.unwrap_or(Termination::Exhausted),
            stop_reason: self.stop_reason,
            stats: self.stats(),
        })
    }

    /// Alg. 4: reach the goal if it lies beyond the mouth, split, key and queue the children.
    ///
    /// Straight through (module docs, "Pruning and straight-through expansion"): when exactly one
    /// child survives and its key equals the funnel's, it is itself a minimum of the queue, so it
    /// is expanded at once instead of making a round trip through the heap (within the expansion
    /// budget, which counts every expansion).
    fn expand(
        &mut self,
        mut key: f64,
        mut word: u64,
        mut f: FunnelState,
        first_kite: Kite,
        mut apex: Apex,
        mut trail: u32,
    ) -> Result<(), SearchError> {
        let mut read = Some(first_kite);
        loop {
            self.stats.expansions += 1;
            // `f`'s kite: the one read before the pruning tests, then each straight-through
            // child's own.
            let kite = read
                .take()
                .unwrap_or_else(|| self.planner.kites.get(f.mouth()));
            let next = kite.beyond().ok_or_else(|| {
                SearchError::Internal("a queued funnel has a closed mouth".into())
            })?;
            if next == self.goal_triangle {
                let node = f.reach(&mut self.scratch.tree, self.goal);
                let goal_key = self.scratch.tree.length(node).max(key);
                self.push_goal(goal_key, node, trail, word);
            }
            if self.pruning && self.scratch.lifts.k == 1 {
                let d = self.planner.btm.dcel();
                self.scratch.arrivals.record(d, &self.scratch.tree, &f);
            }
            let split = f.split_across(&mut self.scratch.tree, &kite)?;
            if self.pruning {
                let g = self.scratch.tree.length(split.node);
                self.scratch.lifts.record(split.vertex, g);
            }
            let mut kept = [None, None];
            for (slot, child) in kept.iter_mut().zip([split.left, split.right]) {
                if let Some(child) = child {
                    // A child keeps its parent's apex, or has the predecessor as its new one.
                    let child_apex = if child.apex() == f.apex() {
                        apex
                    } else {
                        Apex::of(&self.scratch.tree, child.apex())
                    };
                    let (child_key, reach) = self.child_key(&child, child_apex, key);
                    if self.admit(child_key, &child, child_apex) {
                        let child_word =
                            self.funnel_word(child_key, reach, &child, child_apex, word);
                        *slot = Some((child_key, child_word, child, child_apex));
                    }
                }
            }
            if kept.iter().all(Option::is_none)
                && split.node != split.predecessor
                && self.scratch.tree.discard_last(split.node)
            {
                // No funnel holds the new node: its storage is reused by the next one (its
                // vertex's lift is already recorded for pruning). Memory then follows the
                // funnels alive, not every expansion.
                self.scratch.simple_prefix.truncate(self.scratch.tree.len());
                self.stats.nodes_discarded += 1;
            }
            // A child's word is at least `word` (`funnel_word`), so one equal to it is a minimum
            // of the queue.
            let through = match kept {
                [Some(c), None] | [None, Some(c)] => {
                    c.1 <= word && self.stats.expansions < self.stats.expansion_limit
                }
                _ => false,
            };
            for (child_key, child_word, child, child_apex) in kept.into_iter().flatten() {
                let child_trail = self.record_mouth(child.mouth(), trail);
                if through {
                    (key, word, f, apex, trail) =
                        (child_key, child_word, child, child_apex, child_trail);
                } else {
                    self.push(
                        child_word,
                        Kind::Funnel {
                            funnel: child,
                            trail: child_trail,
                            apex: child_apex,
                        },
                    );
                }
            }
            self.stats.queue_peak = self.stats.queue_peak.max(self.scratch.queue.len());
            self.stats.peak_bytes = self.stats.peak_bytes.max(self.bytes());
            if !through {
                return Ok(());
            }
        }
    }

    /// `true` unless a bound or a pruning rule drops a funnel with this key and apex (and counts
    /// why).
    fn admit(&mut self, key: f64, f: &FunnelState, apex: Apex) -> bool {
        if self.length_limit().is_some_and(|limit| key > limit) {
            self.stats.pruned_length += 1;
            return false;
        }
        if self.incumbent().is_some_and(|bound| key >= bound) {
            self.stats.pruned_incumbent += 1;
            return false;
        }
        if self.dominated(apex) {
            self.stats.pruned_dominated += 1;
            return false;
        }
        if self.covered(f, apex) {
            self.stats.pruned_covered += 1;
            return false;
        }
        if self.options.simple_only && !self.prefix_is_simple(f.apex()) {
            self.stats.pruned_simple += 1;
            return false;
        }
        true
    }

    /// Queues a first funnel (keyed `key`) unless a bound or a pruning rule drops it.
    fn offer(&mut self, key: f64, f: FunnelState, apex: Apex, parent_trail: u32) {
        if !self.admit(key, &f, apex) {
            return;
        }
        let trail = self.record_mouth(f.mouth(), parent_trail);
        let word = self.funnel_word(key, None, &f, apex, 0);
        self.push(
            word,
            Kind::Funnel {
                funnel: f,
                trail,
                apex,
            },
        );
    }

    /// Records a queued funnel's mouth after its parent's, returning its trail index; once the
    /// trail holds the options' trail limit of mouths it is dropped (its memory freed) and the
    /// sleeves of the classes still to come are traced from their SHPs instead (`NONE` from
    /// then on).
    fn record_mouth(&mut self, mouth: HalfEdgeId, parent: u32) -> u32 {
        if self.scratch.trail_dropped {
            return NONE;
        }
        if self.scratch.trail.len() >= self.options.trail_limit {
            self.scratch.trail = Vec::new();
            self.scratch.trail_dropped = true;
            return NONE;
        }
        let index = self.scratch.trail.len() as u32;
        self.scratch.trail.push((mouth, parent));
        index
    }

    /// Queues a goal entry keyed `key` (its path length, or the key of the funnel that reached
    /// it if larger) no earlier than `after` (the order word of the funnel that reached it), and
    /// notes its key among the pending goals.
    fn push_goal(&mut self, key: f64, node: NodeId, trail: u32, after: u64) {
        if let Some(wanted) = self.still_wanted() {
            let at = self.scratch.pending_goals.partition_point(|&x| x <= key);
            if at < wanted {
                self.scratch.pending_goals.insert(at, key);
                self.scratch.pending_goals.truncate(wanted);
            }
        }
        let word = match self.wave {
            Some(wave) => wave.word(key, key, WaveEntry::Goal),
            None => ordered_bits(key),
        };
        self.push(word.max(after), Kind::Goal { node, trail });
    }

    /// The number of classes still to find, when every goal reached is a class returned (a class
    /// count is set and the simple-classes mode is off): the incumbent is kept only then.
    fn still_wanted(&self) -> Option<usize> {
        if self.options.simple_only {
            return None;
        }
        Some(self.options.max_classes?.saturating_sub(self.emitted))
    }

    /// The incumbent bound (module docs): with `r` classes still wanted and `r` goals queued with
    /// keys at most `b`, the search ends before any funnel keyed `b` or more is expanded.
    fn incumbent(&self) -> Option<f64> {
        let wanted = self.still_wanted()?;
        (wanted > 0 && self.scratch.pending_goals.len() >= wanted)
            .then(|| self.scratch.pending_goals[wanted - 1])
    }

    /// Queues `kind` under order word `word`: in the A* order goals before funnels on equal
    /// words, in the wave order funnels first (module docs, "The wave order").
    fn push(&mut self, word: u64, kind: Kind) {
        let goal_first = kind.rank() as u32;
        let rank = if self.wave.is_some() {
            1 - goal_first
        } else {
            goal_first
        };
        self.scratch.queue.push_ordered(word, rank, kind);
    }

    /// The order word of a funnel keyed `key`, no smaller than `after` (the word of the funnel
    /// it was split from, so that words never decrease along the tree: the radix queue needs
    /// it, and the max of two valid words is valid). In the A* order the key's bits; in the
    /// wave order its band, then its reach bound (module docs, "The wave order"): `reach`, when
    /// the caller has computed it, else computed here.
    fn funnel_word(
        &self,
        key: f64,
        reach: Option<f64>,
        f: &FunnelState,
        apex: Apex,
        after: u64,
    ) -> u64 {
        let word = match self.wave {
            Some(wave) => {
                let reach = reach.unwrap_or_else(|| self.reach_bound(f, apex));
                // One band orders by the reach alone: its band is the reach's binade.
                let band_key = if wave.is_one_band() { reach } else { key };
                wave.word(band_key, reach, WaveEntry::Funnel)
            }
            None => ordered_bits(key),
        };
        word.max(after)
    }

    /// The key of a child funnel split from a funnel popped under key `parent_key`: its A* key
    /// ([`SptSearch::lower_bound`]), or, in one band while no incumbent or length limit prunes
    /// by key, its reach bound (module docs, "The wave order": there the key orders nothing, and
    /// the reach is a lower bound as well); never below `parent_key`. With it the reach bound
    /// when it was computed (for [`SptSearch::funnel_word`], so that it is computed once).
    fn child_key(&self, f: &FunnelState, apex: Apex, parent_key: f64) -> (f64, Option<f64>) {
        let by_reach = self.wave.is_some_and(Wave::is_one_band)
            && self.incumbent().is_none()
            && self.length_limit().is_none();
        if by_reach {
            let reach = self.reach_bound(f, apex);
            (reach.max(parent_key), Some(reach))
        } else {
            (self.lower_bound(f, apex).max(parent_key), None)
        }
    }

    /// The key a popped word stands for: the key itself in the A* order; in the wave order the
    /// bottom of its band, a lower bound of the key (module docs, "The wave order").
    fn key_of_word(&self, word: u64) -> f64 {
        key_of_ordered(self.wave.map_or(word, |wave| word & wave.band))
    }

    /// A lower bound of the length of every path through the funnel to its mouth: `g(apex)`
    /// plus the distance from the apex to the mouth's segment.
    fn reach_bound(&self, f: &FunnelState, apex: Apex) -> f64 {
        mouth_cover::reach_bound(&self.scratch.tree, f, apex.length)
    }

    /// `f * L_1` once the first class is known.
    fn length_limit(&self) -> Option<f64> {
        Some(self.shortest? * self.options.max_length_factor?)
    }

    /// Dominance pruning (module docs): `K` lifts of the apex's vertex are strictly shorter.
    fn dominated(&self, apex: Apex) -> bool {
        self.pruning
            && apex
                .vertex()
                .is_some_and(|v| self.scratch.lifts.dominates(v, apex.length))
    }

    /// The mouth-cover test (module docs, "Dominance pruning with a class count"; the test in
    /// [`crate::mouth_cover`]), with one class wanted only: the funnel's mouth is reached more
    /// cheaply everywhere from its endpoints' shortest known lifts than through the funnel.
    fn covered(&self, f: &FunnelState, apex: Apex) -> bool {
        if !(self.pruning && self.scratch.lifts.k == 1) {
            return false;
        }
        let tree = &self.scratch.tree;
        let end = |tip: NodeId| MouthEnd {
            point: tree.point(tip),
            best: tree
                .vertex(tip)
                .and_then(|v| self.scratch.lifts.shortest(v.index()))
                .unwrap_or(f64::INFINITY),
        };
        let arrival = self
            .scratch
            .arrivals
            .arrival(self.planner.btm.dcel(), tree, f);
        mouth_cover::is_covered_with(
            &tree.point(f.apex()),
            apex.length,
            end(f.right()),
            end(f.left()),
            arrival,
        )
    }

    /// The A* key of a funnel (module docs): eq. 2.5 at the goal, or at its mirror image across
    /// the mouth's line when the goal lies behind it. `apex` is the funnel's apex record.
    fn lower_bound(&self, f: &FunnelState, apex: Apex) -> f64 {
        let tree = &self.scratch.tree;
        // The mouth runs from the right tip's point to the left tip's (read from the tree, whose
        // tips the sector scans just touched, not from the map's vertex array).
        let (a, b) = (tree.point(f.right()), tree.point(f.left()));
        // Every SHP through the funnel passes through its apex: g(apex) + h(apex) bounds it.
        let through_apex = match &self.to_goal {
            Some(h) => apex.vertex().map_or(0.0, |v| apex.length + h[v.index()]),
            None => 0.0,
        };
        // The funnel's last triangle lies left of its mouth; beyond is the right side.
        let target = if orient2d(&a, &b, &self.goal) <= 0.0 {
            self.goal
        } else {
            mirror(&self.goal, &a, &b)
        };
        let t = f.predecessor(tree, &target);
        (tree.length(t) + (target - tree.point(t)).norm()).max(through_apex)
    }

    /// Builds the class reached at goal node `node` through the funnel mouths of `trail`.
    fn emit(&mut self, node: NodeId, trail: u32) -> Result<Option<RankedShp>, SearchError> {
        let btm = self.planner.btm;
        let taut = self.scratch.tree.taut_path(btm, node);
        let simple = anchors_are_simple(
            taut.anchors.iter().map(|a| (a.vertex, a.obstacle)),
            &mut self.scratch.simple_buffers,
        );
        if self.options.simple_only && !simple {
            self.stats.skipped_not_simple += 1;
            return Ok(None);
        }
        if self.scratch.trail_dropped {
            // The sleeve is the SHP's reduced crossing sequence (module invariant, tested
            // against the trail's): traced in time proportional to the SHP's triangles.
            let chi = CrossingSequence::reduced_of_path(btm, &taut.to_path())
                .map_err(|e| SearchError::Internal(format!("tracing the SHP of a class: {e}")))?;
            let sleeve = Sleeve::from_crossing_sequence(btm, &chi)?;
            return Ok(Some(self.class(taut, sleeve, simple)));
        }
        // The trail is walked twice (count, then fill from the back): one allocation of the
        // sleeve's exact size instead of a vector grown by doubling.
        let trails = &self.scratch.trail;
        let ancestors = |mut t: u32| {
            std::iter::from_fn(move || {
                (t != NONE).then(|| {
                    let (mouth, parent) = trails[t as usize];
                    t = parent;
                    mouth
                })
            })
        };
        let n = ancestors(trail).count();
        let mut portals = vec![HalfEdgeId(0); n];
        for (slot, mouth) in portals.iter_mut().rev().zip(ancestors(trail)) {
            *slot = mouth;
        }
        let sleeve = Sleeve::from_portals(btm, self.start_triangle, portals)?;
        Ok(Some(self.class(taut, sleeve, simple)))
    }

    /// The class answer from its SHP and sleeve.
    fn class(&mut self, taut: TautPath, sleeve: Sleeve, simple: bool) -> RankedShp {
        let crossings = sleeve.crossing_sequence();
        let h_signature =
            self.planner
                .h_signature_reusing(&taut, &sleeve, &mut self.scratch.crossings);
        self.emitted += 1;
        self.shortest.get_or_insert(taut.length);
        RankedShp {
            rank: self.emitted,
            shp: ShortestHomotopicPath {
                taut,
                crossings,
                sleeve,
            },
            h_signature,
            simple,
            expansions: self.stats.expansions,
        }
    }

    /// `true` when the anchors on the tree path to `apex` (strict turns strictly between the root
    /// and `apex`) form a simple sequence. Cached per node.
    fn prefix_is_simple(&mut self, apex: NodeId) -> bool {
        if self.scratch.simple_prefix.len() < self.scratch.tree.len() {
            self.scratch
                .simple_prefix
                .resize(self.scratch.tree.len(), 0);
        }
        match self.scratch.simple_prefix[apex.index()] {
            1 => return true,
            2 => return false,
            _ => {}
        }
        let path = self.scratch.tree.path(apex);
        let btm = self.planner.btm;
        let anchors = path.windows(3).filter_map(|w| {
            let [a, b, c] = [w[0], w[1], w[2]].map(|n| self.scratch.tree.node(n));
            let v = b.vertex()?;
            (orient2d(&a.point, &b.point, &c.point) != 0.0).then(|| (v, btm.obstacle_of_vertex(v)))
        });
        let simple = anchors_are_simple(anchors, &mut self.scratch.simple_buffers);
        self.scratch.simple_prefix[apex.index()] = if simple { 1 } else { 2 };
        simple
    }

    /// Bytes held by the search's structures (see [`SearchStats::peak_bytes`]).
    fn bytes(&self) -> usize {
        self.scratch.live_bytes(self.pruning)
    }

    /// Collects the tree (module docs, "Collecting the tree": [`Scratch::collect`]) and sets the
    /// next collection at twice the nodes kept (at least `collect_min`), so a collection's cost,
    /// linear in the tree and the queue, is paid once per doubling.
    fn collect_tree(&mut self) {
        let dropped = self
            .scratch
            .collect(self.pruning, &mut self.stats.peak_bytes);
        self.stats.nodes_collected += dropped;
        self.collect_at = (2 * self.scratch.tree.len()).max(self.collect_min);
    }

    /// Switches the wave order to one band (module docs, "The wave order"): every queued entry,
    /// and `popped` (the entry just popped), is queued again under its word in the new layout,
    /// a funnel's from its reach bound, a goal's from its length, into the emptied queue.
    fn sweep(&mut self, popped: Kind) {
        self.sweep_from = None;
        self.stats.swept_at = Some(self.stats.expansions);
        let wave = Wave::new(0);
        self.wave = Some(wave);
        let mut entries = Vec::with_capacity(self.scratch.queue.len() + 1);
        while let Some((_, item)) = self.scratch.queue.pop_ordered() {
            entries.push(item);
        }
        entries.push(popped);
        self.scratch.queue.clear();
        for item in entries {
            let word = match item {
                Kind::Goal { node, .. } => {
                    let length = self.scratch.tree.length(node);
                    wave.word(length, length, WaveEntry::Goal)
                }
                Kind::Funnel { funnel, apex, .. } => {
                    // One band orders by the reach alone (`funnel_word`): no A* key is needed.
                    let reach = self.reach_bound(&funnel, apex);
                    self.funnel_word(reach, Some(reach), &funnel, apex, 0)
                }
            };
            self.push(word, item);
        }
    }
}

impl Drop for SptSearch<'_> {
    /// Gives the scratch space back to the planner's pool for the next query.
    fn drop(&mut self) {
        // The placeholder left behind allocates nothing (`FunnelTree::default` has no root).
        let scratch = std::mem::take(&mut self.scratch);
        self.planner.return_scratch(scratch);
    }
}

impl Iterator for SptSearch<'_> {
    type Item = Result<RankedShp, SearchError>;

    fn next(&mut self) -> Option<Self::Item> {
        self.next_best().transpose()
    }
}

/// Mantissa bits of an A* key that make its band in the default wave order ([`QueueOrder::Auto`],
/// module docs, "The wave order"): keys within a factor `1 + 2^-20` (about 1e-6) of each other
/// share a band. A performance setting, not a tolerance: every band width gives the same answer.
pub const WAVE_BAND_BITS: u32 = 20;

/// The popped key from which a one-class search in the automatic order sweeps in one band
/// (module docs, "The wave order"), or `None` when it never should: once every shortest path is
/// known to be at least `key` long, the A* ellipse of foci `start` and `goal` and major axis
/// `key` (semi-minor axis `sqrt(key^2 - D^2) / 2`, `D = |goal - start|`) reaches every
/// boundary vertex's distance from the line through them, i.e. it spans the free space, when
/// `key^2 >= D^2 + 4 w^2`, `w` the largest such distance. Never when the free space reaches
/// behind the start more than [`SWEEP_BEHIND_FRACTION`] of `D` (one band would sweep it all,
/// where A* does not), or when start and goal coincide. `boundary`: the map's outer boundary
/// (a linear function's extreme over the free space is at one of its vertices); linear in it.
fn sweep_key(start: Point2<f64>, goal: Point2<f64>, boundary: &[Point2<f64>]) -> Option<f64> {
    let axis = goal - start;
    let d = axis.norm();
    if d == 0.0 || !d.is_finite() {
        return None;
    }
    let (along, across) = (axis / d, Vector2::new(-axis.y, axis.x) / d);
    let (mut behind, mut width) = (0.0f64, 0.0f64);
    for p in boundary {
        let r = p - start;
        behind = behind.max(-r.dot(&along));
        width = width.max(r.dot(&across).abs());
    }
    (behind <= SWEEP_BEHIND_FRACTION * d).then(|| (d * d + 4.0 * width * width).sqrt())
}

/// How far behind the start (along the line from the goal), as a fraction of the start-goal
/// distance, the free space may reach for the automatic wave order to sweep in one band
/// (module docs, "The wave order"): one band sweeps every funnel that reaches less than the answer, behind the
/// start as well, so at most an eighth more ground than the strip between start and goal.
pub const SWEEP_BEHIND_FRACTION: f64 = 0.125;

/// The wave order's word layout for one band width (module docs, "The wave order").
#[derive(Debug, Clone, Copy)]
struct Wave {
    /// The bits of a word that hold the key's band: the sign, the exponent and the top
    /// `band_bits` bits of the mantissa of the key's order-preserving bits.
    band: u64,
    /// The reach's units per band floor: `2^(51 - band_bits)`, so that a reach up to twice the
    /// floor fits in the bits below the band.
    scale: f64,
}

/// What a wave word is made for: a goal's reach is rounded up, a funnel's down.
#[derive(Clone, Copy, PartialEq)]
enum WaveEntry {
    Funnel,
    Goal,
}

impl Wave {
    /// The layout for bands of `band_bits` (at most 52) bits of mantissa.
    fn new(band_bits: u32) -> Wave {
        Wave {
            band: !0 << (52 - band_bits),
            scale: (2.0f64).powi(51 - band_bits as i32),
        }
    }

    /// `true` for one band per binade (`band_bits` 0): Dijkstra's order by the reach bound.
    fn is_one_band(self) -> bool {
        self.band == !0 << 52
    }

    /// The word of an entry with A* key `key` (non-negative) and reach bound `reach` (at most
    /// `key`): the key's band in the high bits (the key rounded down to the band's mantissa
    /// bits), then `reach` in units of the band's floor over [`Wave::scale`], rounded down for
    /// a funnel and up for a goal, saturating (the order stays valid, only less fine).
    fn word(self, key: f64, reach: f64, entry: WaveEntry) -> u64 {
        let band = ordered_bits(key) & self.band;
        let floor = key_of_ordered(band);
        let units = if floor > 0.0 {
            reach / floor * self.scale
        } else {
            0.0
        };
        let units = match entry {
            WaveEntry::Funnel => units.floor(),
            WaveEntry::Goal => units.ceil(),
        };
        // `as` saturates (and maps NaN to 0, never produced: both inputs are finite).
        band | (units as u64).min(!self.band)
    }
}

/// The mirror image of `p` across the line through `a` and `b` (`a != b`).
fn mirror(p: &Point2<f64>, a: &Point2<f64>, b: &Point2<f64>) -> Point2<f64> {
    let d = b - a;
    let t = (p - a).dot(&d) / d.norm_squared();
    let foot = a + d * t;
    foot + (foot - p)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The word layout the wave order's proof rests on (module docs, "The wave order"): bands
    /// follow the keys, reaches order the entries of one band, a goal never shares a word below
    /// a funnel that reaches less, and the band's floor never exceeds the key.
    #[test]
    fn wave_words_order_bands_then_reaches() {
        for bits in [0, 3, WAVE_BAND_BITS, 52] {
            let wave = Wave::new(bits);
            let keys = [
                0.0,
                1e-300,
                0.75,
                1.0,
                1.0 + 1e-7,
                1.5,
                2.0,
                1e6,
                7.5e5 + 0.3,
                1e300,
            ];
            for &a in &keys {
                let floor = key_of_ordered(ordered_bits(a) & wave.band);
                assert!(
                    floor <= a && (a == 0.0 || floor > 0.0),
                    "{bits}: {a} -> {floor}"
                );
                for &b in &keys {
                    // A smaller key's band is no later, whatever the reaches.
                    let (wa, wb) = (
                        wave.word(a, a, WaveEntry::Goal),
                        wave.word(b, 0.0, WaveEntry::Funnel),
                    );
                    if a < b && (ordered_bits(a) & wave.band) < (ordered_bits(b) & wave.band) {
                        assert!(wa < wb, "{bits}: {a} before {b}");
                    }
                }
                // In one band: reaches in order; a goal of length `l` is no earlier than a
                // funnel reaching at most `l` (equal words pop the funnel first, by rank).
                for (r1, r2) in [(0.0, a * 0.5), (a * 0.25, a), (a * 0.999_999, a)] {
                    if r1 < r2 {
                        assert!(
                            wave.word(a, r1, WaveEntry::Funnel)
                                <= wave.word(a, r2, WaveEntry::Funnel)
                        );
                    }
                    assert!(
                        wave.word(a, r1, WaveEntry::Funnel) <= wave.word(a, a, WaveEntry::Goal)
                    );
                }
                // A reach beyond the key's band saturates within the band.
                let w = wave.word(a, f64::MAX, WaveEntry::Goal);
                assert_eq!(w & wave.band, ordered_bits(a) & wave.band);
            }
        }
        // Within one band of the default width, reaches a millimetre apart on a 750 km strip
        // are told apart.
        let wave = Wave::new(WAVE_BAND_BITS);
        let key = 750_012.1;
        assert!(
            wave.word(key, 400_000.0, WaveEntry::Funnel)
                < wave.word(key, 400_000.001, WaveEntry::Funnel)
        );
    }

    /// Collecting the tree leaves every answer unchanged (module docs, "Collecting the
    /// tree"): on a crater strip, searches that collect whenever their tree reaches 64 nodes
    /// (and at twice what was kept) return the same classes, bit for bit (polylines, anchors,
    /// sleeves, H-signatures), after the same expansions and prunings as searches that never
    /// collect, in the wave order, in the A* order and for several classes; and they did
    /// collect.
    #[test]
    fn collecting_the_tree_changes_no_answer() {
        use rappel_geometry::generate::{CraterStripOptions, crater_strip};
        let g = crater_strip(&CraterStripOptions::new(600, 5)).unwrap();
        let btm = Btm::from_map(&g.map).unwrap();
        let planner = SptPlanner::new(&btm);
        let run = |options: &SearchOptions, collect: bool| {
            let mut search = planner.search(g.start, g.goal, options).unwrap();
            if collect {
                (search.collect_at, search.collect_min) = (64, 64);
            }
            let out = search.run().unwrap();
            let classes = format!("{:?}", out.classes);
            let s = out.stats;
            let counts = [
                s.expansions,
                s.pruned_dominated,
                s.pruned_covered,
                s.pruned_incumbent,
                s.pruned_length,
                s.nodes_discarded,
                s.queue_peak,
            ];
            (classes, counts, s.nodes_collected, s.tree_nodes)
        };
        let one = SearchOptions::default().with_max_classes(Some(1)).unwrap();
        for options in [
            one.clone(),
            one.with_queue_order(QueueOrder::AStar),
            SearchOptions::default().with_max_classes(Some(4)).unwrap(),
        ] {
            let (classes, counts, none_collected, all) = run(&options, false);
            let (classes_c, counts_c, collected, kept) = run(&options, true);
            assert!(!classes.is_empty() && classes.contains("rank: 1"));
            assert_eq!(classes_c, classes, "{options:?}");
            assert_eq!(counts_c, counts, "{options:?}");
            assert_eq!(none_collected, 0);
            assert!(collected > 0, "{options:?}: the small trees were collected");
            assert_eq!(kept + collected, all, "every node kept or collected");
        }
    }

    /// The switch to one band (module docs, "The wave order") from the map's outer boundary: a
    /// long corridor switches once the key proves the ellipse spans it, at `sqrt(D^2 + 4 w^2)`;
    /// free space reaching behind the start, or coinciding ends, never switch.
    #[test]
    fn the_sweep_starts_when_the_ellipse_spans_the_free_space() {
        let p = Point2::new;
        let corridor = [p(0.0, -1.0), p(100.0, -1.0), p(100.0, 1.0), p(0.0, 1.0)];
        // From (1, 0) to (99, 0): D = 98, w = 1, 1 behind the start (under D / 8).
        let from = sweep_key(p(1.0, 0.0), p(99.0, 0.0), &corridor).unwrap();
        assert_eq!(from, (98.0f64 * 98.0 + 4.0).sqrt());
        // The ellipse of that major axis reaches the corridor's walls at its middle.
        let b = (from * from - 98.0 * 98.0).sqrt() / 2.0;
        assert!((b - 1.0).abs() < 1e-12);
        // The other way along it: the same key.
        assert_eq!(sweep_key(p(99.0, 0.0), p(1.0, 0.0), &corridor), Some(from));
        // From the middle, half the corridor lies behind the start.
        assert_eq!(sweep_key(p(50.0, 0.0), p(99.0, 0.0), &corridor), None);
        assert_eq!(sweep_key(p(5.0, 0.0), p(5.0, 0.0), &corridor), None);
        // A square: across the line the free space is as wide as the line is long.
        let square = [p(0.0, 0.0), p(10.0, 0.0), p(10.0, 10.0), p(0.0, 10.0)];
        let key = sweep_key(p(0.0, 5.0), p(10.0, 5.0), &square).unwrap();
        assert!(
            key > 14.1,
            "{key}: only a path 40 % longer than the line would switch"
        );
    }

    /// Switching to one band at any popped key changes no answer: on a crater strip, searches
    /// made to switch at their first pop, at the straight line's length, half-way from it to
    /// the answer, or at the answer, find the A* order's shortest path, bit for bit.
    #[test]
    fn switching_to_one_band_changes_no_answer() {
        use rappel_geometry::generate::{CraterStripOptions, crater_strip};
        let g = crater_strip(&CraterStripOptions::new(400, 2)).unwrap();
        let btm = Btm::from_map(&g.map).unwrap();
        let planner = SptPlanner::new(&btm);
        let one = SearchOptions::default().with_max_classes(Some(1)).unwrap();
        let first = |order, from: Option<f64>| {
            let options = one.clone().with_queue_order(order);
            let mut search = planner.search(g.start, g.goal, &options).unwrap();
            if from.is_some() {
                search.sweep_from = from;
            }
            let c = search.next_best().unwrap().expect("a class");
            let swept_at = search.stats().swept_at;
            // The statistic says whether, and after how many expansions, the order switched.
            assert_eq!(
                search.sweep_from.is_none() && from.is_some(),
                swept_at.is_some()
            );
            assert!(swept_at.is_none_or(|at| at <= c.expansions));
            (c.length(), format!("{:?}", c.shp.taut.points), swept_at)
        };
        let (length, points, _) = first(QueueOrder::AStar, None);
        let line = (g.goal - g.start).norm();
        assert!(length > line + 0.01, "{length} against the line's {line}");
        for (from, must_switch) in [
            (0.0, true),
            (line, false),
            ((line + length) / 2.0, true),
            (length, false),
        ] {
            let (l, pts, swept_at) = first(QueueOrder::Auto, Some(from));
            assert_eq!((l, &pts), (length, &points), "switching at {from}");
            if must_switch {
                // Popped keys are band floors, within a band of the key: the first and the
                // middle switch points are passed; the line and the answer may not be.
                assert!(swept_at.is_some(), "the search switched at {from}");
            }
        }
    }
}
