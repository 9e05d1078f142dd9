//! Result rasters in the DEM's grid and CRS (issue 34), for draping over the DEM in a GIS, as
//! float32 GeoTIFFs ([`rappel_terrain::geotiff_writer`]): the stability map
//! ([`stability_geotiff`]), `rappel dem`'s obstacle mask and PTFO labels ([`dem_geotiff`]) and
//! `settle-map`'s verdicts and margins ([`settle_map_geotiff`], in the map's own grid).
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

use rappel::dem::DemScenario;
use rappel::georeference::Georeference;
use rappel::stability::StabilityReport;
use rappel_terrain::crs::Crs;
use rappel_terrain::geotiff_writer::{GeoTiffImage, GeoTiffWriteError, geotiff_image};
use rappel_terrain::grid::GridGeometry;
use rappel_terrain::obstacle_detection::CellClass;

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

/// The code of each obstacle-detection class in band 1 of [`dem_geotiff`] (thesis §2.1.2-2.1.3):
/// 0 ground, 1 an obstacle's foot, 2 raised (a tether obstacle's cell), 3 sunken (a robot
/// obstacle's cell); unknown heights have no value ([`NODATA`]).
pub fn mask_code(class: CellClass) -> f32 {
    match class {
        CellClass::Unknown => f32::NAN,
        CellClass::Ground => 0.0,
        CellClass::Foot => 1.0,
        CellClass::Raised => 2.0,
        CellClass::Sunken => 3.0,
    }
}

/// The two bands of `rappel dem --geotiff`, in the DEM's grid: band 1 the obstacle mask
/// ([`mask_code`] of each cell's detected class), band 2 the PTFO labels: `k` on the cells of
/// the scenario's `k`-th PTFO (1 = `friction.ptfos[0]`), 0 on other known cells, no value on
/// unknown heights and everywhere when PTFOs were not labelled (`labelled` false: not assessed).
///
/// ```
/// use rappel::dem::dem_scenario;
/// use rappel::dem_ptfo::{label_ptfos, PtfoLabelOptions};
/// use rappel::ptfo_spec::FrictionRange;
/// use rappel_render::raster_export::dem_bands;
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/terrain/mars_hirise_dteec_010228_1490_crop.asc");
/// let mut d = dem_scenario(path.as_ref(), &Default::default()).unwrap();
/// let labels = label_ptfos(&mut d, &PtfoLabelOptions::with_friction(FrictionRange { lo: 0.4, hi: 0.6 })).unwrap();
/// let (mask, ptfo) = dem_bands(&d, true);
/// let obstacle_cells = mask.iter().filter(|v| **v > 0.0).count();
/// assert_eq!(obstacle_cells, d.summary().obstacle_points);
/// for (k, cells) in labels.cells.iter().enumerate() {
///     assert_eq!(ptfo.iter().filter(|v| **v == (k + 1) as f32).count(), *cells);
/// }
/// ```
pub fn dem_bands(d: &DemScenario, labelled: bool) -> (Vec<f32>, Vec<f32>) {
    let mask: Vec<f32> = d
        .ingested
        .detection
        .classes
        .iter()
        .map(|c| mask_code(*c))
        .collect();
    let mut ptfo = vec![f32::NAN; mask.len()];
    // Loops over the DEM's cells (within its reader's cell cap) and the PTFOs' cells (each cell
    // in at most one patch).
    if labelled {
        for (i, v) in ptfo.iter_mut().enumerate() {
            let (r, c) = d.grid.geometry().row_col(i);
            if d.grid.height(r, c).is_some() {
                *v = 0.0;
            }
        }
        for (k, cells) in d.ptfo_cells.iter().enumerate() {
            for &i in cells {
                if let Some(v) = ptfo.get_mut(i) {
                    *v = (k + 1) as f32;
                }
            }
        }
    }
    (mask, ptfo)
}

/// [`dem_bands`] as a GeoTIFF in the DEM's grid and the scenario's CRS.
pub fn dem_geotiff(d: &DemScenario, labelled: bool) -> Result<GeoTiffImage, GeoTiffWriteError> {
    let (mask, ptfo) = dem_bands(d, labelled);
    let crs = d
        .scenario
        .georeference
        .as_ref()
        .and_then(|g| g.crs.as_deref())
        .and_then(Crs::parse);
    geotiff_image(d.grid.geometry(), &[&mask, &ptfo], NODATA, crs.as_ref())
}

