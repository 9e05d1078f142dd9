//! The one output schema of every `--json` report (`docs/output-format.md`): the [`Report`] trait
//! every report type implements, the [`Envelope`] that puts `schema_version` and the report's kind
//! first, the unit helpers ([`deg`], [`micros`]) that keep float noise out of the numbers, and the
//! JSON Schema documents generated from the types (the `rappel-schemas` crate, written by `cargo xtask
//! schemas`).
//!
//! The convention, in short:
//! - every report is an object whose first fields are `schema_version` ([`SCHEMA_VERSION`]) and
//!   `report` (the subcommand's name, [`Report::KIND`]);
//! - a point is `[x, y]` (or `[x, y, z]`), never an object with `x` and `y`;
//! - enum values are lower-case `snake_case` strings (`"class_count"`, `"tether_free"`);
//! - a quantity with a unit carries it in its field name: `_m`, `_m2`, `_deg`, `_n`, `_us`;
//!   angles are in degrees wherever they are shown, rounded to [`ANGLE_DECIMALS`] decimals;
//!   durations are integer microseconds;
//! - every report type derives `Serialize`, `Deserialize` and `JsonSchema`, and reads back what
//!   it wrote ([`round_trip`]).
//!
//! A new report follows it in three steps: derive the three traits on its type (points as
//! `Point2<f64>` fields with `#[schemars(with = "[f64; 2]")]`, enums with
//! `#[serde(rename_all = "snake_case")]`), `report!(T, "name")` (the [`Report`] impl and an inherent `to_json`),
//! and add it to `rappel_schemas::schemas`; the CLI prints it with `print_report`, the schema test then asks for
//! its committed document in `docs/schemas/`.

use schemars::JsonSchema;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

/// The version of the output schema. Raised on any change a reader could notice (a field
/// renamed, removed, or its unit changed); adding a field keeps it.
pub const SCHEMA_VERSION: u32 = 1;

pub use rappel_planners::report_units::{ANGLE_DECIMALS, deg, radians_as_degrees, round_to};

/// A report a subcommand prints with `--json`.
pub trait Report: Serialize + DeserializeOwned + JsonSchema {
    /// The subcommand's name: the `report` field, and the schema file `docs/schemas/KIND.json`.
    const KIND: &'static str;

    /// This report in its [`Envelope`], as pretty JSON.
    fn to_json(&self) -> String {
        serde_json::to_string_pretty(&Envelope::new(self)).unwrap_or_default()
    }
}

/// This report in its [`Envelope`], as pretty JSON: [`Report::to_json`] without naming the
/// trait (for report types of the lower crates, such as the online simulation's).
pub fn to_json<T: Report>(report: &T) -> String {
    report.to_json()
}

/// Implements [`Report`] for a facade report type with its kind, and gives the type an inherent
/// `to_json`, so a user serialises a report without importing a trait.
macro_rules! report {
    ($t:ty, $kind:literal) => {
        impl $crate::report::Report for $t {
            const KIND: &'static str = $kind;
        }
        impl $t {
            /// This report as `--json` prints it: in its envelope (`schema_version` and `report`
            /// first), pretty JSON ([`crate::report::Report::to_json`]).
            pub fn to_json(&self) -> String {
                $crate::report::Report::to_json(self)
            }
        }
    };
}
pub(crate) use report;

/// A report as printed: `schema_version` and `report` first, then the report's own fields.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct Envelope<T> {
    /// [`SCHEMA_VERSION`] of the writer.
    pub schema_version: u32,
    /// The subcommand that wrote it ([`Report::KIND`]).
    pub report: String,
    /// The report.
    #[serde(flatten)]
    pub body: T,
}

impl<'a, T: Report> Envelope<&'a T> {
    /// Wraps `body` with the current version and its kind.
    pub fn new(body: &'a T) -> Self {
        Envelope {
            schema_version: SCHEMA_VERSION,
            report: T::KIND.to_string(),
            body,
        }
    }
}

/// Why a report could not be read back.
#[derive(Debug, thiserror::Error)]
pub enum ReadReportError {
    /// Not JSON of this report's shape.
    #[error("not a {kind} report: {message}")]
    Parse {
        /// The kind expected.
        kind: &'static str,
        /// serde's message.
        message: String,
    },
    /// Another subcommand's report.
    #[error("a {found} report where a {expected} report was expected")]
    Kind {
        /// The kind expected.
        expected: &'static str,
        /// The kind found.
        found: String,
    },
    /// A schema version this build does not read.
    #[error("schema_version {found}: this build reads version {SCHEMA_VERSION}")]
    Version {
        /// The version found.
        found: u32,
    },
}

/// Reads a report printed by `--json` back, checking its kind and version.
///
/// ```
/// use rappel::report::{read_report, Report};
/// use rappel::report::HomotopicReport;
/// let r = HomotopicReport { homotopic: true, paths: ["a".into(), "b".into()], reduced_crossings: [2, 2] };
/// assert_eq!(read_report::<HomotopicReport>(&r.to_json()).unwrap(), r);
/// ```
pub fn read_report<T: Report>(text: &str) -> Result<T, ReadReportError> {
    let e: Envelope<T> = serde_json::from_str(text).map_err(|e| ReadReportError::Parse {
        kind: T::KIND,
        message: e.to_string(),
    })?;
    if e.report != T::KIND {
        return Err(ReadReportError::Kind {
            expected: T::KIND,
            found: e.report,
        });
    }
    if e.schema_version != SCHEMA_VERSION {
        return Err(ReadReportError::Version {
            found: e.schema_version,
        });
    }
    Ok(e.body)
}

/// Serializes `report`, reads it back and serializes it again: the two texts, which are equal
/// when the report type round-trips (the property every report's test asserts).
pub fn round_trip<T: Report>(report: &T) -> Result<(String, String), ReadReportError> {
    let first = report.to_json();
    let back: T = read_report(&first)?;
    Ok((first, back.to_json()))
}

/// A duration as whole microseconds (saturating).
pub fn micros(d: std::time::Duration) -> u64 {
    u64::try_from(d.as_micros()).unwrap_or(u64::MAX)
}

/// The JSON form of `rappel gen-map`: what was written.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct GenMapReport {
    /// The scenario file written.
    pub file: String,
    /// Obstacles.
    pub obstacles: usize,
    /// Map vertices.
    pub vertices: usize,
    /// The seed.
    pub seed: u64,
    /// Strip width across the slope, m.
    pub width_m: f64,
}

crate::report::report!(GenMapReport, "gen_map");

/// The JSON form of `rappel homotopic`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct HomotopicReport {
    /// The answer.
    pub homotopic: bool,
    /// The two path files.
    pub paths: [String; 2],
    /// Length of each path's reduced crossing sequence (equal sequences mean homotopic).
    pub reduced_crossings: [usize; 2],
}

crate::report::report!(HomotopicReport, "homotopic");
