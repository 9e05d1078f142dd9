//! Tether curves lying on surfaces, parametrised by arc length `s ∈ [0, length]`: the seam through
//! which rope statics ([`crate::heavy_rope`], [`crate::sticking`]) read the Darboux frame, with the
//! closed-form curves of the thesis' test cases (§3.3.4): a capstan arc, a helix on a cylinder and
//! a straight line on a plane.

use crate::darboux::{DarbouxError, DarbouxFrame};
use nalgebra::{Point3, Unit, Vector3};
use std::f64::consts::TAU;
use thiserror::Error;

/// Why a curve could not be built.
#[derive(Debug, Error, Clone, Copy, PartialEq)]
pub enum CurveError {
    /// A length, radius or pitch is not finite and positive (pitch may be zero for a circle).
    #[error("curve parameter `{0}` must be finite and positive")]
    Parameter(&'static str),
    /// The direction is not orthogonal to the plane normal, or a vector is zero.
    #[error("the line direction must be non-zero and tangent to the plane")]
    Direction,
}

/// Velocity, acceleration and outward surface normal of a curve at one arc length.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurveJet {
    /// `dρ/ds`.
    pub velocity: Vector3<f64>,
    /// `d²ρ/ds²`.
    pub acceleration: Vector3<f64>,
    /// Outward normal of the surface the curve lies on.
    pub surface_normal: Vector3<f64>,
}

/// A curve on a surface, parametrised by arc length from 0 to [`SurfaceCurve::length`].
pub trait SurfaceCurve {
    /// Total arc length (m).
    fn length(&self) -> f64;
    /// The point at arc length `s`.
    fn point(&self, s: f64) -> Point3<f64>;
    /// Derivatives and surface normal at arc length `s`.
    fn jet(&self, s: f64) -> CurveJet;
    /// The Darboux frame at arc length `s` (thesis eqs. 3.3-3.5).
    fn frame(&self, s: f64) -> Result<DarbouxFrame, DarbouxError> {
        let j = self.jet(s);
        DarbouxFrame::new(&j.velocity, &j.acceleration, &j.surface_normal)
    }
}

fn positive(v: f64, name: &'static str) -> Result<f64, CurveError> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(CurveError::Parameter(name))
    }
}

/// A helix of radius `radius` and pitch `pitch` (rise per full turn) around the `z` axis on the
/// cylinder `x² + y² = radius²`, starting at `(radius, 0, 0)`; a pitch of zero gives a circle (the
/// capstan of thesis Fig. 3.4). It is a geodesic: `κ_g = 0`, `κ_n = -R/(R² + c²)`, `c = pitch/2π`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Helix {
    radius: f64,
    c: f64,
    length: f64,
}

impl Helix {
    /// A helix making the turning angle `angle` (radians around the axis).
    ///
    /// # Example
    /// ```
    /// use rappel_mechanics::surface_curve::{Helix, SurfaceCurve};
    /// let capstan = Helix::new(0.5, 0.0, std::f64::consts::FRAC_PI_2).unwrap();
    /// let f = capstan.frame(0.3).unwrap();
    /// assert!((f.normal_curvature + 2.0).abs() < 1e-12);
    /// ```
    pub fn new(radius: f64, pitch: f64, angle: f64) -> Result<Self, CurveError> {
        positive(radius, "radius")?;
        positive(angle, "angle")?;
        if !(pitch.is_finite() && pitch >= 0.0) {
            return Err(CurveError::Parameter("pitch"));
        }
        let c = pitch / TAU;
        Ok(Helix {
            radius,
            c,
            length: angle * radius.hypot(c),
        })
    }

    fn speed_factor(&self) -> f64 {
        1.0 / self.radius.hypot(self.c)
    }
}

