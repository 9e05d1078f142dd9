//! The facade's integration tests, one module per theme, in one test binary (each file was its
//! own binary; one link instead of seventeen keeps the CI's build shorter). `plan_memory.rs`
//! stays a binary of its own: it measures the process's resident set, which other tests running
//! beside it would disturb.

mod anchor_index;
mod common;
mod dem_formats_agree;
mod dem_ptfo_saddles;
mod distance_source;
mod fuzz_inputs;
mod fuzz_newer_inputs;
mod long_obstacle;
mod navigate;
mod online_friction;
mod online_pair;
mod plan_robot_models;
mod query;
mod stability_tethers;
mod stop;
mod unit_builder;
mod unit_ptfo_spec;
mod unit_report;
mod unit_scenario;
mod verdicts;
