//! What every regression suite returns ([`Case`]: a measured value beside its reference and a
//! verdict) and what the suites share: the workspace root and whether the full-size runs were
//! asked for. Below the runner ([`super`]) and every suite, so that they import it, not each
//! other.

use std::path::PathBuf;

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
    /// `true` for a drift check against a golden file our own code wrote.
    pub drift: bool,
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
            drift: false,
        }
    }

    /// A drift check: the measured value against a golden file our own code wrote (not a
    /// reproduction; printed as `drift`): the terrain suite's golden rows.
    pub fn drift(
        suite: &'static str,
        name: impl Into<String>,
        measured: impl Into<String>,
        golden: impl Into<String>,
        pass: bool,
    ) -> Self {
        Case {
            drift: true,
            ..Case::new(suite, name, measured, golden, pass)
        }
    }
}

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
