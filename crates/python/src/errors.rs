//! The exceptions of the Python package, one class per concern, all under [`RappelError`]:
//!
//! | class | raised when | CLI counterpart |
//! |---|---|---|
//! | `ScenarioError` | a scenario file or dict is unreadable or invalid | `rappel validate` / any command's `error:` on the file |
//! | `InputError` | an argument is out of range (classes, time limit, arrays, paths) | a usage `error:` |
//! | `PlanningError` | the use case refused its input (a map that does not triangulate, planes a robot cannot use, a DEM that does not ingest) | the command's `error:` line |
//! | `BudgetExceeded` | a query pair spent its expansion budget | `rappel query`'s `error:` on that pair |
//! | `StoppedError` | a time limit or cancel flag stopped work that has no partial answer | `stopped: ...` |
//! | `InternalError` | a panic inside rappel (a bug): caught, never crossing into Python | — |
//!
//! The message of each is the text after `error: ` of the CLI on the same input.

use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;

create_exception!(
    rappel,
    RappelError,
    PyException,
    "Base class of every error rappel raises; its message is the CLI's `error:` line."
);
create_exception!(
    rappel,
    ScenarioError,
    RappelError,
    "A scenario (file, dict or arrays) is unreadable or invalid: the message names the field, vertex or line."
);
create_exception!(
    rappel,
    InputError,
    RappelError,
    "An argument is out of range or malformed (classes, time limit, array shapes, paths)."
);
create_exception!(
    rappel,
    PlanningError,
    RappelError,
    "The use case refused its input: a map that does not triangulate, unusable planes or robot, a DEM that does not ingest."
);
create_exception!(
    rappel,
    BudgetExceeded,
    RappelError,
    "A search spent its funnel expansion budget before answering (raise max_expansions)."
);
create_exception!(
    rappel,
    StoppedError,
    RappelError,
    "A time limit or a cancel flag stopped work before it had an answer to report."
);
create_exception!(
    rappel,
    InternalError,
    RappelError,
    "A bug in rappel (a Rust panic), caught at the boundary: please report it with the input."
);

/// Adds the exception classes to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("RappelError", py.get_type::<RappelError>())?;
    m.add("ScenarioError", py.get_type::<ScenarioError>())?;
    m.add("InputError", py.get_type::<InputError>())?;
    m.add("PlanningError", py.get_type::<PlanningError>())?;
    m.add("BudgetExceeded", py.get_type::<BudgetExceeded>())?;
    m.add("StoppedError", py.get_type::<StoppedError>())?;
    m.add("InternalError", py.get_type::<InternalError>())?;
    Ok(())
}

/// A [`ScenarioError`] with `message`.
pub fn scenario(message: impl std::fmt::Display) -> PyErr {
    ScenarioError::new_err(message.to_string())
}

/// An [`InputError`] with `message`.
pub fn input(message: impl std::fmt::Display) -> PyErr {
    InputError::new_err(message.to_string())
}

/// A [`PlanningError`] with `message`.
pub fn planning(message: impl std::fmt::Display) -> PyErr {
    PlanningError::new_err(message.to_string())
}

/// An [`InternalError`] for a caught panic with `payload`.
pub fn panic(payload: &(dyn std::any::Any + Send)) -> PyErr {
    let what = payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "a panic without a message".to_string());
    InternalError::new_err(format!(
        "internal error (a bug in rappel, please report it with the input): {what}"
    ))
}
