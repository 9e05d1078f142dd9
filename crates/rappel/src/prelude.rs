//! What most users need, in one import: `use rappel::prelude::*;`. The scenario and its builder,
//! every use case's entry point with its options, and the report trait.
//!
//! ```
//! use rappel::prelude::*;
//! let options = PlanOptions::default();
//! assert_eq!(options.classes, rappel::plan::DEFAULT_CLASSES);
//! ```

pub use crate::builder::{IntoPoint, ScenarioBuilder};
pub use crate::dem::{DemScenario, dem_scenario};
#[cfg(feature = "mesh")]
pub use crate::navigate::{RoverProblem, navigate};
pub use crate::online::OnlineRun;
pub use crate::plan::{Plan, PlanError, PlanOptions, PlanReport, plan, plan_detailed};
pub use crate::query::{QueryPair, QueryReport};
pub use crate::report::Report;
pub use crate::scenario::{RobotModel, RobotParams, Scenario, ScenarioError};
#[cfg(feature = "mesh")]
pub use crate::settle::{SettleReport, settle_report};
#[cfg(feature = "mesh")]
pub use crate::settle_map::{MapSpec, StabilityMap};
pub use crate::stability::{StabilityOptions, StabilityReport, stability_over_scenario};
pub use crate::track::{TrackReport, track};
pub use rappel_planners::budget::ExpansionBudget;
pub use rappel_planners::stop::{CancelFlag, StopCondition, StopReason};
pub use std::time::Duration;
