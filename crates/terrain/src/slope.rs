//! Slope analysis of a DEM (thesis §2.1.2, §2.5.2: "the gradient magnitude of the DEM", Fig. 2.23):
//! the height gradient per cell by Horn's method, slope and aspect rasters, the fall line, and a
//! hillshade for pictures.
//!
//! **Horn's method** (Horn 1981, the GIS standard). With the 3 x 3 neighbourhood
//! ```text
//! a b c
//! d e f      (north up)
//! g h i
//! ```
//! `dz/dx = ((c + 2f + i) - (a + 2d + g)) / (8 dx)` and `dz/dy = ((a + 2b + c) - (g + 2h + i)) / (8 dy)`,
//! i.e. the 1-2-1 weighted mean of the central differences of the three rows (columns). Where a
//! neighbour is unknown (NODATA) or off the grid, that row's difference falls back to the one-sided
//! difference through the row's middle cell, and a row with no usable pair is left out of the
//! weighted mean. Every one of these estimates is exact on a plane, so a tilted plane has exactly
//! its slope at every known cell, edges included. A cell whose own height is unknown, or with no
//! usable pair in a direction, has an unknown gradient.
//!
//! **Slope** is `atan |grad z|`, **aspect** the compass azimuth (degrees clockwise from north) of
//! the downhill direction `-grad z`. The **fall line** of the whole grid is the mean downhill
//! direction: the direction of `-mean(grad z)` over known cells, which is also the downhill
//! direction of the least-squares plane through a complete grid. It defines the planning frame's
//! `-y` axis (see [`crate::frame`]).

use nalgebra::Vector2;
use serde::{Deserialize, Serialize};

use crate::grid::{GridGeometry, HeightGrid, Raster};

/// Below this slope (degrees) of the mean gradient the terrain has no fall line: it is flat on the
/// whole, and any direction is as good as another. Give the fall line explicitly for such terrain.
pub const MIN_FALL_LINE_SLOPE_DEG: f64 = 0.5;

/// Default sun azimuth for hillshades, degrees clockwise from north (north-west, the cartographic
/// convention).
pub const DEFAULT_SUN_AZIMUTH_DEG: f64 = 315.0;

/// Default sun altitude for hillshades, degrees above the horizon.
pub const DEFAULT_SUN_ALTITUDE_DEG: f64 = 45.0;

/// Why no fall line could be found.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SlopeError {
    /// Every gradient is unknown (a grid of unknown cells, or a single known cell).
    #[error("no cell has a known slope: the grid needs at least two neighbouring known heights")]
    NoKnownSlope,
    /// The terrain is flat on the whole. Fix: give the fall line's azimuth explicitly.
    #[error(
        "the mean slope is {mean_slope_deg:.3} degrees, below {MIN_FALL_LINE_SLOPE_DEG} degrees: the terrain has no fall line; give its azimuth explicitly"
    )]
    NoFallLine {
        /// The slope of the mean gradient.
        mean_slope_deg: f64,
    },
    /// An azimuth that is not a finite number.
    #[error("the fall-line azimuth {} is not a finite number", rappel_geometry::compact::Compact(*.azimuth_deg))]
    BadAzimuth {
        /// The azimuth given.
        azimuth_deg: f64,
    },
}

/// The height gradient `(dz/d east, dz/d north)` of every cell, by Horn's method.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SlopeField {
    /// Shape and georeference (that of the DEM).
    pub geometry: GridGeometry,
    /// Row-major gradients; both components NaN where unknown.
    pub gradient: Vec<Vector2<f64>>,
}

/// The fall line: the mean downhill direction, horizontal, in world `(east, north)` components.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FallLine {
    /// Unit horizontal vector pointing downhill.
    pub downhill: Vector2<f64>,
    /// Slope of the mean gradient, degrees (NaN when the fall line was given, not measured).
    pub mean_slope_deg: f64,
}

