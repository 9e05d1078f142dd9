//! The 3D-ground and sequence use cases, each the flow of its CLI subcommand without the
//! printing: `settle` and `settle_map` (Axel or a four-wheel rover settled on a Paton scene or a
//! DEM, `crates/cli/src/settle*.rs`), `navigate` (ABIT* on a Paton scene), `track` (two robots
//! on one tether) and `online` (descending while the true map is discovered), plus the
//! generated scenarios of `rappel gen-map`. Each returns the facade report's `to_json()`.

use crate::errors;
use crate::run::{detached, guarded, stop_condition};
use crate::scenario::{PyCancelFlag, PyScenario};
use pyo3::create_exception;
use pyo3::prelude::*;
use rappel::nalgebra::{Point2, Point3};
use rappel::planners::budget::ExpansionBudget;
use rappel::planners::rover::ground::{DistanceSource, DistanceSourceError, GroundDistances};
use rappel::planners::stop::CancelFlag;
use rappel::settle::SettleRobot;
use rappel::terrain::mesh::TriMesh;
use std::path::{Path, PathBuf};

create_exception!(
    rappel,
    NotSettled,
    crate::errors::RappelError,
    "The robot does not settle at the pose asked for (the CLI's `not settled: ...`, exit 1)."
);

/// Adds these use cases to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("NotSettled", m.py().get_type::<NotSettled>())?;
    m.add_function(wrap_pyfunction!(settle, m)?)?;
    m.add_function(wrap_pyfunction!(settle_map, m)?)?;
    m.add_function(wrap_pyfunction!(navigate, m)?)?;
    m.add_function(wrap_pyfunction!(track, m)?)?;
    m.add_function(wrap_pyfunction!(online, m)?)?;
    m.add_function(wrap_pyfunction!(crater_strip, m)?)?;
    m.add_function(wrap_pyfunction!(star, m)?)?;
    Ok(())
}

/// The robot of `--robot NAME`.
fn robot(name: &str) -> PyResult<SettleRobot> {
    match name {
        "axel" => Ok(SettleRobot::Axel),
        "four-wheel" | "four_wheel" => Ok(SettleRobot::FourWheel),
        other => Err(errors::input(format!(
            "robot={other:?}: expected 'axel' or 'four-wheel'"
        ))),
    }
}

/// The distances of `--field RES` (exact mesh distances without it), with the CLI's messages.
fn distances(ground: &TriMesh, field: Option<f64>) -> PyResult<GroundDistances> {
    let source = match field {
        Some(resolution_m) => DistanceSource::Field { resolution_m },
        None => DistanceSource::Exact,
    };
    GroundDistances::new(ground, source).map_err(|e| field_error(field, e))
}

/// The CLI's `--field` messages, worded for the keyword argument.
fn field_error(field: Option<f64>, e: DistanceSourceError) -> PyErr {
    errors::input(match (field, e) {
        (Some(res), DistanceSourceError::Field(why)) => {
            format!("field={res}: cannot build the distance field at this resolution: {why}")
        }
        (Some(res), e) => format!("field={res}: {e}"),
        (None, e) => e.to_string(),
    })
}

fn load_ground(path: &Path) -> PyResult<TriMesh> {
    rappel::settle::load_ground(path).map_err(errors::scenario)
}

