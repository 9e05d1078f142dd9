//! rappel's pictures. The facade (`rappel`) computes; this crate draws what it computed, so a user
//! who only plans compiles none of it.
//!
//! - [`style`]: the one style sheet: every legend entry ([`Layer`]) with its look, its label and
//!   its marker, so a legend cannot disagree with its picture.
//! - [`picture`]: the SVG canvas in the map frame ([`Picture`]), with the legend, scale bar,
//!   coordinate ticks and fall-line arrow in a side panel.
//! - [`axonometric`]: the 3D view of scenes and poses; [`viewer`]: the self-contained HTML page
//!   around any picture.
//! - One module per use case of the facade: [`plan`], [`dem`], [`stability`], [`settle`],
//!   [`settle_map`], [`navigate`], [`track`], [`online`].
//!
//! ```
//! use rappel::prelude::*;
//! let scenario = Scenario::builder()
//!     .boundary([(0.0, 0.0), (10.0, 0.0), (10.0, 20.0), (0.0, 20.0)])
//!     .obstacle([(4.0, 8.0), (6.0, 8.0), (5.0, 10.0)])
//!     .start(5.0, 19.0)
//!     .goal(5.0, 1.0)
//!     .plane(20.0, 0.0, 45.0, 0.4)
//!     .build()
//!     .unwrap();
//! let plan = plan_detailed(&scenario.validate().unwrap(), &PlanOptions::default()).unwrap();
//! let svg = rappel_render::plan::picture(&plan, &scenario, None);
//! assert!(svg.contains("taut tether (SHP)"));
//! let page = rappel_render::viewer::html(&svg, "tiny");
//! assert!(page.starts_with("<!DOCTYPE html>"));
//! ```

pub mod axonometric;
pub mod dem;
pub mod export;
#[cfg(feature = "mesh")]
pub mod navigate;
pub mod online;
pub mod picture;
pub mod plan;
pub mod raster_export;
pub mod relief;
#[cfg(feature = "mesh")]
pub mod settle;
#[cfg(feature = "mesh")]
pub mod settle_map;
pub mod stability;
pub mod style;
pub mod track;
pub mod viewer;

pub use picture::Picture;
pub use style::{Layer, Marker};
