//! rappel: motion planning for tethered robots on extreme terrain. This facade crate is what users
//! embed: scenario files, a small high-level API, SVG pictures, and the layered crates re-exported.

pub use rappel_geometry as geometry;
pub use rappel_homotopy as homotopy;
pub use rappel_mechanics as mechanics;
pub use rappel_planners as planners;
