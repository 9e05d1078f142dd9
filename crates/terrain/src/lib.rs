//! Terrain models (thesis §2.1.2; Kumar §II). The [`surface::Terrain`] trait is what planners and
//! mechanics may ask of the ground; [`plane_series_terrain`] and [`multi_slope`] implement it.
//!
//! Terrain models (thesis §2.1.2): the convex series of planes down a crater wall in the unfolded
//! planning frame, and (from DEMs) height fields and the obstacles detected on them.
//!
//! DEM ingestion (thesis §2.1.3, §2.5.1-2.5.5), one concept per module: [`grid`] (height grids,
//! their geometry and limits), [`esri_ascii`] and [`geotiff`] (the readers), [`dem`]
//! ([`dem::read_dem`], the reader chosen by extension), [`slope`] (Horn's slope and
//! aspect, the fall line, hillshade), [`least_squares`] (plane fits by sufficient statistics),
//! [`plane_fit`] (the convex plane series), [`frame`] (the unfolded planning frame),
//! [`obstacle_detection`] (Manduchi's rule on slopes, positive and negative obstacles),
//! [`plane_class`] (tether-free or tether-demand), [`ingest`] (the whole pipeline, DEM to scenario
//! ingredients) and [`synthetic`] (DEMs with known answers).

mod block_index;
pub mod crs;
pub mod dem;
pub mod esri_ascii;
pub mod frame;
pub mod geotiff;
pub mod geotiff_writer;
pub mod grid;
pub mod ingest;
pub mod input;
pub mod kumar;
pub mod least_squares;
pub mod mesh;
#[cfg(feature = "mesh")]
pub mod mesh_file;
pub mod mesh_raster;
pub mod multi_slope;
pub mod obstacle_detection;
#[cfg(feature = "mesh")]
pub mod parry_mesh;
pub mod paton_scene;
pub mod plane_class;
pub mod plane_fit;
pub mod plane_series;
pub mod plane_series_terrain;
#[cfg(feature = "mesh")]
pub mod point_cloud;
pub mod sdf;
pub mod slope;
pub mod sparse_sdf;
pub mod surface;
pub mod synthetic;
