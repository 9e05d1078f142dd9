//! ESRI ASCII grids (the `.asc` format of the thesis' DEM pipeline, §2.5.1-2.5.2): reading and
//! writing.
//!
//! Format: a header of `key value` lines, then `nrows x ncols` numbers from the north-west corner,
//! row by row (line breaks within the data carry no meaning: a row may span lines, or several rows
//! share one). Header keys are matched case-insensitively and may come in any order:
//!
//! | key | meaning |
//! |---|---|
//! | `ncols`, `nrows` | grid size (required) |
//! | `xllcorner` or `xllcenter` | easting of the lower-left cell's west edge, or of its centre (one required) |
//! | `yllcorner` or `yllcenter` | northing of the lower-left cell's south edge, or of its centre (one required) |
//! | `cellsize`, or `dx` and `dy` | cell size (required; `dx`/`dy` is GDAL's non-square variant) |
//! | `NODATA_value` | the value marking unknown cells (optional: without it no cell is unknown) |
//!
//! Cells equal to `NODATA_value`, and NaN cells, become unknown (never zero). Every error names the
//! line where the problem was found.

use std::fmt::Write as _;

use crate::grid::{DemLimits, GridError, GridGeometry, HeightGrid};

/// Longest excerpt of offending text quoted in an error.
const MAX_QUOTED_CHARS: usize = 40;

/// What is wrong with an ESRI ASCII grid, and on which line (1-based).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EsriAsciiError {
    /// A header line that is not exactly a key and a value.
    #[error("line {line}: header line `{text}` must be one key and one value")]
    MalformedHeaderLine {
        /// The line.
        line: usize,
        /// Its text (shortened).
        text: String,
    },
    /// A header key that is not part of the format.
    #[error(
        "line {line}: unknown header key `{key}`; expected ncols, nrows, xllcorner or xllcenter, yllcorner or yllcenter, cellsize (or dx and dy), NODATA_value"
    )]
    UnknownKey {
        /// The line.
        line: usize,
        /// The key as written (shortened).
        key: String,
    },
    /// The same key twice.
    #[error("line {line}: header key `{key}` repeats the one on line {first_line}")]
    DuplicateKey {
        /// The line of the repeat.
        line: usize,
        /// The key (lower case).
        key: &'static str,
        /// Where it first appeared.
        first_line: usize,
    },
    /// Both variants of one setting (`xllcorner` and `xllcenter`, or `cellsize` and `dx`).
    #[error("line {line}: `{key}` conflicts with `{other}` on line {other_line}; give only one")]
    ConflictingKeys {
        /// The line of the second key.
        line: usize,
        /// The second key.
        key: &'static str,
        /// The first key.
        other: &'static str,
        /// Its line.
        other_line: usize,
    },
    /// A header value of the wrong kind.
    #[error("line {line}: `{key}` has value `{text}`; expected {expected}")]
    BadHeaderValue {
        /// The line.
        line: usize,
        /// The key (lower case).
        key: &'static str,
        /// The value as written (shortened).
        text: String,
        /// What was expected.
        expected: &'static str,
    },
    /// A required key is absent.
    #[error("the header has no `{key}` line")]
    MissingKey {
        /// The key (lower case; `xllcorner` stands for either variant).
        key: &'static str,
    },
    /// A data value that is not a number, or is infinite.
    #[error("line {line}: value {index} (`{text}`) is not a finite number")]
    BadValue {
        /// The line.
        line: usize,
        /// The value's 0-based position in the data (row-major).
        index: usize,
        /// The text (shortened).
        text: String,
    },
    /// The data ends early.
    #[error(
        "the header announces {expected} values ({nrows} rows x {ncols} columns) but the data ends after {found}, on line {line}"
    )]
    TooFewValues {
        /// `nrows * ncols`.
        expected: usize,
        /// Values found.
        found: usize,
        /// Rows announced.
        nrows: usize,
        /// Columns announced.
        ncols: usize,
        /// The last line read.
        line: usize,
    },
    /// More values than announced.
    #[error("line {line}: more values than the {expected} announced by the header")]
    TooManyValues {
        /// `nrows * ncols`.
        expected: usize,
        /// The line of the first extra value.
        line: usize,
    },
    /// The header describes an unusable grid (zero or huge size, non-positive cell size...).
    #[error("the header describes an unusable grid: {0}")]
    Grid(#[from] GridError),
}

