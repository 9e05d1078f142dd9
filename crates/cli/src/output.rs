//! Shared output plumbing for subcommands: the error type (one line, exit code 2), the answer a
//! yes/no subcommand gives (exit 0 or 1), JSON printing, stdout that reports its write errors,
//! the refusal to write over an input file, and atomic file writes, so no subcommand leaves a
//! half-written file.

use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

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

/// The answer of a subcommand that asks a question: exit code 0 for yes, 1 for a clean no.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Answer {
    /// A feasible plan, homotopic paths, a valid file: exit code 0.
    Yes,
    /// No feasible class, not homotopic: exit code 1.
    No,
}

/// Prints a report as pretty JSON on stdout, in its envelope (`schema_version` and `report`
/// first; the convention is `rappel::report` and `docs/output-format.md`). Every `--json` goes
/// through here.
pub fn print_report<T: rappel::report::Report>(report: &T) -> Result<(), CliError> {
    let text = serde_json::to_string_pretty(&rappel::report::Envelope::new(report))?;
    crate::output::outln!("{text}");
    Ok(())
}

/// Writes a text file atomically, creating missing parent directories (so that `--svg out/x.svg`
/// works in a fresh checkout), naming the file in any error.
pub fn write_file(path: &Path, text: &str) -> Result<(), CliError> {
    write_bytes(path, text.as_bytes())
}

/// Writes `bytes` to `path` as [`write_file`] does (binary outputs: GeoTIFFs).
pub fn write_bytes(path: &Path, bytes: &[u8]) -> Result<(), CliError> {
    let cannot = |e: std::io::Error| CliError(format!("{}: cannot write: {e}", path.display()));
    if let Some(dir) = path.parent()
        && !dir.as_os_str().is_empty()
    {
        std::fs::create_dir_all(dir).map_err(cannot)?;
    }
    rappel::io::write_atomically(path, bytes).map_err(cannot)
}

/// The path `p` with symbolic links resolved: the file itself when it exists, else its existing
/// parent directory joined with its name (an output file usually does not exist yet). `None`
/// when neither can be resolved (then no existing file can be the same).
fn resolved(p: &Path) -> Option<PathBuf> {
    if let Ok(c) = std::fs::canonicalize(p) {
        return Some(c);
    }
    let name = p.file_name()?;
    let dir = match p.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    Some(std::fs::canonicalize(dir).ok()?.join(name))
}

/// `true` when `a` and `b` name the same existing file (same device and inode: catches hard
/// links too).
#[cfg(unix)]
fn same_inode(a: &Path, b: &Path) -> bool {
    use std::os::unix::fs::MetadataExt as _;
    match (std::fs::metadata(a), std::fs::metadata(b)) {
        (Ok(x), Ok(y)) => x.dev() == y.dev() && x.ino() == y.ino(),
        _ => false,
    }
}

#[cfg(not(unix))]
fn same_inode(_: &Path, _: &Path) -> bool {
    false
}

/// Refuses an output path that is one of the input paths, after resolving symbolic links (and,
/// on Unix, hard links): `rappel btm S.ron --svg S.ron` must not overwrite the scenario. Call it
/// before anything is written.
pub fn refuse_overwriting_inputs(output: &Path, inputs: &[&Path]) -> Result<(), CliError> {
    let out = resolved(output);
    for input in inputs {
        let same_path = out.is_some() && out == resolved(input);
        if same_path || same_inode(output, input) {
            return Err(CliError(format!(
                "{}: the output would overwrite the input file {}; choose another output path",
                output.display(),
                input.display()
            )));
        }
    }
    Ok(())
}

/// [`refuse_overwriting_inputs`] for every output, and refuses two outputs that are the same file
/// (`dem X.asc --out S.ron --svg S.ron`); `outputs` pairs each path with its flag for the message.
pub fn refuse_clashing_outputs(
    outputs: &[(&str, &Path)],
    inputs: &[&Path],
) -> Result<(), CliError> {
    for (i, (flag, out)) in outputs.iter().enumerate() {
        refuse_overwriting_inputs(out, inputs)?;
        for (flag2, out2) in &outputs[..i] {
            let same_path = resolved(out).is_some() && resolved(out) == resolved(out2);
            if same_path || same_inode(out, out2) {
                return Err(CliError(format!(
                    "{}: {flag} and {flag2} name the same file; choose two output paths",
                    out.display()
                )));
            }
        }
    }
    Ok(())
}

/// A quantity for a report: one decimal in everyday magnitudes, compact scientific notation
/// beyond (an area of a map near the coordinate domain's edge has 70 digits).
pub fn quantity(v: f64) -> String {
    if v.abs() < 1e9 {
        format!("{:.1}", v + 0.0)
    } else {
        rappel::geometry::compact::Compact(v).to_string()
    }
}

/// The first error met writing to stdout (kept so that the exit code can report it).
static STDOUT_ERROR: OnceLock<String> = OnceLock::new();