/// `rappel settle FILE --at X,Y --yaw DEG --json`: the settle report's JSON.
#[pyfunction]
#[pyo3(signature = (path, at, yaw, robot_name, anchor, field))]
fn settle(
    py: Python<'_>,
    path: PathBuf,
    at: (f64, f64),
    yaw: f64,
    robot_name: &str,
    anchor: Option<(f64, f64, f64)>,
    field: Option<f64>,
) -> PyResult<String> {
    use rappel::settle::{four_wheel_report_with, settle_report_with};
    let robot = robot(robot_name)?;
    let own = CancelFlag::new();
    detached(py, &own, move || {
        let ground = load_ground(&path)?;
        rappel::settle::within_ground(&ground, at.0, at.1)
            .map_err(|why| errors::input(format!("at=({}, {}): {why}", at.0, at.1)))?;
        let anchor = anchor.map(|(x, y, z)| [x, y, z]);
        let d = distances(&ground, field)?;
        let settled = match robot {
            SettleRobot::Axel => {
                settle_report_with(&ground, &d, at.0, at.1, yaw, anchor).map(|(_, r)| r)
            }
            SettleRobot::FourWheel => {
                four_wheel_report_with(&d, at.0, at.1, yaw, anchor).map(|(_, r)| r)
            }
        };
        match settled {
            Ok(report) => Ok(report.to_json()),
            Err(e @ rappel::mechanics::settle::SettleError::Parameter(_)) => Err(errors::input(e)),
            Err(e) => Err(NotSettled::new_err(format!("not settled: {e}"))),
        }
    })
}

/// `rappel settle-map FILE --json`: the stability map's JSON. Ranges default to the scene's
/// (a Paton scene, `.ron`); a DEM needs `x`, `y`, `start` and `root`.
#[pyfunction]
#[pyo3(signature = (path, x, y, step, yaw, start, root, test, robot_name, field, time_limit, cancel))]
#[allow(clippy::too_many_arguments)]
fn settle_map(
    py: Python<'_>,
    path: PathBuf,
    x: Option<(f64, f64)>,
    y: Option<(f64, f64)>,
    step: f64,
    yaw: f64,
    start: Option<(f64, f64)>,
    root: Option<(f64, f64, f64)>,
    test: Option<usize>,
    robot_name: &str,
    field: Option<f64>,
    time_limit: Option<f64>,
    cancel: Option<PyRef<'_, PyCancelFlag>>,
) -> PyResult<String> {
    use rappel::planners::anchor_prediction::AnchorHistory;
    use rappel::planners::rover::stability_map::{
        AxelMap, FourWheelMap, MapSpec, stability_map_for,
    };
    let robot = robot(robot_name)?;
    let own = CancelFlag::new();
    let stop = stop_condition(
        ExpansionBudget::Auto,
        time_limit,
        cancel.map(|c| c.inner.clone()).as_ref(),
        &own,
    )?;
    detached(py, &own, move || {
        let ground = load_ground(&path)?;
        let is_scene = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("ron"));
        let scene = if is_scene {
            Some(rappel::settle::load_scene(&path).map_err(errors::scenario)?)
        } else {
            None
        };
        let need = |name: &str| errors::input(format!("{name} is required for an elevation model"));
        let x = x
            .or_else(|| scene.as_ref().map(|s| (-s.width, s.slope_foot_x() + 1.0)))
            .ok_or_else(|| need("x"))?;
        let y = y
            .or_else(|| scene.as_ref().map(|s| (-0.5 * s.length, 0.5 * s.length)))
            .ok_or_else(|| need("y"))?;
        let start = start
            .or_else(|| scene.as_ref().map(|s| (s.start().x, s.start().y)))
            .ok_or_else(|| need("start"))?;
        let root = match (root, test, &scene) {
            (Some((a, b, c)), None, _) => Point3::new(a, b, c),
            (Some(_), Some(_), _) => return Err(errors::input("give root or test, not both")),
            (None, Some(n), Some(s)) => {
                let a = s.anchor_points();
                *n.checked_sub(1).and_then(|k| a.get(k)).ok_or_else(|| {
                    errors::input(format!("test={n}: the scene has tests 1 to {}", a.len()))
                })?
            }
            (None, Some(_), None) => {
                return Err(errors::input("test needs a Paton scene (.ron); give root"));
            }
            (None, None, _) => {
                return Err(errors::input(
                    "give the root anchor: root=(x, y, z) or test=N",
                ));
            }
        };
        let root = AnchorHistory::new(root).map_err(errors::input)?;
        let spec = MapSpec {
            x,
            y,
            step,
            yaw_deg: yaw,
            start: [start.0, start.1],
        };
        let stop = stop.started();
        let d = distances(&ground, field)?;
        let map = match robot {
            SettleRobot::Axel => stability_map_for(&AxelMap, &ground, &d, &root, &spec, &stop),
            SettleRobot::FourWheel => {
                stability_map_for(&FourWheelMap, &ground, &d, &root, &spec, &stop)
            }
        }
        .map_err(errors::planning)?;
        Ok(rappel::report::to_json(&map))
    })
}