impl FallLine {
    /// The fall line pointing down towards compass azimuth `azimuth_deg` (clockwise from north).
    ///
    /// ```
    /// use rappel_terrain::slope::FallLine;
    /// let south = FallLine::from_azimuth(180.0).unwrap();
    /// assert!((south.downhill.y + 1.0).abs() < 1e-12);
    /// assert!((south.azimuth_deg() - 180.0).abs() < 1e-9);
    /// ```
    pub fn from_azimuth(azimuth_deg: f64) -> Result<Self, SlopeError> {
        if !azimuth_deg.is_finite() {
            return Err(SlopeError::BadAzimuth { azimuth_deg });
        }
        let a = azimuth_deg.to_radians();
        Ok(FallLine {
            downhill: Vector2::new(a.sin(), a.cos()),
            mean_slope_deg: f64::NAN,
        })
    }

    /// Compass azimuth of the downhill direction, degrees clockwise from north, in `[0, 360)`.
    pub fn azimuth_deg(&self) -> f64 {
        azimuth_of(self.downhill)
    }
}

/// Compass azimuth (degrees clockwise from north, in `[0, 360)`) of a horizontal vector.
fn azimuth_of(v: Vector2<f64>) -> f64 {
    let a = v.x.atan2(v.y).to_degrees();
    if a < 0.0 { a + 360.0 } else { a }
}

/// Hillshade lighting.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct HillshadeOptions {
    /// Sun azimuth, degrees clockwise from north. Default [`DEFAULT_SUN_AZIMUTH_DEG`].
    pub sun_azimuth_deg: f64,
    /// Sun altitude above the horizon, degrees. Default [`DEFAULT_SUN_ALTITUDE_DEG`].
    pub sun_altitude_deg: f64,
}

impl Default for HillshadeOptions {
    fn default() -> Self {
        HillshadeOptions {
            sun_azimuth_deg: DEFAULT_SUN_AZIMUTH_DEG,
            sun_altitude_deg: DEFAULT_SUN_ALTITUDE_DEG,
        }
    }
}

/// Horn's estimate of the derivative across one row (or column) of the 3 x 3 window: `lo`, `mid`,
/// `hi` are the heights at offsets -1, 0, +1 and `h` the cell spacing.
fn one_line(lo: Option<f64>, mid: Option<f64>, hi: Option<f64>, h: f64) -> Option<f64> {
    match (lo, mid, hi) {
        (Some(l), _, Some(r)) => Some((r - l) / (2.0 * h)),
        (None, Some(m), Some(r)) => Some((r - m) / h),
        (Some(l), Some(m), None) => Some((m - l) / h),
        _ => None,
    }
}

/// Horn's 1-2-1 weighted mean of three line derivatives, leaving out the unknown ones.
fn weighted(d: [Option<f64>; 3]) -> Option<f64> {
    let (mut sum, mut w) = (0.0, 0.0);
    for (di, wi) in d.into_iter().zip([1.0, 2.0, 1.0]) {
        if let Some(v) = di {
            sum += wi * v;
            w += wi;
        }
    }
    (w > 0.0).then(|| sum / w)
}

impl SlopeField {
    /// The gradient of every cell of `dem` by Horn's method (see the module docs).
    ///
    /// ```
    /// use rappel_terrain::grid::{GridGeometry, HeightGrid};
    /// use rappel_terrain::slope::SlopeField;
    /// // z = 0.5 * north: a 26.57 degree slope facing south.
    /// let g = GridGeometry::new(5, 5, 1.0, 1.0, 0.0, 5.0).unwrap();
    /// let dem = HeightGrid::from_fn(g, |_, _, p| Some(0.5 * p.y)).unwrap();
    /// let field = SlopeField::horn(&dem);
    /// let slope = field.slope_deg();
    /// assert!((slope.get(0, 0).unwrap() - 0.5f64.atan().to_degrees()).abs() < 1e-9);
    /// assert!((field.aspect_deg().get(2, 2).unwrap() - 180.0).abs() < 1e-9);
    /// ```
    pub fn horn(dem: &HeightGrid) -> SlopeField {
        let g = *dem.geometry();
        let (nr, nc) = (g.nrows as isize, g.ncols as isize);
        let z = |r: isize, c: isize| -> Option<f64> {
            if r < 0 || c < 0 || r >= nr || c >= nc {
                None
            } else {
                dem.height(r as usize, c as usize)
            }
        };
        let unknown = Vector2::new(f64::NAN, f64::NAN);
        let mut gradient = Vec::with_capacity(g.len());
        for r in 0..nr {
            for c in 0..nc {
                if z(r, c).is_none() {
                    gradient.push(unknown);
                    continue;
                }
                let dzdx =
                    weighted([-1, 0, 1].map(|k| {
                        one_line(z(r + k, c - 1), z(r + k, c), z(r + k, c + 1), g.cell_x)
                    }));
                // Northward derivative: row r - 1 is north of row r.
                let dzdy =
                    weighted([-1, 0, 1].map(|k| {
                        one_line(z(r + 1, c + k), z(r, c + k), z(r - 1, c + k), g.cell_y)
                    }));
                gradient.push(match (dzdx, dzdy) {
                    (Some(x), Some(y)) => Vector2::new(x, y),
                    _ => unknown,
                });
            }
        }
        SlopeField {
            geometry: g,
            gradient,
        }
    }

