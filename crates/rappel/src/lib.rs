//! rappel: motion planning for tethered robots on extreme terrain. This facade crate is what users
//! embed: the scenario schema and its loading, one module per use case (each with its options and
//! its report), and the layered crates re-exported. Pictures are drawn by `rappel-render`.
//!
//! Build a scenario in code and plan it (thesis Ch. 2: homotopy classes shortest first, ascent
//! feasibility, and the chosen ascent/descent pair):
//!
//! ```
//! use rappel::prelude::*;
//!
//! let scenario = Scenario::builder()
//!     .boundary([(0.0, 0.0), (10.0, 0.0), (10.0, 20.0), (0.0, 20.0)])
//!     .obstacle([(4.0, 8.0), (6.0, 8.0), (5.0, 10.0)])
//!     .start(5.0, 19.0)
//!     .goal(5.0, 1.0)
//!     .plane(20.0, 0.0, 45.0, 0.4)
//!     .build()?;
//! // Stop after 100 ms, or earlier when the automatic expansion budget runs out.
//! let options = PlanOptions {
//!     stop: StopCondition::time(Duration::from_millis(100)),
//!     ..Default::default()
//! };
//! let report = plan(&scenario, &options)?;
//! let pair = report.outcome.chosen.as_ref().expect("a feasible class");
//! assert_eq!(pair.rank, 1);
//! assert!(report.to_json().contains("\"report\": \"plan\""));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Scenario files (RON or JSON, `docs/scenario-format.md`) load with [`Scenario::load`]. The use
//! cases: [`plan`](mod@plan), [`query`], [`stability`], [`dem`], [`settle`], [`settle_map`],
//! [`navigate`], [`track`], [`online`], and the taut tether of a path ([`tether`]).
//!
//! [`Scenario::load`]: scenario::Scenario::load

pub mod btm_summary;
pub mod builder;
pub mod dem;
pub mod dem_ptfo;
pub mod friction_plan;
pub mod generated;
pub mod georeference;
pub mod huge_pages;
pub mod input_kind;
pub mod io;
#[cfg(feature = "mesh")]
pub mod navigate;
pub mod online;
pub mod pair;
pub mod plan;
pub mod plan_stream;
pub mod prelude;
pub mod progress;
pub mod ptfo_spec;
pub mod query;
pub mod report;
pub mod robot;
pub mod scenario;
#[cfg(feature = "mesh")]
pub mod settle;
#[cfg(feature = "mesh")]
pub mod settle_map;
pub mod stability;
pub mod sticking_profile;
pub mod tether;
pub mod track;
pub mod verdict;

pub use plan::plan;

pub use nalgebra;
pub use rappel_geometry as geometry;
pub use rappel_homotopy as homotopy;
pub use rappel_mechanics as mechanics;
pub use rappel_planners as planners;
pub use rappel_terrain as terrain;
