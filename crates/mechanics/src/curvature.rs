//! Principal curvatures and directions of terrain given as a height field, convexity classes of
//! its cells, and the tangent directions along which a saddle is convex (thesis §3.3.3, §3.3.5,
//! eqs. 3.28-3.31).
//!
//! # Math
//! The terrain `z = h(x, y)` is parametrised by `X(x, y) = (x, y, h)`. With the upward (outward)
//! normal `n = (-h_x, -h_y, 1)/W`, `W = sqrt(1 + h_x² + h_y²)`, the first and second fundamental
//! forms are `I = [[1 + h_x², h_x h_y], [h_x h_y, 1 + h_y²]]` and
//! `II = [[h_xx, h_xy], [h_xy, h_yy]] / W`. The shape operator `S = -dn` (thesis footnote 9) has
//! the matrix `I⁻¹ II`; its eigenvalues are the principal curvatures `κ_1 >= κ_2` (eqs. 3.29-3.30)
//! and its eigenvectors, mapped through `dX`, the principal directions `v_1, v_2`. We solve the
//! symmetric problem `C⁻¹ II C⁻ᵀ` with `I = C Cᵀ` (Cholesky). Derivatives come from central
//! finite differences, so border cells have no curvature.
//!
//! Sign: these are normal curvatures `ρ''·n` with the outward normal, as in [`crate::darboux`]:
//! a hump has `κ_1, κ_2 < 0`. (The thesis' §3.3.3 states the tests with the opposite sign.) A
//! tether can only press on the ground where `κ_n < 0` (condition 1, eq. 3.25), so:
//!
//! * **convex**: no tangent direction is strictly concave and some direction is convex
//!   (`κ_1 <= tol`, `κ_2 < -tol`): sticking is possible in every direction;
//! * **concave**: `κ_2 >= -tol`, `κ_1 > tol`: never;
//! * **saddle**: `κ_1 > tol > -tol > κ_2`: only along some directions;
//! * **flat**: both within `tol` of zero.
//!
//! # The break angle at a saddle (eq. 3.31, re-derived)
//! Euler's formula (eq. 3.28) gives the normal curvature along the tangent at angle `ξ` from `v_1`:
//! `κ_n(ξ) = κ_1 cos² ξ + κ_2 sin² ξ`. Setting it to zero, `tan² ξ = -κ_1/κ_2`, so the break angle
//! is `ξ_flat = atan(sqrt(-κ_1/κ_2))` (the printed `tan^{-2}(-κ_1/κ_2)` is a garbled form of
//! this). The surface is convex (`κ_n < 0`) for `ξ_flat < |ξ| < π - ξ_flat`, i.e. within the
//! half-angle `π/2 - ξ_flat = atan(sqrt(-κ_2/κ_1))` of `±v_2`.

use nalgebra::{DMatrix, Matrix2, Unit, Vector2, Vector3};
use std::f64::consts::FRAC_PI_2;
use thiserror::Error;

/// Default tolerance (1/m) below which a principal curvature counts as zero in [`Convexity`].
pub const DEFAULT_FLAT_CURVATURE: f64 = 1e-6;

/// Why curvature could not be computed.
#[derive(Debug, Error, Clone, Copy, PartialEq)]
pub enum CurvatureError {
    /// A derivative or height is NaN or infinite; fill the DEM's holes first.
    #[error("non-finite height or derivative")]
    NonFinite,
    /// The grid spacing is not finite and positive.
    #[error("grid spacing must be finite and positive")]
    Spacing,
    /// The flatness tolerance is negative or not finite.
    #[error("flatness tolerance must be finite and >= 0")]
    Tolerance,
}

/// Convexity class of a surface point (thesis Fig. 3.11).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Convexity {
    /// Convex in every tangent direction (a hump or ridge): a tether may stick in any direction.
    Convex,
    /// Concave in every direction where it bends: a tether never sticks.
    Concave,
    /// Convex along some directions and concave along others.
    Saddle,
    /// No measurable curvature.
    Flat,
}

/// The tangent directions along which a saddle is convex: within `half_width` radians of
/// `±axis` (the most convex principal direction `v_2`), see the module docs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConvexDirections {
    /// The principal direction of minimum (most convex) normal curvature, `v_2`.
    pub axis: Unit<Vector3<f64>>,
    /// Half the opening angle, `π/2 - ξ_flat = atan(sqrt(-κ_2/κ_1))`.
    pub half_width: f64,
}