/// The header keys, lower case.
const KEYS: [&str; 10] = [
    "ncols",
    "nrows",
    "xllcorner",
    "xllcenter",
    "yllcorner",
    "yllcenter",
    "cellsize",
    "dx",
    "dy",
    "nodata_value",
];

/// Index of each key in [`KEYS`].
const NCOLS: usize = 0;
const NROWS: usize = 1;
const XLLCORNER: usize = 2;
const XLLCENTER: usize = 3;
const YLLCORNER: usize = 4;
const YLLCENTER: usize = 5;
const CELLSIZE: usize = 6;
const DX: usize = 7;
const DY: usize = 8;
const NODATA: usize = 9;

/// Shortened, printable excerpt of raw bytes.
fn quote(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes)
        .chars()
        .take(MAX_QUOTED_CHARS)
        .collect()
}

/// Whitespace-separated tokens of one line.
fn tokens(line: &[u8]) -> impl Iterator<Item = &[u8]> {
    line.split(|b| b.is_ascii_whitespace())
        .filter(|t| !t.is_empty())
}

/// Parses a token as `f64` (any non-UTF-8 byte makes it not a number).
fn parse_f64(tok: &[u8]) -> Option<f64> {
    std::str::from_utf8(tok).ok()?.parse::<f64>().ok()
}

/// One header entry: its value's text and line.
#[derive(Clone, Copy)]
struct Entry<'a> {
    text: &'a [u8],
    line: usize,
}

/// Parses an ESRI ASCII grid from its bytes (see the module docs for the format).
///
/// ```
/// use rappel_terrain::esri_ascii::parse_esri_ascii;
/// let text = "NCOLS 3\nnrows 2\nxllcenter 0.5\nyllcenter 0.5\ncellsize 1\nnodata_value -9999\n\
///             1 2 3\n4 -9999\n6\n";
/// let dem = parse_esri_ascii(text.as_bytes()).unwrap();
/// assert_eq!(dem.geometry().west, 0.0);
/// assert_eq!(dem.geometry().north, 2.0);
/// assert_eq!(dem.height(1, 1), None);
/// assert_eq!(dem.height(1, 2), Some(6.0));
/// let err = parse_esri_ascii(b"ncols 2\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 x\n").unwrap_err();
/// assert_eq!(err.to_string(), "line 6: value 1 (`x`) is not a finite number");
/// ```
pub fn parse_esri_ascii(bytes: &[u8]) -> Result<HeightGrid, EsriAsciiError> {
    parse_esri_ascii_with(bytes, &DemLimits::default())
}

