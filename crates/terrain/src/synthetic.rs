//! Synthetic DEMs with known answers, for tests, benchmarks and examples: a convex series of planes
//! down a chosen fall line (thesis §2.1.2, Fig. 2.3), boxes raised or sunk into it (boulders and
//! pits, the positive and negative obstacles of §2.1.2), and the roughness of a real DEM tiled over
//! it (to make large grids that look like HiRISE terrain, §2.5.1).

use serde::{Deserialize, Serialize};
use std::ops::Range;

use crate::frame::PlanningFrame;
use crate::grid::{GridError, GridGeometry, HeightGrid};
use crate::least_squares::PlaneStats;
use crate::slope::FallLine;

/// One plane of a synthetic profile: its horizontal run along the fall line and its slope.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ProfilePlane {
    /// Horizontal length along the fall line, metres.
    pub run_m: f64,
    /// Inclination, degrees.
    pub slope_deg: f64,
}

impl ProfilePlane {
    /// A plane of the given horizontal run and slope.
    pub fn new(run_m: f64, slope_deg: f64) -> Self {
        ProfilePlane { run_m, slope_deg }
    }
}

/// How far the profile has dropped at horizontal distance `d` below its top (planes listed top
/// first; beyond the last plane its slope continues).
///
/// ```
/// use rappel_terrain::synthetic::{profile_drop, ProfilePlane};
/// let p = [ProfilePlane::new(10.0, 45.0), ProfilePlane::new(10.0, 0.0)];
/// assert!((profile_drop(&p, 5.0) - 5.0).abs() < 1e-12);
/// assert!((profile_drop(&p, 30.0) - 10.0).abs() < 1e-12);
/// ```
pub fn profile_drop(planes: &[ProfilePlane], d: f64) -> f64 {
    let mut drop = 0.0;
    let mut left = d;
    for (i, p) in planes.iter().enumerate() {
        let run = if i + 1 == planes.len() {
            left
        } else {
            left.min(p.run_m)
        };
        drop += run * p.slope_deg.to_radians().tan();
        left -= run;
        if left <= 0.0 {
            break;
        }
    }
    drop
}

/// A DEM of the profile `planes` (top first) falling along `fall_line`, at height `top_height`
/// at the uphill-most cell centre (distances along the profile are measured from there, as in the
/// planning frame of [`crate::frame`]).
///
/// ```
/// use rappel_terrain::grid::GridGeometry;
/// use rappel_terrain::slope::FallLine;
/// use rappel_terrain::synthetic::{plane_series_dem, ProfilePlane};
/// let g = GridGeometry::new(10, 10, 1.0, 1.0, 0.0, 10.0).unwrap();
/// let south = FallLine::from_azimuth(180.0).unwrap();
/// let dem = plane_series_dem(g, &south, 100.0, &[ProfilePlane::new(100.0, 45.0)]).unwrap();
/// assert!((dem.height(0, 3).unwrap() - 100.0).abs() < 1e-12);
/// assert!((dem.height(9, 3).unwrap() - 91.0).abs() < 1e-12);
/// ```
pub fn plane_series_dem(
    geometry: GridGeometry,
    fall_line: &FallLine,
    top_height: f64,
    planes: &[ProfilePlane],
) -> Result<HeightGrid, GridError> {
    geometry.validate()?;
    let frame = PlanningFrame::for_grid(&geometry, fall_line);
    let s_top = geometry
        .sample_corners()
        .iter()
        .map(|c| frame.horizontal(c).1)
        .fold(f64::NEG_INFINITY, f64::max);
    HeightGrid::from_fn(geometry, |_, _, p| {
        let s = frame.horizontal(&p).1;
        Some(top_height - profile_drop(planes, s_top - s))
    })
}

/// A copy of `dem` with the cells of `rows x cols` raised by `rise_m` (a boulder or mesa) or, with
/// a negative `rise_m`, sunk (a pit). Heights change vertically; unknown cells stay unknown.
/// Errors when a raised height is not finite.
///
/// ```
/// use rappel_terrain::grid::{GridGeometry, HeightGrid};
/// use rappel_terrain::synthetic::with_box;
/// let g = GridGeometry::new(4, 4, 1.0, 1.0, 0.0, 4.0).unwrap();
/// let flat = HeightGrid::from_fn(g, |_, _, _| Some(0.0)).unwrap();
/// let pit = with_box(&flat, 1..3, 1..3, -2.0).unwrap();
/// assert_eq!((pit.height(1, 1), pit.height(0, 0)), (Some(-2.0), Some(0.0)));
/// assert!(with_box(&flat, 0..1, 0..1, f64::INFINITY).is_err());
/// ```
pub fn with_box(
    dem: &HeightGrid,
    rows: Range<usize>,
    cols: Range<usize>,
    rise_m: f64,
) -> Result<HeightGrid, GridError> {
    dem.map(|r, c, h| {
        h.map(|h| {
            if rows.contains(&r) && cols.contains(&c) {
                h + rise_m
            } else {
                h
            }
        })
    })
}

/// The roughness of `dem`: its heights minus their least-squares plane (unknown cells stay
/// unknown). `None` when no plane can be fitted.
pub fn detrended(dem: &HeightGrid) -> Option<HeightGrid> {
    let g = dem.geometry();
    let mut st = PlaneStats::default();
    for r in 0..g.nrows {
        for c in 0..g.ncols {
            if let Some(h) = dem.height(r, c) {
                st.add(c as f64, r as f64, h);
            }
        }
    }
    let plane = st.fit()?;
    dem.map(|r, c, h| h.map(|h| h - plane.height(c as f64, r as f64)))
        .ok()
}

