//! The regression runner: every suite returns [`Case`]s (a measured value beside its reference and a
//! verdict); the runner prints them as one table and fails if any case failed.

mod btm;
mod friction;
mod mechanics;
mod online;
mod planner;
pub mod terrain;
mod tracking;

use std::path::PathBuf;
use std::process::ExitCode;

/// One regression case: what was measured, what it is compared with, and whether it passed.
pub struct Case {
    /// The suite's name, e.g. `btm`.
    pub suite: &'static str,
    /// What the case checks, e.g. `fixtures/thesis-fig-2-7.ron: triangle count`.
    pub name: String,
    /// The measured value, formatted.
    pub measured: String,
    /// The reference value or condition it is compared with, formatted.
    pub reference: String,
    /// Whether the measured value meets the reference.
    pub pass: bool,
}

impl Case {
    /// A case that passes when `pass` holds.
    pub fn new(
        suite: &'static str,
        name: impl Into<String>,
        measured: impl Into<String>,
        reference: impl Into<String>,
        pass: bool,
    ) -> Self {
        Case {
            suite,
            name: name.into(),
            measured: measured.into(),
            reference: reference.into(),
            pass,
        }
    }
}

/// A suite: a name and the function that runs it.
type Suite = (&'static str, fn() -> Result<Vec<Case>, String>);

const SUITES: &[Suite] = &[
    ("btm", btm::suite),
    ("mechanics", mechanics::suite),
    ("terrain", terrain::suite),
    ("planner", planner::suite),
    ("online", online::suite),
    ("tracking", tracking::suite),
    ("friction", friction::suite),
];

static FULL: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Asks the suites for their full-size runs (`cargo xtask regress --full`).
pub fn set_full(full: bool) {
    FULL.store(full, std::sync::atomic::Ordering::Relaxed);
}

/// `true` when the full-size runs were asked for.
pub fn full() -> bool {
    FULL.load(std::sync::atomic::Ordering::Relaxed)
}

/// The workspace root (the parent of `xtask/`).
pub fn workspace_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("xtask lives in the workspace")
        .to_path_buf()
}

/// Runs every suite whose name contains `filter` and prints the table.
pub fn run(filter: Option<&str>) -> Result<ExitCode, String> {
    let mut cases = Vec::new();
    for (name, suite) in SUITES {
        if filter.is_some_and(|f| !name.contains(f)) {
            continue;
        }
        eprintln!("running suite {name} ...");
        cases.extend(suite().map_err(|e| format!("suite {name}: {e}"))?);
    }
    if cases.is_empty() {
        return Err(format!(
            "no regression suite matches {:?}",
            filter.unwrap_or("")
        ));
    }
    let width = |f: fn(&Case) -> &str, title: &str| {
        cases
            .iter()
            .map(|c| f(c).chars().count())
            .chain([title.len()])
            .max()
            .unwrap_or(0)
    };
    let (ws, wn, wm, wr) = (
        width(|c| c.suite, "suite"),
        width(|c| &c.name, "case"),
        width(|c| &c.measured, "measured"),
        width(|c| &c.reference, "reference"),
    );
    println!(
        "{:ws$}  {:wn$}  {:wm$}  {:wr$}  result",
        "suite", "case", "measured", "reference"
    );
    for c in &cases {
        let verdict = if c.pass { "ok" } else { "FAIL" };
        println!(
            "{:ws$}  {:wn$}  {:wm$}  {:wr$}  {verdict}",
            c.suite, c.name, c.measured, c.reference
        );
    }
    let failed = cases.iter().filter(|c| !c.pass).count();
    println!(
        "regress: {} passed, {} failed",
        cases.len() - failed,
        failed
    );
    Ok(if failed == 0 {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}
