//! The homotopy crate's integration tests, one module per concept, in one test binary (each file
//! was its own binary; one link instead of three keeps the CI's build shorter).

mod common;
mod crossing;
mod h_signature;
mod shp;
