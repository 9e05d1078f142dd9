//! The `rappel` binary's end-to-end tests, one module per command or theme, in one test binary
//! (each file was its own binary; one link instead of thirteen keeps the CI's build shorter).
//! Every test runs the built binary as a subprocess, so sharing a process changes nothing.

mod cli;
mod common;
mod dem;
mod field;
mod friction;
mod gdal;
mod hostile;
mod input_files;
mod json_reports;
mod navigate;
mod online;
mod plan;
mod plan_stream;
mod settle;
mod settle_map;
mod shp;
mod stop;
mod track;
