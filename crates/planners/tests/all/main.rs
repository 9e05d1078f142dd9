//! The planners' integration tests, one module per planner or algorithm, in one test binary
//! (each file was its own binary; one link instead of eight keeps the CI's build shorter).

mod anchor_prediction;
mod common;
mod feasibility;
mod frictional;
mod mouth_cover;
mod online;
mod online_pair;
mod shortest_path_map;
mod spt;
mod stop;
mod terrain_trait;
mod tether_tracking;