    /// The gradient of cell `(row, col)`, `None` where unknown or outside the grid.
    pub fn gradient_at(&self, row: usize, col: usize) -> Option<Vector2<f64>> {
        if row >= self.geometry.nrows || col >= self.geometry.ncols {
            return None;
        }
        let v = self.gradient[self.geometry.index(row, col)];
        (!v.x.is_nan()).then_some(v)
    }

    /// Slope per cell, degrees from horizontal (NaN where unknown).
    pub fn slope_deg(&self) -> Raster {
        self.raster(|v| v.norm().atan().to_degrees())
    }

    /// Aspect per cell: compass azimuth of the downhill direction, degrees clockwise from north in
    /// `[0, 360)`; NaN where unknown or exactly flat.
    pub fn aspect_deg(&self) -> Raster {
        self.raster(|v| {
            if v.x == 0.0 && v.y == 0.0 {
                f64::NAN
            } else {
                azimuth_of(-v)
            }
        })
    }

    /// A raster of `f(gradient)` over known gradients, NaN elsewhere.
    fn raster(&self, f: impl Fn(Vector2<f64>) -> f64) -> Raster {
        Raster {
            geometry: self.geometry,
            values: self
                .gradient
                .iter()
                .map(|v| if v.x.is_nan() { f64::NAN } else { f(*v) })
                .collect(),
        }
    }

    /// The fall line: the direction of `-mean(grad z)` over known gradients.
    ///
    /// Errors: [`SlopeError::NoKnownSlope`] without any known gradient;
    /// [`SlopeError::NoFallLine`] when the mean gradient's slope is below
    /// [`MIN_FALL_LINE_SLOPE_DEG`].
    pub fn fall_line(&self) -> Result<FallLine, SlopeError> {
        let (mut sum, mut n) = (Vector2::zeros(), 0usize);
        for v in self.gradient.iter().filter(|v| !v.x.is_nan()) {
            sum += v;
            n += 1;
        }
        if n == 0 {
            return Err(SlopeError::NoKnownSlope);
        }
        let mean = sum / n as f64;
        let mean_slope_deg = mean.norm().atan().to_degrees();
        if mean_slope_deg.is_nan() || mean_slope_deg < MIN_FALL_LINE_SLOPE_DEG {
            return Err(SlopeError::NoFallLine { mean_slope_deg });
        }
        Ok(FallLine {
            downhill: -mean / mean.norm(),
            mean_slope_deg,
        })
    }