impl ConvexDirections {
    /// Whether the tangent direction `direction` (any length, projected onto the tangent plane by
    /// the caller) lies strictly inside the convex range.
    pub fn contains(&self, direction: &Vector3<f64>) -> bool {
        let n = direction.norm();
        n > 0.0 && (self.axis.dot(direction).abs() / n).min(1.0).acos() < self.half_width
    }
}

/// Principal curvatures and directions at one surface point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrincipalCurvatures {
    /// `κ_1`, the maximum normal curvature (eq. 3.29).
    pub max: f64,
    /// `κ_2`, the minimum normal curvature (eq. 3.30).
    pub min: f64,
    /// `v_1`, the direction of `κ_1` (unit, tangent).
    pub max_direction: Unit<Vector3<f64>>,
    /// `v_2`, the direction of `κ_2` (unit, tangent).
    pub min_direction: Unit<Vector3<f64>>,
    /// The outward unit normal.
    pub normal: Unit<Vector3<f64>>,
}

impl PrincipalCurvatures {
    /// Principal curvatures of `z = h(x, y)` from its first and second partial derivatives.
    ///
    /// # Example
    /// ```
    /// use rappel_mechanics::curvature::{Convexity, PrincipalCurvatures, DEFAULT_FLAT_CURVATURE};
    /// // The saddle z = (x² - 3y²)/2 at its centre: κ_1 = 1 along x, κ_2 = -3 along y.
    /// let k = PrincipalCurvatures::from_height_derivatives(0.0, 0.0, 1.0, 0.0, -3.0).unwrap();
    /// assert!((k.max - 1.0).abs() < 1e-12 && (k.min + 3.0).abs() < 1e-12);
    /// assert_eq!(k.convexity(DEFAULT_FLAT_CURVATURE).unwrap(), Convexity::Saddle);
    /// let range = k.convex_directions(DEFAULT_FLAT_CURVATURE).unwrap().unwrap();
    /// assert!((range.half_width - 3f64.sqrt().atan()).abs() < 1e-12);
    /// ```
    pub fn from_height_derivatives(
        hx: f64,
        hy: f64,
        hxx: f64,
        hxy: f64,
        hyy: f64,
    ) -> Result<Self, CurvatureError> {
        if ![hx, hy, hxx, hxy, hyy].iter().all(|v| v.is_finite()) {
            return Err(CurvatureError::NonFinite);
        }
        let w = (1.0 + hx * hx + hy * hy).sqrt();
        let first = Matrix2::new(1.0 + hx * hx, hx * hy, hx * hy, 1.0 + hy * hy);
        let second = Matrix2::new(hxx, hxy, hxy, hyy) / w;
        // I is positive definite for finite slopes, so Cholesky cannot fail on finite input.
        let chol = first.cholesky().ok_or(CurvatureError::NonFinite)?;
        let c = chol.l();
        let c_inv = c.try_inverse().ok_or(CurvatureError::NonFinite)?;
        let sym = c_inv * second * c_inv.transpose();
        let sym = (sym + sym.transpose()) * 0.5;
        let eig = sym.symmetric_eigen();
        let (i_max, i_min) = if eig.eigenvalues[0] >= eig.eigenvalues[1] {
            (0, 1)
        } else {
            (1, 0)
        };
        let to_3d = |e: Vector2<f64>| {
            let d = c_inv.transpose() * e;
            Unit::new_normalize(Vector3::new(d[0], d[1], hx * d[0] + hy * d[1]))
        };
        Ok(PrincipalCurvatures {
            max: eig.eigenvalues[i_max],
            min: eig.eigenvalues[i_min],
            max_direction: to_3d(eig.eigenvectors.column(i_max).into_owned()),
            min_direction: to_3d(eig.eigenvectors.column(i_min).into_owned()),
            normal: Unit::new_normalize(Vector3::new(-hx, -hy, 1.0)),
        })
    }

