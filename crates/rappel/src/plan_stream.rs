//! The streamed form of a plan (`rappel plan --jsonl`, issue 10): one JSON object per line, each
//! in the report [`Envelope`] (`schema_version`, `"report":
//! "plan_stream"`) and tagged by `type`:
//! - `"class"`: one homotopy class, as soon as it is decided (the fields of
//!   [`ClassReport`]), shortest first;
//! - `"summary"`: the last line of a run that succeeded ([`PlanSummary`]: the plan's report
//!   without its classes, with their count);
//! - `"error"`: the last line of a run that failed, whether or not classes were printed before
//!   (`message`).
//!
//! A stream is complete exactly when its last line is a `summary`; one ending in an `error` (exit
//! code 2) or in neither (the process was killed) is not. The schema is
//! `docs/schemas/plan_stream.json` (`docs/output-format.md`).

use crate::plan::ClassReport;
pub use crate::plan::PlanSummary;
use crate::report::Envelope;
use serde::{Deserialize, Serialize};

/// One line of `rappel plan --jsonl` (module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum PlanStreamLine {
    /// One class, as soon as it is decided.
    Class(Box<ClassReport>),
    /// The run succeeded: the last line.
    Summary(Box<PlanSummary>),
    /// The run failed (exit code 2): the last line.
    Error {
        /// What failed (the same text as the `error:` line on stderr).
        message: String,
    },
}

crate::report::report!(PlanStreamLine, "plan_stream");

impl PlanStreamLine {
    /// This line in its envelope as one line of compact JSON (no newline).
    ///
    /// ```
    /// use rappel::plan_stream::PlanStreamLine;
    /// use rappel::report::read_report;
    /// let line = PlanStreamLine::Error { message: "disk full".into() }.to_line();
    /// assert_eq!(line, r#"{"schema_version":1,"report":"plan_stream","type":"error","message":"disk full"}"#);
    /// assert!(matches!(read_report::<PlanStreamLine>(&line), Ok(PlanStreamLine::Error { .. })));
    /// ```
    pub fn to_line(&self) -> String {
        serde_json::to_string(&Envelope::new(self)).unwrap_or_default()
    }
}
