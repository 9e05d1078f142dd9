//! Terrain models (thesis §2.1.2): the convex series of planes down a crater wall in the unfolded
//! planning frame, and (from DEMs) height fields and the obstacles detected on them.

pub mod plane_series;
