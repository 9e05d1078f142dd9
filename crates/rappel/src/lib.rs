//! rappel: motion planning for tethered robots on extreme terrain. This facade crate is what users
//! embed: scenario files, a small high-level API, SVG pictures, and the layered crates re-exported.
//!
//! ```
//! use rappel::scenario::Scenario;
//! use rappel::btm_summary::summarize_btm;
//! let s = Scenario::from_ron_str(r#"(
//!     map: (boundary: [(0.0, 0.0), (10.0, 0.0), (10.0, 20.0), (0.0, 20.0)],
//!           obstacles: [[(4.0, 8.0), (6.0, 8.0), (5.0, 10.0)]]),
//!     start: (5.0, 19.0), goal: (5.0, 1.0))"#).unwrap();
//! let (btm, summary) = summarize_btm(s.validate().unwrap().map()).unwrap();
//! assert_eq!(summary.triangles, 7);
//! let mut pic = rappel::svg::Picture::of_map(&s.map);
//! pic.btm(&btm);
//! pic.map(&s.map);
//! pic.start_goal(s.start, s.goal);
//! assert!(pic.finish("tiny").contains("BTM edge"));
//! ```
//!
//! The Chapter-2 planner in one call ([`plan()`]): homotopy classes shortest first, ascent
//! feasibility, and the chosen ascent/descent pair.
//!
//! ```
//! use rappel::plan::PlanOptions;
//! let s = rappel::scenario::Scenario::from_ron_str(r#"(
//!     map: (boundary: [(0.0, 0.0), (10.0, 0.0), (10.0, 20.0), (0.0, 20.0)],
//!           obstacles: [[(4.0, 8.0), (6.0, 8.0), (5.0, 10.0)]]),
//!     start: (5.0, 19.0), goal: (5.0, 1.0),
//!     terrain: (planes: [(y_top: 20.0, y_bottom: 0.0, slope_deg: 45.0, friction: 0.4)]))"#).unwrap();
//! let report = rappel::plan(&s, &PlanOptions::default()).unwrap();
//! assert_eq!(report.classes[0].rank, 1);
//! assert!(report.outcome.chosen.is_some(), "{}", report.outcome.verdict);
//! ```

pub mod btm_summary;
pub mod dem;
pub mod dem_ptfo;
pub mod export;
pub mod friction_plan;
pub mod generated;
pub mod georeference;
pub mod io;
pub mod navigate;
pub mod online;
pub mod plan;
pub mod plan_stream;
pub mod progress;
pub mod ptfo_spec;
pub mod query;
pub mod report;
pub mod robot;
pub mod scenario;
pub mod schema_check;
pub mod settle;
pub mod settle_map;
pub mod stability;
pub mod sticking_profile;
pub mod tether;
pub mod track;

pub use plan::plan;

pub use nalgebra;
pub use rappel_geometry as geometry;
pub use rappel_homotopy as homotopy;
pub use rappel_mechanics as mechanics;
pub use rappel_planners as planners;
pub use rappel_terrain as terrain;
