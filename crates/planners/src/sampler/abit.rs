//! ABIT* (Strub & Gammell 2020, as Paton 2020 §V uses it) with non-Markovian states (§V-A).
//!
//! One *iteration* processes one edge of the queue, or starts a search when the queue is empty:
//!
//! 1. **Batches.** Each batch adds `batch_size` valid samples to the edge-implicit RGG; once a
//!    solution of cost `c_best` exists they are drawn from the informed set (Gammell et al. 2018).
//!    The RGG's `k` is fixed when a batch is added, as OMPL 1.5.2's BIT* and ABIT* fix it
//!    (`ImplicitGraph::updateNearestTerms`, `calculateK`): `k = ceil(f (e + e/d) ln n)` with
//!    `f = rgg_k_factor` (OMPL's rewire factor, default 1.1), `n` the locations held before the
//!    batch (those that could improve the solution, once one exists; plus the batch's size for
//!    the first batch), and a state's own location among its `k` nearest.
//! 2. **Searches** (OMPL's `BITstar::iterate`). A batch is first searched forward from the start
//!    with the cost-to-go inflated by `initial_inflation` (a greedy search that finds a first
//!    solution quickly). When that search ends without a solution, a new batch is added; with
//!    one, the batch's final search follows with the inflation `1 + inflation_scaling / q`, and
//!    after it a new batch. Expanding a state queues its edges (OMPL's `insertOutgoingEdges`);
//!    its expansion is *registered* for the batch when one of its edges enters the tree or one
//!    of its tree edges is popped (OMPL's `registerExpansion`). A state whose cost falls is
//!    expanded again at once if its expansion is not registered, else it joins the
//!    *inconsistent* set, and the final search re-keys the queue and expands just those states
//!    (ABIT*'s repairing search) rather than restarting. The tree persists across searches and
//!    batches; a tree edge met in the queue expands its child again (OMPL).
//! 3. **Edge queue.** Edges `(v, x)` are ordered by OMPL 1.5.2's key `[g(v) + ĉ(v, x) + ε ĥ(x),
//!    g(v) + ĉ(v, x), g(v)]`, lexicographically (inflated potential solution quality first;
//!    exact ties then by ids, so the order is deterministic). An edge is queued at most once:
//!    queuing it again updates its key, and when a state's cost falls the queued outgoing edges
//!    of the state and of its descendants are re-keyed (OMPL's `SearchQueue::enqueueEdge` and
//!    `Vertex::updateCostAndDepth`). `ĉ` is the space's estimate
//!    of one motion ([`StateSpace::motion_cost_heuristic`]), `ĥ` (and the informed set's
//!    cost-to-come) its estimate of any path ([`StateSpace::cost_heuristic`]).
//! 4. **Truncation.** When the best edge's uninflated `f = g(v) + ĉ + ĥ` satisfies
//!    `(1 + truncation_scaling / q) f >= c_best`, the search is done (the next one starts);
//!    `q` is OMPL's `numVertices() + numSamples()`: the states in the tree plus the locations.
//! 5. **Lazy evaluation.** An edge is queued when it could improve its child and the solution
//!    by the *lower bound* `ĝ(v)` of its parent's cost-to-come (`ĝ(v) + ĉ <= g(x)`, `ĝ(v) + ĉ +
//!    ĥ(x) <= c_best`, OMPL's `canPossiblyImproveCurrentSolution`); only a popped edge that could
//!    still improve its child and the solution by its parent's cost `g(v)` is checked by
//!    [`MotionValidator::motion`], at most once per parent and child location (the
//!    states at a location share the geometric motion).
//! 6. **Histories.** The motion extends the parent's history; a child whose history is already
//!    set (in the tree, or copied at sampling) accepts only a parent whose extension equals it:
//!    no rewiring across incompatible histories. A fraction `history_copy_fraction` of new
//!    samples copy one of the distinct (not [`MotionValidator::compatible`]) histories of their
//!    k nearest tree states; a copied history accepts a compatible extension when the sample is
//!    first connected. After each
//!    improved solution a fresh goal state with undetermined history is added.
//! 7. **Biased samples.** A fraction `biased_sample_fraction` of new samples comes from the
//!    space's bias distribution ([`StateSpace::sample_biased`]), e.g. where a tether can wrap.
//!
//! Vertices are never pruned (ids stay stable; OMPL's pruning only acts once a solution
//! exists); informed sampling keeps new density where it can improve the solution, and edges
//! that cannot are never queued.

use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap};
use std::time::{Duration, Instant};

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use thiserror::Error;

use super::graph::{Graph, IndexError};
use super::settings::{AbitSettings, SettingsError};
use super::space::{Informed, StateSpace};
use super::stop::Stop;
use super::termination::Termination;
use super::validator::MotionValidator;
use crate::budget::ExpansionBudget;
use crate::stop::{CancelFlag, StopCondition, StopReason};

/// Why the planner could not be set up or run.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum AbitError {
    /// A setting or the termination condition is invalid.
    #[error(transparent)]
    Settings(#[from] SettingsError),
    /// The start state fails [`MotionValidator::state_valid`].
    #[error("the start state {0} is invalid")]
    InvalidStart(String),
    /// The goal state fails [`MotionValidator::state_valid`].
    #[error("the goal state {0} is invalid")]
    InvalidGoal(String),
    /// The nearest-neighbour index rejected a state.
    #[error(transparent)]
    Index(#[from] IndexError),
}

/// A solution: the states from start to goal and the history at each.
#[derive(Debug, Clone, PartialEq)]
pub struct Solution<S, H> {
    /// Total cost (sum of the motions' true costs).
    pub cost: f64,
    /// The states, start first.
    pub path: Vec<S>,
    /// The history at each state of `path`.
    pub histories: Vec<H>,
}

/// One improvement of the best solution, for cost-against-time curves.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolutionEvent {
    /// Iterations done when it was found.
    pub iteration: u64,
    /// Wall time since the planner was created.
    pub elapsed: Duration,
    /// The new best cost.
    pub cost: f64,
    /// Motions checked by the validator until then ([`PlannerStatus::motions_checked`] at that
    /// moment: valid or not, each geometric motion once; OMPL's `numEdgeCollisionChecks_`, its
    /// log's "collision checked" edges), an effort measure beside the iterations, which also
    /// count edges dropped unchecked.
    pub motions_checked: u64,
}

