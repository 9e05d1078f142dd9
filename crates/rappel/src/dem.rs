//! From a digital elevation model to a planning scenario (thesis §2.1.2-2.1.3, §2.5.1-2.5.2; the
//! work of `rappel dem`): read the grid, ingest it (fall line, plane series, obstacle detection on
//! slopes, normalised convex obstacles in the unfolded frame), wrap the result as a [`Scenario`],
//! and draw it over a hillshade.

use crate::georeference::Georeference;
use crate::scenario::{RobotParams, Scenario, Terrain};
use rappel_terrain::dem::{DemError, read_dem_crs, read_dem_with};
use rappel_terrain::grid::{DemLimits, HeightGrid};
use rappel_terrain::ingest::{IngestError, IngestOptions, IngestSummary, Ingested, ingest};
use rappel_terrain::plane_class::PlaneClass;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Why a DEM could not become a scenario.
#[derive(Debug, thiserror::Error)]
pub enum DemScenarioError {
    /// The file could not be read or decoded.
    #[error(transparent)]
    Read(#[from] DemError),
    /// The grid could not be ingested.
    #[error("{path}: {source}")]
    Ingest {
        /// The file.
        path: String,
        /// The cause.
        source: IngestError,
    },
    /// A fitted plane is steeper than the planner's slope domain (`plan` and `stability` accept
    /// slopes up to [`rappel_mechanics::robot::MAX_SLOPE`], 89 degrees): no scenario is written.
    #[error(
        "{path}: plane {plane} is {slope_deg:.3} degrees steep, beyond the {max_deg} degrees that \
         `rappel plan` accepts; no scenario written"
    )]
    TooSteep {
        /// The file.
        path: String,
        /// Plane index (0 = top).
        plane: usize,
        /// Its slope, degrees.
        slope_deg: f64,
        /// The limit, degrees.
        max_deg: f64,
    },
}

/// One plane of a DEM scenario in `rappel dem`'s report.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct DemPlaneReport {
    /// Index, 0 at the top.
    pub index: usize,
    /// Slope, degrees.
    pub slope_deg: f64,
    /// Band top in the planning frame, m.
    pub y_top_m: f64,
    /// Band bottom, m.
    pub y_bottom_m: f64,
    /// Wheel friction.
    pub friction: f64,
    /// Tether-free or tether-demand.
    pub class: rappel_terrain::plane_class::PlaneClass,
}

/// What `rappel dem --json` prints: everything its text shows.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct DemReport {
    /// The DEM file read.
    pub dem: String,
    /// The scenario file written.
    pub scenario: String,
    /// Azimuth of the fall line, degrees clockwise from north.
    pub fall_line_azimuth_deg: f64,
    /// The planes, top first.
    pub planes: Vec<DemPlaneReport>,
    /// The ingestion's counts.
    pub counts: IngestSummary,
    /// PTFO labelling, when asked for (`--ptfo-friction`).
    pub ptfos: Option<PtfoLabels>,
    /// The CRS recorded in the scenario, in one line (`EPSG:32610`, `PROJCS "Mars ..."`), or
    /// the local grid results are written in when the DEM declared none.
    #[serde(default)]
    pub crs: String,
    /// What was read but not used, one message each (GeoKeys the CRS does not take: vertical
    /// CRS keys, unused projection parameters, a non-metre unit).
    #[serde(default)]
    pub warnings: Vec<String>,
    /// The start, `[x, y]` in the planning frame.
    #[schemars(with = "[f64; 2]")]
    pub start: nalgebra::Point2<f64>,
    /// The goal.
    #[schemars(with = "[f64; 2]")]
    pub goal: nalgebra::Point2<f64>,
}

crate::report::report!(DemReport, "dem");

