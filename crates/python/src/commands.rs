//! One function per use case, each the flow of its CLI subcommand (`crates/cli/src/*.rs`) without
//! the printing: the same option checks, the same facade call, the same error messages. Each
//! returns the facade report's `to_json()` text (the CLI's `--json`), which the Python layer
//! wraps in a typed report.

use crate::errors;
use crate::run::{budget, detached, guarded, stop_condition};
use crate::scenario::{PyCancelFlag, PyScenario};
use pyo3::prelude::*;
use rappel::nalgebra::Point2;
use rappel::planners::budget::ExpansionBudget;
use rappel::planners::stop::CancelFlag;
use rappel::scenario::Format;
use std::path::{Path, PathBuf};

/// Adds the use-case functions to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(plan, m)?)?;
    m.add_function(wrap_pyfunction!(query, m)?)?;
    m.add_function(wrap_pyfunction!(stability, m)?)?;
    m.add_function(wrap_pyfunction!(dem_file, m)?)?;
    m.add_function(wrap_pyfunction!(dem_grid, m)?)?;
    Ok(())
}

/// The caller's flag, if any.
fn flag(cancel: Option<PyRef<'_, PyCancelFlag>>) -> Option<CancelFlag> {
    cancel.map(|c| c.inner.clone())
}

/// `rappel plan SCENARIO --json`: the plan report's JSON.
#[pyfunction]
#[pyo3(signature = (scenario, classes, max_length_factor, simple_only, max_expansions, time_limit, cancel, reachable_areas))]
#[allow(clippy::too_many_arguments)]
fn plan(
    py: Python<'_>,
    scenario: PyRef<'_, PyScenario>,
    classes: usize,
    max_length_factor: Option<f64>,
    simple_only: bool,
    max_expansions: &str,
    time_limit: Option<f64>,
    cancel: Option<PyRef<'_, PyCancelFlag>>,
    reachable_areas: bool,
) -> PyResult<String> {
    if classes == 0 {
        return Err(errors::input("classes=0: list at least one class"));
    }
    if classes > rappel::plan::MAX_CLASSES {
        return Err(errors::input(format!(
            "classes={classes}: at most {} classes can be listed (each class costs a search, a feasibility check and its report)",
            rappel::plan::MAX_CLASSES
        )));
    }
    if let Some(f) = max_length_factor
        && !(f.is_finite() && f >= 1.0)
    {
        return Err(errors::input(format!(
            "max_length_factor={f}: must be a number >= 1"
        )));
    }
    let own = CancelFlag::new();
    let stop = stop_condition(
        budget(max_expansions)?,
        time_limit,
        flag(cancel).as_ref(),
        &own,
    )?;
    let options = rappel::plan::PlanOptions {
        classes,
        max_length_factor,
        simple_only,
        stop,
        reachable_areas,
    };
    let (s, label) = (&scenario.inner, scenario.label());
    detached(py, &own, move || {
        rappel::plan::plan(s, &options)
            .map(|r| r.to_json())
            .map_err(|e| errors::planning(format!("{label}: {e}")))
    })
}

