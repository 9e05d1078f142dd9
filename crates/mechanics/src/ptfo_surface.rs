//! The surface a potential tether friction obstacle (PTFO) stands for, and the tether's contact
//! with it where a taut tether wraps it in the planning frame (thesis §3.3.5, §3.4, Alg. 9 line 2:
//! "find tether configuration at point f").
//!
//! # The wrap model
//! In the planning frame (the unfolded slope, `z` along its outward normal) a taut tether turns by
//! its turning angle `θ` at an anchor on the PTFO's outline. On the ground it does so by wrapping
//! the PTFO's flank along the **level curve** (contour) of the surface through the anchor: the
//! tether stays in the plane of its straight segments, and where it touches the surface its
//! horizontal normal is the contour's normal, i.e. the uphill direction `∇h/|∇h|`. Along such a
//! wrap the tangent `t` is horizontal, the curvature vector is `κ_h N` (`N` the uphill unit
//! vector, `κ_h` the contour's curvature) and the outward surface normal is
//! `n = (-∇h, 1)/W`, `W = sqrt(1 + |∇h|²)`. The Darboux frame ([`crate::darboux`]) then gives
//!
//! * `κ_n = -κ_h |∇h| / W` (equal to Euler's `tᵀ H t / W`: the contour is convex toward the hump
//!   exactly when the surface is convex along `t`, so condition 1 is the saddle test of
//!   [`crate::curvature::ConvexDirections`]);
//! * `|κ_g| = κ_h / W`, so `tan φ = 1/|∇h|` (the steeper the flank, the better it holds);
//! * `∫ω ds = θ sqrt(μ² |∇h|² - 1) / W` over the wrap, with `ds = θ/κ_h`: the radius drops out,
//!   as in the capstan (thesis §3.2.5). A vertical wall (`|∇h| → ∞`, the [`PtfoSurface::Cylinder`])
//!   gives the capstan `μθ`; a sphere of radius `R` wrapped at plan radius `r` gives
//!   `θ sqrt(μ² r² - (R² - r²))/R`, sticking iff `sqrt(R² - r²)/r < μ`.
//!
//! The surface quantities are taken at the anchor and held along the wrap: exact where they are
//! constant along the contour (cylinder, sphere; any surface of revolution about a vertical axis),
//! a first-order model elsewhere (ridges, saddles, height-field patches), documented in
//! `docs/friction.md`. Because the integrand is a constant, `∫ω ds` is **linear in the wrap angle**:
//! the monotonicity Alg. 10 relies on.
//!
//! Where the tether cannot wrap the surface the contact is [`WrapError::NoContact`]: the anchor is
//! off the PTFO's footprint, at its apex (no contour), on a straight contour, or the tether bends
//! away from the hump. Such an anchor cannot hold the tether (it slides over, thesis §3.4.1 rule 2).

use crate::darboux::{DarbouxFrame, STRAIGHT_CURVATURE};
use crate::sticking::TetherSample;
use nalgebra::{Matrix2, Point2, Vector2, Vector3};
use thiserror::Error;

/// Relative tolerance of the cylinder's footprint test: an anchor counts as on the pillar when its
/// distance from the axis is at most `radius (1 + FOOTPRINT_TOLERANCE)`, so that a polygon vertex
/// placed on the pillar's circle (an inscribed polygon) is on it despite round-off.
pub const FOOTPRINT_TOLERANCE: f64 = 1e-9;

/// Gradients below this magnitude (dimensionless slope) count as a horizontal tangent plane,
/// where the level curve and thus the wrap are undefined (an apex or a saddle point).
pub const MIN_CONTOUR_SLOPE: f64 = 1e-9;

/// Why the tether's contact with a PTFO surface could not be built.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum WrapError {
    /// A parameter of the surface is unusable.
    #[error("PTFO surface: {0}")]
    Surface(String),
    /// The turning angle is not in `(0, π)` or a direction is zero or not finite.
    #[error("tether wrap: turning angle {} must be in (0, pi) with finite, non-zero directions", rappel_geometry::compact::Compact(*.0))]
    Turn(f64),
    /// The tether does not wrap the surface here (see the module docs); it cannot hold.
    #[error("no contact: {0}")]
    NoContact(&'static str),
}