/// `base` plus `texture` tiled over it cell by cell, every other tile mirrored so that the tiling
/// is continuous. Cells where either is unknown are unknown. Errors when a sum is not finite.
///
/// ```
/// use rappel_terrain::grid::{GridGeometry, HeightGrid};
/// use rappel_terrain::synthetic::tiled_texture;
/// let g = GridGeometry::new(2, 3, 1.0, 1.0, 0.0, 2.0).unwrap();
/// let tex = HeightGrid::new(g, vec![1., 2., 3., 4., 5., 6.]).unwrap();
/// let big = GridGeometry::new(4, 7, 1.0, 1.0, 0.0, 4.0).unwrap();
/// let flat = HeightGrid::from_fn(big, |_, _, _| Some(0.0)).unwrap();
/// let t = tiled_texture(&flat, &tex).unwrap();
/// // Columns 0 1 2 | 2 1 0 | 0 ... of the texture; rows 0 1 | 1 0.
/// assert_eq!((0..7).map(|c| t.height(0, c).unwrap()).collect::<Vec<_>>(), [1., 2., 3., 3., 2., 1., 1.]);
/// assert_eq!(t.height(2, 0), Some(4.0));
/// ```
pub fn tiled_texture(base: &HeightGrid, texture: &HeightGrid) -> Result<HeightGrid, GridError> {
    let tg = *texture.geometry();
    let mirror = |i: usize, n: usize| {
        let k = i % (2 * n);
        if k < n { k } else { 2 * n - 1 - k }
    };
    base.map(|r, c, h| Some(h? + texture.height(mirror(r, tg.nrows), mirror(c, tg.ncols))?))
}

/// Compass azimuth of the fall line of [`textured_wall`], degrees (deliberately off the grid axes).
pub const TEXTURED_WALL_AZIMUTH_DEG: f64 = 200.0;

/// Slopes of the three planes of [`textured_wall`], top first, degrees: a convex crater wall.
pub const TEXTURED_WALL_SLOPES_DEG: [f64; 3] = [15.0, 25.0, 35.0];

/// A large crater wall made from a small real DEM: `nrows x ncols` cells of `texture`'s size, a
/// convex series of three planes ([`TEXTURED_WALL_SLOPES_DEG`], each a third of the run along the
/// fall line) falling towards [`TEXTURED_WALL_AZIMUTH_DEG`], plus the roughness of `texture`
/// ([`detrended`]) mirror-tiled over it ([`tiled_texture`]). `None` when the texture has no
/// fittable plane or the size is unusable.
///
/// ```
/// use rappel_terrain::grid::{GridGeometry, HeightGrid};
/// use rappel_terrain::synthetic::textured_wall;
/// let g = GridGeometry::new(8, 8, 1.0, 1.0, 0.0, 8.0).unwrap();
/// let bumpy = HeightGrid::from_fn(g, |r, c, _| Some(((r * 3 + c * 5) % 7) as f64 * 0.1)).unwrap();
/// let wall = textured_wall(&bumpy, 100, 60).unwrap();
/// assert_eq!((wall.geometry().nrows, wall.geometry().ncols), (100, 60));
/// ```
pub fn textured_wall(texture: &HeightGrid, nrows: usize, ncols: usize) -> Option<HeightGrid> {
    let tg = texture.geometry();
    let g = GridGeometry::new(
        nrows,
        ncols,
        tg.cell_x,
        tg.cell_y,
        0.0,
        nrows as f64 * tg.cell_y,
    )
    .ok()?;
    let fall = FallLine::from_azimuth(TEXTURED_WALL_AZIMUTH_DEG).ok()?;
    let frame = PlanningFrame::for_grid(&g, &fall);
    let run = g
        .sample_corners()
        .iter()
        .map(|c| frame.horizontal(c).1)
        .fold(0.0f64, f64::max);
    let planes = TEXTURED_WALL_SLOPES_DEG.map(|deg| ProfilePlane::new(run / 3.0, deg));
    let base = plane_series_dem(g, &fall, 1000.0, &planes).ok()?;
    tiled_texture(&base, &detrended(texture)?).ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn profile_is_continuous_and_piecewise_linear() {
        let p = [
            ProfilePlane::new(10.0, 20.0),
            ProfilePlane::new(5.0, 40.0),
            ProfilePlane::new(1.0, 60.0),
        ];
        let t = |deg: f64| deg.to_radians().tan();
        assert!((profile_drop(&p, 10.0) - 10.0 * t(20.0)).abs() < 1e-12);
        assert!((profile_drop(&p, 12.0) - 10.0 * t(20.0) - 2.0 * t(40.0)).abs() < 1e-12);
        let far = 10.0 * t(20.0) + 5.0 * t(40.0) + 4.0 * t(60.0);
        assert!((profile_drop(&p, 19.0) - far).abs() < 1e-9);
    }

    #[test]
    fn detrended_plane_is_zero_and_box_is_local() {
        let g = GridGeometry::new(6, 5, 1.0, 1.0, 0.0, 6.0).unwrap();
        let fall = FallLine::from_azimuth(30.0).unwrap();
        let dem = plane_series_dem(g, &fall, 10.0, &[ProfilePlane::new(50.0, 25.0)]).unwrap();
        let flat = detrended(&dem).unwrap();
        assert!(flat.heights().iter().all(|h| h.abs() < 1e-9));
        let b = with_box(&dem, 1..3, 2..4, 1.5).unwrap();
        for r in 0..6 {
            for c in 0..5 {
                let d = b.height(r, c).unwrap() - dem.height(r, c).unwrap();
                let inside = (1..3).contains(&r) && (2..4).contains(&c);
                assert_eq!(d != 0.0, inside);
            }
        }
    }
}
