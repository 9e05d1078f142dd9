//! Numbers in messages: compact, readable, never `-0`. `1e300` prints as `1e300`, not as a
//! 301-digit integer; `0.1 + 0.2` as `0.30000000000000004` (the shortest text that reads back to
//! the same number, so nothing is hidden); `-0.0` as `0`.

use std::fmt;

/// A number displayed compactly (module docs).
///
/// ```
/// use rappel_geometry::compact::Compact;
/// assert_eq!(Compact(1e300).to_string(), "1e300");
/// assert_eq!(Compact(-4.5e-307).to_string(), "-4.5e-307");
/// assert_eq!(Compact(12.5).to_string(), "12.5");
/// assert_eq!(Compact(-0.0).to_string(), "0");
/// assert_eq!(Compact(f64::NAN).to_string(), "NaN");
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Compact(pub f64);

/// A number rounded to `.1` decimals in positional notation when its magnitude is in the
/// positional range, else [`Compact`] (so a coordinate of `1e300` never prints 300 digits).
///
/// ```
/// use rappel_geometry::compact::Rounded;
/// assert_eq!(Rounded(12.34567, 3).to_string(), "12.346");
/// assert_eq!(Rounded(1e300, 3).to_string(), "1e300");
/// assert_eq!(Rounded(-0.0001, 2).to_string(), "-0.00");
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rounded(pub f64, pub usize);

impl fmt::Display for Rounded {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let Rounded(v, decimals) = *self;
        if v.is_finite() && v.abs() < POSITIONAL.end {
            write!(f, "{v:.decimals$}")
        } else {
            Compact(v).fmt(f)
        }
    }
}

/// Magnitudes printed in positional notation: `[1e-4, 1e9)`; others in scientific notation.
const POSITIONAL: std::ops::Range<f64> = 1e-4..1e9;

impl fmt::Display for Compact {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let v = self.0;
        if v == 0.0 {
            f.write_str("0")
        } else if !v.is_finite() || POSITIONAL.contains(&v.abs()) {
            write!(f, "{v}")
        } else {
            write!(f, "{v:e}")
        }
    }
}
