//! File output that never leaves a half-written file behind: write to a temporary file beside the
//! target, flush it to disk, then rename it over the target (atomic on POSIX file systems).

use std::io::Write;
use std::path::Path;

/// Writes `bytes` to `path` atomically: either the whole new content is there or the old file
/// (or nothing) is.
///
/// ```
/// let dir = std::env::temp_dir().join(format!("rappel-doc-{}", std::process::id()));
/// std::fs::create_dir_all(&dir).unwrap();
/// let file = dir.join("out.txt");
/// rappel::io::write_atomically(&file, b"hello").unwrap();
/// assert_eq!(std::fs::read(&file).unwrap(), b"hello");
/// # std::fs::remove_dir_all(&dir).unwrap();
/// ```
pub fn write_atomically(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let name = path
        .file_name()
        .ok_or_else(|| std::io::Error::new(std::io::ErrorKind::InvalidInput, "no file name"))?;
    let tmp = dir.join(format!(
        ".{}.tmp-{}",
        name.to_string_lossy(),
        std::process::id()
    ));
    let result = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}