    /// The normal curvature along tangent `direction` by Euler's formula (eq. 3.28); the direction
    /// is projected onto the tangent plane. Returns `None` for a direction along the normal.
    pub fn normal_curvature(&self, direction: &Vector3<f64>) -> Option<f64> {
        let a = direction.dot(&self.max_direction);
        let b = direction.dot(&self.min_direction);
        let r2 = a * a + b * b;
        (r2 > 0.0).then(|| (self.max * a * a + self.min * b * b) / r2)
    }

    /// The convexity class with flatness tolerance `tol` (1/m, see the module docs).
    pub fn convexity(&self, tol: f64) -> Result<Convexity, CurvatureError> {
        if !(tol.is_finite() && tol >= 0.0) {
            return Err(CurvatureError::Tolerance);
        }
        Ok(match (self.max > tol, self.min < -tol) {
            (true, true) => Convexity::Saddle,
            (false, true) => Convexity::Convex,
            (true, false) => Convexity::Concave,
            (false, false) => Convexity::Flat,
        })
    }

    /// The break angle `ξ_flat = atan(sqrt(-κ_1/κ_2))` from `v_1` at a saddle (re-derived eq.
    /// 3.31), or `None` if the point is not a saddle under tolerance `tol`.
    pub fn break_angle(&self, tol: f64) -> Result<Option<f64>, CurvatureError> {
        Ok((self.convexity(tol)? == Convexity::Saddle)
            .then(|| (-self.max / self.min).sqrt().atan()))
    }

    /// The convex tangent directions at a saddle (`None` elsewhere; at a convex point every
    /// direction is convex).
    pub fn convex_directions(&self, tol: f64) -> Result<Option<ConvexDirections>, CurvatureError> {
        Ok(self.break_angle(tol)?.map(|xi| ConvexDirections {
            axis: self.min_direction,
            half_width: FRAC_PI_2 - xi,
        }))
    }
}

/// Principal curvatures of every interior cell of a height grid.
#[derive(Clone, Debug, PartialEq)]
pub struct CurvatureMap {
    cells: DMatrix<Option<PrincipalCurvatures>>,
}

impl CurvatureMap {
    /// The curvatures at row `i` (y index), column `j` (x index); `None` on the border or out of
    /// range.
    pub fn get(&self, i: usize, j: usize) -> Option<&PrincipalCurvatures> {
        self.cells.get((i, j)).and_then(Option::as_ref)
    }

    /// `(rows, columns)` of the grid.
    pub fn shape(&self) -> (usize, usize) {
        self.cells.shape()
    }

    /// The convexity class of every cell (`None` on the border), with flatness tolerance `tol`.
    pub fn classify(&self, tol: f64) -> Result<DMatrix<Option<Convexity>>, CurvatureError> {
        if !(tol.is_finite() && tol >= 0.0) {
            return Err(CurvatureError::Tolerance);
        }
        let classes = self.cells.map(|c| c.and_then(|k| k.convexity(tol).ok()));
        Ok(classes)
    }
}

/// First and second derivatives of a height grid at one cell (grid frame: `x` along columns,
/// `y` along rows).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeightDerivatives {
    /// `∂h/∂x`.
    pub hx: f64,
    /// `∂h/∂y`.
    pub hy: f64,
    /// `∂²h/∂x²`.
    pub hxx: f64,
    /// `∂²h/∂x∂y`.
    pub hxy: f64,
    /// `∂²h/∂y²`.
    pub hyy: f64,
}

