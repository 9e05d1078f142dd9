//! Exact planar geometry for tethered-robot planning (thesis §2.2.2, §2.5.3, §3.5.2): polygons with
//! holes and their validation, exact predicates, the half-edge DCEL, boundary-triangulated
//! 2-manifolds built as constrained Delaunay triangulations, point location and local updates.

pub mod btm;
pub mod compact;
pub mod dcel;
pub mod domain;
mod expansion;
pub mod generate;
pub mod map;
pub mod normalize;
pub mod overlay;
pub mod polygon;
pub mod predicates;
pub mod region;
pub mod spatial_grid;