/// What [`Abit::solve`] returns.
#[derive(Debug, Clone, PartialEq)]
pub struct PlannerStatus<S, H> {
    /// The best solution so far, if any.
    pub solution: Option<Solution<S, H>>,
    /// Iterations done in total.
    pub iterations: u64,
    /// Batches of samples added.
    pub batches: u64,
    /// States in the graph (samples, start, goal copies).
    pub states: usize,
    /// Motions evaluated by the validator.
    pub motions_checked: u64,
    /// Samples that came from the space's bias distribution
    /// ([`StateSpace::sample_biased`]; 0 unless `biased_sample_fraction` > 0).
    pub biased_samples: u64,
    /// Every improvement so far, in order (costs strictly decrease).
    pub events: Vec<SolutionEvent>,
    /// Which budget or condition ended the last [`Abit::solve`] (`None` from [`Abit::status`]
    /// outside `solve`).
    pub stopped_by: Option<Stop>,
    /// The shared reason ([`crate::stop`]) when an iteration limit, a time limit or a cancel
    /// flag ended the last [`Abit::solve_until`] (`None` for the cost threshold, and outside
    /// `solve`). A cancel has no [`Stop`] (`stopped_by` is then `None`).
    pub stop_reason: Option<StopReason>,
    /// Where the iterations went.
    pub counters: AbitCounters,
}

/// Where the iterations of a run went (`docs/sampler.md`, "Where the iterations go"): every
/// iteration is a search start or one popped edge, and every popped edge ends in exactly one
/// of the edge outcomes below.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct AbitCounters {
    /// Searches started (the greedy search of a batch, or its final search).
    pub searches: u64,
    /// States expanded (their outgoing edges queued).
    pub expansions: u64,
    /// Popped tree edges (`v` already the parent of `x`): the child re-expanded if needed.
    pub tree_edges: u64,
    /// Popped edges dropped unevaluated by truncation (they cannot improve the solution).
    pub truncated: u64,
    /// Popped edges dropped unevaluated because their child is already reached more cheaply.
    pub covered: u64,
    /// Popped edges whose motion was checked for the first time and found valid.
    pub checks_valid: u64,
    /// Popped edges whose motion was checked for the first time and found invalid.
    pub checks_invalid: u64,
    /// Popped edges whose motion (or the same geometric motion) was already checked.
    pub checks_cached: u64,
    /// Valid motions that did not improve their child or could not improve the solution.
    pub no_improvement: u64,
    /// Valid improving motions refused for their history (no rewiring across histories).
    pub history_refused: u64,
    /// Edges added to the tree.
    pub edges_added: u64,
    /// Edges queued to states already in the tree that are not the expanded state's children
    /// (rewiring candidates).
    pub rewiring_edges_queued: u64,
}

/// Counter by counter: the totals of several runs.
///
/// ```
/// use rappel_planners::sampler::AbitCounters;
/// let mut total = AbitCounters::default();
/// total += AbitCounters { expansions: 3, ..Default::default() };
/// total += AbitCounters { expansions: 4, edges_added: 1, ..Default::default() };
/// assert_eq!((total.expansions, total.edges_added), (7, 1));
/// ```
impl std::ops::AddAssign for AbitCounters {
    fn add_assign(&mut self, c: AbitCounters) {
        // Destructured, so that a new counter cannot be left out of the sum.
        let AbitCounters {
            searches,
            expansions,
            tree_edges,
            truncated,
            covered,
            checks_valid,
            checks_invalid,
            checks_cached,
            no_improvement,
            history_refused,
            edges_added,
            rewiring_edges_queued,
        } = c;
        self.searches += searches;
        self.expansions += expansions;
        self.tree_edges += tree_edges;
        self.truncated += truncated;
        self.covered += covered;
        self.checks_valid += checks_valid;
        self.checks_invalid += checks_invalid;
        self.checks_cached += checks_cached;
        self.no_improvement += no_improvement;
        self.history_refused += history_refused;
        self.edges_added += edges_added;
        self.rewiring_edges_queued += rewiring_edges_queued;
    }
}