/// `rappel query MAP --pairs PAIRS --json`: the query report's JSON. `map` is a scenario, or
/// `map_path` a scenario or map-only file; `pairs` flat `[sx, sy, gx, gy, ...]`, or
/// `pairs_path` a pairs file.
#[pyfunction]
#[pyo3(signature = (scenario, map_path, pairs, pairs_path, classes, repeat, max_expansions, time_limit, cancel))]
#[allow(clippy::too_many_arguments)]
fn query(
    py: Python<'_>,
    scenario: Option<PyRef<'_, PyScenario>>,
    map_path: Option<PathBuf>,
    pairs: Option<Vec<f64>>,
    pairs_path: Option<PathBuf>,
    classes: usize,
    repeat: usize,
    max_expansions: &str,
    time_limit: Option<f64>,
    cancel: Option<PyRef<'_, PyCancelFlag>>,
) -> PyResult<String> {
    use rappel::query::{QueryOptions, QueryPair, answer, load_pairs, read_map};
    let qerr = |e: rappel::query::QueryError| errors::input(e);
    let own = CancelFlag::new();
    let stop = stop_condition(
        budget(max_expansions)?,
        time_limit,
        flag(cancel).as_ref(),
        &own,
    )?;
    let options = QueryOptions {
        classes,
        repeat,
        stop,
    };
    let file = match (&scenario, &map_path) {
        (None, Some(p)) => Some(guarded(|| read_map(p).map_err(qerr))?),
        (Some(_), None) => None,
        _ => return Err(errors::input("give a scenario or a map file, not both")),
    };
    let pairs: Vec<QueryPair> = match (pairs, &pairs_path) {
        (None, Some(p)) => guarded(|| load_pairs(p).map_err(qerr))?,
        (Some(flat), None) => {
            if !flat.len().is_multiple_of(4) {
                return Err(errors::input(
                    "pairs: an (n, 4) array of start x, start y, goal x, goal y",
                ));
            }
            flat.chunks_exact(4)
                .map(|c| QueryPair {
                    start: Point2::new(c[0], c[1]),
                    goal: Point2::new(c[2], c[3]),
                })
                .collect()
        }
        _ => return Err(errors::input("give pairs or a pairs file, not both")),
    };
    let s = scenario.as_deref();
    detached(py, &own, move || {
        let map = match (&file, s) {
            (Some(f), _) => f.validate().map_err(qerr)?,
            (None, Some(s)) => match &s.path {
                Some(p) => s.inner.validate_at(p),
                None => s.inner.validate(),
            }
            .map_err(errors::scenario)?
            .map(),
            (None, None) => return Err(errors::input("give a scenario or a map file")),
        };
        let answers = answer(map, &pairs, &options).map_err(qerr)?;
        Ok(rappel::query::QueryReport { answers }.to_json())
    })
}

/// `rappel stability SCENARIO --json`: the stability report's JSON.
#[pyfunction]
#[pyo3(signature = (scenario, grid, tension_limit, time_limit, cancel))]
fn stability(
    py: Python<'_>,
    scenario: PyRef<'_, PyScenario>,
    grid: f64,
    tension_limit: Option<f64>,
    time_limit: Option<f64>,
    cancel: Option<PyRef<'_, PyCancelFlag>>,
) -> PyResult<String> {
    let own = CancelFlag::new();
    let stop = stop_condition(
        ExpansionBudget::Auto,
        time_limit,
        flag(cancel).as_ref(),
        &own,
    )?;
    let options = rappel::stability::StabilityOptions {
        grid_step: grid,
        tension_limit,
        stop,
    };
    let (s, label) = (&*scenario, scenario.label());
    detached(py, &own, move || {
        let valid = match &s.path {
            Some(p) => s.inner.validate_at(p),
            None => s.inner.validate(),
        }
        .map_err(errors::scenario)?;
        rappel::stability::stability_over_scenario(valid, &options)
            .map(|r| r.to_json())
            .map_err(|e| errors::planning(format!("{label}: {e}")))
    })
}

/// The ingest options of `rappel dem` (`--hmin`, `--hmax`, `--theta-max`, `--friction`).
fn ingest_options(
    hmin: Option<f64>,
    hmax: Option<f64>,
    theta_max: Option<f64>,
    friction: Option<f64>,
) -> rappel::terrain::ingest::IngestOptions {
    let mut options = rappel::terrain::ingest::IngestOptions::default();
    if let Some(v) = hmin {
        options.obstacles.h_min_m = v;
    }
    if let Some(v) = hmax {
        options.obstacles.h_max_m = v;
    }
    if let Some(v) = theta_max {
        options.obstacles.theta_max_deg = v;
    }
    if let Some(v) = friction {
        options.friction = v;
    }
    options
}

/// Refuses an output scenario path of unknown format, or one that is the input file.
fn check_out(out: Option<&Path>, input: Option<&Path>) -> PyResult<()> {
    let Some(out) = out else { return Ok(()) };
    if Format::of_path(out).is_none() {
        return Err(errors::input(format!(
            "{}: unknown scenario format; use a .ron or .json file",
            out.display()
        )));
    }
    if let Some(input) = input
        && let (Ok(a), Ok(b)) = (std::fs::canonicalize(out), std::fs::canonicalize(input))
        && a == b
    {
        return Err(errors::input(format!(
            "{}: the output would overwrite the input file {}; choose another output path",
            out.display(),
            input.display()
        )));
    }
    Ok(())
}

