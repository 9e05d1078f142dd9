//! Whether standard output was closed when the process started (`rappel plan … >&-`).
//!
//! The Rust runtime reopens a closed descriptor 0, 1 or 2 on `/dev/null` before `main` runs, and
//! then every write "succeeds": a report sent nowhere would pass for a delivered one (exit 0).
//! Neither the descriptor's target nor its flags tell that apart afterwards from a deliberate
//! `>/dev/null` or Python's `subprocess.DEVNULL`, so this module looks before the runtime does:
//! a constructor in `.init_array` (run by the C runtime before `main`) asks `fcntl(1, F_GETFD)`
//! and records a failure. With `rappel::huge_pages` this is the workspace's audited `unsafe`
//! code: a foreign call with integer arguments and no pointers. On other platforms the check
//! reports "open".

#![allow(unsafe_code)]

use std::sync::atomic::{AtomicBool, Ordering};

/// Set before `main` when descriptor 1 was closed.
static CLOSED_AT_START: AtomicBool = AtomicBool::new(false);

/// `true` when standard output was closed before the Rust runtime started.
pub fn stdout_closed_at_start() -> bool {
    CLOSED_AT_START.load(Ordering::Relaxed)
}

#[cfg(all(target_os = "linux", target_env = "gnu"))]
mod probe {
    use super::{CLOSED_AT_START, Ordering};

    /// `F_GETFD` on Linux.
    const F_GETFD: i32 = 1;

    unsafe extern "C" {
        fn fcntl(fd: i32, cmd: i32, ...) -> i32;
    }

    /// Runs before `main` (and before the runtime reopens closed descriptors).
    extern "C" fn check_stdout() {
        // SAFETY: fcntl with F_GETFD reads the descriptor's flags; no memory is passed.
        if unsafe { fcntl(1, F_GETFD) } == -1 {
            CLOSED_AT_START.store(true, Ordering::Relaxed);
        }
    }

    #[used]
    #[unsafe(link_section = ".init_array")]
    static CHECK_STDOUT: extern "C" fn() = check_stdout;
}