/// The derivatives of `heights` (row `i` at `y = i dy`, column `j` at `x = j dx`) at interior
/// cell `(i, j)` by central differences; `None` on the border or when a height of the cell or its
/// eight neighbours is not finite.
///
/// ```
/// use nalgebra::DMatrix;
/// use rappel_mechanics::curvature::height_derivatives;
/// // h = x² + 3 x y on a unit grid: exact for central differences.
/// let h = DMatrix::from_fn(3, 3, |i, j| { let (x, y) = (j as f64, i as f64); x * x + 3.0 * x * y });
/// let d = height_derivatives(&h, 1, 1, 1.0, 1.0).unwrap();
/// assert_eq!((d.hx, d.hy, d.hxx, d.hxy, d.hyy), (5.0, 3.0, 2.0, 3.0, 0.0));
/// assert!(height_derivatives(&h, 0, 1, 1.0, 1.0).is_none());
/// ```
pub fn height_derivatives(
    heights: &DMatrix<f64>,
    i: usize,
    j: usize,
    dx: f64,
    dy: f64,
) -> Option<HeightDerivatives> {
    let (rows, cols) = heights.shape();
    if i == 0 || j == 0 || i + 1 >= rows || j + 1 >= cols {
        return None;
    }
    let h =
        |di: isize, dj: isize| heights[((i as isize + di) as usize, (j as isize + dj) as usize)];
    if !(-1..=1).all(|di| (-1..=1).all(|dj| h(di, dj).is_finite())) {
        return None;
    }
    Some(HeightDerivatives {
        hx: (h(0, 1) - h(0, -1)) / (2.0 * dx),
        hy: (h(1, 0) - h(-1, 0)) / (2.0 * dy),
        hxx: (h(0, 1) - 2.0 * h(0, 0) + h(0, -1)) / (dx * dx),
        hyy: (h(1, 0) - 2.0 * h(0, 0) + h(-1, 0)) / (dy * dy),
        hxy: (h(1, 1) - h(1, -1) - h(-1, 1) + h(-1, -1)) / (4.0 * dx * dy),
    })
}

