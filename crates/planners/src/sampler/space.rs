//! The state-space trait of the sampling planner: what ABIT* needs to know about states.
//!
//! `K` is the dimension of the Euclidean embedding that the k-nearest-neighbour search runs in
//! ([`StateSpace::key`]); for a real-vector space it is the space itself, for SE(3) rover states it
//! is, e.g., the position and the yaw's unit vector.

use rand_chacha::ChaCha8Rng;

/// Whether a space can sample directly in the informed set (the prolate hyperspheroid of
/// Gammell et al. 2018) of states that could improve a solution of a given cost.
#[derive(Debug, Clone, PartialEq)]
pub enum Informed<S> {
    /// A state drawn uniformly from the informed set (intersected with the space's bounds).
    Sample(S),
    /// The informed set is empty within the bounds or could not be hit within the space's
    /// own attempt bound; the planner falls back to rejection sampling.
    Missed,
    /// The space has no direct informed sampler; the planner uses rejection sampling.
    Unsupported,
}

/// A state space for ABIT*.
pub trait StateSpace<const K: usize> {
    /// One state.
    type State: Clone + std::fmt::Debug;

    /// A state drawn uniformly from the space's bounds (validity is not checked here).
    fn sample_uniform(&self, rng: &mut ChaCha8Rng) -> Self::State;

    /// A state drawn uniformly from `{x : h(start, x) + h(x, goal) < max_cost}` where the space
    /// supports it (see [`Informed`]).
    fn sample_informed(
        &self,
        rng: &mut ChaCha8Rng,
        start: &Self::State,
        goal: &Self::State,
        max_cost: f64,
    ) -> Informed<Self::State>;

    /// A state drawn from the space's *bias* distribution (the sample-bias hook): a
    /// problem-specific distribution that concentrates samples where the problem is hard, e.g.
    /// near features a tether can wrap (the rover's shadow sampling, `docs/sampler.md`), like
    /// the obstacle-based and visibility-based samplers of the PRM literature. The planner
    /// draws a fraction `biased_sample_fraction` of its samples here and checks their validity
    /// (and, once a solution exists, membership of the informed set) itself. `None` when the
    /// space has no bias or its own bounded search missed; the planner then samples uniformly
    /// (or informed). Must take its randomness from `rng` only (determinism). The default has
    /// no bias.
    fn sample_biased(&self, rng: &mut ChaCha8Rng) -> Option<Self::State> {
        let _ = rng;
        None
    }

    /// The metric distance between two states.
    fn distance(&self, a: &Self::State, b: &Self::State) -> f64;

    /// An admissible estimate (a lower bound) of the cost of *any path* from `a` to `b`, of one
    /// motion or many: the cost-to-come and cost-to-go heuristics, and the informed set
    /// `{x : ĥ(start, x) + ĥ(x, goal) < c_best}` (OMPL's `OptimizationObjective::costToGo`).
    fn cost_heuristic(&self, a: &Self::State, b: &Self::State) -> f64;

    /// An admissible estimate of the cost of the *single motion* from `a` to `b` that
    /// [`MotionValidator::motion`](super::MotionValidator::motion) checks: ABIT*'s edge-cost
    /// estimate `ĉ` (the edge queue's key and the prunings of edges that cannot improve their
    /// child or the solution; OMPL's `OptimizationObjective::motionCostHeuristic`). It must not
    /// exceed the validator's cost of that motion whenever the motion is valid. It may exceed
    /// [`StateSpace::cost_heuristic`] where one motion is more constrained than a path between
    /// the same states (a rover's motion turns to the heading of `b - a` before it drives, a
    /// path of several motions need not), and should not be below it (it would only be a
    /// weaker bound). The default is [`StateSpace::cost_heuristic`].
    ///
    /// ```
    /// use rappel_planners::sampler::{RealVectorSpace, StateSpace};
    /// let space = RealVectorSpace::new([0.0, 0.0], [1.0, 1.0]).unwrap();
    /// let (a, b) = ([0.0, 0.0], [0.3, 0.4]);
    /// // A straight line is the cheapest path and the motion: the two estimates agree.
    /// assert_eq!(space.motion_cost_heuristic(&a, &b), space.cost_heuristic(&a, &b));
    /// assert!((space.cost_heuristic(&a, &b) - 0.5).abs() < 1e-12);
    /// ```
    fn motion_cost_heuristic(&self, a: &Self::State, b: &Self::State) -> f64 {
        self.cost_heuristic(a, b)
    }

    /// The state at fraction `t` in `[0, 1]` of the way from `a` to `b`.
    fn interpolate(&self, a: &Self::State, b: &Self::State, t: f64) -> Self::State;

    /// The point that represents `s` in the k-nearest-neighbour search.
    fn key(&self, s: &Self::State) -> [f64; K];

    /// The number of degrees of freedom, which sets the RGG's k (`k = e (1 + 1/d) ln n`).
    fn dimension(&self) -> usize;
}