/// The gradient and Hessian of a height field at a point.
pub type HeightJet = (Vector2<f64>, Matrix2<f64>);

/// A regular grid of heights (m) above the planning plane: `heights[row * cols + col]` at
/// `origin + (col, row) * spacing`.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HeightPatch {
    /// Plan position of node `(0, 0)`.
    pub origin: Point2<f64>,
    /// Node spacing (m, > 0).
    pub spacing: f64,
    /// Number of columns (>= 3).
    pub cols: usize,
    /// Heights, row-major, `rows * cols` of them (rows >= 3).
    pub heights: Vec<f64>,
}

/// The surface a PTFO stands for, in planning-frame coordinates (heights along the plane normal).
/// It is also the scenario schema of a PTFO's `surface` (`docs/scenario-format.md`).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub enum PtfoSurface {
    /// An upright boulder or pillar of radius `radius` about `center`: a vertical wall, the
    /// capstan of thesis Fig. 3.4.
    Cylinder {
        /// Axis position.
        center: Point2<f64>,
        /// Radius (m, > 0).
        radius: f64,
    },
    /// A spherical cap `h = sqrt(R² - |p - c|²)`.
    Sphere {
        /// Centre (plan).
        center: Point2<f64>,
        /// Radius (m, > 0).
        radius: f64,
    },
    /// An elongated hump `h = -(u²/R_along + v²/R_across)/2` (`u` along the crest at
    /// `axis_deg` from the x axis): principal curvatures `-1/R_along`, `-1/R_across` at the crest.
    Ridge {
        /// Crest point.
        center: Point2<f64>,
        /// Crest direction, degrees from the x axis.
        axis_deg: f64,
        /// Radius of curvature along the crest (m, > 0).
        along_radius: f64,
        /// Radius of curvature across the crest (m, > 0).
        across_radius: f64,
    },
    /// A saddle `h = (-k_c u² + k_v v²)/2`: convex along `u` (at `axis_deg`), concave across.
    Saddle {
        /// Saddle point.
        center: Point2<f64>,
        /// The convex principal direction, degrees from the x axis.
        axis_deg: f64,
        /// `k_c > 0` (1/m).
        convex_curvature: f64,
        /// `k_v > 0` (1/m).
        concave_curvature: f64,
    },
    /// A height-field patch (e.g. cut from a DEM); derivatives by central differences at the node
    /// nearest the anchor.
    HeightField(HeightPatch),
}

fn positive(v: f64, what: &str) -> Result<f64, WrapError> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(WrapError::Surface(format!(
            "{what} {v} must be finite and positive"
        )))
    }
}

fn finite_point(p: &Point2<f64>, what: &str) -> Result<(), WrapError> {
    if p.x.is_finite() && p.y.is_finite() {
        Ok(())
    } else {
        Err(WrapError::Surface(format!("{what} is not finite")))
    }
}

/// Checks the centre and axis of an oriented surface (ridge, saddle): both finite.
fn axis_frame(center: &Point2<f64>, axis_deg: f64) -> Result<(), WrapError> {
    finite_point(center, "centre")?;
    if axis_deg.is_finite() {
        Ok(())
    } else {
        Err(WrapError::Surface("axis_deg is not finite".into()))
    }
}

/// `(∇h, H)` of `h = ½ dᵀ A d` with `A = Rot diag(a_u, a_v) Rotᵀ`, `d = p - c`.
fn quadric(center: &Point2<f64>, axis_deg: f64, a_u: f64, a_v: f64, p: &Point2<f64>) -> HeightJet {
    let (s, c) = axis_deg.to_radians().sin_cos();
    let rot = Matrix2::new(c, -s, s, c);
    let a = rot * Matrix2::new(a_u, 0.0, 0.0, a_v) * rot.transpose();
    (a * (p - center), a)
}

