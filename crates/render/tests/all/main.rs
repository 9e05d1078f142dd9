//! The pictures' and exports' integration tests in one test binary: the GeoJSON and CSV exports of a plan, pictures rendered to pixels and checked
//! for what must be visible, the settled-pose and hill views, and the stability map picture of a
//! mesh scene.

mod export;
mod mesh_stability;
mod render;
mod settle_picture;
mod sticking_profile;