/// A scenario made from a DEM, with what ingestion found.
pub struct DemScenario {
    /// The scenario (map, start, goal, planes).
    pub scenario: Scenario,
    /// Everything ingestion computed (rasters, frame, robot obstacles, reports).
    pub ingested: Ingested,
    /// The elevation model read (for analyses after ingestion, e.g. PTFO labelling).
    pub grid: HeightGrid,
    /// What the DEM's file holds that was not used, one message each naming the file and the
    /// key ([`rappel_terrain::dem::DemCrs::ignored`]); callers show them as warnings.
    pub warnings: Vec<String>,
    /// The cells of each labelled PTFO (row-major indices into [`DemScenario::grid`]), in the
    /// order of the scenario's `friction.ptfos`; empty until
    /// [`crate::dem_ptfo::label_ptfos`] labels them.
    pub ptfo_cells: Vec<Vec<usize>>,
}

impl DemScenario {
    /// Counts for printing and golden files.
    pub fn summary(&self) -> IngestSummary {
        self.ingested.summary()
    }

    /// Each terrain plane with its class, in order down the slope.
    pub fn classified_planes(
        &self,
    ) -> impl Iterator<Item = (&rappel_terrain::plane_series::TerrainPlane, PlaneClass)> + '_ {
        self.scenario
            .terrain
            .planes
            .iter()
            .zip(self.ingested.plane_classes.iter().copied())
    }

    /// The CRS results are written in, in one line: the scenario's (`EPSG:n`, `PROJCS "name"`)
    /// or the local grid named [`rappel_terrain::crs::UNKNOWN_CRS_NAME`] when the DEM declared
    /// none.
    pub fn crs_written(&self) -> String {
        let crs = self
            .scenario
            .georeference
            .as_ref()
            .and_then(|g| g.crs.as_deref());
        crs.and_then(rappel_terrain::crs::Crs::parse)
            .unwrap_or_else(|| {
                rappel_terrain::crs::Crs::local(rappel_terrain::crs::UNKNOWN_CRS_NAME)
            })
            .describe()
    }

    /// The report of `rappel dem`: the DEM `dem` turned into the scenario file `scenario`, with
    /// the PTFO labelling `ptfos` when it was asked for.
    pub fn report(&self, dem: &Path, scenario: &Path, ptfos: Option<PtfoLabels>) -> DemReport {
        let s = &self.scenario;
        DemReport {
            dem: dem.display().to_string(),
            scenario: scenario.display().to_string(),
            fall_line_azimuth_deg: crate::report::round_to(
                self.ingested.frame.fall_line_azimuth_deg(),
                crate::report::ANGLE_DECIMALS,
            ),
            planes: self
                .classified_planes()
                .enumerate()
                .map(|(index, (p, class))| DemPlaneReport {
                    index,
                    slope_deg: crate::report::round_to(p.slope_deg, crate::report::ANGLE_DECIMALS),
                    y_top_m: p.y_top,
                    y_bottom_m: p.y_bottom,
                    friction: p.friction,
                    class,
                })
                .collect(),
            counts: self.summary(),
            ptfos,
            crs: self.crs_written(),
            warnings: self.warnings.clone(),
            start: s.start,
            goal: s.goal,
        }
    }
}

/// Reads the DEM at `path` and turns it into a scenario.
///
/// ```
/// use rappel::dem::dem_scenario;
/// use rappel::terrain::ingest::IngestOptions;
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/terrain/mars_hirise_dteec_010228_1490_crop.asc");
/// let d = dem_scenario(path.as_ref(), &IngestOptions::default()).unwrap();
/// d.scenario.validate().unwrap();
/// assert!(!d.scenario.terrain.planes.is_empty());
/// ```
pub fn dem_scenario(path: &Path, options: &IngestOptions) -> Result<DemScenario, DemScenarioError> {
    dem_scenario_with(path, options, &DemLimits::default())
}

