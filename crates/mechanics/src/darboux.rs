//! The Darboux frame of a curve lying on a surface (thesis §3.2.1, eqs. 3.1-3.5): the tangent
//! `t`, the surface normal `n`, the tangent normal `g = t × n`, and the curve's curvature split
//! into its normal and geodesic parts.
//!
//! # Math
//! For a curve `ρ(u)` with velocity `ρ'` and acceleration `ρ''` (any regular parameter `u`), the
//! unit tangent is `t = ρ'/|ρ'|` and the curvature vector is `κN = (ρ'' - (ρ''·t) t) / |ρ'|²`
//! (eqs. 3.1-3.2 without assuming unit speed). With `n` the **outward** unit surface normal
//! (pointing from the ground into the air) and `g = t × n` (eq. 3.3):
//!
//! * `κ_n = κN · n`, `κ_g = κN · g` (eq. 3.4);
//! * `κ_n = κ cos φ`, `κ_g = -κ sin φ` (eq. 3.5), so `φ = atan2(-κ_g, κ_n)` is the angle from the
//!   curve normal `N` to the surface normal `n` about `t`.
//!
//! Sign convention (used throughout the crate): a rope over a convex hump bends toward the ground,
//! so there `κ_n < 0` and `φ ≈ π` (the thesis' Fig. 3.3 apex); the contact force per unit length
//! of a weightless rope is `F_n = -κ_n T` (eq. 3.25).

use nalgebra::{Unit, Vector3};
use thiserror::Error;

/// Below this speed `|ρ'|` the parametrisation is considered singular (no tangent).
pub const MIN_SPEED: f64 = 1e-12;
/// Below this curvature (1/m) a curve is treated as straight: `N` and `φ` are undefined.
pub const STRAIGHT_CURVATURE: f64 = 1e-9;
/// The surface normal must keep at least this sine of angle with the tangent to define `g`.
pub const MIN_NORMAL_TANGENT_SINE: f64 = 1e-6;

/// Why a Darboux frame could not be formed.
#[derive(Debug, Error, Clone, Copy, PartialEq)]
pub enum DarbouxError {
    /// An input vector has a NaN or infinite component.
    #[error("non-finite curve derivative or surface normal")]
    NonFinite,
    /// The curve's velocity vanishes: reparametrise the curve so that it is regular.
    #[error("the curve velocity is (nearly) zero: the parametrisation is singular")]
    SingularParametrisation,
    /// The surface normal is zero or (nearly) parallel to the tangent: the curve does not lie on
    /// the surface; pass the normal of the surface at the curve point.
    #[error("the surface normal is zero or parallel to the curve tangent")]
    BadNormal,
}

/// The Darboux frame and curvatures of a curve on a surface at one point (thesis eqs. 3.3-3.5).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DarbouxFrame {
    /// Unit tangent `t`.
    pub tangent: Unit<Vector3<f64>>,
    /// Outward unit surface normal `n`, made orthogonal to `t`.
    pub normal: Unit<Vector3<f64>>,
    /// Tangent normal (geodesic direction) `g = t × n`.
    pub tangent_normal: Unit<Vector3<f64>>,
    /// Curvature `κ >= 0` (eq. 3.2).
    pub curvature: f64,
    /// Normal curvature `κ_n` (eq. 3.4); negative where the curve bends toward the ground.
    pub normal_curvature: f64,
    /// Geodesic curvature `κ_g` (eq. 3.4); zero on a geodesic.
    pub geodesic_curvature: f64,
}

impl DarbouxFrame {
    /// The frame of a curve with velocity `velocity` and acceleration `acceleration` (with respect
    /// to any regular parameter) on a surface whose outward normal there is `surface_normal`
    /// (any length; it is normalised and projected orthogonal to the tangent).
    ///
    /// # Example
    /// ```
    /// use nalgebra::Vector3;
    /// use rappel_mechanics::darboux::DarbouxFrame;
    /// // The equator of a unit sphere, at (1, 0, 0): a geodesic bending into the sphere.
    /// let f = DarbouxFrame::new(&Vector3::y(), &-Vector3::x(), &Vector3::x()).unwrap();
    /// assert!((f.normal_curvature + 1.0).abs() < 1e-12 && f.geodesic_curvature.abs() < 1e-12);
    /// assert!((f.phi().unwrap() - std::f64::consts::PI).abs() < 1e-12);
    /// ```
    pub fn new(
        velocity: &Vector3<f64>,
        acceleration: &Vector3<f64>,
        surface_normal: &Vector3<f64>,
    ) -> Result<Self, DarbouxError> {
        let finite = |v: &Vector3<f64>| v.iter().all(|c| c.is_finite());
        if !(finite(velocity) && finite(acceleration) && finite(surface_normal)) {
            return Err(DarbouxError::NonFinite);
        }
        let speed = velocity.norm();
        if speed < MIN_SPEED {
            return Err(DarbouxError::SingularParametrisation);
        }
        let t = velocity / speed;
        let n_len = surface_normal.norm();
        if n_len == 0.0 {
            return Err(DarbouxError::BadNormal);
        }
        let n_raw = surface_normal / n_len;
        let n_perp = n_raw - t * n_raw.dot(&t);
        if n_perp.norm() < MIN_NORMAL_TANGENT_SINE {
            return Err(DarbouxError::BadNormal);
        }
        let n = Unit::new_normalize(n_perp);
        let g = Unit::new_normalize(t.cross(&n));
        let kappa_vec = (acceleration - t * acceleration.dot(&t)) / (speed * speed);
        Ok(DarbouxFrame {
            tangent: Unit::new_unchecked(t),
            normal: n,
            tangent_normal: g,
            curvature: kappa_vec.norm(),
            normal_curvature: kappa_vec.dot(&n),
            geodesic_curvature: kappa_vec.dot(&g),
        })
    }