    /// A hillshade: the cosine of the angle between the surface normal and the sun, clamped to
    /// `[0, 1]` (0 in shadow); NaN where the gradient is unknown.
    ///
    /// ```
    /// use rappel_terrain::grid::{GridGeometry, HeightGrid};
    /// use rappel_terrain::slope::{HillshadeOptions, SlopeField};
    /// let g = GridGeometry::new(3, 3, 1.0, 1.0, 0.0, 3.0).unwrap();
    /// let flat = HeightGrid::from_fn(g, |_, _, _| Some(7.0)).unwrap();
    /// let hs = SlopeField::horn(&flat).hillshade(&HillshadeOptions::default());
    /// // Flat ground is lit by the sine of the sun's altitude.
    /// assert!((hs.get(1, 1).unwrap() - 45f64.to_radians().sin()).abs() < 1e-12);
    /// ```
    pub fn hillshade(&self, options: &HillshadeOptions) -> Raster {
        let (az, alt) = (
            options.sun_azimuth_deg.to_radians(),
            options.sun_altitude_deg.to_radians(),
        );
        let sun = [az.sin() * alt.cos(), az.cos() * alt.cos(), alt.sin()];
        self.raster(|v| {
            let n = (1.0 + v.norm_squared()).sqrt();
            ((-v.x * sun[0] - v.y * sun[1] + sun[2]) / n).clamp(0.0, 1.0)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plane(nrows: usize, ncols: usize, gx: f64, gy: f64) -> HeightGrid {
        let g = GridGeometry::new(nrows, ncols, 2.0, 3.0, 10.0, 100.0).unwrap();
        HeightGrid::from_fn(g, |_, _, p| Some(5.0 + gx * p.x + gy * p.y)).unwrap()
    }

    #[test]
    fn plane_gradient_is_exact_everywhere_even_with_holes() {
        let (gx, gy) = (0.3, -0.7);
        let full = plane(6, 5, gx, gy);
        // Punch NODATA holes: a corner, an interior cell, an edge cell.
        let holes = [(0, 0), (2, 2), (5, 3)];
        let dem = full
            .map(|r, c, h| if holes.contains(&(r, c)) { None } else { h })
            .unwrap();
        let f = SlopeField::horn(&dem);
        for r in 0..6 {
            for c in 0..5 {
                match f.gradient_at(r, c) {
                    None => assert!(holes.contains(&(r, c))),
                    Some(v) => {
                        assert!((v.x - gx).abs() < 1e-9, "{r} {c} {v:?}");
                        assert!((v.y - gy).abs() < 1e-9, "{r} {c} {v:?}");
                    }
                }
            }
        }
        let fl = f.fall_line().unwrap();
        let expect = -Vector2::new(gx, gy).normalize();
        assert!((fl.downhill - expect).norm() < 1e-9);
        let slope = (gx * gx + gy * gy).sqrt().atan().to_degrees();
        assert!((fl.mean_slope_deg - slope).abs() < 1e-9);
        assert!((f.slope_deg().get(5, 4).unwrap() - slope).abs() < 1e-9);
    }

    #[test]
    fn aspect_points_downhill() {
        // Rising to the east: downhill is west (270).
        let f = SlopeField::horn(&plane(3, 3, 1.0, 0.0));
        assert!((f.aspect_deg().get(1, 1).unwrap() - 270.0).abs() < 1e-9);
        // Rising to the south: downhill is north (0).
        let f = SlopeField::horn(&plane(3, 3, 0.0, -1.0));
        assert!(f.aspect_deg().get(1, 1).unwrap().abs() < 1e-9);
    }

    #[test]
    fn isolated_cell_and_flat_terrain() {
        let g = GridGeometry::new(3, 3, 1.0, 1.0, 0.0, 3.0).unwrap();
        let lone = HeightGrid::from_fn(g, |r, c, _| (r == 1 && c == 1).then_some(1.0)).unwrap();
        let f = SlopeField::horn(&lone);
        assert_eq!(f.gradient_at(1, 1), None);
        assert_eq!(f.fall_line(), Err(SlopeError::NoKnownSlope));
        let flat = HeightGrid::from_fn(g, |_, _, _| Some(1.0)).unwrap();
        assert!(matches!(
            SlopeField::horn(&flat).fall_line(),
            Err(SlopeError::NoFallLine { .. })
        ));
        assert!(FallLine::from_azimuth(f64::NAN).is_err());
    }

    #[test]
    fn hillshade_is_brightest_facing_the_sun() {
        // A slope facing north-west (downhill towards 315) at 45 degrees, sun at 315 / 45:
        // the sun is exactly normal to it.
        let d = Vector2::new(-1.0, 1.0).normalize(); // downhill direction
        let f = SlopeField::horn(&plane(3, 3, -d.x, -d.y));
        let hs = f.hillshade(&HillshadeOptions::default());
        assert!((hs.get(1, 1).unwrap() - 1.0).abs() < 1e-12);
        let away = SlopeField::horn(&plane(3, 3, d.x * 3.0, d.y * 3.0));
        assert_eq!(
            away.hillshade(&HillshadeOptions::default()).get(1, 1),
            Some(0.0)
        );
    }
}