/// [`parse_esri_ascii`] under explicit [`DemLimits`]: a header announcing more cells than the
/// work cap is refused before any height is read.
///
/// ```
/// use rappel_terrain::grid::DemLimits;
/// use rappel_terrain::esri_ascii::parse_esri_ascii_with;
/// let text = "ncols 3\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2 3 4 5 6\n";
/// assert!(parse_esri_ascii_with(text.as_bytes(), &DemLimits::with_max_cells(6).unwrap()).is_ok());
/// let err = parse_esri_ascii_with(text.as_bytes(), &DemLimits::with_max_cells(5).unwrap()).unwrap_err();
/// assert!(err.to_string().contains("work cap of 5 cells"));
/// ```
pub fn parse_esri_ascii_with(
    bytes: &[u8],
    limits: &DemLimits,
) -> Result<HeightGrid, EsriAsciiError> {
    let mut header: [Option<Entry<'_>>; KEYS.len()] = [None; KEYS.len()];
    let mut lines = bytes.split(|&b| b == b'\n').enumerate().peekable();

    // Header: lines whose first token is a known key.
    while let Some(&(i, line)) = lines.peek() {
        let line_no = i + 1;
        let toks: Vec<&[u8]> = tokens(line).collect();
        let Some(first) = toks.first() else {
            lines.next();
            continue;
        };
        let key_text = String::from_utf8_lossy(first).to_ascii_lowercase();
        let Some(k) = KEYS.iter().position(|&k| k == key_text) else {
            if first[0].is_ascii_alphabetic() && parse_f64(first).is_none() {
                return Err(EsriAsciiError::UnknownKey {
                    line: line_no,
                    key: quote(first),
                });
            }
            break; // the data start here
        };
        if toks.len() != 2 {
            return Err(EsriAsciiError::MalformedHeaderLine {
                line: line_no,
                text: quote(line.trim_ascii()),
            });
        }
        if let Some(prev) = header[k] {
            return Err(EsriAsciiError::DuplicateKey {
                line: line_no,
                key: KEYS[k],
                first_line: prev.line,
            });
        }
        for (a, b) in [
            (XLLCORNER, XLLCENTER),
            (YLLCORNER, YLLCENTER),
            (CELLSIZE, DX),
            (CELLSIZE, DY),
        ] {
            let other = if k == a {
                b
            } else if k == b {
                a
            } else {
                continue;
            };
            if let Some(o) = header[other] {
                return Err(EsriAsciiError::ConflictingKeys {
                    line: line_no,
                    key: KEYS[k],
                    other: KEYS[other],
                    other_line: o.line,
                });
            }
        }
        header[k] = Some(Entry {
            text: toks[1],
            line: line_no,
        });
        lines.next();
    }

    let count = |k: usize| -> Result<usize, EsriAsciiError> {
        let e = header[k].ok_or(EsriAsciiError::MissingKey { key: KEYS[k] })?;
        std::str::from_utf8(e.text)
            .ok()
            .and_then(|s| s.parse::<usize>().ok())
            .filter(|&n| n > 0)
            .ok_or_else(|| EsriAsciiError::BadHeaderValue {
                line: e.line,
                key: KEYS[k],
                text: quote(e.text),
                expected: "a positive whole number",
            })
    };
    let number = |k: usize| -> Result<Option<f64>, EsriAsciiError> {
        let Some(e) = header[k] else {
            return Ok(None);
        };
        parse_f64(e.text)
            .filter(|v| v.is_finite())
            .map(Some)
            .ok_or_else(|| EsriAsciiError::BadHeaderValue {
                line: e.line,
                key: KEYS[k],
                text: quote(e.text),
                expected: "a finite number",
            })
    };
    let ncols = count(NCOLS)?;
    let nrows = count(NROWS)?;
    let (cell_x, cell_y) = match (number(CELLSIZE)?, number(DX)?, number(DY)?) {
        (Some(c), _, _) => (c, c),
        (None, Some(dx), Some(dy)) => (dx, dy),
        (None, Some(_), None) => return Err(EsriAsciiError::MissingKey { key: "dy" }),
        (None, None, _) => return Err(EsriAsciiError::MissingKey { key: "cellsize" }),
    };
    let west = match (number(XLLCORNER)?, number(XLLCENTER)?) {
        (Some(x), _) => x,
        (None, Some(x)) => x - 0.5 * cell_x,
        (None, None) => return Err(EsriAsciiError::MissingKey { key: "xllcorner" }),
    };
    let south = match (number(YLLCORNER)?, number(YLLCENTER)?) {
        (Some(y), _) => y,
        (None, Some(y)) => y - 0.5 * cell_y,
        (None, None) => return Err(EsriAsciiError::MissingKey { key: "yllcorner" }),
    };
    // NODATA may be NaN (as GDAL writes it for float grids); NaN cells are unknown anyway.
    let nodata = match header[NODATA] {
        None => None,
        Some(e) => Some(
            parse_f64(e.text)
                .filter(|v| !v.is_infinite())
                .ok_or_else(|| EsriAsciiError::BadHeaderValue {
                    line: e.line,
                    key: KEYS[NODATA],
                    text: quote(e.text),
                    expected: "a number",
                })?,
        ),
    };
    let north = south + nrows as f64 * cell_y;
    let geometry = GridGeometry::new(nrows, ncols, cell_x, cell_y, west, north)?;
    limits.check(&geometry)?;
    let expected = geometry.len();

    // Data: never reserve more than the file could hold.
    let mut heights: Vec<f64> = Vec::with_capacity(expected.min(bytes.len() / 2 + 1));
    let mut last_line = 0;
    for (i, line) in lines {
        let line_no = i + 1;
        for tok in tokens(line) {
            last_line = line_no;
            if heights.len() == expected {
                return Err(EsriAsciiError::TooManyValues {
                    expected,
                    line: line_no,
                });
            }
            let v = parse_f64(tok).filter(|v| !v.is_infinite()).ok_or_else(|| {
                EsriAsciiError::BadValue {
                    line: line_no,
                    index: heights.len(),
                    text: quote(tok),
                }
            })?;
            heights.push(if Some(v) == nodata { f64::NAN } else { v });
        }
    }
    if heights.len() < expected {
        return Err(EsriAsciiError::TooFewValues {
            expected,
            found: heights.len(),
            nrows,
            ncols,
            line: last_line.max(1),
        });
    }
    Ok(HeightGrid::new(geometry, heights)?)
}

/// Writes `dem` as an ESRI ASCII grid, unknown cells as `nodata_value`, one grid row per line.
/// Square cells are written with `cellsize`, others with `dx` and `dy`. Numbers are written in
/// their shortest exact form, so [`parse_esri_ascii`] reads back the same grid.
///
/// ```
/// use rappel_terrain::grid::{GridGeometry, HeightGrid};
/// use rappel_terrain::esri_ascii::{parse_esri_ascii, write_esri_ascii};
/// let g = GridGeometry::new(2, 2, 0.5, 0.5, 10.0, 20.0).unwrap();
/// let dem = HeightGrid::new(g, vec![1.25, f64::NAN, 3.0, -4.5]).unwrap();
/// let text = write_esri_ascii(&dem, -9999.0);
/// assert_eq!(parse_esri_ascii(text.as_bytes()).unwrap(), dem);
/// ```
pub fn write_esri_ascii(dem: &HeightGrid, nodata_value: f64) -> String {
    let g = dem.geometry();
    let mut out = String::new();
    // Writing into a String cannot fail.
    let _ = writeln!(out, "ncols {}\nnrows {}", g.ncols, g.nrows);
    let _ = writeln!(out, "xllcorner {}\nyllcorner {}", g.west, g.south());
    if g.cell_x == g.cell_y {
        let _ = writeln!(out, "cellsize {}", g.cell_x);
    } else {
        let _ = writeln!(out, "dx {}\ndy {}", g.cell_x, g.cell_y);
    }
    let _ = writeln!(out, "NODATA_value {nodata_value}");
    for row in 0..g.nrows {
        for col in 0..g.ncols {
            if col > 0 {
                out.push(' ');
            }
            let _ = write!(out, "{}", dem.height(row, col).unwrap_or(nodata_value));
        }
        out.push('\n');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEADER: &str = "ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n";

    fn err(text: &str) -> EsriAsciiError {
        parse_esri_ascii(text.as_bytes()).unwrap_err()
    }

    #[test]
    fn header_keys_any_case_any_order() {
        let dem = parse_esri_ascii(
            b"CellSize 2\r\nNODATA_VALUE -1\r\nYLLCORNER 10\r\nNRows 1\r\nxLLcorner 5\r\nncols 3\r\n7 -1 9\r\n",
        )
        .unwrap();
        let g = dem.geometry();
        assert_eq!(
            (g.nrows, g.ncols, g.cell_x, g.west, g.north),
            (1, 3, 2.0, 5.0, 12.0)
        );
        assert_eq!(dem.height(0, 1), None);
        assert_eq!(dem.height(0, 2), Some(9.0));
    }

    #[test]
    fn centre_variant_shifts_by_half_a_cell() {
        let corner =
            parse_esri_ascii(b"ncols 1\nnrows 1\nxllcorner 99\nyllcorner 199\ncellsize 2\n5\n")
                .unwrap();
        let centre =
            parse_esri_ascii(b"ncols 1\nnrows 1\nxllcenter 100\nyllcenter 200\ncellsize 2\n5\n")
                .unwrap();
        assert_eq!(corner, centre);
    }

    #[test]
    fn dx_dy_variant_and_missing_nodata() {
        let dem =
            parse_esri_ascii(b"ncols 2\nnrows 1\nxllcorner 0\nyllcorner 0\ndx 2\ndy 3\n-9999 1\n")
                .unwrap();
        assert_eq!((dem.geometry().cell_x, dem.geometry().cell_y), (2.0, 3.0));
        // Without a NODATA line, -9999 is a height like any other.
        assert_eq!(dem.height(0, 0), Some(-9999.0));
        assert_eq!(
            err("ncols 2\nnrows 1\nxllcorner 0\nyllcorner 0\ndx 2\n1 1\n"),
            EsriAsciiError::MissingKey { key: "dy" }
        );
    }

    #[test]
    fn nan_values_are_unknown_and_may_start_the_data() {
        let dem = parse_esri_ascii(format!("{HEADER}nan 1\n2 NaN\n").as_bytes()).unwrap();
        assert_eq!(dem.unknown_count(), 2);
        assert_eq!(dem.height(0, 1), Some(1.0));
    }

    #[test]
    fn each_defect_names_its_line() {
        assert_eq!(
            err("ncols 2\nnrows 2\nbogus 1\n"),
            EsriAsciiError::UnknownKey {
                line: 3,
                key: "bogus".into()
            }
        );
        assert_eq!(
            err("ncols 2\nnrows 2\nncols 3\n"),
            EsriAsciiError::DuplicateKey {
                line: 3,
                key: "ncols",
                first_line: 1
            }
        );
        assert!(matches!(
            err("ncols 2 3\n"),
            EsriAsciiError::MalformedHeaderLine { line: 1, .. }
        ));
        assert!(matches!(
            err("ncols 2\nnrows 2\nxllcorner 0\nxllcenter 0\n"),
            EsriAsciiError::ConflictingKeys {
                line: 4,
                other_line: 3,
                ..
            }
        ));
        assert!(matches!(
            err("ncols 2.5\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2 3 4\n"),
            EsriAsciiError::BadHeaderValue {
                line: 1,
                key: "ncols",
                ..
            }
        ));
        assert!(matches!(
            err("ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize abc\n1 2 3 4\n"),
            EsriAsciiError::BadHeaderValue {
                line: 5,
                key: "cellsize",
                ..
            }
        ));
        assert_eq!(
            err("ncols 2\nnrows 2\nxllcorner 0\ncellsize 1\n1 2 3 4\n"),
            EsriAsciiError::MissingKey { key: "yllcorner" }
        );
        assert!(matches!(
            err("ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize -1\n1 2 3 4\n"),
            EsriAsciiError::Grid(GridError::BadCellSize { .. })
        ));
        assert_eq!(
            err(&format!("{HEADER}1 2\n3 4x\n")),
            EsriAsciiError::BadValue {
                line: 7,
                index: 3,
                text: "4x".into()
            }
        );
        assert!(matches!(
            err(&format!("{HEADER}1 2\ninf 4\n")),
            EsriAsciiError::BadValue { line: 7, .. }
        ));
        assert_eq!(
            err(&format!("{HEADER}1 2\n3\n\n")),
            EsriAsciiError::TooFewValues {
                expected: 4,
                found: 3,
                nrows: 2,
                ncols: 2,
                line: 7
            }
        );
        assert_eq!(
            err(&format!("{HEADER}1 2\n3 4\n5\n")),
            EsriAsciiError::TooManyValues {
                expected: 4,
                line: 8
            }
        );
    }

    #[test]
    fn huge_announced_size_is_refused_without_allocating() {
        assert!(matches!(
            err(
                "ncols 100000000000\nnrows 100000000000\nxllcorner 0\nyllcorner 0\ncellsize 1\n1\n"
            ),
            EsriAsciiError::Grid(GridError::TooLarge { .. })
        ));
        // Over the default work cap: refused before reading heights.
        let text = "ncols 10000\nnrows 10000\nxllcorner 0\nyllcorner 0\ncellsize 1\n1\n";
        assert!(matches!(
            err(text),
            EsriAsciiError::Grid(GridError::OverWorkCap {
                nrows: 10000,
                ncols: 10000,
                ..
            })
        ));
        // Within a raised cap but far more than the file holds: an error, quickly.
        let all = DemLimits::with_max_cells(crate::grid::MAX_CELLS).unwrap();
        assert!(matches!(
            parse_esri_ascii_with(text.as_bytes(), &all),
            Err(EsriAsciiError::TooFewValues { found: 1, .. })
        ));
    }

    #[test]
    fn round_trip_non_square_cells() {
        let g = GridGeometry::new(3, 2, 0.25, 4.0, -7.5, 1e6).unwrap();
        let dem = HeightGrid::from_fn(g, |r, c, _| {
            (r + c != 2).then_some(0.1 * (r * 7 + c) as f64)
        })
        .unwrap();
        let back = parse_esri_ascii(write_esri_ascii(&dem, -32768.0).as_bytes()).unwrap();
        assert_eq!(back, dem);
    }
}