/// [`dem_scenario`] with the readers' work cap and size checks set by `limits` (see
/// [`DemLimits`]; `rappel dem --max-cells`).
///
/// ```
/// use rappel::dem::dem_scenario_with;
/// use rappel::terrain::grid::DemLimits;
/// use rappel::terrain::ingest::IngestOptions;
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/terrain/mars_hirise_dteec_010228_1490_crop.asc");
/// let tight = DemLimits::with_max_cells(100).unwrap();
/// let Err(err) = dem_scenario_with(path.as_ref(), &IngestOptions::default(), &tight) else {
///     panic!("a grid of 8,400 cells is over a cap of 100");
/// };
/// assert!(err.to_string().contains("--max-cells"));
/// ```
pub fn dem_scenario_with(
    path: &Path,
    options: &IngestOptions,
    limits: &DemLimits,
) -> Result<DemScenario, DemScenarioError> {
    let grid = read_dem_with(path, limits)?;
    let crs = read_dem_crs(path)?;
    file_scenario(grid, path, crs.crs, &crs.ignored, options)
}

/// [`dem_scenario_of_grid`] of the grid read from the file at `path` (its stem the scenario's
/// name), with the file's keys not used (`ignored`) as warnings naming it.
fn file_scenario(
    grid: HeightGrid,
    path: &Path,
    crs: Option<String>,
    ignored: &[String],
    options: &IngestOptions,
) -> Result<DemScenario, DemScenarioError> {
    let name = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let mut d = dem_scenario_of_grid(grid, &path.display().to_string(), &name, crs, options)?;
    d.warnings = ignored
        .iter()
        .map(|w| format!("{}: {w}", path.display()))
        .collect();
    Ok(d)
}