/// The end of `rappel dem`: the ingested scenario validated, saved to `out` if given (naming
/// the DEM `file`, if any, relative to it), and the report (its `scenario` field is `out`, or
/// empty when not saved) with the scenario.
fn dem_finish(
    mut d: rappel::dem::DemScenario,
    source: &str,
    file: Option<&Path>,
    out: Option<PathBuf>,
) -> PyResult<(String, PyScenario)> {
    d.scenario.validate().map_err(|e| {
        errors::planning(format!("{source}: the ingested scenario is invalid: {e}"))
    })?;
    if let Some(out) = &out {
        // As `rappel dem`: the DEM file named relative to the scenario file.
        if let (Some(file), Some(g)) = (file, &mut d.scenario.georeference) {
            g.dem = rappel::georeference::dem_relative_to(file, out);
        }
        d.scenario.save(out).map_err(errors::scenario)?;
    }
    let report = d
        .report(
            Path::new(source),
            out.as_deref().unwrap_or(Path::new("")),
            None,
        )
        .to_json();
    let scenario = PyScenario {
        inner: d.scenario,
        path: out,
    };
    Ok((report, scenario))
}

/// `rappel dem FILE --out OUT --json`: the report's JSON and the scenario.
#[pyfunction]
#[pyo3(signature = (path, out, hmin, hmax, theta_max, friction, max_cells))]
#[allow(clippy::too_many_arguments)]
fn dem_file(
    py: Python<'_>,
    path: PathBuf,
    out: Option<PathBuf>,
    hmin: Option<f64>,
    hmax: Option<f64>,
    theta_max: Option<f64>,
    friction: Option<f64>,
    max_cells: Option<usize>,
) -> PyResult<(String, PyScenario)> {
    check_out(out.as_deref(), Some(&path))?;
    let options = ingest_options(hmin, hmax, theta_max, friction);
    let limits = match max_cells {
        None => rappel::terrain::grid::DemLimits::default(),
        Some(n) => rappel::terrain::grid::DemLimits::with_max_cells(n)
            .map_err(|e| errors::input(format!("max_cells: {e}")))?,
    };
    let own = CancelFlag::new();
    detached(py, &own, move || {
        let d =
            rappel::dem::dem_scenario_with(&path, &options, &limits).map_err(errors::planning)?;
        dem_finish(d, &path.display().to_string(), Some(&path), out)
    })
}

/// A DEM from memory: `heights` row-major little-endian f64 bytes (north row first, NaN
/// unknown), `nrows` x `ncols` cells of `cell_x` x `cell_y` m whose north-west corner is
/// (`west`, `north`); `name` names it in messages and as the scenario's name.
#[pyfunction]
#[pyo3(signature = (heights, nrows, ncols, cell_x, cell_y, west, north, name, crs, out, hmin, hmax, theta_max, friction))]
#[allow(clippy::too_many_arguments)]
fn dem_grid(
    py: Python<'_>,
    heights: Vec<u8>,
    nrows: usize,
    ncols: usize,
    cell_x: f64,
    cell_y: f64,
    west: f64,
    north: f64,
    name: String,
    crs: Option<String>,
    out: Option<PathBuf>,
    hmin: Option<f64>,
    hmax: Option<f64>,
    theta_max: Option<f64>,
    friction: Option<f64>,
) -> PyResult<(String, PyScenario)> {
    use rappel::terrain::grid::{GridGeometry, HeightGrid};
    check_out(out.as_deref(), None)?;
    if !heights.len().is_multiple_of(8) {
        return Err(errors::input(
            "heights: not a whole number of float64 values",
        ));
    }
    let values: Vec<f64> = heights
        .chunks_exact(8)
        .map(|b| f64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]))
        .collect();
    let geometry = GridGeometry::new(nrows, ncols, cell_x, cell_y, west, north)
        .map_err(|e| errors::input(format!("{name}: {e}")))?;
    let grid =
        HeightGrid::new(geometry, values).map_err(|e| errors::input(format!("{name}: {e}")))?;
    let options = ingest_options(hmin, hmax, theta_max, friction);
    let own = CancelFlag::new();
    detached(py, &own, move || {
        let d = rappel::dem::dem_scenario_of_grid(grid, &name, &name, crs, &options)
            .map_err(errors::planning)?;
        dem_finish(d, &name, None, out)
    })
}
