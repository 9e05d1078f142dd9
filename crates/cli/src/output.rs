//! Shared output plumbing for subcommands: the error type (one line, exit code 2), JSON printing
//! and atomic file writes, so no subcommand leaves a half-written file.

use std::fmt;
use std::path::Path;

/// A subcommand failure: printed as one `error:` line, exit code 2.
#[derive(Debug)]
pub struct CliError(pub String);

impl fmt::Display for CliError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl<E: std::error::Error> From<E> for CliError {
    fn from(e: E) -> Self {
        CliError(e.to_string())
    }
}

/// Prints a value as pretty JSON on stdout.
pub fn print_json<T: serde::Serialize>(value: &T) -> Result<(), CliError> {
    let text = serde_json::to_string_pretty(value)?;
    crate::outln!("{text}");
    Ok(())
}

/// Writes a text file atomically, creating missing parent directories (so that `--svg out/x.svg`
/// works in a fresh checkout), naming the file in any error.
pub fn write_file(path: &Path, text: &str) -> Result<(), CliError> {
    let cannot = |e: std::io::Error| CliError(format!("{}: cannot write: {e}", path.display()));
    if let Some(dir) = path.parent()
        && !dir.as_os_str().is_empty()
    {
        std::fs::create_dir_all(dir).map_err(cannot)?;
    }
    rappel::io::write_atomically(path, text.as_bytes()).map_err(cannot)
}

/// Prints a line on stdout; a closed pipe (`rappel ... | head`) ends the program quietly instead
/// of panicking.
#[macro_export]
macro_rules! outln {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let mut out = std::io::stdout().lock();
        if let Err(e) = writeln!(out, $($arg)*) {
            if e.kind() == std::io::ErrorKind::BrokenPipe {
                std::process::exit(0);
            }
        }
    }};
}