/// Why a mesh or a point cloud could not become a scenario.
#[cfg(feature = "mesh")]
#[derive(Debug, thiserror::Error)]
pub enum GriddedDemError {
    /// The mesh file could not be read.
    #[error(transparent)]
    Read(#[from] rappel_terrain::mesh_file::MeshFileError),
    /// The point cloud could not be read or gridded.
    #[error(transparent)]
    PointCloud(#[from] rappel_terrain::point_cloud::PointCloudError),
    /// A CRS was given for a file that declares its own.
    #[error("{path} declares its CRS ({declared}); the CRS given is for files that declare none")]
    CrsConflict {
        /// The file.
        path: String,
        /// What it declares, in one line.
        declared: String,
    },
    /// The mesh could not be rasterised.
    #[error("{path}: {source}")]
    Raster {
        /// The file.
        path: String,
        /// The cause.
        source: rappel_terrain::mesh_raster::MeshRasterError,
    },
    /// The height grid could not become a scenario.
    #[error(transparent)]
    Scenario(#[from] DemScenarioError),
}

/// A scenario from a lidar point cloud (LAS or LAZ): the points gridded to `cell` metre cells
/// by `statistic` (the max of a cell's heights, or their mean), cells without a point unknown
/// ([`rappel_terrain::point_cloud`]), then ingested as a DEM. The CRS is the file's (its WKT or
/// GeoTIFF-key records; keys not used become [`DemScenario::warnings`]), else `crs`; both is an
/// error. As for a mesh, the georeference names the file: write the grid as a GeoTIFF and point
/// the georeference at it to export results (`rappel dem` does).
///
/// ```
/// use rappel::dem::point_cloud_dem_scenario;
/// use rappel::terrain::{grid::DemLimits, point_cloud::Statistic};
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/lidar/boulder_slope_utm10n.laz");
/// let d = point_cloud_dem_scenario(path.as_ref(), 1.0, Statistic::Max, None, &Default::default(), &DemLimits::default()).unwrap();
/// assert_eq!(d.scenario.georeference.unwrap().crs.as_deref(), Some("EPSG:32610"));
/// ```
#[cfg(feature = "mesh")]
pub fn point_cloud_dem_scenario(
    path: &Path,
    cell: f64,
    statistic: rappel_terrain::point_cloud::Statistic,
    crs: Option<String>,
    options: &IngestOptions,
    limits: &DemLimits,
) -> Result<DemScenario, GriddedDemError> {
    let pc = rappel_terrain::point_cloud::read_point_cloud(path, cell, statistic, limits)?;
    let crs = match (pc.crs, crs) {
        (Some(declared), Some(_)) => {
            return Err(GriddedDemError::CrsConflict {
                path: path.display().to_string(),
                declared: rappel_terrain::crs::Crs::parse(&declared)
                    .map_or(declared, |c| c.describe()),
            });
        }
        (a, b) => a.or(b),
    };
    Ok(file_scenario(pc.grid, path, crs, &pc.ignored, options)?)
}

/// A scenario from a terrain mesh (OBJ, PLY or STL, as `rappel settle` reads them; `x` east,
/// `y` north, `z` up): the mesh rasterised to `cell` metre cells, the highest surface at each
/// cell's centre, holes unknown ([`rappel_terrain::mesh_raster`]), then ingested as a DEM. `crs`
/// is the mesh's coordinate reference system when the caller knows it (a mesh file declares
/// none). The scenario's georeference names the mesh; write the grid
/// ([`DemScenario::grid`]) as a GeoTIFF and point the georeference at it to export results in
/// its grid (`rappel dem` does).
///
/// ```
/// use rappel::dem::mesh_dem_scenario;
/// use rappel::terrain::grid::DemLimits;
/// let dir = std::env::temp_dir().join("rappel-doc-mesh-dem");
/// std::fs::create_dir_all(&dir).unwrap();
/// let path = dir.join("wall.obj");
/// // A 40 m x 60 m wall rising 0.8 m per metre northwards, two triangles.
/// std::fs::write(&path, "v 0 0 0\nv 40 0 0\nv 40 60 48\nv 0 60 48\nf 1 2 3\nf 1 3 4\n").unwrap();
/// let d = mesh_dem_scenario(&path, 1.0, Some("EPSG:32610".into()), &Default::default(), &DemLimits::default()).unwrap();
/// assert_eq!(d.grid.geometry().ncols, 40);
/// assert_eq!(d.scenario.georeference.unwrap().crs.as_deref(), Some("EPSG:32610"));
/// ```
#[cfg(feature = "mesh")]
pub fn mesh_dem_scenario(
    path: &Path,
    cell: f64,
    crs: Option<String>,
    options: &IngestOptions,
    limits: &DemLimits,
) -> Result<DemScenario, GriddedDemError> {
    let mesh = rappel_terrain::mesh_file::read_mesh(path)?;
    let grid =
        rappel_terrain::mesh_raster::rasterize_mesh(&mesh, cell, limits).map_err(|source| {
            GriddedDemError::Raster {
                path: path.display().to_string(),
                source,
            }
        })?;
    Ok(file_scenario(grid, path, crs, &[], options)?)
}

/// [`dem_scenario`] of a grid already in memory (the Python package hands over a 2-D height
/// array and its geotransform, as rasterio reads them): `source` names the grid in messages and
/// in the scenario's georeference (`dem`), `name` becomes the scenario's name, and `crs` is the
/// grid's coordinate reference system, if known. The same ingest, the same checks and the same
/// scenario as from a file.
///
/// ```
/// use rappel::dem::dem_scenario_of_grid;
/// use rappel::terrain::grid::{GridGeometry, HeightGrid};
/// use rappel::terrain::ingest::IngestOptions;
/// // A 40 m x 60 m wall rising 0.8 m per metre northwards, 1 m cells.
/// let g = GridGeometry::new(60, 40, 1.0, 1.0, 0.0, 60.0).unwrap();
/// let grid = HeightGrid::from_fn(g, |_, _, p| Some(0.8 * p.y)).unwrap();
/// let d = dem_scenario_of_grid(grid, "wall", "wall", None, &IngestOptions::default()).unwrap();
/// d.scenario.validate().unwrap();
/// assert_eq!(d.scenario.name, "wall");
/// ```
pub fn dem_scenario_of_grid(
    grid: HeightGrid,
    source: &str,
    name: &str,
    crs: Option<String>,
    options: &IngestOptions,
) -> Result<DemScenario, DemScenarioError> {
    let ingested = ingest(&grid, options).map_err(|e| DemScenarioError::Ingest {
        path: source.to_string(),
        source: e,
    })?;
    let max_deg = rappel_mechanics::robot::MAX_SLOPE.to_degrees();
    if let Some((plane, p)) = ingested
        .planes
        .iter()
        .enumerate()
        .find(|(_, p)| p.slope_deg.is_nan() || p.slope_deg > max_deg)
    {
        return Err(DemScenarioError::TooSteep {
            path: source.to_string(),
            plane,
            slope_deg: p.slope_deg,
            max_deg,
        });
    }
    let s = ingested.summary();
    let scenario = Scenario {
        name: name.to_string(),
        description: format!(
            "Ingested from {} by rappel dem: {} planes ({} tether-demand), {} tether obstacles, {} robot obstacles (H_min {} m, H_max {} m, theta_max {} deg, mu {}).",
            source,
            s.planes,
            s.tether_demand_planes,
            s.tether_obstacles,
            s.robot_obstacles,
            options.obstacles.h_min_m,
            options.obstacles.h_max_m,
            options.obstacles.theta_max_deg,
            options.friction
        ),
        map: ingested.map.clone(),
        start: ingested.start,
        goal: ingested.goal,
        robot: RobotParams::default(),
        terrain: Terrain {
            planes: ingested.planes.clone(),
        },
        friction: None,
        georeference: Some(Georeference {
            dem: source.to_string(),
            crs,
            frame: ingested.frame.clone(),
        }),
    };
    Ok(DemScenario {
        scenario,
        ingested,
        grid,
        warnings: Vec::new(),
        ptfo_cells: Vec::new(),
    })
}

/// The planning-frame outline of the `step` x `step` block of cells whose north-west cell is
/// `(r, c)` (clipped to the grid): how DEM pictures draw subsampled cells.
pub fn block_footprint(
    d: &DemScenario,
    r: usize,
    c: usize,
    step: usize,
) -> Vec<nalgebra::Point2<f64>> {
    let g = d.grid.geometry();
    let (r1, c1) = (
        (r + step.max(1) - 1).min(g.nrows - 1),
        (c + step.max(1) - 1).min(g.ncols - 1),
    );
    [
        g.cell_corners(r, c)[0],
        g.cell_corners(r, c1)[1],
        g.cell_corners(r1, c1)[2],
        g.cell_corners(r1, c)[3],
    ]
    .iter()
    .map(|w| d.ingested.frame.to_planning(w))
    .collect()
}

/// What [`crate::dem_ptfo::label_ptfos`] did.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct PtfoLabels {
    /// Convex cells in free space.
    pub convex_cells: usize,
    /// Saddle cells in free space convex along the fall line (counted only with
    /// [`crate::dem_ptfo::PtfoLabelOptions::saddles`]; they join the convex cells' patches).
    pub saddle_cells: usize,
    /// Patches of at least `min_cells` cells.
    pub patches: usize,
    /// PTFOs added to the scenario.
    pub ptfos: usize,
    /// Cells of each PTFO's patch, in the order of the scenario's `friction.ptfos` (PTFO `k`
    /// is label `k + 1` in `rappel dem --geotiff`'s band 2).
    #[serde(default)]
    pub cells: Vec<usize>,
    /// Patches dropped because their hull would make the map invalid, or beyond [`crate::dem_ptfo::MAX_PTFOS`],
    /// or without a usable height patch; with the reason.
    pub dropped: Vec<String>,
}
