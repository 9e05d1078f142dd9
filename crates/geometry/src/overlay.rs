//! The one adapter to the polygon-overlay dependency (`i_overlay`). i_overlay panics on input it
//! cannot place on its integer grid ("Invalid adapter bounds: CoordinatesOutOfRange"), so every
//! call goes through [`overlay`], which first proves the input is in its domain (every coordinate
//! finite with magnitude at most [`MAX_OVERLAY_COORDINATE`]) and then catches any panic left at
//! this boundary, turning both into a typed [`OverlayError`].

use crate::compact::Compact;
use i_overlay::core::fill_rule::FillRule;
use i_overlay::float::single::SingleFloatOverlay;

pub use i_overlay::core::overlay_rule::OverlayRule;

/// Contours as i_overlay takes them: rings of `[x, y]`.
pub type Contours = Vec<Vec<[f64; 2]>>;

/// Shapes as i_overlay returns them: each an outer ring followed by its holes.
pub type Shapes = Vec<Contours>;

/// The largest coordinate magnitude passed to i_overlay: `2^400`, a factor `2^100` inside the
/// `2^500` its float adapter accepts (so that its internal padding cannot push the bounds out).
/// Maps are limited to the far smaller [`crate::domain::MAX_COORDINATE`].
pub const MAX_OVERLAY_COORDINATE: f64 = 2.582_249_878_086_908_6e120;

/// Why an overlay could not be computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum OverlayError {
    /// A coordinate lies outside the overlay's domain.
    #[error("polygon overlay: coordinate ({}, {}) outside its domain |x| <= 2^400", Compact(*x), Compact(*y))]
    OutOfDomain {
        /// x.
        x: f64,
        /// y.
        y: f64,
    },
    /// The dependency panicked on input in its domain (a bug to report upstream).
    #[error("polygon overlay failed: {0}")]
    Failed(String),
}

/// `subject (rule) clip` with the non-zero fill rule (module docs).
///
/// ```
/// use rappel_geometry::overlay::{OverlayRule, overlay};
/// let sq = |x: f64, s: f64| vec![vec![[x, x], [x + s, x], [x + s, x + s], [x, x + s]]];
/// let shapes = overlay(&sq(0.0, 2.0), &sq(1.0, 2.0), OverlayRule::Intersect).unwrap();
/// assert_eq!(shapes.len(), 1);
/// assert!(overlay(&sq(-1e100, 2.0), &sq(1.0, 2.0), OverlayRule::Union).is_ok());
/// assert!(overlay(&sq(-1e300, 2.0), &sq(1.0, 2.0), OverlayRule::Union).is_err());
/// ```
pub fn overlay(
    subject: &Contours,
    clip: &Contours,
    rule: OverlayRule,
) -> Result<Shapes, OverlayError> {
    for p in subject.iter().chain(clip).flatten() {
        let ok = |v: f64| v.is_finite() && v.abs() <= MAX_OVERLAY_COORDINATE;
        if !(ok(p[0]) && ok(p[1])) {
            return Err(OverlayError::OutOfDomain { x: p[0], y: p[1] });
        }
    }
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        subject.overlay_as::<i64>(clip, rule, FillRule::NonZero)
    }))
    .map_err(|payload| {
        let message = payload
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "panic".to_string());
        OverlayError::Failed(message)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bound_is_two_to_the_400() {
        assert_eq!(MAX_OVERLAY_COORDINATE, 2f64.powi(400));
    }
}
