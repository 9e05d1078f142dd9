//! Progress on stderr for long work (issue 16): a bar with the position, the rate and an ETA when
//! stderr is a terminal, and nothing at all otherwise, so pipes, CI logs and tests stay clean.
//! Forced on ([`Show::Always`], a command's `--progress`) while stderr is not a terminal, it
//! writes plain lines instead of a bar: `WHAT POS/LEN (ELAPSED s)`, one each time the whole
//! percentage changes and one at the end, so at most 101 lines whatever the length (issue 10).
//!
//!
//! [`Observer`] hands the facade's progress ([`rappel::progress::Progress`]) to such a bar.

use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

/// When progress is shown.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Show {
    /// Only when stderr is a terminal (a bar).
    #[default]
    Auto,
    /// Always: a bar on a terminal, plain lines otherwise (module docs).
    Always,
}

/// Plain progress lines on a stderr that is not a terminal (module docs).
#[derive(Debug)]
struct Lines {
    what: String,
    len: u64,
    pos: AtomicU64,
    start: Instant,
}

impl Lines {
    /// Advances by `n` and writes a line when the whole percentage changed or the end is reached.
    fn inc(&self, n: u64) {
        let before = self.pos.fetch_add(n, Ordering::Relaxed);
        let after = before.saturating_add(n);
        let percent = |p: u64| p.min(self.len).saturating_mul(100) / self.len.max(1);
        if percent(after) != percent(before) || (after >= self.len && before < self.len) {
            eprintln!(
                "{} {}/{} ({:.1} s)",
                self.what,
                after.min(self.len),
                self.len,
                self.start.elapsed().as_secs_f64()
            );
        }
    }
}

/// A progress bar on stderr, or nothing when stderr is not a terminal (module docs).
#[derive(Debug)]
pub struct Progress {
    bar: Option<ProgressBar>,
    lines: Option<Lines>,
}

impl Progress {
    /// A bar over `len` steps of `what`, shown as `show` says (module docs).
    pub fn with(len: u64, what: &str, show: Show) -> Self {
        if !std::io::stderr().is_terminal() {
            let lines = (show == Show::Always).then(|| Lines {
                what: what.to_string(),
                len,
                pos: AtomicU64::new(0),
                start: Instant::now(),
            });
            return Progress { bar: None, lines };
        }
        let bar = ProgressBar::new(len);
        let style = ProgressStyle::with_template(
            "{prefix} [{bar:32}] {pos}/{len} {msg} ({per_sec}, eta {eta})",
        )
        .map(|s| s.progress_chars("=> "))
        .unwrap_or_else(|_| ProgressStyle::default_bar());
        bar.set_style(style);
        bar.set_prefix(what.to_string());
        Progress {
            bar: Some(bar),
            lines: None,
        }
    }

    /// A spinner with the elapsed time, for work of unknown length (e.g. reading a DEM).
    pub fn spinner(what: &str) -> Self {
        if !std::io::stderr().is_terminal() {
            return Progress {
                bar: None,
                lines: None,
            };
        }
        let bar = ProgressBar::new_spinner();
        if let Ok(style) = ProgressStyle::with_template("{spinner} {prefix} {msg} ({elapsed})") {
            bar.set_style(style);
        }
        bar.set_prefix(what.to_string());
        bar.enable_steady_tick(std::time::Duration::from_millis(120));
        Progress {
            bar: Some(bar),
            lines: None,
        }
    }

    /// Advances by `n` steps.
    pub fn inc(&self, n: u64) {
        if let Some(b) = &self.bar {
            b.inc(n);
        }
        if let Some(l) = &self.lines {
            l.inc(n);
        }
    }

    /// Shows `msg` beside the bar (the step under way).
    pub fn message(&self, msg: &str) {
        if let Some(b) = &self.bar {
            b.set_message(msg.to_string());
        }
    }

    /// Removes the bar.
    pub fn finish(self) {
        if let Some(b) = self.bar {
            b.finish_and_clear();
        }
    }
}

/// The command line's observer of a facade call: a bar (or plain lines, as `show` says) begun
/// when the call's work begins and removed when it ends.
#[derive(Debug, Default)]
pub struct Observer {
    show: Show,
    current: Mutex<Option<Progress>>,
}

impl Observer {
    /// An observer that shows progress as `show` says.
    pub fn new(show: Show) -> Self {
        Observer {
            show,
            current: Mutex::new(None),
        }
    }
}

impl rappel::progress::Progress for Observer {
    fn begin(&self, what: &str, len: u64) {
        if let Ok(mut c) = self.current.lock() {
            *c = Some(Progress::with(len, what, self.show));
        }
    }

    fn advance(&self, n: u64) {
        if let Ok(c) = self.current.lock()
            && let Some(p) = c.as_ref()
        {
            p.inc(n);
        }
    }

    fn end(&self) {
        if let Ok(mut c) = self.current.lock()
            && let Some(p) = c.take()
        {
            p.finish();
        }
    }
}