/// `rappel navigate SCENE --seed S --json`: the navigate report's JSON.
#[pyfunction]
#[pyo3(signature = (path, seed, test, iterations, time, held, shadow, field, time_limit, cancel))]
#[allow(clippy::too_many_arguments)]
fn navigate(
    py: Python<'_>,
    path: PathBuf,
    seed: u64,
    test: usize,
    iterations: u64,
    time: Option<f64>,
    held: bool,
    shadow: bool,
    field: Option<f64>,
    time_limit: Option<f64>,
    cancel: Option<PyRef<'_, PyCancelFlag>>,
) -> PyResult<String> {
    use rappel::navigate::{DEFAULT_TIME, RoverProblem, SHADOW_SAMPLE_FRACTION};
    use rappel::planners::sampler::Termination;
    if iterations == 0 {
        return Err(errors::input("iterations must be at least 1"));
    }
    let time = match time {
        None => DEFAULT_TIME,
        Some(t) if t.is_finite() && t > 0.0 && t <= 86_400.0 => {
            std::time::Duration::from_secs_f64(t)
        }
        Some(t) => {
            return Err(errors::input(format!(
                "time={t}: must be a positive number of seconds up to 86400"
            )));
        }
    };
    let own = CancelFlag::new();
    let stop = stop_condition(
        ExpansionBudget::Auto,
        time_limit,
        cancel.map(|c| c.inner.clone()).as_ref(),
        &own,
    )?;
    detached(py, &own, move || {
        let at = |why: String| errors::planning(format!("{}: {why}", path.display()));
        let scene = rappel::settle::load_scene(&path).map_err(errors::scenario)?;
        let anchor = test
            .checked_sub(1)
            .filter(|&a| a < scene.anchors.len())
            .ok_or_else(|| {
                errors::input(format!(
                    "test={test}: the scene has tests 1 to {}",
                    scene.anchors.len()
                ))
            })?;
        let mut problem = RoverProblem::paton(&scene, anchor).map_err(at)?;
        if let Some(resolution_m) = field {
            problem
                .use_distances(DistanceSource::Field { resolution_m })
                .map_err(|e| field_error(field, e))?;
        }
        problem.held_within_boom_reach = held;
        if shadow {
            problem.shadow_sample_fraction = SHADOW_SAMPLE_FRACTION;
        }
        let term = Termination::iterations(iterations).or_time(time);
        let report = rappel::navigate::navigate(&problem, seed, term, &stop).map_err(at)?;
        Ok(report.to_json())
    })
}

/// `rappel track SCENARIO --robot1 P1 --robot2 P2 --json`: the track report's JSON. The paths
/// are files, or point lists.
#[pyfunction]
#[pyo3(signature = (path, robot1_path, robot1, robot2_path, robot2))]
fn track(
    py: Python<'_>,
    path: PathBuf,
    robot1_path: Option<PathBuf>,
    robot1: Option<Vec<(f64, f64)>>,
    robot2_path: Option<PathBuf>,
    robot2: Option<Vec<(f64, f64)>>,
) -> PyResult<String> {
    use rappel::track::{load_path, load_terrain};
    let err = |e: rappel::track::TrackRunError| errors::planning(e);
    let read = |file: Option<PathBuf>, points: Option<Vec<(f64, f64)>>, which: &str| match (
        file, points,
    ) {
        (Some(f), None) => guarded(|| load_path(&f).map_err(errors::scenario)),
        (None, Some(p)) => Ok(p.into_iter().map(|(x, y)| Point2::new(x, y)).collect()),
        _ => Err(errors::input(format!(
            "{which}: a path file or an (n, 2) array"
        ))),
    };
    let p1: Vec<Point2<f64>> = read(robot1_path, robot1, "robot1")?;
    let p2: Vec<Point2<f64>> = read(robot2_path, robot2, "robot2")?;
    let own = CancelFlag::new();
    detached(py, &own, move || {
        let (scenario, terrain) = load_terrain(&path).map_err(errors::scenario)?;
        let report = rappel::track::track(&scenario, &terrain, &p1, &p2).map_err(err)?;
        Ok(report.to_json())
    })
}