impl PtfoSurface {
    /// Checks the parameters (finite, positive radii and curvatures, a well-formed patch).
    pub fn validate(&self) -> Result<(), WrapError> {
        match self {
            PtfoSurface::Cylinder { center, radius } | PtfoSurface::Sphere { center, radius } => {
                finite_point(center, "centre")?;
                positive(*radius, "radius")?;
            }
            PtfoSurface::Ridge {
                center,
                axis_deg,
                along_radius,
                across_radius,
            } => {
                axis_frame(center, *axis_deg)?;
                positive(*along_radius, "along_radius")?;
                positive(*across_radius, "across_radius")?;
            }
            PtfoSurface::Saddle {
                center,
                axis_deg,
                convex_curvature,
                concave_curvature,
            } => {
                axis_frame(center, *axis_deg)?;
                positive(*convex_curvature, "convex_curvature")?;
                positive(*concave_curvature, "concave_curvature")?;
            }
            PtfoSurface::HeightField(g) => {
                finite_point(&g.origin, "origin")?;
                positive(g.spacing, "spacing")?;
                if g.cols < 3 || g.heights.len() % g.cols != 0 || g.heights.len() / g.cols < 3 {
                    return Err(WrapError::Surface(format!(
                        "height patch needs at least 3 x 3 nodes and rows * cols heights \
                         (cols {}, {} heights)",
                        g.cols,
                        g.heights.len()
                    )));
                }
                if let Some(i) = g.heights.iter().position(|h| !h.is_finite()) {
                    return Err(WrapError::Surface(format!("height {i} is not finite")));
                }
            }
        }
        Ok(())
    }

    /// Gradient and Hessian of the height at `p`, for the height-field surfaces (`None` for the
    /// vertical cylinder). Errors when `p` is off the surface's footprint.
    pub fn height_jet(&self, p: &Point2<f64>) -> Result<Option<HeightJet>, WrapError> {
        Ok(match self {
            PtfoSurface::Cylinder { .. } => None,
            PtfoSurface::Sphere { center, radius } => {
                let d = p - center;
                let h2 = radius * radius - d.norm_squared();
                if h2 <= 0.0 {
                    return Err(WrapError::NoContact(
                        "anchor outside the sphere's footprint",
                    ));
                }
                let h = h2.sqrt();
                let hess = -Matrix2::identity() / h - d * d.transpose() / (h * h2);
                Some((-d / h, hess))
            }
            PtfoSurface::Ridge {
                center,
                axis_deg,
                along_radius,
                across_radius,
            } => Some(quadric(
                center,
                *axis_deg,
                -1.0 / along_radius,
                -1.0 / across_radius,
                p,
            )),
            PtfoSurface::Saddle {
                center,
                axis_deg,
                convex_curvature,
                concave_curvature,
            } => Some(quadric(
                center,
                *axis_deg,
                -convex_curvature,
                *concave_curvature,
                p,
            )),
            PtfoSurface::HeightField(g) => {
                let rows = g.heights.len() / g.cols;
                let fx = (p.x - g.origin.x) / g.spacing;
                let fy = (p.y - g.origin.y) / g.spacing;
                let (c, r) = (fx.round(), fy.round());
                if !(c >= 1.0 && r >= 1.0 && c <= (g.cols - 2) as f64 && r <= (rows - 2) as f64) {
                    return Err(WrapError::NoContact(
                        "anchor outside the height patch's interior",
                    ));
                }
                let (c, r) = (c as usize, r as usize);
                let h = |dc: isize, dr: isize| {
                    g.heights[(r as isize + dr) as usize * g.cols + (c as isize + dc) as usize]
                };
                let s = g.spacing;
                let hx = (h(1, 0) - h(-1, 0)) / (2.0 * s);
                let hy = (h(0, 1) - h(0, -1)) / (2.0 * s);
                let hxx = (h(1, 0) - 2.0 * h(0, 0) + h(-1, 0)) / (s * s);
                let hyy = (h(0, 1) - 2.0 * h(0, 0) + h(0, -1)) / (s * s);
                let hxy = (h(1, 1) - h(1, -1) - h(-1, 1) + h(-1, -1)) / (4.0 * s * s);
                Some((Vector2::new(hx, hy), Matrix2::new(hxx, hxy, hxy, hyy)))
            }
        })
    }

