//! Progress of long calls, told to an observer the caller hands over: the facade draws nothing
//! (the command line's bars live in the CLI). `stability` tells the tethers it looks up, `query`
//! the pairs it answers; `plan` hands over each class as it is decided instead.
//!
//! ```
//! use rappel::progress::Progress;
//! use std::sync::atomic::{AtomicU64, Ordering};
//! struct Count(AtomicU64);
//! impl Progress for Count {
//!     fn advance(&self, n: u64) {
//!         self.0.fetch_add(n, Ordering::Relaxed);
//!     }
//! }
//! let c = Count(AtomicU64::new(0));
//! c.begin("pairs", 2);
//! c.advance(2);
//! assert_eq!(c.0.load(Ordering::Relaxed), 2);
//! ```

/// An observer of a long call's progress; every method does nothing unless overridden. Called
/// from the worker threads of a parallel step, hence `Sync`.
pub trait Progress: Sync {
    /// Work of `len` steps of `what` (e.g. "tethers", "pairs") begins.
    fn begin(&self, what: &str, len: u64) {
        let _ = (what, len);
    }
    /// `n` more steps are done.
    fn advance(&self, n: u64) {
        let _ = n;
    }
    /// The work begun last is over (done or stopped).
    fn end(&self) {}
}

/// The observer that shows nothing.
#[derive(Debug, Clone, Copy, Default)]
pub struct Quiet;

impl Progress for Quiet {}