    /// The angle `φ ∈ (-π, π]` from the curve normal `N` to the surface normal `n` (eq. 3.5), or
    /// `None` where the curve is straight (`κ` below [`STRAIGHT_CURVATURE`]).
    pub fn phi(&self) -> Option<f64> {
        (self.curvature >= STRAIGHT_CURVATURE).then(|| {
            let phi = (-self.geodesic_curvature).atan2(self.normal_curvature);
            // atan2(-0, x < 0) is -π; keep the half-open range (-π, π].
            if phi <= -std::f64::consts::PI {
                std::f64::consts::PI
            } else {
                phi
            }
        })
    }

    /// The Frenet-Serret normal `N` (eq. 3.1), or `None` on a straight curve.
    pub fn curve_normal(&self) -> Option<Unit<Vector3<f64>>> {
        (self.curvature >= STRAIGHT_CURVATURE).then(|| {
            Unit::new_normalize(
                self.normal.into_inner() * self.normal_curvature
                    + self.tangent_normal.into_inner() * self.geodesic_curvature,
            )
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn circle_of_latitude_on_sphere_has_known_curvatures() {
        // Unit sphere, latitude β: radius cos β; κ = 1/cos β, κ_n = -1, κ_g = ±tan β.
        let beta: f64 = 0.4;
        let (r, z) = (beta.cos(), beta.sin());
        let u: f64 = 1.1; // parameter = longitude
        let p = Vector3::new(r * u.cos(), r * u.sin(), z);
        let v = Vector3::new(-r * u.sin(), r * u.cos(), 0.0) * 3.0; // non-unit speed
        let a = Vector3::new(-r * u.cos(), -r * u.sin(), 0.0) * 9.0;
        let f = DarbouxFrame::new(&v, &a, &p).unwrap();
        assert!((f.curvature - 1.0 / r).abs() < 1e-12);
        assert!((f.normal_curvature + 1.0).abs() < 1e-12);
        assert!((f.geodesic_curvature.abs() - beta.tan()).abs() < 1e-12);
        let phi = f.phi().unwrap();
        assert!((f.curvature * phi.cos() - f.normal_curvature).abs() < 1e-12);
        assert!((-f.curvature * phi.sin() - f.geodesic_curvature).abs() < 1e-12);
        let nn = f.curve_normal().unwrap();
        assert!((nn.into_inner() - (-Vector3::new(u.cos(), u.sin(), 0.0))).norm() < 1e-12);
    }

    #[test]
    fn straight_line_has_no_phi_and_bad_inputs_are_errors() {
        let f = DarbouxFrame::new(&Vector3::x(), &Vector3::zeros(), &Vector3::z()).unwrap();
        assert_eq!(f.phi(), None);
        assert_eq!(f.curvature, 0.0);
        assert_eq!(
            DarbouxFrame::new(&Vector3::zeros(), &Vector3::x(), &Vector3::z()),
            Err(DarbouxError::SingularParametrisation)
        );
        assert_eq!(
            DarbouxFrame::new(&Vector3::x(), &Vector3::zeros(), &Vector3::x()),
            Err(DarbouxError::BadNormal)
        );
        assert_eq!(
            DarbouxFrame::new(
                &Vector3::x(),
                &Vector3::new(f64::NAN, 0.0, 0.0),
                &Vector3::z()
            ),
            Err(DarbouxError::NonFinite)
        );
        // A rope bending over a hump (toward the ground) has φ = π.
        let f = DarbouxFrame::new(&Vector3::x(), &-Vector3::z(), &Vector3::z()).unwrap();
        assert!((f.phi().unwrap() - PI).abs() < 1e-12);
    }
}
