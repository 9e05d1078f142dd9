//! Why the sampling planner's [`crate::sampler::Abit::solve`] returned ([`Stop`]): the budget or
//! condition of its [`crate::sampler::Termination`] that ended the run. Its own module so that
//! the planner (`abit`) and its termination condition (`termination`) both use it without
//! importing each other.

/// Why [`crate::sampler::Abit::solve`] returned.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stop {
    /// The iteration budget ran out.
    Iterations,
    /// The wall-time budget ran out (checked between edge evaluations and between samples).
    Time,
    /// A solution at most the cost threshold was found.
    CostThreshold,
}