impl SurfaceCurve for Helix {
    fn length(&self) -> f64 {
        self.length
    }
    fn point(&self, s: f64) -> Point3<f64> {
        let th = s * self.speed_factor();
        Point3::new(self.radius * th.cos(), self.radius * th.sin(), self.c * th)
    }
    fn jet(&self, s: f64) -> CurveJet {
        let k = self.speed_factor();
        let th = s * k;
        let (sn, cs) = th.sin_cos();
        CurveJet {
            velocity: Vector3::new(-self.radius * sn, self.radius * cs, self.c) * k,
            acceleration: Vector3::new(-self.radius * cs, -self.radius * sn, 0.0) * (k * k),
            surface_normal: Vector3::new(cs, sn, 0.0),
        }
    }
}

/// A straight segment on a plane (thesis Figs. 3.6-3.8): `κ_n = κ_g = 0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlaneLine {
    start: Point3<f64>,
    direction: Unit<Vector3<f64>>,
    normal: Unit<Vector3<f64>>,
    length: f64,
}

/// Largest allowed `|direction · normal|` for a line to count as lying in its plane.
pub const TANGENCY_TOLERANCE: f64 = 1e-9;

impl PlaneLine {
    /// The segment from `start` along `direction` (tangent to the plane with outward normal
    /// `normal`) of length `length`.
    pub fn new(
        start: Point3<f64>,
        direction: Vector3<f64>,
        normal: Vector3<f64>,
        length: f64,
    ) -> Result<Self, CurveError> {
        positive(length, "length")?;
        let (Some(d), Some(n)) = (Unit::try_new(direction, 0.0), Unit::try_new(normal, 0.0)) else {
            return Err(CurveError::Direction);
        };
        if d.dot(&n).abs() > TANGENCY_TOLERANCE || !start.iter().all(|c| c.is_finite()) {
            return Err(CurveError::Direction);
        }
        Ok(PlaneLine {
            start,
            direction: d,
            normal: n,
            length,
        })
    }

    /// The unit direction of the line.
    pub fn direction(&self) -> Unit<Vector3<f64>> {
        self.direction
    }

    /// The plane's outward unit normal.
    pub fn normal(&self) -> Unit<Vector3<f64>> {
        self.normal
    }
}

impl SurfaceCurve for PlaneLine {
    fn length(&self) -> f64 {
        self.length
    }
    fn point(&self, s: f64) -> Point3<f64> {
        self.start + self.direction.into_inner() * s
    }
    fn jet(&self, _s: f64) -> CurveJet {
        CurveJet {
            velocity: self.direction.into_inner(),
            acceleration: Vector3::zeros(),
            surface_normal: self.normal.into_inner(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn helix_is_unit_speed_geodesic_with_known_normal_curvature() {
        let h = Helix::new(1.0, 1.0, 2.0).unwrap();
        let c = 1.0 / TAU;
        for i in 0..5 {
            let s = h.length() * i as f64 / 4.0;
            let j = h.jet(s);
            assert!((j.velocity.norm() - 1.0).abs() < 1e-12);
            let f = h.frame(s).unwrap();
            assert!(f.geodesic_curvature.abs() < 1e-12);
            assert!((f.normal_curvature + 1.0 / (1.0 + c * c)).abs() < 1e-12);
            // The point lies on the cylinder.
            let p = h.point(s);
            assert!((p.x.hypot(p.y) - 1.0).abs() < 1e-12);
        }
        assert!(Helix::new(-1.0, 1.0, 1.0).is_err());
    }

    #[test]
    fn plane_line_validates_tangency() {
        assert!(PlaneLine::new(Point3::origin(), Vector3::x(), Vector3::z(), 1.0).is_ok());
        assert_eq!(
            PlaneLine::new(Point3::origin(), Vector3::z(), Vector3::z(), 1.0),
            Err(CurveError::Direction)
        );
        assert_eq!(
            PlaneLine::new(Point3::origin(), Vector3::x(), Vector3::z(), 0.0),
            Err(CurveError::Parameter("length"))
        );
    }
}
