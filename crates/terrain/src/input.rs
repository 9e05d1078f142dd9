//! Reading the user's input files within a size cap (issue 30): every reader of rappel (scenarios,
//! pairs and path files, Paton scenes, tracking terrains, DEMs, meshes) opens its file here.
//!
//! - Only regular files are read: a FIFO, a character device (a link to `/dev/zero`), a socket
//!   or a directory is refused before a byte is read, naming what it is.
//! - A file larger than the cap is refused from its size before it is read; the read itself
//!   stops one byte past the cap, so a file that grows while it is read is refused too, never
//!   read until memory runs out.
//! - The cap is [`DEFAULT_MAX_INPUT_BYTES`] (1 GiB), raised (or lowered) by the environment
//!   variable [`MAX_INPUT_BYTES_VAR`] (`RAPPEL_MAX_INPUT_BYTES=4000000000`); a value that is
//!   not a positive whole number of bytes is an error, not ignored.
//!
//! ```
//! use rappel_terrain::input::{read_input_text, InputError};
//! let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/thesis-fig-2-7.ron");
//! assert!(read_input_text(path.as_ref(), 1 << 20).unwrap().contains("map"));
//! assert!(matches!(read_input_text(path.as_ref(), 10), Err(InputError::TooLarge { .. })));
//! assert!(matches!(read_input_text("/dev/zero".as_ref(), 1 << 20), Err(InputError::NotAFile { .. })));
//! ```

use std::fs::File;
use std::io::Read;
use std::path::{Path, PathBuf};

/// The default cap on an input file's size, bytes (1 GiB: a 1,000,000-obstacle scenario is about
/// 300 MB of JSON; a mesh of [`crate::mesh::MAX_TRIANGLES`] triangles about 200 MB of binary STL).
pub const DEFAULT_MAX_INPUT_BYTES: u64 = 1 << 30;

/// The environment variable that sets the cap, in bytes.
pub const MAX_INPUT_BYTES_VAR: &str = "RAPPEL_MAX_INPUT_BYTES";

/// Why an input file was not read.
#[derive(Debug, thiserror::Error)]
pub enum InputError {
    /// The file cannot be opened or read.
    #[error("{}: cannot read: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// Not a regular file.
    #[error("{}: is {what}, not a regular file; rappel reads input from regular files only", path.display())]
    NotAFile {
        /// The file.
        path: PathBuf,
        /// What it is (`a directory`, `a FIFO`, `a character device`, ...).
        what: &'static str,
    },
    /// Larger than the cap.
    #[error(
        "{}: {size} bytes, more than the input limit of {cap} bytes (set {MAX_INPUT_BYTES_VAR} to raise it)",
        path.display()
    )]
    TooLarge {
        /// The file.
        path: PathBuf,
        /// Its size (at least), bytes.
        size: u64,
        /// The cap, bytes.
        cap: u64,
    },
    /// Not UTF-8 text where text is expected.
    #[error("{}: not UTF-8 text (byte {offset})", path.display())]
    NotText {
        /// The file.
        path: PathBuf,
        /// Where the first invalid byte is.
        offset: usize,
    },
    /// The cap's environment variable is not a positive whole number.
    #[error("{MAX_INPUT_BYTES_VAR}={value}: must be a positive whole number of bytes")]
    BadLimit {
        /// The variable's value.
        value: String,
    },
}

/// The cap on input files: [`MAX_INPUT_BYTES_VAR`] when set, else [`DEFAULT_MAX_INPUT_BYTES`].
pub fn max_input_bytes() -> Result<u64, InputError> {
    match std::env::var(MAX_INPUT_BYTES_VAR) {
        Err(_) => Ok(DEFAULT_MAX_INPUT_BYTES),
        Ok(v) => match v.trim().parse::<u64>() {
            Ok(n) if n > 0 => Ok(n),
            _ => Err(InputError::BadLimit { value: v }),
        },
    }
}

/// Opens `path` for reading if it is a regular file of at most `cap` bytes (module docs);
/// returns the file and its size.
pub fn open_input(path: &Path, cap: u64) -> Result<(File, u64), InputError> {
    let io = |source| InputError::Io {
        path: path.to_path_buf(),
        source,
    };
    let meta = std::fs::metadata(path).map_err(io)?;
    let kind = meta.file_type();
    if !kind.is_file() {
        return Err(InputError::NotAFile {
            path: path.to_path_buf(),
            what: describe(&kind),
        });
    }
    if meta.len() > cap {
        return Err(InputError::TooLarge {
            path: path.to_path_buf(),
            size: meta.len(),
            cap,
        });
    }
    Ok((File::open(path).map_err(io)?, meta.len()))
}

/// The bytes of `path`, a regular file of at most `cap` bytes (module docs).
pub fn read_input(path: &Path, cap: u64) -> Result<Vec<u8>, InputError> {
    let (file, len) = open_input(path, cap)?;
    let mut bytes = Vec::with_capacity(usize::try_from(len).unwrap_or(0));
    file.take(cap.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(|source| InputError::Io {
            path: path.to_path_buf(),
            source,
        })?;
    if bytes.len() as u64 > cap {
        return Err(InputError::TooLarge {
            path: path.to_path_buf(),
            size: bytes.len() as u64,
            cap,
        });
    }
    Ok(bytes)
}

/// The text of `path`, a regular UTF-8 file of at most `cap` bytes (module docs).
pub fn read_input_text(path: &Path, cap: u64) -> Result<String, InputError> {
    String::from_utf8(read_input(path, cap)?).map_err(|e| InputError::NotText {
        path: path.to_path_buf(),
        offset: e.utf8_error().valid_up_to(),
    })
}

/// [`read_input_text`] under [`max_input_bytes`]: what every text reader of rappel calls.
pub fn read_text(path: &Path) -> Result<String, InputError> {
    read_input_text(path, max_input_bytes()?)
}

/// What a file that is not a regular file is, in words.
fn describe(kind: &std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if kind.is_fifo() {
            return "a FIFO (named pipe)";
        }
        if kind.is_char_device() {
            return "a character device";
        }
        if kind.is_block_device() {
            return "a block device";
        }
        if kind.is_socket() {
            return "a socket";
        }
    }
    if kind.is_dir() {
        "a directory"
    } else {
        "not a regular file"
    }
}
