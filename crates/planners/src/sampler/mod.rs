//! A tether-aware sampling-based planner: ABIT* (Strub & Gammell 2020) with non-Markovian states
//! (Paton 2020 §V-A), generic over a state space and a motion validator.
//!
//! | module | holds |
//! |---|---|
//! | [`space`] | the [`StateSpace`] trait: sampling (uniform and informed), distances, heuristics, interpolation |
//! | [`validator`] | the [`MotionValidator`] trait: state validity and lazy, history-extending motion checks |
//! | [`settings`] | [`AbitSettings`], the validated builder of the planner's options |
//! | [`termination`] | [`Termination`]: iterations, wall time, cost threshold (OMPL's termination conditions) |
//! | [`stop`] | [`Stop`]: which of them ended a run |
//! | [`graph`] | the edge-implicit random geometric graph: states, search tree, k-nearest neighbours |
//! | [`abit`] | the [`Abit`] planner itself: batches, inflated edge queue, truncation, anytime solutions |
//! | [`real_vector`] | [`RealVectorSpace`], the box-bounded Euclidean space in D dimensions with informed sampling |
//! | [`obstacle_world`] | [`ObstacleWorld`]: axis-aligned boxes and spheres, a discrete motion-check resolution |
//! | [`peer_worlds`] | the 2D and 3D worlds of the comparison with OMPL's BIT* (also the tests' worlds) |
//!
//! The algorithm, its settings and the comparison with OMPL's BIT* are described in
//! `docs/sampler.md`.

pub mod abit;
pub mod graph;
pub mod obstacle_world;
pub mod peer_worlds;
pub mod real_vector;
pub mod settings;
pub mod space;
pub mod stop;
pub mod termination;
pub mod validator;

#[cfg(test)]
mod tests_bias;
#[cfg(test)]
mod tests_geometric;
#[cfg(test)]
mod tests_history;

pub use abit::{Abit, AbitCounters, PlannerStatus, Solution, SolutionEvent};
pub use obstacle_world::{Obstacle, ObstacleWorld, WorldError, WorldFile};
pub use real_vector::RealVectorSpace;
pub use settings::{AbitSettings, SettingsError};
pub use space::{Informed, StateSpace};
pub use stop::Stop;
pub use termination::Termination;
pub use validator::MotionValidator;