/// The local frame a `settle-map` over a Paton scene is written in: the scene has no CRS.
pub const SCENE_FRAME_NAME: &str =
    "rappel Paton scene frame (x down the slope, y along the ledge), metres; no CRS";

/// The local frame a `settle-map` over a mesh file is written in: a mesh declares no CRS.
pub const MESH_FRAME_NAME: &str =
    "mesh coordinates (x, y), metres; CRS unknown (a mesh declares none)";

/// The grid of a `settle-map`: one cell per pose, centred on the pose's ground point (cell
/// `(row, col)` holds the pose `i = col`, `j = ny - 1 - row`: rows run north, i.e. down `y`).
#[cfg(feature = "mesh")]
pub fn settle_map_grid(
    map: &rappel::settle_map::StabilityMap,
) -> Result<GridGeometry, rappel_terrain::grid::GridError> {
    let s = map.spec.step;
    GridGeometry::new(
        map.ny,
        map.nx,
        s,
        s,
        map.spec.x.0 - 0.5 * s,
        map.spec.y.0 + (map.ny as f64 - 0.5) * s,
    )
}

/// The two bands of a `settle-map` in [`settle_map_grid`]: band 1 the verdict (1 stable in some
/// boom configuration, 0 settled with its anchors known but not stable), band 2 the best margin
/// of a stable cell; no value where the pose did not settle, its anchor history could not be
/// predicted or the map stopped before it (not assessed).
#[cfg(feature = "mesh")]
pub fn settle_map_bands(map: &rappel::settle_map::StabilityMap) -> (Vec<f32>, Vec<f32>) {
    let n = map.nx * map.ny;
    let (mut verdict, mut margin) = (vec![f32::NAN; n], vec![f32::NAN; n]);
    // One pass over the map's cells (at most `MAX_MAP_CELLS`).
    for (k, cell) in map.cells.iter().enumerate().take(n) {
        let (i, j) = (k % map.nx, k / map.nx);
        let out = (map.ny - 1 - j) * map.nx + i;
        if let Some(p) = &cell.pose {
            verdict[out] = if p.stable { 1.0 } else { 0.0 };
            if p.stable {
                margin[out] = p.margin as f32;
            }
        }
    }
    (verdict, margin)
}

/// A `settle-map` as a GeoTIFF in its own grid ([`settle_map_grid`], [`settle_map_bands`]) and
/// `crs`: the DEM's when the ground is an elevation model, else the local frame the caller
/// names (a Paton scene or a mesh has none).
///
/// ```
/// use rappel::settle_map::{MapSpec, stability_map};
/// use rappel::planners::anchor_prediction::AnchorHistory;
/// use rappel::terrain::paton_scene::PatonScene;
/// use rappel_render::raster_export::{settle_map_bands, settle_map_grid};
/// let scene = PatonScene::paper(false);
/// let ground = scene.mesh().unwrap();
/// let spec = MapSpec { x: (-1.0, 0.0), y: (-0.5, 0.5), step: 0.5, yaw_deg: 0.0, start: [-1.0, 0.0] };
/// let root = AnchorHistory::new(scene.anchor_points()[0]).unwrap();
/// let map = stability_map(&ground, &root, &spec).unwrap();
/// let g = settle_map_grid(&map).unwrap();
/// assert_eq!((g.ncols, g.nrows), (3, 3));
/// // The pose at (x, y) = (-1, 0.5) is in the top row, first column.
/// assert_eq!(map.cells[2 * 3].ground, [-1.0, 0.5]);
/// let (verdict, _) = settle_map_bands(&map);
/// let expected = map.cells[2 * 3].pose.as_ref().map_or(f32::NAN, |p| p.stable as u8 as f32);
/// assert!(verdict[0] == expected || (verdict[0].is_nan() && expected.is_nan()));
/// ```
#[cfg(feature = "mesh")]
pub fn settle_map_geotiff(
    map: &rappel::settle_map::StabilityMap,
    crs: &Crs,
) -> Result<GeoTiffImage, GeoTiffWriteError> {
    let grid = settle_map_grid(map)
        .map_err(|e| GeoTiffWriteError::Shape(format!("the settle-map's grid: {e}")))?;
    let (verdict, margin) = settle_map_bands(map);
    geotiff_image(&grid, &[&verdict, &margin], NODATA, Some(crs))
}