/// `rappel online PRIOR --truth TRUE --json`: the simulation report's JSON.
#[pyfunction]
#[pyo3(signature = (prior, truth, sensor_range, step, max_steps, classes, switch_to_shorter, time_limit, cancel))]
#[allow(clippy::too_many_arguments)]
fn online(
    py: Python<'_>,
    prior: PyRef<'_, PyScenario>,
    truth: PyRef<'_, PyScenario>,
    sensor_range: Option<f64>,
    step: Option<f64>,
    max_steps: Option<usize>,
    classes: Option<usize>,
    switch_to_shorter: bool,
    time_limit: Option<f64>,
    cancel: Option<PyRef<'_, PyCancelFlag>>,
) -> PyResult<String> {
    use rappel::planners::online::simulate::{
        DEFAULT_MAX_STEPS, DEFAULT_SENSOR_RANGE, DEFAULT_STEP,
    };
    use rappel::planners::online::{DEFAULT_ONLINE_CLASSES, OnlineOptions, SimulationOptions};
    use rappel::planners::spt::SearchOptions;
    let classes = classes.unwrap_or(DEFAULT_ONLINE_CLASSES);
    if classes == 0 {
        return Err(errors::input("classes=0: examine at least one class"));
    }
    let own = CancelFlag::new();
    let stop = stop_condition(
        ExpansionBudget::Auto,
        time_limit,
        cancel.map(|c| c.inner.clone()).as_ref(),
        &own,
    )?;
    let search = SearchOptions::default()
        .with_max_classes(Some(classes))
        .and_then(|o| o.with_stop(stop))
        .map_err(errors::input)?;
    let options = SimulationOptions {
        sensor_range: sensor_range.unwrap_or(DEFAULT_SENSOR_RANGE),
        step: step.unwrap_or(DEFAULT_STEP),
        max_steps: max_steps.unwrap_or(DEFAULT_MAX_STEPS),
        session: OnlineOptions {
            search,
            switch_to_shorter,
            ..Default::default()
        },
    };
    let (p, t, label) = (&prior.inner, &truth.inner, prior.label());
    detached(py, &own, move || {
        let result = rappel::online::run(p, t, &options, &mut |_, _| {})
            .map_err(|e| errors::planning(format!("{label}: {e}")))?;
        Ok(rappel::report::to_json(&result.report))
    })
}

/// `rappel gen-map --obstacles N --seed S --width W`: a random crater strip.
#[pyfunction]
#[pyo3(signature = (obstacles, seed, width))]
fn crater_strip(obstacles: usize, seed: u64, width: f64) -> PyResult<PyScenario> {
    guarded(|| {
        let s = rappel::generated::crater_strip_scenario(obstacles, seed, width)
            .map_err(errors::input)?;
        PyScenario::checked(s, None)
    })
}

/// One long star obstacle of `vertices` vertices (the long-obstacle benchmark).
#[pyfunction]
#[pyo3(signature = (vertices))]
fn star(vertices: usize) -> PyResult<PyScenario> {
    guarded(|| {
        let s = rappel::generated::star_scenario(vertices).map_err(errors::input)?;
        PyScenario::checked(s, None)
    })
}