/// Records a write error on stdout; later writes are skipped.
pub fn stdout_failed(e: &std::io::Error) {
    let _ = STDOUT_ERROR.set(e.to_string());
}

/// `true` once a write to stdout has failed.
pub fn stdout_has_failed() -> bool {
    STDOUT_ERROR.get().is_some()
}

/// Flushes stdout and returns the first write error, if any: a report that did not reach its
/// reader is a failure (exit code 2), whether stdout is a full disk (`/dev/full`) or a closed
/// pipe. (A descriptor closed before the start, `>&-`, is caught before `main` by
/// [`crate::closed_stdout`].)
pub fn finish_stdout() -> Result<(), CliError> {
    use std::io::Write as _;
    if let Err(e) = std::io::stdout().lock().flush() {
        stdout_failed(&e);
    }
    match STDOUT_ERROR.get() {
        Some(e) => Err(CliError(format!(
            "cannot write to standard output: {e}; the output is incomplete"
        ))),
        None => Ok(()),
    }
}

/// Prints a line on stdout. A failed write (a full disk, a closed pipe) is recorded and later
/// lines are skipped; [`finish_stdout`] turns it into an error and exit code 2.
macro_rules! outln {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        if !$crate::output::stdout_has_failed() {
            let mut out = std::io::stdout().lock();
            if let Err(e) = writeln!(out, $($arg)*) {
                $crate::output::stdout_failed(&e);
            }
        }
    }};
}

pub(crate) use outln;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_output_equal_to_an_input_is_refused_through_links() {
        let dir = std::env::temp_dir().join(format!("rappel-out-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let input = dir.join("s.ron");
        std::fs::write(&input, "x").unwrap();
        assert!(refuse_overwriting_inputs(&input, &[&input]).is_err());
        let dotted = dir.join(".").join("s.ron");
        assert!(refuse_overwriting_inputs(&dotted, &[&input]).is_err());
        #[cfg(unix)]
        {
            let link = dir.join("link.svg");
            let _ = std::fs::remove_file(&link);
            std::os::unix::fs::symlink(&input, &link).unwrap();
            assert!(refuse_overwriting_inputs(&link, &[&input]).is_err());
            let hard = dir.join("hard.svg");
            let _ = std::fs::remove_file(&hard);
            std::fs::hard_link(&input, &hard).unwrap();
            assert!(refuse_overwriting_inputs(&hard, &[&input]).is_err());
        }
        assert!(refuse_overwriting_inputs(&dir.join("other.svg"), &[&input]).is_ok());
        assert!(refuse_overwriting_inputs(&dir.join("new/out.svg"), &[&input]).is_ok());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn two_outputs_naming_one_file_are_refused() {
        let dir = std::env::temp_dir().join(format!("rappel-outs-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let input = dir.join("x.asc");
        std::fs::write(&input, "x").unwrap();
        let (a, b) = (dir.join("s.ron"), dir.join(".").join("s.ron"));
        let clash = refuse_clashing_outputs(&[("--out", &a), ("--svg", &b)], &[&input]);
        assert!(clash.is_err_and(|e| e.0.contains("--svg and --out name the same file")));
        let c = dir.join("s.svg");
        assert!(refuse_clashing_outputs(&[("--out", &a), ("--svg", &c)], &[&input]).is_ok());
        assert!(refuse_clashing_outputs(&[("--out", &a), ("--svg", &input)], &[&input]).is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

/// `--svg OUT` and `--html OUT`: a subcommand's picture, and the interactive viewer page around
/// it (`rappel::viewer`: pan, zoom, layer toggles, tag picker, hover details; self-contained).
#[derive(clap::Args, Debug, Default)]
pub struct PictureArgs {
    /// Draw the picture to this SVG file.
    #[arg(long, value_name = "OUT")]
    pub svg: Option<PathBuf>,
    /// Write the picture as an interactive page (one self-contained HTML file) to this file.
    #[arg(long, value_name = "OUT")]
    pub html: Option<PathBuf>,
}

impl PictureArgs {
    /// The outputs asked for, named by flag, for [`refuse_clashing_outputs`].
    pub fn outputs(&self) -> Vec<(&'static str, &Path)> {
        [("--svg", &self.svg), ("--html", &self.html)]
            .into_iter()
            .filter_map(|(flag, p)| p.as_deref().map(|p| (flag, p)))
            .collect()
    }

    /// Whether a picture is wanted at all.
    pub fn wanted(&self) -> bool {
        self.svg.is_some() || self.html.is_some()
    }

    /// Writes the picture `svg` (titled `title`) to the outputs asked for.
    pub fn write(&self, svg: &str, title: &str) -> Result<(), CliError> {
        if let Some(out) = &self.svg {
            write_file(out, svg)?;
        }
        if let Some(out) = &self.html {
            write_file(out, &rappel_render::viewer::html(svg, title))?;
        }
        Ok(())
    }
}
