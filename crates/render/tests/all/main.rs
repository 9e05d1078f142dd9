//! The pictures' integration tests in one test binary: pictures rendered to pixels and checked
//! for what must be visible, the settled-pose and hill views, and the stability map picture of a
//! mesh scene.

mod mesh_stability;
mod render;
mod settle_picture;
mod sticking_profile;
