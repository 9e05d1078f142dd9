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

    /// The motion from `from` (reached with `history`) to `to`: `None` if it is invalid,
    /// otherwise its true cost and the history at `to`. Called lazily, only for edges the search
    /// actually processes, and at most once per ordered pair of graph states.
    fn motion(
        &self,
        from: &S::State,
        history: &Self::History,
        to: &S::State,
    ) -> Option<(f64, Self::History)>;
}
