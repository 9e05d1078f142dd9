//! The `Scenario` class (a validated [`rappel::scenario::Scenario`], read from a file or from
//! scenario-schema JSON text, which is how the Python layer passes dicts and numpy arrays) and
//! the `CancelFlag` class (a [`rappel::planners::stop::CancelFlag`] another thread sets).

use crate::errors;
use crate::run::guarded;
use pyo3::prelude::*;
use rappel::planners::stop::CancelFlag;
use rappel::scenario::{Format, Scenario};
use std::path::PathBuf;

/// A scenario (`docs/scenario-format.md`), validated when made: every use case accepts it.
#[pyclass(name = "Scenario", module = "rappel._native", frozen)]
pub struct PyScenario {
    /// The scenario.
    pub inner: Scenario,
    /// The file it was read from, if any: messages name it as the CLI does.
    pub path: Option<PathBuf>,
}

impl PyScenario {
    /// How messages name this scenario: its file, else its name, else `scenario`.
    pub fn label(&self) -> String {
        match (&self.path, self.inner.name.as_str()) {
            (Some(p), _) => p.display().to_string(),
            (None, "") => "scenario".to_string(),
            (None, name) => name.to_string(),
        }
    }

    /// A scenario checked as a loaded file is checked.
    pub fn checked(inner: Scenario, path: Option<PathBuf>) -> PyResult<Self> {
        match &path {
            Some(p) => inner.validate_at(p).map(|_| ()),
            None => inner.validate().map(|_| ()),
        }
        .map_err(errors::scenario)?;
        Ok(PyScenario { inner, path })
    }
}

#[pymethods]
impl PyScenario {
    /// Reads and validates a scenario file (`.ron` or `.json`, by extension).
    #[staticmethod]
    fn load(path: PathBuf) -> PyResult<Self> {
        guarded(|| {
            let s = Scenario::read(&path).map_err(errors::scenario)?;
            PyScenario::checked(s, Some(path))
        })
    }

    /// Parses and validates scenario JSON text (the file format's JSON flavour).
    #[staticmethod]
    fn from_json(text: &str) -> PyResult<Self> {
        guarded(|| {
            let s = Scenario::from_json_str(text).map_err(errors::scenario)?;
            PyScenario::checked(s, None)
        })
    }

    /// Parses and validates scenario RON text.
    #[staticmethod]
    fn from_ron(text: &str) -> PyResult<Self> {
        guarded(|| {
            let s = Scenario::from_ron_str(text).map_err(errors::scenario)?;
            PyScenario::checked(s, None)
        })
    }

    /// The scenario as JSON text (the file format).
    fn to_json(&self) -> String {
        self.inner.to_text(Format::Json)
    }

    /// The scenario as RON text (the file format).
    fn to_ron(&self) -> String {
        self.inner.to_text(Format::Ron)
    }

    /// Writes the scenario to `path` (format by extension), atomically.
    fn save(&self, path: PathBuf) -> PyResult<()> {
        guarded(|| self.inner.save(&path).map_err(errors::scenario))
    }

    /// The scenario's name.
    #[getter]
    fn name(&self) -> String {
        self.inner.name.clone()
    }

    /// The file the scenario was read from, or None.
    #[getter]
    fn path(&self) -> Option<PathBuf> {
        self.path.clone()
    }

    fn __repr__(&self) -> String {
        format!(
            "Scenario({:?}, {} obstacles, {} planes)",
            self.label(),
            self.inner.map.obstacles.len(),
            self.inner.terrain.planes.len()
        )
    }
}

/// A flag another thread sets to stop a long call cleanly (`flag.cancel()`); the call then
/// reports a cancel request as what stopped it.
#[pyclass(name = "CancelFlag", module = "rappel._native", frozen)]
pub struct PyCancelFlag {
    /// The flag.
    pub inner: CancelFlag,
}

#[pymethods]
impl PyCancelFlag {
    /// A flag not yet set.
    #[new]
    fn new() -> Self {
        PyCancelFlag {
            inner: CancelFlag::new(),
        }
    }

    /// Sets the flag: every call watching it stops at its next check.
    fn cancel(&self) {
        self.inner.cancel();
    }

    /// Whether the flag is set.
    fn is_cancelled(&self) -> bool {
        self.inner.is_cancelled()
    }

    /// Clears the flag, so it can watch another call.
    fn reset(&self) {
        self.inner.reset();
    }

    fn __repr__(&self) -> String {
        format!("CancelFlag(cancelled={})", self.inner.is_cancelled())
    }
}
