//! Planners for tethered robots: A* over the shortest path tree (thesis Alg. 3-4), ascent
//! feasibility and path pairs (Alg. 5-6), frictional and online planning (Ch. 3), and an
//! ABIT*-style sampler with anchor histories (Paton §V). Depends on terrain and robot traits only.
//!
//! The Chapter-2 planner (thesis §2.3.3-2.4, the operator's "show me the ways down, shortest
//! first, and tell me which ones I can climb back up"):
//!
//! | module | computes | source |
//! |---|---|---|
//! | [`spt`] | SHPs in non-decreasing length, one per homotopy class; termination rules | Alg. 3-4, eq. 2.5 |
//! | [`shortest_path_map`] | geodesic length and last anchor of every point from one start, built once | Mitchell's continuous Dijkstra, Polyanya's root pruning |
//! | [`tether_anchors`] | a stability map's plane bands, free poses and each pose's taut tether (an `AnchorSource`) | Kumar Fig. 5, §2.1.2 |
//! | [`terrain`] | the plane series under the map and each plane's tether limit | §2.1.2, §2.4.4 |
//! | [`feasibility`] | anchors, anchor reachable sets, passability, waypoints | Alg. 5, Defs. 2.1-2.4, eq. 2.7 |
//! | [`anchor_index`] | the anchors of a class near a move, a leg or an edge (a grid superset) | issue 10 (long obstacles) |
//! | [`path_pair`] | homotopic ascent/descent path pairs, next class on failure | Alg. 6, §2.2.4 |
//! | [`online`] | map changes, sleeve update, H-constrained replanning, backtracking, simulator | §3.5, Alg. 11-13 |
//! | [`stop`] | when a long call stops early: expansions, a time limit, a cancel flag, combined | OMPL's termination conditions |
//! | [`visibility_graph`] | brute-force Euclidean shortest paths, the independent test oracle | Lozano-Pérez and Wesley |
//!
//! The robot enters only through the [`rappel_mechanics::anchor_traversability::AnchorTraversability`]
//! trait; definitions and choices are collected in `docs/planner.md`.

pub mod anchor_index;
pub mod anchor_prediction;
pub mod budget;
pub mod feasibility;
pub mod frictional;
mod min_heap;
pub mod mouth_cover;
pub mod online;
pub mod path_pair;
pub mod report_units;
#[cfg(feature = "mesh")]
pub mod rover;
pub mod sampler;
pub mod search_report;
pub mod shortest_path_map;
pub mod spt;
pub mod stop;
pub mod terrain;
pub mod tether_anchors;
pub mod tether_tracking;
pub mod visibility_graph;
