//! Long calls from Python: the work runs on a worker thread while the calling thread waits with
//! the GIL released, waking every [`POLL`] to run Python's signal handlers
//! (`Python::check_signals`). A Ctrl-C (`KeyboardInterrupt`, or any exception a signal handler
//! raises) sets the call's own [`CancelFlag`], waits for the work to stop at its next check, and
//! re-raises: the search stops cleanly, never abandoned mid-write. Other Python threads run
//! meanwhile (two plans on two threads overlap). A panic in the work is caught on the worker
//! and becomes an `InternalError`; no unwinding crosses into Python.
//!
//! The stop condition of every call is built here ([`stop_condition`]) the way the CLI builds
//! it (`crates/cli/src/stop.rs`): the expansion budget, the `time_limit` in seconds, the
//! caller's cancel flag and the call's own flag, whichever fires first.

use crate::errors;
use pyo3::prelude::*;
use rappel::planners::budget::ExpansionBudget;
use rappel::planners::stop::{CancelFlag, StopCondition};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::mpsc;
use std::time::Duration;

/// How often the waiting thread looks for signals (Ctrl-C latency is at most this plus the
/// work's own check interval).
pub const POLL: Duration = Duration::from_millis(20);

/// A time limit in seconds as a [`Duration`]: refused unless positive and finite (the CLI's
/// `--time-limit` rule, worded for the keyword argument).
pub fn time_limit(seconds: Option<f64>) -> PyResult<Option<Duration>> {
    let Some(t) = seconds else {
        return Ok(None);
    };
    if !(t.is_finite() && t > 0.0) {
        return Err(errors::input(format!(
            "time_limit={t}: must be a positive number of seconds"
        )));
    }
    Duration::try_from_secs_f64(t)
        .map(Some)
        .map_err(|_| errors::input(format!("time_limit={t}: too large")))
}

/// An expansion budget from `"auto"` or a count (as `--max-expansions` takes it).
pub fn budget(text: &str) -> PyResult<ExpansionBudget> {
    ExpansionBudget::parse(text).map_err(|e| errors::input(format!("max_expansions: {e}")))
}

/// The stop condition of a call: `budget`, the time limit if given, the caller's flag if given
/// and the call's own flag `own` (set on Ctrl-C by [`detached`]).
pub fn stop_condition(
    budget: ExpansionBudget,
    seconds: Option<f64>,
    cancel: Option<&CancelFlag>,
    own: &CancelFlag,
) -> PyResult<StopCondition> {
    let mut stop = StopCondition::budget_of(budget).or_cancel(own.clone());
    if let Some(flag) = cancel {
        stop = stop.or_cancel(flag.clone());
    }
    if let Some(t) = time_limit(seconds)? {
        stop = stop.or_time(t);
    }
    Ok(stop)
}

/// Runs `work` on a worker thread with the GIL released, polling for signals; on a signal's
/// exception sets `own`, waits for the work to stop, and returns that exception. A panic in
/// `work` is an `InternalError`.
pub fn detached<T, F>(py: Python<'_>, own: &CancelFlag, work: F) -> PyResult<T>
where
    T: Send,
    F: FnOnce() -> PyResult<T> + Send,
{
    let (tx, rx) = mpsc::channel::<()>();
    std::thread::scope(|s| {
        let handle = s.spawn(move || {
            let out = catch_unwind(AssertUnwindSafe(work));
            // The receiver may be gone only after an interrupt; nothing to tell then.
            let _ = tx.send(());
            out
        });
        let mut rx = Some(rx);
        let mut interrupted: Option<PyErr> = None;
        loop {
            let r = rx.take().unwrap_or_else(|| mpsc::channel().1);
            let (r, done) = py.detach(move || {
                let done = !matches!(r.recv_timeout(POLL), Err(mpsc::RecvTimeoutError::Timeout));
                (r, done)
            });
            rx = Some(r);
            if done {
                break;
            }
            if let Err(e) = py.check_signals() {
                own.cancel();
                interrupted = Some(e);
                break;
            }
        }
        // The work has ended, or stops at its next check of `own`: wait for it off the GIL.
        let joined = py.detach(move || handle.join());
        if let Some(e) = interrupted {
            return Err(e);
        }
        match joined {
            Ok(Ok(result)) => result,
            Ok(Err(payload)) | Err(payload) => Err(errors::panic(payload.as_ref())),
        }
    })
}

/// Runs a short `work` on the calling thread, turning a panic into an `InternalError`.
pub fn guarded<T>(work: impl FnOnce() -> PyResult<T>) -> PyResult<T> {
    catch_unwind(AssertUnwindSafe(work))
        .unwrap_or_else(|payload| Err(errors::panic(payload.as_ref())))
}
