//! Result rasters in the DEM's grid and CRS (issue 34), for draping over the DEM in a GIS: the
//! stability map as a two-band float32 GeoTIFF ([`rappel_terrain::geotiff_writer`]).
//!
//! A stability map assesses poses on a square grid in the planning frame
//! ([`rappel::stability`]); each pose is mapped back to the DEM's `(east, north)` through the
//! scenario's georeference and falls in one DEM cell (cell `(r, c)` spans `[r, r + 1) x [c, c + 1)`
//! of [`GridGeometry::world_to_grid`]). A cell's values, from the poses in it:
//! - band 1, **verdict**: 1 when every pose in the cell is stable, 0 when one is not (unstable,
//!   beyond the tether, or not assessable);
//! - band 2, **margin**: the smallest stability margin of the cell's poses when all are stable,
//!   else no value;
//! - both bands [`NODATA`] for cells no pose falls in (unassessed: obstacles, outside the map, or
//!   between poses of a grid coarser than the DEM).

use rappel::georeference::Georeference;
use rappel::stability::StabilityReport;
use rappel_terrain::crs::Crs;
use rappel_terrain::geotiff_writer::{GeoTiffImage, GeoTiffWriteError, geotiff_image};
use rappel_terrain::grid::GridGeometry;

/// The no-value marker of exported rasters (GDAL_NODATA).
pub const NODATA: f32 = -9999.0;

/// The two bands of a stability map over `grid` (module docs): `(verdict, margin)`, NaN where
/// no value, and the number of poses that fell outside the grid.
///
/// ```
/// use rappel::dem::dem_scenario;
/// use rappel::stability::{StabilityOptions, stability_over_scenario};
/// use rappel_render::raster_export::stability_bands;
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/terrain/mars_hirise_dteec_010228_1490_crop.asc");
/// let d = dem_scenario(path.as_ref(), &Default::default()).unwrap();
/// let opts = StabilityOptions { grid_step: 4.0, ..Default::default() };
/// let report = stability_over_scenario(d.scenario.validate().unwrap(), &opts).unwrap();
/// let geo = d.scenario.georeference.as_ref().unwrap();
/// let (verdict, margin, outside) = stability_bands(&report, geo, d.grid.geometry());
/// assert_eq!(outside, 0);
/// let cells = verdict.iter().filter(|v| !v.is_nan()).count();
/// assert!(cells > 0 && cells <= report.assessed);
/// // A margin only where the verdict is stable.
/// assert!(verdict.iter().zip(&margin).all(|(v, m)| m.is_nan() || *v == 1.0));
/// ```
pub fn stability_bands(
    report: &StabilityReport,
    geo: &Georeference,
    grid: &GridGeometry,
) -> (Vec<f32>, Vec<f32>, usize) {
    let mut verdict = vec![f32::NAN; grid.len()];
    let mut margin = vec![f32::NAN; grid.len()];
    let mut outside = 0;
    for dot in &report.dots {
        let (r, c) = grid.world_to_grid(&geo.to_world(&dot.point));
        let (r, c) = (r.floor(), c.floor());
        if !(r >= 0.0 && c >= 0.0 && r < grid.nrows as f64 && c < grid.ncols as f64) {
            outside += 1;
            continue;
        }
        let i = grid.index(r as usize, c as usize);
        let first = verdict[i].is_nan();
        match (dot.stable, dot.margin) {
            (true, Some(m)) if first || verdict[i] == 1.0 => {
                verdict[i] = 1.0;
                let m = m as f32;
                margin[i] = if first { m } else { margin[i].min(m) };
            }
            _ => {
                verdict[i] = 0.0;
                margin[i] = f32::NAN;
            }
        }
    }
    (verdict, margin, outside)
}

/// The stability map as a GeoTIFF in the DEM's grid and CRS ([`stability_bands`]; `crs` is the
/// scenario's `georeference.crs`, `None` when the DEM declared none).
pub fn stability_geotiff(
    report: &StabilityReport,
    geo: &Georeference,
    grid: &GridGeometry,
) -> Result<(GeoTiffImage, usize), GeoTiffWriteError> {
    let (verdict, margin, outside) = stability_bands(report, geo, grid);
    let crs = geo.crs.as_deref().and_then(Crs::parse);
    let image = geotiff_image(grid, &[&verdict, &margin], NODATA, crs.as_ref())?;
    Ok((image, outside))
}
