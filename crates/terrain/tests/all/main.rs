//! The terrain crate's integration tests, one module per reader, model or query, in one test
//! binary (each file was its own binary; one link instead of thirteen keeps the CI's build
//! shorter). Temporary files are named per module and process.

mod crs;
mod dem_fuzz;
mod ground_along;
mod ground_below;
mod mesh_file;
mod parry_mesh;
mod point_cloud;
mod sparse_sdf;
mod surfaces;
mod terrain_distance;
mod terrain_ingest;
mod terrain_obstacles;
mod terrain_planes;
mod terrain_readers;
