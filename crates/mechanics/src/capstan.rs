//! The capstan (Euler-Eytelwein) relation and its generalisation to a constant friction rate
//! (thesis §3.2.5, eqs. 3.20-3.24).
//!
//! # Math
//! A weightless rope in contact over an angle `ζ` with a frictional cylinder holds a load
//! `T_load = T_hold e^{μζ}` (eq. 3.20). More generally, where `ω` (eq. 3.17) is constant along a
//! contact of length `s`, the end tensions of a rope in equilibrium satisfy
//! `e^{-ωs} <= T_1/T_0 <= e^{ωs}` (eq. 3.24); on a capstan of radius `R`, `ω = μ/R` and `s = Rζ`,
//! so the radius drops out.

use crate::friction::{FrictionError, check_coefficient};

/// The capstan amplification `e^{μζ}` for a contact (winding) angle `zeta` in radians
/// (thesis eq. 3.20; Kumar eq. 2 applies it anchor by anchor).
///
/// # Example
/// ```
/// use rappel_mechanics::capstan::amplification;
/// let a = amplification(0.4, std::f64::consts::FRAC_PI_2).unwrap();
/// assert!((a - (0.2 * std::f64::consts::PI).exp()).abs() < 1e-12);
/// ```
pub fn amplification(mu: f64, zeta: f64) -> Result<f64, FrictionError> {
    check_coefficient(mu)?;
    Ok((mu * zeta.abs()).exp())
}

/// The range `[T_0 e^{-ωs}, T_0 e^{ωs}]` of end tensions that a contact with constant friction rate
/// `omega` over length `length` can hold against a tension `t0` at its other end (eq. 3.24).
pub fn tension_bounds(t0: f64, omega: f64, length: f64) -> (f64, f64) {
    let k = (omega.abs() * length.abs()).exp();
    (t0 / k, t0 * k)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn radius_drops_out_of_capstan_bounds() {
        let (mu, zeta, t0) = (0.4, 1.2, 50.0);
        for r in [0.1, 0.5, 3.0] {
            let (lo, hi) = tension_bounds(t0, mu / r, r * zeta);
            let a = amplification(mu, zeta).unwrap();
            assert!((hi - t0 * a).abs() < 1e-9 && (lo - t0 / a).abs() < 1e-9);
        }
        assert!(amplification(-1.0, 1.0).is_err());
    }
}
