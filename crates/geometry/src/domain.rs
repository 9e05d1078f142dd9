//! The coordinate domain: the numbers a map, a point or a terrain band may hold so that every
//! exact predicate ([`crate::predicates`], Shewchuk's adaptive orient2d and incircle) and the
//! polygon-overlay dependency stay exact and never overflow or underflow.
//!
//! Shewchuk's predicates are exact only while no intermediate product overflows to infinity or
//! underflows below the normal range. incircle multiplies four coordinate differences. With every
//! coordinate either 0 or of magnitude in `[2^-120, 2^120]`, a difference lies in
//! `[2^-172, 2^121]` (a non-zero difference of two such numbers is a multiple of the smaller one's
//! unit in the last place, `2^-172`), a degree-4 product in `[2^-688, 2^484]`, and the error
//! terms of the adaptive expansions (about `2^-160` below their product) stay above the smallest
//! normal `2^-1022`; areas and squared lengths (degree 2) are far from overflow. i_overlay's
//! float adapter accepts `|x| <= 2^500`, also far above.
//!
//! The domain is absolute and symmetric under scaling by powers of ten within it: a map in
//! metres, millimetres or kilometres plans the same (every tolerance elsewhere is relative to the
//! map's extent or named and justified); one scaled by `1e300` is refused with this reason
//! instead of failing later with a misleading one.

/// The largest magnitude of a coordinate, `2^120` (about `1.3e36`).
pub const MAX_COORDINATE: f64 = 1_329_227_995_784_915_872_903_807_060_280_344_576.0;

/// The smallest magnitude of a non-zero coordinate, `2^-120` (about `7.5e-37`).
pub const MIN_NONZERO_COORDINATE: f64 = 1.0 / MAX_COORDINATE;

/// `true` when `v` is a coordinate of the domain: finite, and 0 or of magnitude in
/// `[MIN_NONZERO_COORDINATE, MAX_COORDINATE]`.
///
/// ```
/// use rappel_geometry::domain::in_domain;
/// assert!(in_domain(0.0) && in_domain(-123.456) && in_domain(1e30) && in_domain(1e-30));
/// assert!(!in_domain(1e151) && !in_domain(-1e-300) && !in_domain(f64::NAN));
/// ```
pub fn in_domain(v: f64) -> bool {
    v == 0.0 || (MIN_NONZERO_COORDINATE..=MAX_COORDINATE).contains(&v.abs())
}

/// One line saying what the domain is, for error messages.
pub const DOMAIN_TEXT: &str = "coordinates must be 0 or of magnitude between 7.5e-37 and 1.3e36 (beyond, the exact geometric predicates would overflow or underflow)";

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bounds_are_powers_of_two() {
        assert_eq!(MAX_COORDINATE, 2f64.powi(120));
        assert_eq!(MIN_NONZERO_COORDINATE, 2f64.powi(-120));
        // The extreme degree-4 products of the module docs are normal numbers.
        let smallest_difference = MIN_NONZERO_COORDINATE * f64::EPSILON / 2.0;
        assert!(smallest_difference.powi(4) * 2f64.powi(-160) >= f64::MIN_POSITIVE);
        assert!((2.0 * MAX_COORDINATE).powi(4).is_finite());
    }
}