/// An edge's sort key, OMPL 1.5.2's (`BITstar::SearchQueue::createSortKey`, compared by
/// `lexicographicalBetterThan`): `[g(v) + ĉ(v, x) + ε ĥ(x), g(v) + ĉ(v, x), g(v)]`, compared
/// lexicographically (the queue then breaks exact ties by the ids, so the order is
/// deterministic).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Key([f64; 3]);
impl Eq for Key {}
impl PartialOrd for Key {
    fn partial_cmp(&self, o: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Key {
    fn cmp(&self, o: &Self) -> std::cmp::Ordering {
        self.0[0]
            .total_cmp(&o.0[0])
            .then(self.0[1].total_cmp(&o.0[1]))
            .then(self.0[2].total_cmp(&o.0[2]))
    }
}
impl Key {
    /// Bit-for-bit equality (the live entry of an edge is the one whose key equals the recorded).
    fn same(&self, o: &Key) -> bool {
        self.0
            .iter()
            .zip(o.0.iter())
            .all(|(a, b)| a.to_bits() == b.to_bits())
    }
}

type Motion<H> = Option<(f64, H)>;

/// A queued edge `(v, x)`, its recorded key and its key computed now (for the tests).
#[cfg(test)]
pub(crate) type QueuedKey = ((u32, u32), [f64; 3], [f64; 3]);

/// Most states at one location (a sample and its copies for other history classes, made by
/// `history_copies_on_expansion`): the bound on copies per location.
pub const MAX_STATES_PER_LOCATION: usize = 8;

/// Draws from the space's bias distribution per biased sample before the planner falls back to
/// uniform (or informed) sampling: the bound of the biased sampling loop. Each draw is already
/// the result of the space's own bounded search, so a few suffice.
pub const BIASED_DRAWS: usize = 16;

/// The `k` of the k-nearest RGG for `n` locations in a `dimension`-dimensional space, as OMPL
/// 1.5.2's BIT* and ABIT* compute it (`BITstar::ImplicitGraph::calculateK` with
/// `calculateMinimumRggK`): `ceil(rewire_factor · (e + e/d) · ln n)`, in that order of
/// operations. The `k` nearest include the querying state itself (OMPL's `nearestK` over its
/// samples, which hold the vertex), so a state has `k - 1` neighbours. At least 1 (OMPL's
/// `unsigned int` of a non-positive `ceil` is undefined; `n <= 1` never happens before a
/// solution, and after one only when nothing can improve it).
pub(crate) fn rgg_k(rewire_factor: f64, dimension: usize, n: usize) -> usize {
    let d = dimension.max(1) as f64;
    let k_rgg = std::f64::consts::E + std::f64::consts::E / d;
    let k = (rewire_factor * k_rgg * (n as f64).ln()).ceil();
    if k >= 1.0 { k as usize } else { 1 }
}

/// The ABIT* planner over space `S` and validator `V` (k-d embedding dimension `K`).
pub struct Abit<'a, S, V, const K: usize>
where
    S: StateSpace<K>,
    V: MotionValidator<S, K>,
{
    space: &'a S,
    validator: &'a V,
    settings: AbitSettings,
    rng: ChaCha8Rng,
    graph: Graph<S::State, V::History, K>,
    start: u32,
    goal_state: S::State,
    goals: Vec<u32>,
    /// The edge queue. An edge is queued at most once, as in OMPL's `SearchQueue`: queuing it
    /// again, or a fall of its parent's cost, updates its key (`enqueueEdge`,
    /// `Vertex::updateCostAndDepth`), done here by pushing the new key and leaving the old entry
    /// in the heap, where it is skipped when popped (its key is no longer `queued`'s).
    queue: BinaryHeap<Reverse<(Key, u32, u32)>>,
    /// The live key of every queued edge.
    queued: HashMap<(u32, u32), Key>,
    /// The queued outgoing edges' children, by parent (OMPL's `edgeQueueOutLookup`), to re-key
    /// them when the parent's cost falls.
    queued_out: Vec<Vec<u32>>,
    /// Checked motions by parent state and the child's location: the states at one location
    /// (goal copies, history copies) share the geometric motion, which the parent's history
    /// decides, so it is checked once (OMPL's edge white- and blacklists).
    motions: HashMap<(u32, u32), Motion<V::History>>,
    expanded_at: Vec<f64>,
    /// States expanded at least once in any search (OMPL's `hasEverBeenExpandedAsRewiring`):
    /// without cascading rewirings, their later expansions queue no edges to tree states.
    expanded_ever: Vec<bool>,
    /// The `k` of the k-nearest RGG, fixed per batch ([`rgg_k`] of [`Abit::rgg_n`]).
    k: usize,
    /// The lower bound `ĥ(start, x) + ĥ(x, goal)` of every location counted so far (for
    /// `rgg_n` once a solution exists; a location's state never changes).
    location_bounds: Vec<f64>,
    best_cost: f64,
    best_goal: Option<u32>,
    inflation: f64,
    truncation: f64,
    /// The running search is the batch's final (uninflated) one (OMPL's `isFinalSearchOnBatch_`).
    final_search: bool,
    /// The running search met an edge that truncation drops: it is over (OMPL's `isSearchDone_`).
    search_done: bool,
    /// States improved after their expansion in this batch's searches (OMPL's inconsistent
    /// set): the final search expands them again instead of restarting from the start.
    inconsistent: Vec<u32>,
    iterations: u64,
    batches: u64,
    biased_samples: u64,
    counters: AbitCounters,
    events: Vec<SolutionEvent>,
    created: Instant,
    /// The wall-time limit of the running [`Abit::solve`], checked between samples of a batch.
    deadline: Option<Instant>,
    /// The cancel flags of the running [`Abit::solve_until`], checked with the deadline.
    cancel: Vec<CancelFlag>,
}

impl<'a, S, V, const K: usize> Abit<'a, S, V, K>
where
    S: StateSpace<K>,
    V: MotionValidator<S, K>,
{
    /// Sets up the planner: checks start and goal, adds them and the first batch of samples.
    pub fn new(
        space: &'a S,
        validator: &'a V,
        start: S::State,
        goal: S::State,
        settings: AbitSettings,
    ) -> Result<Self, AbitError> {
        if !validator.state_valid(&start) {
            return Err(AbitError::InvalidStart(format!("{start:?}")));
        }
        if !validator.state_valid(&goal) {
            return Err(AbitError::InvalidGoal(format!("{goal:?}")));
        }
        let mut graph = Graph::default();
        let h0 = validator.initial_history(&start);
        let s = graph.add(start.clone(), Some(h0), space.key(&start), false)?;
        graph.nodes[s as usize].g = 0.0;
        let gid = graph.add(goal.clone(), None, space.key(&goal), false)?;
        graph.set_goal(gid);
        let mut me = Self {
            space,
            validator,
            rng: ChaCha8Rng::seed_from_u64(settings.seed),
            settings,
            graph,
            start: s,
            goal_state: goal,
            goals: vec![gid],
            queue: BinaryHeap::new(),
            queued: HashMap::new(),
            queued_out: Vec::new(),
            motions: HashMap::new(),
            expanded_at: Vec::new(),
            expanded_ever: Vec::new(),
            k: 1,
            location_bounds: Vec::new(),
            best_cost: f64::INFINITY,
            best_goal: None,
            inflation: 1.0,
            truncation: 1.0,
            final_search: false,
            search_done: false,
            inconsistent: Vec::new(),
            iterations: 0,
            batches: 0,
            biased_samples: 0,
            counters: AbitCounters::default(),
            events: Vec::new(),
            created: Instant::now(),
            deadline: None,
            cancel: Vec::new(),
        };
        me.new_batch()?;
        me.restart_search();
        Ok(me)
    }

    /// Runs until `termination` holds; may be called again to continue (anytime).
    pub fn solve(
        &mut self,
        termination: Termination,
    ) -> Result<PlannerStatus<S::State, V::History>, AbitError> {
        self.solve_until(termination, &StopCondition::none())
    }

    /// [`Abit::solve`] that also stops at `stop`, the condition shared with the other planners
    /// ([`crate::stop`]): its cancel flags and time limit are read on every iteration and
    /// between the samples of a batch, and a fixed expansion budget counts iterations (the
    /// automatic budget, made for funnel expansions on a map, does not apply). Its time limit
    /// counts from this call unless `stop` was [started](StopCondition::started).
    /// [`PlannerStatus::stop_reason`] says which condition fired.
    ///
    /// ```
    /// use rappel_planners::sampler::{Abit, AbitSettings, ObstacleWorld, RealVectorSpace, Termination};
    /// use rappel_planners::stop::{CancelFlag, StopCondition, StopReason};
    /// let world = ObstacleWorld {
    ///     space: RealVectorSpace::new([0.0, 0.0], [1.0, 1.0]).unwrap(),
    ///     obstacles: Vec::new(),
    ///     start: [0.1, 0.1],
    ///     goal: [0.9, 0.9],
    ///     resolution: 0.01,
    /// };
    /// let mut abit =
    ///     Abit::new(&world.space, &world, world.start, world.goal, AbitSettings::default())
    ///         .unwrap();
    /// let flag = CancelFlag::new();
    /// flag.cancel();
    /// let st = abit
    ///     .solve_until(Termination::iterations(1_000_000), &StopCondition::cancel(flag))
    ///     .unwrap();
    /// assert_eq!(st.stop_reason, Some(StopReason::Cancelled));
    /// ```
    pub fn solve_until(
        &mut self,
        termination: Termination,
        stop: &StopCondition,
    ) -> Result<PlannerStatus<S::State, V::History>, AbitError> {
        let mut termination = termination;
        if let ExpansionBudget::Fixed(n) = stop.budget() {
            let n = n as u64;
            termination.max_iterations = Some(termination.max_iterations.map_or(n, |m| m.min(n)));
        }
        if let Some(t) = stop.time_limit() {
            termination.max_time = Some(termination.max_time.map_or(t, |u| u.min(t)));
        }
        termination.validate()?;
        let stop = stop.started();
        let began = Instant::now();
        self.deadline = match (
            termination.max_time.and_then(|t| began.checked_add(t)),
            stop.deadline(),
        ) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        };
        self.cancel = stop.cancel_flags().cloned().collect();
        let first = self.iterations;
        let (stopped_by, stop_reason) = loop {
            if let Some(s) =
                termination.reason(self.iterations - first, began.elapsed(), self.best_cost)
            {
                let reason = match s {
                    Stop::Iterations => termination
                        .max_iterations
                        .map(|limit| StopReason::Iterations { limit }),
                    Stop::Time => termination
                        .max_time
                        .map(|limit| StopReason::TimeLimit { limit }),
                    Stop::CostThreshold => None,
                };
                break (Some(s), reason);
            }
            // A cancel, or the clock of a condition started before this call.
            if let Some(r) = stop.poll() {
                let s = matches!(r, StopReason::TimeLimit { .. }).then_some(Stop::Time);
                break (s, Some(r));
            }
            self.iterate()?;
        };
        self.deadline = None;
        self.cancel.clear();
        let mut status = self.status();
        status.stopped_by = stopped_by;
        status.stop_reason = stop_reason;
        Ok(status)
    }

    /// The graph, for white-box tests.
    #[cfg(test)]
    pub(crate) fn graph(&self) -> &Graph<S::State, V::History, K> {
        &self.graph
    }

    /// States expanded at least once in any search, for white-box tests.
    #[cfg(test)]
    pub(crate) fn states_ever_expanded(&self) -> usize {
        self.expanded_ever.iter().filter(|&&e| e).count()
    }

    /// The current best solution and statistics.
    pub fn status(&self) -> PlannerStatus<S::State, V::History> {
        let solution = self.best_goal.map(|g| {
            let ids = self.graph.path_to(g);
            Solution {
                cost: self.best_cost,
                path: ids
                    .iter()
                    .map(|&i| self.graph.nodes[i as usize].state.clone())
                    .collect(),
                histories: ids
                    .iter()
                    .filter_map(|&i| self.graph.nodes[i as usize].history.clone())
                    .collect(),
            }
        });
        PlannerStatus {
            solution,
            iterations: self.iterations,
            batches: self.batches,
            states: self.graph.nodes.len(),
            motions_checked: self.motions.len() as u64,
            biased_samples: self.biased_samples,
            events: self.events.clone(),
            stopped_by: None,
            stop_reason: None,
            counters: self.counters,
        }
    }

    /// One iteration: process the best edge, or start the next search when the queue is empty
    /// or the search is done (its best edge could not improve the solution).
    pub fn iterate(&mut self) -> Result<(), AbitError> {
        self.iterations += 1;
        if !self.search_done
            && let Some((v, x)) = self.pop_edge()
        {
            self.process(v, x);
            return Ok(());
        }
        self.next_search()
    }

    /// The `q` of ABIT*'s inflation `1 + inflation_scaling / q` and truncation `1 +
    /// truncation_scaling / q`, as OMPL 1.5.2's `BITstar::iterate` counts it:
    /// `numVertices() + numSamples()`, the states in the tree plus all samples (which hold the
    /// vertices too, so a vertex counts twice). Ours: the states in the tree plus the locations
    /// (OMPL has one sample per location). It acts only once a solution exists.
    fn n(&self) -> f64 {
        let vertices = self.graph.nodes.iter().filter(|n| n.in_tree()).count();
        (self.graph.location_count() + vertices).max(2) as f64
    }

    /// The `k` of the running batch's k-nearest RGG (fixed when the batch is added).
    #[cfg(test)]
    pub(crate) fn rgg_k(&self) -> usize {
        self.k
    }

    /// Every queued edge with its recorded key and its key recomputed now (for the tests of
    /// the queue's updates).
    #[cfg(test)]
    pub(crate) fn queued_keys(&self) -> Vec<QueuedKey> {
        let mut v: Vec<_> = self
            .queued
            .iter()
            .map(|(&(a, b), k)| ((a, b), k.0, self.edge_key(a, b).0))
            .collect();
        v.sort_by_key(|e| e.0);
        v
    }

    /// The running search's inflation and truncation factors and whether it is the batch's
    /// final search (for the tests of OMPL's `q`).
    #[cfg(test)]
    pub(crate) fn inflation_truncation_final(&self) -> (f64, f64, bool) {
        (self.inflation, self.truncation, self.final_search)
    }

    /// The batches so far, the best cost and the number of locations (for the tests of `k`).
    #[cfg(test)]
    pub(crate) fn batches_cost_locations(&self) -> (u64, f64, usize) {
        (self.batches, self.best_cost, self.graph.location_count())
    }

    /// One state per location, the first `n` locations (for the tests of `k`).
    #[cfg(test)]
    pub(crate) fn location_states(&self, n: usize) -> Vec<S::State> {
        (0..n)
            .map(|l| {
                self.graph.nodes[self.graph.at_location(l as u32)[0] as usize]
                    .state
                    .clone()
            })
            .collect()
    }

    /// The `n` of the RGG's `k` for the batch about to be sampled, counted as OMPL 1.5.2's
    /// `BITstar::ImplicitGraph::updateNearestTerms` counts it when `addNewSamples` starts a
    /// batch: the locations held *before* the batch's samples (the start and the goal
    /// included), only those that could still improve the solution once one exists (the
    /// lower bound `ĥ(start, x) + ĥ(x, goal) < c_best`: OMPL's count without pruning,
    /// `computeNumberOfSamplesInInformedSet`, which is what its pruning keeps), and, for the
    /// first batch, when only the start and the goal are held, plus the batch's size.
    fn rgg_n(&mut self) -> usize {
        let locations = self.graph.location_count();
        let n = if self.best_cost.is_finite() {
            let start = &self.graph.nodes[self.start as usize].state;
            for loc in self.location_bounds.len()..locations {
                let id = self.graph.at_location(loc as u32)[0];
                let s = &self.graph.nodes[id as usize].state;
                self.location_bounds.push(
                    self.space.cost_heuristic(start, s)
                        + self.space.cost_heuristic(s, &self.goal_state),
                );
            }
            self.location_bounds
                .iter()
                .filter(|&&b| b < self.best_cost)
                .count()
        } else {
            locations
        };
        if n == 2 {
            n + self.settings.batch_size
        } else {
            n
        }
    }

    /// The cost-to-go estimate `ĥ(x)`: a lower bound of any *path* from `x` to the goal, so
    /// the space's path estimate ([`StateSpace::cost_heuristic`]). Used in the edge queue's key
    /// and `f = g(v) + ĉ + ĥ` (expansion, truncation), and in the check that a checked motion
    /// can still improve the solution (`g(v) + c + ĥ(x) >= c_best`). The informed set of the
    /// samplers uses the same path estimate for the cost-to-come from the start.
    fn h(&self, x: u32) -> f64 {
        self.space
            .cost_heuristic(&self.graph.nodes[x as usize].state, &self.goal_state)
    }

    /// The edge-cost estimate `ĉ(v, x)` of the one motion from `v` to `x` that the validator
    /// would check, so the space's motion estimate ([`StateSpace::motion_cost_heuristic`],
    /// OMPL's `motionCostHeuristic`). Every use is about that single edge: the queue keys
    /// `g(v) + ĉ + ε ĥ` (at expansion, for tree edges and new edges, and when the final search
    /// re-keys the queue), the expansion's prunings `g(v) + ĉ + ĥ >= c_best` (the edge cannot
    /// improve the solution) and `g(v) + ĉ >= g(x)` (it cannot improve its child: a history
    /// copy or nothing), the same test against a history copy's cost (`copy_for`), and the
    /// popped edge's truncation and `covered` tests. Each is a bound on the cost through the
    /// edge `(v, x)` itself, never on a path of several motions, so the motion estimate, which
    /// may exceed the path estimate, keeps them admissible.
    fn c_hat(&self, v: u32, x: u32) -> f64 {
        self.space.motion_cost_heuristic(
            &self.graph.nodes[v as usize].state,
            &self.graph.nodes[x as usize].state,
        )
    }

    /// The search is over (OMPL's `BITstar::iterate`): after the batch's final search, or when
    /// no solution exists yet, a new batch searched greedily from the start; otherwise the
    /// batch's final search with the inflation `1 + inflation_scaling / q` (`Abit::n`).
    fn next_search(&mut self) -> Result<(), AbitError> {
        if self.final_search || !self.best_cost.is_finite() {
            self.new_batch()?;
            self.final_search = false;
            self.search_done = false;
            self.restart_search();
        } else {
            self.inflation = 1.0 + self.settings.inflation_scaling / self.n();
            self.final_search = true;
            self.search_done = false;
            self.repair_search();
        }
        Ok(())
    }

    /// The batch's final search (OMPL's `rebuildEdgeQueue` and
    /// `insertOutgoingEdgesOfInconsistentVertices`): the edges still queued re-keyed with the
    /// new inflation, and the states whose cost fell after their expansion expanded again. The
    /// expansions of the batch's greedy search stand.
    fn repair_search(&mut self) {
        self.counters.searches += 1;
        let entries = std::mem::take(&mut self.queue).into_vec();
        for Reverse((key, v, x)) in entries {
            // Only the live entries (a stale one's edge has a newer key).
            if self.queued.get(&(v, x)).is_some_and(|k| k.same(&key)) {
                let key = self.edge_key(v, x);
                self.queued.insert((v, x), key);
                self.queue.push(Reverse((key, v, x)));
            }
        }
        for v in std::mem::take(&mut self.inconsistent) {
            self.expand(v);
        }
    }

    fn restart_search(&mut self) {
        self.queue.clear();
        self.queued.clear();
        self.queued_out.iter_mut().for_each(Vec::clear);
        self.inconsistent.clear();
        self.expanded_at.clear();
        self.expanded_at
            .resize(self.graph.nodes.len(), f64::INFINITY);
        self.truncation = 1.0 + self.settings.truncation_scaling / self.n();
        self.counters.searches += 1;
        self.expand(self.start);
    }

    /// Queues the outgoing edges of tree state `v` (OMPL's `SearchQueue::insertOutgoingEdges`
    /// and `enqueueEdges`): nothing if `v` cannot improve the solution (`ĝ(v) + ĥ(v) <=
    /// c_best` fails); else the edges to its children (they may have left its k nearest as the
    /// graph grew, yet the search must reach them to repair their subtrees) and to its k nearest
    /// that pass [`Abit::enqueue_conditionally`] (OMPL's filter, on the lower bound `ĝ(v)` of
    /// `v`'s cost-to-come, not on `g(v)`: an edge that cannot improve its child now is still
    /// queued, and dropped when popped unless `v`'s cost has fallen since). A state's expansion
    /// is *registered* (OMPL's `registerExpansion`) only when one of its edges enters the tree,
    /// in [`Abit::process`].
    fn expand(&mut self, v: u32) {
        let gv = self.graph.nodes[v as usize].g;
        let g_lower = self.g_hat(v);
        if g_lower + self.h(v) > self.best_cost {
            return;
        }
        self.counters.expansions += 1;
        if self.expanded_ever.len() < self.graph.nodes.len() {
            self.expanded_ever.resize(self.graph.nodes.len(), false);
        }
        // OMPL's BIT* (no cascading rewirings) queues edges to tree states only on a state's
        // first expansion: the state is always among its own neighbours and in the tree, so
        // every expansion marks it (`SearchQueue::enqueueEdges`).
        let rewirings = self.settings.cascading_rewirings || !self.expanded_ever[v as usize];
        self.expanded_ever[v as usize] = true;
        for i in 0..self.graph.nodes[v as usize].children.len() {
            let x = self.graph.nodes[v as usize].children[i];
            self.enqueue_conditionally(v, g_lower, x);
        }
        let key = self.space.key(&self.graph.nodes[v as usize].state);
        // The k nearest locations with `v`'s own among them (OMPL queries its samples, which
        // hold the vertex itself, and skips it below): k - 1 neighbours.
        let mut near = self.graph.near(&key, self.k);
        if v == self.start {
            // The start-goal edge is always a candidate (the straight-line attempt): BIT*'s
            // r-disc graph includes it in the first batches, whose radius spans the space,
            // while the k nearest of a sparse batch may not reach the goal.
            for &g in &self.goals {
                if !near.contains(&g) {
                    near.push(g);
                }
            }
        }
        let parent = self.graph.nodes[v as usize].parent;
        for x in near {
            let node = &self.graph.nodes[x as usize];
            if !node.in_tree() {
                self.enqueue_conditionally(v, g_lower, x);
                continue;
            }
            // A tree state (OMPL: not the root, not `v`, not already `v`'s child, not `v`'s
            // parent).
            if !rewirings
                || x == v
                || x == self.start
                || node.parent == Some(v)
                || parent == Some(x)
            {
                continue;
            }
            // History copies on expansion (ours, `copy_for`): a tree state that `v` cannot
            // reach more cheaply, claimed by an incompatible history class, gets a copy of its
            // location for `v`'s class instead of the edge.
            let x = if gv + self.c_hat(v, x) >= node.g
                && let Some(copy) = self.copy_for(v, x)
            {
                copy
            } else {
                x
            };
            self.enqueue_conditionally(v, g_lower, x);
        }
    }

    /// The lower bound `ĝ(v)` of `v`'s cost-to-come: the space's path estimate from the start
    /// (OMPL's `costToComeHeuristic`).
    fn g_hat(&self, v: u32) -> f64 {
        self.space.cost_heuristic(
            &self.graph.nodes[self.start as usize].state,
            &self.graph.nodes[v as usize].state,
        )
    }

    /// Queues edge `(v, x)` unless its motion is known to be invalid or it cannot possibly
    /// improve the solution or its child (OMPL's `enqueueEdgeConditionally` and
    /// `canPossiblyImproveCurrentSolution`): `ĝ(v) + ĉ + ĥ(x) <= c_best` and, when `x` is in the
    /// tree, `ĝ(v) + ĉ <= g(x)`, with the lower bound `ĝ(v)` (`g_lower`, [`Abit::g_hat`], computed
    /// once per expansion by the caller), not `g(v)`.
    fn enqueue_conditionally(&mut self, v: u32, g_lower: f64, x: u32) {
        let node = &self.graph.nodes[x as usize];
        if matches!(self.motions.get(&(v, node.location)), Some(None)) {
            return;
        }
        let to_target = g_lower + self.c_hat(v, x);
        if to_target + self.h(x) > self.best_cost || (node.in_tree() && to_target > node.g) {
            return;
        }
        if node.in_tree() && node.parent != Some(v) {
            self.counters.rewiring_edges_queued += 1;
        }
        self.enqueue(v, x);
    }

    /// The sort key of edge `(v, x)` now ([`Key`], OMPL's `createSortKey`).
    fn edge_key(&self, v: u32, x: u32) -> Key {
        let g = self.graph.nodes[v as usize].g;
        let to_target = g + self.c_hat(v, x);
        Key([to_target + self.inflation * self.h(x), to_target, g])
    }

    /// Queues edge `(v, x)`, or updates its key if it is queued already (OMPL's
    /// `SearchQueue::enqueueEdge`): an edge is never queued twice.
    fn enqueue(&mut self, v: u32, x: u32) {
        let key = self.edge_key(v, x);
        match self.queued.insert((v, x), key) {
            Some(old) if old.same(&key) => return,
            Some(_) => {}
            None => {
                if self.queued_out.len() <= v as usize {
                    self.queued_out.resize(v as usize + 1, Vec::new());
                }
                self.queued_out[v as usize].push(x);
            }
        }
        self.queue.push(Reverse((key, v, x)));
    }

    /// The best live edge, removed from the queue (OMPL's `popFrontEdge`); stale entries (keys
    /// since updated) are dropped on the way and are not iterations.
    fn pop_edge(&mut self) -> Option<(u32, u32)> {
        while let Some(Reverse((key, v, x))) = self.queue.pop() {
            if self.queued.get(&(v, x)).is_some_and(|k| k.same(&key)) {
                self.queued.remove(&(v, x));
                let out = &mut self.queued_out[v as usize];
                if let Some(i) = out.iter().position(|&c| c == x) {
                    out.swap_remove(i);
                }
                return Some((v, x));
            }
        }
        None
    }

    /// After `x`'s cost fell: the queued outgoing edges of `x` and of every descendant (whose
    /// costs fell with it) take their new keys (OMPL's `Vertex::updateCostAndDepth`, which
    /// updates the edges in a vertex's `edgeQueueOutLookup` and cascades to its children).
    fn rekey_subtree(&mut self, x: u32) {
        let mut stack = vec![x];
        while let Some(u) = stack.pop() {
            if let Some(out) = self.queued_out.get_mut(u as usize) {
                // Every edge listed is queued already, so `enqueue` only updates its key and
                // leaves the list alone: taken out and put back rather than copied.
                let out = std::mem::take(out);
                for &c in &out {
                    self.enqueue(u, c);
                }
                self.queued_out[u as usize] = out;
            }
            stack.extend(self.graph.nodes[u as usize].children.iter().copied());
        }
    }

    /// With `history_copies_on_expansion`: tree state `x` is claimed more cheaply than `v` could
    /// reach it, by a parent whose history is not [`MotionValidator::compatible`] with `v`'s.
    /// Rewiring across the classes is forbidden, so `v`'s class would never enter `x`'s
    /// location; instead a copy of `x`'s location with undetermined history is made (or the
    /// pending one reused) for `v` to connect (Paton §V-A's copied states, made when a second
    /// class meets the location rather than at sampling). At most
    /// [`MAX_STATES_PER_LOCATION`] states share a location.
    fn copy_for(&mut self, v: u32, x: u32) -> Option<u32> {
        if !self.settings.history_copies_on_expansion {
            return None;
        }
        let nx = &self.graph.nodes[x as usize];
        let hv = self.graph.nodes[v as usize].history.as_ref()?;
        let hp = nx
            .parent
            .and_then(|p| self.graph.nodes[p as usize].history.as_ref())?;
        if nx.is_goal || self.validator.compatible(hv, hp) {
            return None;
        }
        let siblings = self.graph.at_location(nx.location);
        for &s in siblings {
            let ns = &self.graph.nodes[s as usize];
            if ns.history.is_none() && !ns.in_tree() {
                return Some(s);
            }
            if let Some(p) = ns.parent
                && let Some(hp) = &self.graph.nodes[p as usize].history
                && self.validator.compatible(hv, hp)
            {
                // The class already has a state here: the ordinary rules decide.
                return (self.graph.nodes[v as usize].g + self.c_hat(v, s) < ns.g).then_some(s);
            }
        }
        if siblings.len() >= MAX_STATES_PER_LOCATION {
            return None;
        }
        let state = nx.state.clone();
        let copy = self.graph.add_at(x, state, false).ok()?;
        self.expanded_at.push(f64::INFINITY);
        Some(copy)
    }

    fn process(&mut self, v: u32, x: u32) {
        let gv = self.graph.nodes[v as usize].g;
        if self.graph.nodes[x as usize].parent == Some(v) {
            // A tree edge (OMPL's "freebie"): `v` counts as expanded, `x` is expanded again.
            self.counters.tree_edges += 1;
            self.register_expansion(v);
            self.expand(x);
            return;
        }
        let gx = self.graph.nodes[x as usize].g;
        let c_hat = self.c_hat(v, x);
        let h = self.h(x);
        if self.truncation * (gv + c_hat + h) >= self.best_cost {
            // The best edge cannot improve the solution: the search is done (OMPL).
            self.counters.truncated += 1;
            self.search_done = true;
            return;
        }
        if gv + c_hat >= gx {
            self.counters.covered += 1;
            return;
        }
        let Some((c, hist)) = self.motion(v, x) else {
            return;
        };
        let g_new = gv + c;
        // OMPL: the edge can improve the solution with the lower bound of `v`'s cost-to-come
        // (`ĝ(v) + c + ĥ(x) < c_best`) and improves its child (`g(v) + c < g(x)`).
        if self.g_hat(v) + c + h >= self.best_cost || g_new >= gx {
            self.counters.no_improvement += 1;
            return;
        }
        let node = &self.graph.nodes[x as usize];
        let accept = match &node.history {
            // In the tree: only the exact history, so no descendant's validity changes.
            Some(existing) if node.in_tree() => *existing == hist,
            // A copied history reserves the sample for its class; it takes the history the
            // motion brings when that is compatible.
            Some(existing) => self.validator.compatible(existing, &hist),
            // A copy made for another class must bring a class its location lacks.
            None if !node.is_goal => {
                let loc = node.location;
                !self.graph.at_location(loc).iter().any(|&s| {
                    s != x
                        && self.graph.nodes[s as usize]
                            .history
                            .as_ref()
                            .is_some_and(|h| self.validator.compatible(h, &hist))
                })
            }
            None => true,
        };
        if !accept {
            self.counters.history_refused += 1;
            return;
        }
        self.counters.edges_added += 1;
        let rewired = node.in_tree();
        if !rewired {
            self.graph.nodes[x as usize].history = Some(hist);
        }
        self.graph.attach(x, v, g_new);
        if rewired {
            self.rekey_subtree(x);
        }
        self.update_solution();
        if self.expanded_at[x as usize].is_finite() {
            // Expanded before in this batch: repaired by the final search (OMPL).
            self.inconsistent.push(x);
        } else {
            self.expand(x);
        }
        self.register_expansion(v);
    }

    /// OMPL's `Vertex::registerExpansion`, called when an edge of `v` enters the tree or a tree
    /// edge of `v` is popped: from now on in this batch, a fall of `v`'s cost makes it
    /// inconsistent (repaired by the final search) instead of expanding it again at once.
    fn register_expansion(&mut self, v: u32) {
        if !self.expanded_at[v as usize].is_finite() {
            self.expanded_at[v as usize] = self.graph.nodes[v as usize].g;
        }
    }

    fn motion(&mut self, v: u32, x: u32) -> Motion<V::History> {
        let edge = (v, self.graph.nodes[x as usize].location);
        if let Some(m) = self.motions.get(&edge) {
            self.counters.checks_cached += 1;
            return m.clone();
        }
        let nv = &self.graph.nodes[v as usize];
        let m = match &nv.history {
            Some(hv) => self
                .validator
                .motion(&nv.state, hv, &self.graph.nodes[x as usize].state),
            None => None,
        };
        if m.is_some() {
            self.counters.checks_valid += 1;
        } else {
            self.counters.checks_invalid += 1;
        }
        self.motions.insert(edge, m.clone());
        m
    }

    fn update_solution(&mut self) {
        let Some((cost, id)) = self
            .goals
            .iter()
            .map(|&g| (self.graph.nodes[g as usize].g, g))
            .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)))
        else {
            return;
        };
        if cost < self.best_cost {
            self.best_cost = cost;
            self.best_goal = Some(id);
            self.events.push(SolutionEvent {
                iteration: self.iterations,
                elapsed: self.created.elapsed(),
                cost,
                motions_checked: self.motions.len() as u64,
            });
            // Paton §V-A: a fresh goal with undetermined history for the next better path.
            if self
                .goals
                .iter()
                .all(|&g| self.graph.nodes[g as usize].in_tree())
                && let Ok(fresh) = self.graph.add_at(id, self.goal_state.clone(), true)
            {
                self.goals.push(fresh);
                self.expanded_at.push(f64::INFINITY);
            }
        }
    }

    /// Adds one batch of valid samples (informed once a solution exists).
    fn new_batch(&mut self) -> Result<(), AbitError> {
        self.batches += 1;
        // OMPL fixes k for the batch before sampling it (`ImplicitGraph::addNewSamples`).
        self.k = rgg_k(
            self.settings.rgg_k_factor,
            self.space.dimension(),
            self.rgg_n(),
        );
        self.inflation = self.settings.initial_inflation;
        let start_state = self.graph.nodes[self.start as usize].state.clone();
        for _ in 0..self.settings.batch_size {
            // A time budget or a cancel interrupts a batch (the rest of it is not sampled).
            if self.deadline.is_some_and(|d| Instant::now() >= d)
                || self.cancel.iter().any(CancelFlag::is_cancelled)
            {
                break;
            }
            let copy = self.rng.random::<f64>() < self.settings.history_copy_fraction;
            // No draw at fraction 0, so uniform runs keep their random stream.
            let biased = self.settings.biased_sample_fraction > 0.0
                && self.rng.random::<f64>() < self.settings.biased_sample_fraction;
            let (s, from_bias) = match biased.then(|| self.sample_biased(&start_state)).flatten() {
                Some(s) => {
                    self.biased_samples += 1;
                    (s, true)
                }
                None => match self.sample(&start_state) {
                    Some(s) => (s, false),
                    None => continue,
                },
            };
            let key = self.space.key(&s);
            let history = if copy {
                self.neighbour_history(&s, &key)
            } else {
                None
            };
            self.graph.add(s, history, key, from_bias)?;
        }
        Ok(())
    }

    /// One valid sample, by informed or rejection sampling within `max_sample_attempts`.
    fn sample(&mut self, start: &S::State) -> Option<S::State> {
        for _ in 0..self.settings.max_sample_attempts {
            let s = if self.best_cost.is_finite() {
                match self.space.sample_informed(
                    &mut self.rng,
                    start,
                    &self.goal_state,
                    self.best_cost,
                ) {
                    Informed::Sample(s) => s,
                    Informed::Missed | Informed::Unsupported => {
                        let s = self.space.sample_uniform(&mut self.rng);
                        // The informed set: paths start -> s -> goal, so the path estimate.
                        let f = self.space.cost_heuristic(start, &s)
                            + self.space.cost_heuristic(&s, &self.goal_state);
                        if f >= self.best_cost {
                            continue;
                        }
                        s
                    }
                }
            } else {
                self.space.sample_uniform(&mut self.rng)
            };
            if self.validator.state_valid(&s) {
                return Some(s);
            }
        }
        None
    }

    /// One valid sample from the space's bias distribution that could improve the solution,
    /// within [`BIASED_DRAWS`] draws; `None` (uniform or informed sampling takes over) when the
    /// space has no bias, its own search missed, or every draw was invalid or uninformative.
    fn sample_biased(&mut self, start: &S::State) -> Option<S::State> {
        for _ in 0..BIASED_DRAWS {
            let s = self.space.sample_biased(&mut self.rng)?;
            // The informed set, as in `sample`: the path estimate.
            if self.best_cost.is_finite()
                && self.space.cost_heuristic(start, &s)
                    + self.space.cost_heuristic(&s, &self.goal_state)
                    >= self.best_cost
            {
                continue;
            }
            if self.validator.state_valid(&s) {
                return Some(s);
            }
        }
        None
    }

    /// A history drawn uniformly from the distinct histories of the k nearest tree states that
    /// `state` can be valid with (Paton §V-A; [`MotionValidator::history_valid`]), so that a
    /// minority history in a region is copied as often as the majority.
    fn neighbour_history(&mut self, state: &S::State, key: &[f64; K]) -> Option<V::History> {
        let mut distinct: Vec<V::History> = Vec::new();
        for i in self.graph.near(key, self.k) {
            if let Some(h) = &self.graph.nodes[i as usize].history
                && self.graph.nodes[i as usize].in_tree()
                && !distinct.iter().any(|d| self.validator.compatible(d, h))
                && self.validator.history_valid(state, h)
            {
                distinct.push(h.clone());
            }
        }
        if distinct.is_empty() {
            return None;
        }
        let pick = self.rng.random_range(0..distinct.len());
        Some(distinct.swap_remove(pick))
    }
}

#[cfg(test)]
mod tests {
    use super::Key;

    #[test]
    fn keys_compare_as_ompls_three_part_lexicographic_key() {
        // OMPL's `[g + ĉ + ε ĥ, g + ĉ, g]`: ties of the first part go to the smaller `g + ĉ`,
        // then to the smaller `g`.
        assert!(Key([1.0, 0.5, 0.2]) < Key([1.0, 0.6, 0.1]));
        assert!(Key([1.0, 0.5, 0.1]) < Key([1.0, 0.5, 0.2]));
        assert!(Key([0.9, 0.9, 0.9]) < Key([1.0, 0.0, 0.0]));
        assert!(Key([1.0, 0.5, 0.1]).same(&Key([1.0, 0.5, 0.1])));
        assert!(!Key([1.0, 0.5, 0.1]).same(&Key([1.0, 0.5, 0.1 + 1e-17 + f64::EPSILON])));
    }
}
