//! What every regression suite returns ([`Case`]: a measured value beside its reference, the
//! [`Kind`] of that reference and a verdict) and what the suites share: the workspace root and whether the full-size runs were
//! asked for. Below the runner ([`super`]) and every suite, so that they import it, not each
//! other.

use std::path::PathBuf;

/// What a row's reference is, and so what its agreement means. Only the two paper kinds are
/// reproductions; the rest check the code against something else outside it (or, for drift, only
/// against its own earlier output).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Kind {
    /// A number the paper prints (a table entry, a tension, a count), within a stated tolerance.
    PaperNumber,
    /// A yes/no or a qualitative outcome the paper states or draws (feasible, stable, red/green).
    PaperVerdict,
    /// A closed form or planted geometry evaluated here, independently of the code under test:
    /// the capstan, eq. 2.7, tangents and arcs, an input built so that its answer is known.
    ClosedForm,
    /// A second, independent computation of the same answer: brute force (visibility graph), a
    /// from-scratch rebuild, the homotopy crate's SHP for the tracker.
    Oracle,
    /// A property the answer must have whatever its value (invariants, orderings, bounds, our
    /// own goals): it can fail, but it reproduces nothing.
    Property,
    /// A golden file our own code wrote: it catches change, not error.
    Drift,
}

impl Kind {
    /// Every kind, in the order the ledger prints them.
    pub const ALL: [Kind; 6] = [
        Kind::PaperNumber,
        Kind::PaperVerdict,
        Kind::ClosedForm,
        Kind::Oracle,
        Kind::Property,
        Kind::Drift,
    ];

    /// The short name printed in the table and the ledger.
    pub fn label(self) -> &'static str {
        match self {
            Kind::PaperNumber => "paper number",
            Kind::PaperVerdict => "paper verdict",
            Kind::ClosedForm => "closed form",
            Kind::Oracle => "oracle",
            Kind::Property => "property",
            Kind::Drift => "drift",
        }
    }

    /// `true` for the kinds compared with a paper: the only rows that may be called reproduced,
    /// and the only rows that may be known differences.
    pub fn is_paper(self) -> bool {
        matches!(self, Kind::PaperNumber | Kind::PaperVerdict)
    }
}

/// The band a known difference is expected in: what it says, and whether the measured value is
/// inside it. A row listed as a known difference fails when it leaves its band in either
/// direction (worse, or better without agreeing), so the list is updated when the difference moves.
pub struct Band {
    /// The band, in words and numbers, e.g. `green 0, yellow 20..=40 of 98`.
    pub description: String,
    /// Whether the measured value lies inside the band.
    pub holds: bool,
}

/// One regression case: what was measured, what it is compared with, and whether it passed.
pub struct Case {
    /// The suite's name, e.g. `btm`.
    pub suite: &'static str,
    /// What kind of reference the row has.
    pub kind: Kind,
    /// What the case checks, e.g. `fixtures/thesis-fig-2-7.ron: triangle count`.
    pub name: String,
    /// The measured value, formatted.
    pub measured: String,
    /// The reference value or condition it is compared with, formatted.
    pub reference: String,
    /// Whether the measured value meets the reference.
    pub pass: bool,
    /// For a known difference from its paper: the band the difference is expected in.
    pub band: Option<Band>,
}

impl Case {
    /// A case of kind `kind` that passes when `pass` holds.
    pub fn new(
        suite: &'static str,
        kind: Kind,
        name: impl Into<String>,
        measured: impl Into<String>,
        reference: impl Into<String>,
        pass: bool,
    ) -> Self {
        Case {
            suite,
            kind,
            name: name.into(),
            measured: measured.into(),
            reference: reference.into(),
            pass,
            band: None,
        }
    }

    /// A row against a number the paper prints ([`Kind::PaperNumber`]).
    pub fn paper_number(
        suite: &'static str,
        name: impl Into<String>,
        measured: impl Into<String>,
        reference: impl Into<String>,
        pass: bool,
    ) -> Self {
        Case::new(suite, Kind::PaperNumber, name, measured, reference, pass)
    }

    /// A row against an outcome the paper states or draws ([`Kind::PaperVerdict`]).
    pub fn paper_verdict(
        suite: &'static str,
        name: impl Into<String>,
        measured: impl Into<String>,
        reference: impl Into<String>,
        pass: bool,
    ) -> Self {
        Case::new(suite, Kind::PaperVerdict, name, measured, reference, pass)
    }

    /// A row against a closed form or planted geometry evaluated here ([`Kind::ClosedForm`]).
    pub fn closed_form(
        suite: &'static str,
        name: impl Into<String>,
        measured: impl Into<String>,
        reference: impl Into<String>,
        pass: bool,
    ) -> Self {
        Case::new(suite, Kind::ClosedForm, name, measured, reference, pass)
    }

    /// A row against an independent second computation ([`Kind::Oracle`]).
    pub fn oracle(
        suite: &'static str,
        name: impl Into<String>,
        measured: impl Into<String>,
        reference: impl Into<String>,
        pass: bool,
    ) -> Self {
        Case::new(suite, Kind::Oracle, name, measured, reference, pass)
    }

    /// A row checking a property the answer must have ([`Kind::Property`]).
    pub fn property(
        suite: &'static str,
        name: impl Into<String>,
        measured: impl Into<String>,
        reference: impl Into<String>,
        pass: bool,
    ) -> Self {
        Case::new(suite, Kind::Property, name, measured, reference, pass)
    }

    /// A drift check: the measured value against a golden file our own code wrote (not a
    /// reproduction; [`Kind::Drift`]).
    pub fn drift(
        suite: &'static str,
        name: impl Into<String>,
        measured: impl Into<String>,
        golden: impl Into<String>,
        pass: bool,
    ) -> Self {
        Case::new(suite, Kind::Drift, name, measured, golden, pass)
    }

    /// The band this row's known difference from its paper is expected in (see [`Band`]); only
    /// meaningful on a row listed in [`super::KNOWN_DIFFERENCES`].
    pub fn differs_within(mut self, description: impl Into<String>, holds: bool) -> Self {
        self.band = Some(Band {
            description: description.into(),
            holds,
        });
        self
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
