//! The tethered rover on 3D ground (Paton 2020 §III-§V): where settling and anchor prediction
//! read their distances ([`ground`]), whether a settled pose stands ([`verdict`]), stability maps
//! of mesh scenes and drives with their anchor histories ([`stability_map`]), the shadow sample
//! bias ([`shadow`]), uniform samples over the ground's surface area ([`surface_sampling`]) and
//! the tethered-rover problem the ABIT* sampler solves ([`problem`]).
//!
//! Layers, lowest first: `verdict`, `ground`, `shadow`, `surface_sampling`; then
//! `stability_map`; then `problem`.

pub mod ground;
pub mod problem;
pub mod shadow;
pub mod stability_map;
pub mod surface_sampling;
pub mod verdict;

#[cfg(test)]
mod tests_heuristic;
