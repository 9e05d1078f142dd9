//! A series of terrain planes down the fall line (thesis §2.1.2, Fig. 2.3; Kumar's multi-surface
//! environment), unfolded isometrically into the planar map frame.
//!
//! Frame convention used throughout rappel: `x` runs across the slope, `y` runs **up** the slope,
//! so the fall line (the direction of steepest descent, along which gravity pulls the robot)
//! is `-y`. Unfolding is isometric: distances measured in the map frame are distances on the
//! ground. Plane `i` covers the band `y_bottom <= y <= y_top`; the planes are listed from the top
//! of the wall down and meet edge to edge.

use serde::{Deserialize, Serialize};

/// One plane of the series: a band of the unfolded frame with its slope and wheel friction.
///
/// ```
/// use rappel_terrain::plane_series::TerrainPlane;
/// let p = TerrainPlane { y_top: 100.0, y_bottom: 0.0, slope_deg: 45.0, friction: 0.4 };
/// assert!(p.contains_y(50.0));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TerrainPlane {
    /// Upper edge of the band, in map-frame y (metres along the ground).
    pub y_top: f64,
    /// Lower edge of the band.
    pub y_bottom: f64,
    /// Inclination of the plane from horizontal, degrees, in `[0, 90)` (thesis eta).
    pub slope_deg: f64,
    /// Wheel-terrain friction coefficient mu, `>= 0`.
    pub friction: f64,
}

impl TerrainPlane {
    /// A plane covering `y_bottom..=y_top` with `slope_deg` and wheel `friction` (not validated:
    /// see [`validate_planes`]).
    pub fn new(y_top: f64, y_bottom: f64, slope_deg: f64, friction: f64) -> Self {
        TerrainPlane {
            y_top,
            y_bottom,
            slope_deg,
            friction,
        }
    }

    /// `true` when map-frame `y` lies in this plane's band (edges included).
    pub fn contains_y(&self, y: f64) -> bool {
        y <= self.y_top && y >= self.y_bottom
    }

    /// Inclination in radians.
    pub fn slope_rad(&self) -> f64 {
        self.slope_deg.to_radians()
    }
}

/// A defect in a plane series.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PlaneSeriesError {
    /// A number is NaN or infinite.
    #[error("plane {plane} has a non-finite {field}")]
    NonFinite {
        /// Plane index (0 = top).
        plane: usize,
        /// Which field.
        field: &'static str,
    },
    /// `y_top <= y_bottom`.
    #[error("plane {plane} is empty: y_top {y_top} is not above y_bottom {y_bottom}")]
    Empty {
        /// Plane index.
        plane: usize,
        /// Its top.
        y_top: f64,
        /// Its bottom.
        y_bottom: f64,
    },
    /// Slope outside `[0, 90)` degrees.
    #[error("plane {plane} has slope {} degrees; it must be in [0, 90)", rappel_geometry::compact::Compact(*.slope_deg))]
    BadSlope {
        /// Plane index.
        plane: usize,
        /// The slope given.
        slope_deg: f64,
    },
    /// Negative friction.
    #[error("plane {plane} has friction {}; it must be >= 0", rappel_geometry::compact::Compact(*.friction))]
    BadFriction {
        /// Plane index.
        plane: usize,
        /// The friction given.
        friction: f64,
    },
    /// Plane `plane` does not start where the one above it ends.
    #[error(
        "plane {plane} starts at y = {y_top} but the plane above ends at y = {above_bottom}: planes must meet edge to edge, top first"
    )]
    Gap {
        /// Plane index.
        plane: usize,
        /// Its top.
        y_top: f64,
        /// The bottom of the plane above.
        above_bottom: f64,
    },
}

/// Checks a plane series: finite numbers, non-empty bands, slopes in `[0, 90)`, friction `>= 0`,
/// listed top first and meeting edge to edge. An empty series is valid (no terrain given).
///
/// ```
/// use rappel_terrain::plane_series::{validate_planes, TerrainPlane};
/// let planes = [
///     TerrainPlane { y_top: 100.0, y_bottom: 40.0, slope_deg: 35.0, friction: 0.5 },
///     TerrainPlane { y_top: 40.0, y_bottom: 0.0, slope_deg: 50.0, friction: 0.5 },
/// ];
/// validate_planes(&planes).unwrap();
/// ```
pub fn validate_planes(planes: &[TerrainPlane]) -> Result<(), PlaneSeriesError> {
    for (i, p) in planes.iter().enumerate() {
        for (field, v) in [
            ("y_top", p.y_top),
            ("y_bottom", p.y_bottom),
            ("slope_deg", p.slope_deg),
            ("friction", p.friction),
        ] {
            if !v.is_finite() {
                return Err(PlaneSeriesError::NonFinite { plane: i, field });
            }
        }
        if p.y_top <= p.y_bottom {
            return Err(PlaneSeriesError::Empty {
                plane: i,
                y_top: p.y_top,
                y_bottom: p.y_bottom,
            });
        }
        if !(0.0..90.0).contains(&p.slope_deg) {
            return Err(PlaneSeriesError::BadSlope {
                plane: i,
                slope_deg: p.slope_deg,
            });
        }
        if p.friction < 0.0 {
            return Err(PlaneSeriesError::BadFriction {
                plane: i,
                friction: p.friction,
            });
        }
        if i > 0 && planes[i - 1].y_bottom != p.y_top {
            return Err(PlaneSeriesError::Gap {
                plane: i,
                y_top: p.y_top,
                above_bottom: planes[i - 1].y_bottom,
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_defect_is_named() {
        assert!(validate_planes(&[]).is_ok());
        assert!(matches!(
            validate_planes(&[TerrainPlane::new(0., 10., 30., 0.4)]),
            Err(PlaneSeriesError::Empty { .. })
        ));
        assert!(matches!(
            validate_planes(&[TerrainPlane::new(10., 0., 90., 0.4)]),
            Err(PlaneSeriesError::BadSlope { .. })
        ));
        assert!(matches!(
            validate_planes(&[TerrainPlane::new(10., 0., 30., -0.1)]),
            Err(PlaneSeriesError::BadFriction { .. })
        ));
        assert!(matches!(
            validate_planes(&[TerrainPlane::new(10., 0., f64::NAN, 0.1)]),
            Err(PlaneSeriesError::NonFinite {
                field: "slope_deg",
                ..
            })
        ));
        assert!(matches!(
            validate_planes(&[
                TerrainPlane::new(10., 5., 30., 0.4),
                TerrainPlane::new(4., 0., 40., 0.4)
            ]),
            Err(PlaneSeriesError::Gap { plane: 1, .. })
        ));
    }
}