    /// The tether's contact when it turns by `turning_angle` at `anchor`, arriving along
    /// `incoming` and leaving along `outgoing` (plan directions, any length): one
    /// [`TetherSample`] standing for the whole wrap (module docs), ready for
    /// [`crate::sticking::tether_slips`] and [`crate::ptfo::classify`].
    ///
    /// # Example
    /// ```
    /// use nalgebra::{Point2, Vector2};
    /// use rappel_mechanics::ptfo_surface::PtfoSurface;
    /// use rappel_mechanics::sticking::omega_integral;
    /// // A quarter turn around a 2 m pillar: the capstan exponent μθ.
    /// let pillar = PtfoSurface::Cylinder { center: Point2::new(0.0, 0.0), radius: 2.0 };
    /// let s = pillar
    ///     .wrap(&Point2::new(2.0, 0.0), &Vector2::new(0.0, -1.0), &Vector2::new(-1.0, 0.0))
    ///     .unwrap();
    /// let i = omega_integral(&s, 0.4).unwrap();
    /// assert!((i - 0.4 * std::f64::consts::FRAC_PI_2).abs() < 1e-12);
    /// ```
    pub fn wrap(
        &self,
        anchor: &Point2<f64>,
        incoming: &Vector2<f64>,
        outgoing: &Vector2<f64>,
    ) -> Result<Vec<TetherSample>, WrapError> {
        self.validate()?;
        finite_point(anchor, "anchor")?;
        let ok = |v: &Vector2<f64>| v.iter().all(|c| c.is_finite()) && v.norm() > 0.0;
        if !(ok(incoming) && ok(outgoing)) {
            return Err(WrapError::Turn(f64::NAN));
        }
        let (u, w) = (incoming.normalize(), outgoing.normalize());
        let cross = u.x * w.y - u.y * w.x;
        let theta = cross.abs().atan2(u.dot(&w));
        if !(theta > 0.0 && theta < std::f64::consts::PI) {
            return Err(WrapError::Turn(theta));
        }
        // The tether bends toward its inner side: the bisector of the turn, `w - u`.
        let inward = (w - u).normalize();
        let (kappa_h, uphill, grad) = match self.height_jet(anchor)? {
            None => {
                let PtfoSurface::Cylinder { center, radius } = self else {
                    unreachable!("only the cylinder has no height jet");
                };
                let to_axis = center - anchor;
                // The anchor must lie on the pillar's footprint: a vertex farther from the axis
                // than the radius is a corner of the map's outline in the air beside the pillar,
                // not a point the tether can press on (as for the sphere's footprint).
                if to_axis.norm() > radius * (1.0 + FOOTPRINT_TOLERANCE) {
                    return Err(WrapError::NoContact(
                        "anchor off the pillar's footprint (farther from its axis than its radius)",
                    ));
                }
                if inward.dot(&to_axis) <= 0.0 {
                    return Err(WrapError::NoContact(
                        "the tether bends away from the pillar",
                    ));
                }
                (1.0 / radius, to_axis.normalize(), None)
            }
            Some((g, hess)) => {
                let slope = g.norm();
                if slope < MIN_CONTOUR_SLOPE {
                    return Err(WrapError::NoContact(
                        "horizontal tangent plane (apex or saddle point): no contour to wrap",
                    ));
                }
                let n_up = g / slope;
                if inward.dot(&n_up) <= 0.0 {
                    return Err(WrapError::NoContact(
                        "the tether bends away from the hump (downhill)",
                    ));
                }
                let t = Vector2::new(-n_up.y, n_up.x);
                // Contour curvature toward uphill: -tᵀHt/|∇h| (> 0 where the flank is convex).
                let kappa_h = -(t.transpose() * hess * t)[(0, 0)] / slope;
                if kappa_h.abs() < STRAIGHT_CURVATURE {
                    return Err(WrapError::NoContact("the contour is straight here"));
                }
                (kappa_h, n_up, Some(g))
            }
        };
        let t2 = Vector2::new(-uphill.y, uphill.x);
        let velocity = Vector3::new(t2.x, t2.y, 0.0);
        let acceleration = Vector3::new(uphill.x, uphill.y, 0.0) * kappa_h;
        let normal = match grad {
            // The pillar's wall faces away from its axis.
            None => Vector3::new(-uphill.x, -uphill.y, 0.0),
            Some(g) => Vector3::new(-g.x, -g.y, 1.0),
        };
        let frame = DarbouxFrame::new(&velocity, &acceleration, &normal)
            .map_err(|e| WrapError::Surface(format!("Darboux frame: {e}")))?;
        Ok(vec![TetherSample::from_frame(
            &frame,
            theta / kappa_h.abs(),
        )])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sticking::{omega_integral, tether_slips};
    use std::f64::consts::FRAC_PI_2;

    fn quarter() -> (Vector2<f64>, Vector2<f64>) {
        // Arriving downward, leaving to the left: a turn of π/2 whose inner side is (-1, 1).
        (Vector2::new(0.0, -1.0), Vector2::new(-1.0, 0.0))
    }

    #[test]
    fn sphere_matches_the_small_circle_closed_form() {
        let (u, w) = quarter();
        let sphere = PtfoSurface::Sphere {
            center: Point2::new(0.0, 0.0),
            radius: 5.0,
        };
        // Anchor on the diagonal at plan radius r, the hump on the inner side.
        for r in [3.0f64, 4.0, 4.9] {
            let a = Point2::new(1.0, -1.0) * (r / 2f64.sqrt());
            let s = sphere.wrap(&a, &u, &w).unwrap();
            let mu = 0.8;
            let h = (25.0 - r * r).sqrt();
            let expected = FRAC_PI_2 * (mu * mu * r * r - h * h).max(0.0).sqrt() / 5.0;
            let i = omega_integral(&s, mu).unwrap();
            assert!((i - expected).abs() < 1e-9, "r {r}: {i} vs {expected}");
            // Condition 2 ⇔ tan e = h/r < μ.
            let cone = !tether_slips(&s, mu, 1.0, 1.0).unwrap();
            assert_eq!(cone, h / r < mu, "r {r}");
        }
    }

    #[test]
    fn saddle_contact_follows_its_convex_directions() {
        let (u, w) = quarter();
        let saddle = PtfoSurface::Saddle {
            center: Point2::new(0.0, 0.0),
            axis_deg: 0.0,
            convex_curvature: 1.0,
            concave_curvature: 1.0,
        };
        // The turn's inner side is (-1, 1); the gradient (-x, y) points there for x, y > 0.
        for (x, y) in [(1.0, 0.2), (0.2, 1.0), (1.0, 0.9), (0.9, 1.0), (0.5, 0.3)] {
            let a = Point2::new(x, y);
            let s = saddle.wrap(&a, &u, &w).unwrap();
            // Independent check: the contour tangent ⊥ (−x, y) lies in the saddle's convex
            // directions (curvature.rs, Euler's formula) exactly when the wrap presses (κ_n < 0).
            let k = crate::curvature::PrincipalCurvatures::from_height_derivatives(
                -x, y, -1.0, 0.0, 1.0,
            )
            .unwrap();
            let range = k.convex_directions(1e-9).unwrap().unwrap();
            let tangent = Vector3::new(y, x, -x * y + y * x); // ⊥ to the gradient, horizontal
            assert_eq!(
                range.contains(&tangent),
                s[0].normal_curvature < 0.0,
                "at ({x}, {y})"
            );
        }
    }

    #[test]
    fn wrap_normal_curvature_is_eulers_along_the_contour() {
        // Independent check of κ_n = tᵀHt/W: curvature.rs's principal curvatures (from the same
        // derivatives) evaluated along the contour tangent, on a ridge, a saddle and a patch.
        let ridge = PtfoSurface::Ridge {
            center: Point2::new(1.0, -2.0),
            axis_deg: 30.0,
            along_radius: 20.0,
            across_radius: 3.0,
        };
        let saddle = PtfoSurface::Saddle {
            center: Point2::new(0.0, 0.0),
            axis_deg: -40.0,
            convex_curvature: 0.7,
            concave_curvature: 0.3,
        };
        let patch = PtfoSurface::HeightField(HeightPatch {
            origin: Point2::new(-5.0, -5.0),
            spacing: 0.5,
            cols: 21,
            heights: (0..21 * 21)
                .map(|k| {
                    let (x, y) = ((k % 21) as f64 * 0.5 - 5.0, (k / 21) as f64 * 0.5 - 5.0);
                    3.0 - 0.1 * x * x - 0.05 * y * y + 0.02 * x * y
                })
                .collect(),
        });
        let mut checked = 0;
        for surface in [&ridge, &saddle, &patch] {
            for i in 0..9 {
                for j in 0..9 {
                    let p = Point2::new(-4.0 + i as f64, -4.0 + j as f64);
                    let Ok(Some((g, h))) = surface.height_jet(&p) else {
                        continue;
                    };
                    if g.norm() < 1e-6 {
                        continue;
                    }
                    let (u, w) = {
                        let n = g.normalize();
                        let t = Vector2::new(-n.y, n.x);
                        (0.9 * t - 0.3 * n, 0.9 * t + 0.3 * n)
                    };
                    let Ok(s) = surface.wrap(&p, &u, &w) else {
                        continue;
                    };
                    let k = crate::curvature::PrincipalCurvatures::from_height_derivatives(
                        g.x,
                        g.y,
                        h[(0, 0)],
                        h[(0, 1)],
                        h[(1, 1)],
                    )
                    .unwrap();
                    let t3 = Vector3::new(-g.y, g.x, 0.0);
                    let euler = k.normal_curvature(&t3).unwrap();
                    assert!(
                        (s[0].normal_curvature - euler).abs() < 1e-9 * (1.0 + euler.abs()),
                        "{surface:?} at {p:?}: {} vs {euler}",
                        s[0].normal_curvature
                    );
                    checked += 1;
                }
            }
        }
        assert!(checked > 60, "only {checked} points checked");
    }

    #[test]
    fn bad_surfaces_and_turns_are_errors() {
        let (u, w) = quarter();
        let bad = PtfoSurface::Cylinder {
            center: Point2::new(0.0, 0.0),
            radius: -1.0,
        };
        assert!(matches!(
            bad.wrap(&Point2::new(1.0, 1.0), &u, &w),
            Err(WrapError::Surface(_))
        ));
        let pillar = PtfoSurface::Cylinder {
            center: Point2::new(0.0, 0.0),
            radius: 1.0,
        };
        assert!(matches!(
            pillar.wrap(&Point2::new(1.0, 1.0), &u, &u),
            Err(WrapError::Turn(_))
        ));
        // The pillar on the outer side of the turn: no contact.
        let h = std::f64::consts::FRAC_1_SQRT_2;
        assert!(matches!(
            pillar.wrap(&Point2::new(-h, -h), &u, &w),
            Err(WrapError::NoContact(why)) if why.contains("bends away")
        ));
    }

    #[test]
    fn a_pillar_anchor_must_lie_on_its_footprint() {
        // Issue 33: an anchor 7.07 m from the axis of a 5 m pillar (the corner of a square drawn
        // round it) cannot press on the pillar; on the circle, or inside it, it can.
        let (u, w) = quarter();
        let pillar = PtfoSurface::Cylinder {
            center: Point2::new(20.0, 50.0),
            radius: 5.0,
        };
        let h = std::f64::consts::FRAC_1_SQRT_2;
        // The turn's inner side is (-1, 1): the axis lies that way from the anchor.
        let inward_corner = |d: f64| Point2::new(20.0 + d * h, 50.0 - d * h);
        assert!(matches!(
            pillar.wrap(&Point2::new(25.0, 45.0), &u, &w),
            Err(WrapError::NoContact(why)) if why.contains("footprint")
        ));
        for d in [5.0, 5.0 * (1.0 + 0.5 * FOOTPRINT_TOLERANCE), 4.0] {
            let s = pillar.wrap(&inward_corner(d), &u, &w);
            assert!(s.is_ok(), "{d}: {s:?}");
        }
        assert!(matches!(
            pillar.wrap(
                &inward_corner(5.0 * (1.0 + 4.0 * FOOTPRINT_TOLERANCE)),
                &u,
                &w
            ),
            Err(WrapError::NoContact(_))
        ));
        let patch = PtfoSurface::HeightField(HeightPatch {
            origin: Point2::new(0.0, 0.0),
            spacing: 1.0,
            cols: 2,
            heights: vec![0.0; 4],
        });
        assert!(patch.validate().is_err());
    }
}