/// Principal curvatures of the height grid `heights` (row `i` at `y = i dy`, column `j` at
/// `x = j dx`) by central differences; border cells, and cells with a non-finite height among
/// their eight neighbours or themselves (unknown heights), are `None`.
///
/// # Example
/// ```
/// use nalgebra::DMatrix;
/// use rappel_mechanics::curvature::{analyze_height_field, Convexity};
/// // A dome z = -(x² + y²)/2 sampled on a 5 x 5 grid: convex at the centre.
/// let h = DMatrix::from_fn(5, 5, |i, j| { let (x, y) = (j as f64 - 2.0, i as f64 - 2.0); -(x * x + y * y) / 2.0 });
/// let map = analyze_height_field(&h, 1.0, 1.0).unwrap();
/// assert_eq!(map.classify(1e-6).unwrap()[(2, 2)], Some(Convexity::Convex));
/// assert!(map.get(0, 0).is_none());
/// ```
pub fn analyze_height_field(
    heights: &DMatrix<f64>,
    dx: f64,
    dy: f64,
) -> Result<CurvatureMap, CurvatureError> {
    if !(dx.is_finite() && dx > 0.0 && dy.is_finite() && dy > 0.0) {
        return Err(CurvatureError::Spacing);
    }
    let (rows, cols) = heights.shape();
    let mut cells = DMatrix::from_element(rows, cols, None);
    for i in 1..rows.saturating_sub(1) {
        for j in 1..cols.saturating_sub(1) {
            // Unknown heights (NaN, a DEM's NODATA) leave the cell unanalysed.
            let Some(d) = height_derivatives(heights, i, j, dx, dy) else {
                continue;
            };
            cells[(i, j)] = Some(PrincipalCurvatures::from_height_derivatives(
                d.hx, d.hy, d.hxx, d.hxy, d.hyy,
            )?);
        }
    }
    Ok(CurvatureMap { cells })
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn sphere_and_bowl_have_curvature_minus_and_plus_one_over_r() {
        let r = 10.0;
        let dome = DMatrix::from_fn(21, 21, |i, j| {
            let (x, y) = ((j as f64 - 10.0) * 0.05, (i as f64 - 10.0) * 0.05);
            (r * r - x * x - y * y).sqrt()
        });
        let map = analyze_height_field(&dome, 0.05, 0.05).unwrap();
        for (i, j) in [(10, 10), (5, 13), (15, 3)] {
            let k = map.get(i, j).unwrap();
            assert!(
                (k.max + 1.0 / r).abs() < 1e-4 && (k.min + 1.0 / r).abs() < 1e-4,
                "{k:?}"
            );
            assert_eq!(k.convexity(1e-6).unwrap(), Convexity::Convex);
        }
        let bowl = dome.map(|z| -z);
        let k = *analyze_height_field(&bowl, 0.05, 0.05)
            .unwrap()
            .get(4, 7)
            .unwrap();
        assert!((k.min - 1.0 / r).abs() < 1e-4);
        assert_eq!(k.convexity(1e-6).unwrap(), Convexity::Concave);
        let flat = DMatrix::from_fn(4, 4, |i, j| 0.3 * i as f64 + 0.1 * j as f64);
        let classes = analyze_height_field(&flat, 1.0, 1.0)
            .unwrap()
            .classify(1e-9)
            .unwrap();
        assert_eq!(classes[(1, 1)], Some(Convexity::Flat));
        assert_eq!(classes[(0, 1)], None);
    }

    #[test]
    fn tilted_cylinder_ridge_is_convex_with_direction_along_ridge_flat() {
        // z = -x²/(2R) + 0.5 y: a ridge along y with curvature -1/R across it.
        let k = PrincipalCurvatures::from_height_derivatives(0.0, 0.5, -0.2, 0.0, 0.0).unwrap();
        assert_eq!(k.convexity(1e-9).unwrap(), Convexity::Convex);
        assert!(k.max.abs() < 1e-12);
        let along = Vector3::new(0.0, 1.0, 0.5);
        assert!(k.normal_curvature(&along).unwrap().abs() < 1e-12);
        assert!((k.min_direction.x.abs() - 1.0).abs() < 1e-12);
    }

    #[test]
    fn bad_input_is_an_error() {
        assert_eq!(
            PrincipalCurvatures::from_height_derivatives(f64::NAN, 0.0, 0.0, 0.0, 0.0),
            Err(CurvatureError::NonFinite)
        );
        assert_eq!(
            analyze_height_field(&DMatrix::zeros(3, 3), 0.0, 1.0),
            Err(CurvatureError::Spacing)
        );
        let k = PrincipalCurvatures::from_height_derivatives(0.0, 0.0, 1.0, 0.0, 1.0).unwrap();
        assert_eq!(k.convexity(-1.0), Err(CurvatureError::Tolerance));
    }

    #[test]
    fn unknown_heights_leave_their_neighbourhood_unanalysed() {
        let mut h = DMatrix::from_fn(6, 6, |i, j| -((i * i + j * j) as f64) / 10.0);
        h[(2, 2)] = f64::NAN;
        let map = analyze_height_field(&h, 1.0, 1.0).unwrap();
        for i in 1..5usize {
            for j in 1..5usize {
                let near = i.abs_diff(2) <= 1 && j.abs_diff(2) <= 1;
                assert_eq!(map.get(i, j).is_none(), near, "cell ({i}, {j})");
            }
        }
    }

    proptest! {
        /// Euler's formula and the break angle agree: along any tangent direction the surface is
        /// convex exactly when the direction lies in the saddle's convex range; principal
        /// curvatures bound every normal curvature (eqs. 3.28-3.31).
        #[test]
        fn saddle_range_matches_sign_of_normal_curvature(
            hx in -1.5f64..1.5, hy in -1.5f64..1.5, hxx in -3.0f64..3.0, hxy in -3.0f64..3.0, hyy in -3.0f64..3.0,
            angle in 0.0f64..std::f64::consts::TAU,
        ) {
            let k = PrincipalCurvatures::from_height_derivatives(hx, hy, hxx, hxy, hyy).unwrap();
            // A tangent vector at parameter angle `angle`, and its exact normal curvature II/I.
            let (a, b) = (angle.cos(), angle.sin());
            let t = Vector3::new(a, b, hx * a + hy * b);
            let w = (1.0 + hx * hx + hy * hy).sqrt();
            let exact = (hxx * a * a + 2.0 * hxy * a * b + hyy * b * b) / w / t.norm_squared();
            let euler = k.normal_curvature(&t).unwrap();
            prop_assert!((euler - exact).abs() < 1e-9 * (1.0 + exact.abs()));
            prop_assert!(euler <= k.max + 1e-9 && euler >= k.min - 1e-9);
            prop_assert!(k.max_direction.dot(&k.normal).abs() < 1e-9 && k.max_direction.dot(&k.min_direction).abs() < 1e-9);
            if let Some(range) = k.convex_directions(1e-6).unwrap() {
                let margin = 1e-6 * (k.max.abs() + k.min.abs());
                if exact < -margin { prop_assert!(range.contains(&t)); }
                if exact > margin { prop_assert!(!range.contains(&t)); }
            }
        }
    }
}
