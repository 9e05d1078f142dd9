//! The mechanics crate's integration tests, one module per model or solver, in one test binary
//! (each file was its own binary; one link instead of six keeps the CI's build shorter).

mod boom_contact;
mod dense_qp;
mod four_wheel_settle;
mod settle;
mod stability_qp;
mod tension_lp;
