//! When a long command stops early (issue 32): `--time-limit SECONDS` and Ctrl-C, made into the
//! one stop condition every long call takes ([`rappel::planners::stop::StopCondition`]).
//!
//! - `--time-limit SECONDS` (`plan`, `query`, `stability`, `settle-map`, `navigate`, `online`):
//!   the wall-clock time the command's work may take, counted from when it starts; a positive,
//!   finite number of seconds (anything else is refused: one `error:` line, exit 2).
//! - Ctrl-C: the first SIGINT sets the run's [`CancelFlag`], so the work stops at its next check
//!   and the command reports "stopped: a cancel request" (or its report's words for it) with
//!   the answer it has; a second SIGINT exits at once (code 130, the shell's convention for an
//!   interrupted command).
//!
//! The report says which condition stopped the work.

use crate::output::CliError;
use rappel::planners::budget::ExpansionBudget;
use rappel::planners::stop::{CancelFlag, StopCondition, StopReason};
use std::sync::OnceLock;
use std::time::Duration;

/// Exit code of a command interrupted by a second Ctrl-C (128 + SIGINT).
const INTERRUPTED: i32 = 130;

/// The `--time-limit` argument of a long command.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct TimeLimitArg {
    /// Stop the work after SECONDS of wall-clock time (a positive number, fractions allowed);
    /// the report then says "the time limit of SECONDS s" stopped it. Ctrl-C stops the work too
    /// (and the report says so); a second Ctrl-C exits at once.
    #[arg(long, value_parser = crate::numbers::finite, value_name = "SECONDS", allow_negative_numbers = true)]
    pub time_limit: Option<f64>,
}

impl TimeLimitArg {
    /// The time limit, if given: refused unless a positive, finite number of seconds that a
    /// [`Duration`] holds.
    pub fn duration(&self) -> Result<Option<Duration>, CliError> {
        let Some(t) = self.time_limit else {
            return Ok(None);
        };
        if !(t.is_finite() && t > 0.0) {
            return Err(CliError(format!(
                "--time-limit {t}: must be a positive number of seconds"
            )));
        }
        Duration::try_from_secs_f64(t)
            .map(Some)
            .map_err(|_| CliError(format!("--time-limit {t}: too large")))
    }
}

/// The stop condition of a command: `budget` expansions, the `--time-limit` if given, and the
/// process's Ctrl-C flag ([`cancel_flag`]).
pub fn condition(budget: ExpansionBudget, time: &TimeLimitArg) -> Result<StopCondition, CliError> {
    let mut stop = StopCondition::budget_of(budget).or_cancel(cancel_flag());
    if let Some(t) = time.duration()? {
        stop = stop.or_time(t);
    }
    Ok(stop)
}

/// The flag the first Ctrl-C sets; the handler is installed on the first call (a command that
/// never asks for it keeps the default: Ctrl-C ends the process). Should the handler not install
/// (another one is set), the flag is still returned and Ctrl-C keeps its default.
pub fn cancel_flag() -> CancelFlag {
    static FLAG: OnceLock<CancelFlag> = OnceLock::new();
    FLAG.get_or_init(|| {
        let flag = CancelFlag::new();
        let seen = flag.clone();
        let _ = ctrlc::set_handler(move || {
            if seen.is_cancelled() {
                // The second Ctrl-C: the user does not want to wait for a clean stop.
                std::process::exit(INTERRUPTED);
            }
            eprintln!("stopping (Ctrl-C again to exit at once)");
            seen.cancel();
        });
        flag
    })
    .clone()
}

/// Says on stderr that a time limit or a cancel request stopped the work ("stopped: the time
/// limit of 0.5 s", "stopped: a cancel request"), whatever stdout holds (text or JSON, which
/// say it in their own words); an expansion budget is the report's alone to name.
pub fn say(reason: Option<StopReason>) {
    if let Some(r @ (StopReason::TimeLimit { .. } | StopReason::Cancelled)) = reason {
        eprintln!("stopped: {r}");
    }
}
