//! Why a stability question could not be answered ([`StabilityError`]): bad input, a robot that
//! could not be placed, or solver trouble. Shared by the stability criteria
//! ([`crate::traversability`]) and the solver adapter ([`crate::conic`]), below both.

use crate::robot::RobotError;
use thiserror::Error;

/// Why a stability question could not be answered. "Not stable" is **not** an error: it is an
/// [`crate::traversability::Assessment`] with `stable == false`.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum StabilityError {
    /// An input is out of range or not finite; the message names it.
    #[error("invalid stability input: {0}")]
    Input(&'static str),
    /// The robot could not be placed.
    #[error(transparent)]
    Robot(#[from] RobotError),
    /// clarabel rejected the problem data or settings.
    #[error("solver setup failed: {0}")]
    Setup(String),
    /// clarabel stopped without a verdict (iteration or time limit, numerical error, lack of
    /// progress, or an unbounded problem). Retry with more iterations; report if it persists.
    #[error("solver trouble: {0}")]
    Trouble(String),
}
