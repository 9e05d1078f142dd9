//! The motion-validator trait of the sampling planner: state validity and lazily evaluated motion
//! validity that extends a per-state *history* (Paton §V-A: the anchor history).
//!
//! A Markovian problem uses `History = ()`. For a tethered robot the history is the sequence of
//! points where the tether touches the terrain: validity of a motion depends on it and the
//! motion extends it, which makes states non-Markovian.

use super::space::StateSpace;

/// Checks states and motions for ABIT*.
pub trait MotionValidator<S: StateSpace<K>, const K: usize> {
    /// What a path has done so far that matters for validity (Paton's anchor history).
    type History: Clone + PartialEq + std::fmt::Debug;

    /// The history of the start state.
    fn initial_history(&self, start: &S::State) -> Self::History;

    /// History-free validity of a single state (e.g. collision, settling); samples that fail it
    /// are discarded before they enter the graph.
    fn state_valid(&self, state: &S::State) -> bool;

    /// Whether `state` can be valid when reached with `history` (e.g. stability with those
    /// anchors). Used when a new sample copies a neighbour's history, so that no sample is given
    /// a history it can never be valid with. The default accepts every history.
    fn history_valid(&self, state: &S::State, history: &Self::History) -> bool {
        let _ = (state, history);
        true
    }

    /// Whether two histories are the same for planning purposes (Paton §V-A's "compatible"
    /// anchor histories): a sample whose history was copied from a neighbour accepts, when it is
    /// first connected, a parent whose motion brings a compatible history (and then stores the
    /// history the motion actually brings), and copying draws from the neighbours' distinct
    /// compatibility classes. Rewiring a state already in the tree still requires the exact
    /// history, so no descendant's validity ever changes. The default is equality, which suits
    /// discrete histories; a history of real-valued contact points needs a tolerance, else a
    /// copied history is almost never reproduced by any motion.
    fn compatible(&self, a: &Self::History, b: &Self::History) -> bool {
        a == b
    }

    /// The motion from `from` (reached with `history`) to `to`: `None` if it is invalid,
    /// otherwise its true cost and the history at `to`. Called lazily, only for edges the search
    /// actually processes, and at most once per ordered pair of graph states. Both ends are
    /// graph states, each of which passed [`MotionValidator::state_valid`] when it was added
    /// (start, goal, samples; copies share a checked state's location), so an implementation
    /// need not check `to` itself again (OMPL's `DiscreteMotionValidator` does).
    fn motion(
        &self,
        from: &S::State,
        history: &Self::History,
        to: &S::State,
    ) -> Option<(f64, Self::History)>;
}
