//! `rappel._native`: the PyO3 extension module behind the `rappel` Python package. It binds the
//! facade crate (`rappel`) and computes nothing itself: every call builds the facade's options,
//! runs the facade's entry point and hands back the report as the facade's own `to_json()` text,
//! which the Python layer (`python/rappel/`) parses into typed report objects. So a report's
//! `to_dict()` is the CLI's `--json` for the same input by construction.
//!
//! - [`errors`]: one Python exception class per concern, with the CLI's `error:` messages.
//! - [`run`]: long calls off the GIL on a worker thread, with a time limit and cancel flags,
//!   polling for Ctrl-C (`KeyboardInterrupt`) and turning panics into exceptions.
//! - [`scenario`]: the `Scenario` and `CancelFlag` classes.
//! - [`commands`]: `plan`, `query`, `stability`, `dem`.
//! - [`rover`]: `settle`, `settle_map`, `navigate`, `track`, `online`, generated scenarios.

use pyo3::prelude::*;

/// The Rust side's large arrays on 2 MiB pages, as in the `rappel` command line
/// (`rappel::huge_pages`; Python's own allocations are not affected).
#[global_allocator]
static ALLOC: rappel::huge_pages::HugePageAlloc = rappel::huge_pages::HugePageAlloc;

pub mod commands;
pub mod errors;
pub mod rover;
pub mod run;
pub mod scenario;

/// The extension module `rappel._native`.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    errors::register(m)?;
    m.add_class::<scenario::PyScenario>()?;
    m.add_class::<scenario::PyCancelFlag>()?;
    commands::register(m)?;
    rover::register(m)?;
    m.add("SCHEMA_VERSION", rappel::report::SCHEMA_VERSION)?;
    m.add("MAX_CLASSES", rappel::plan::MAX_CLASSES)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
