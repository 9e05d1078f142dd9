//! From a DEM to the ingredients of a planning scenario (thesis §2.1.3: "First, a DEM or other
//! terrain map must be approximated as a series of planes, with tether obstacles identified using
//! the sloped terrain obstacle-detection algorithm ... these obstacles must be further filtered to
//! remove obstacles that sink below the plane"; §2.5.2-2.5.3: obstacle hulls written as a map).
//!
//! [`ingest`] runs the whole pipeline:
//! 1. slope analysis by Horn's method and the fall line ([`crate::slope`]), unless the
//!    fall line is given;
//! 2. the convex plane series along the fall line ([`crate::plane_fit`]) and the unfolded
//!    planning frame ([`crate::frame`]);
//! 3. obstacle detection relative to the plane under each cell
//!    ([`crate::obstacle_detection`]);
//! 4. each cluster replaced by the convex hull of its cells' corners in the planning frame; the
//!    tether obstacles, inside the unfolded sampled footprint of the grid (see
//!    [`crate::frame`]), normalised into a valid [`Map`] ([`rappel_geometry::normalize`] in hull
//!    mode: overlapping hulls merged into the hull of their union, hulls touching the edge carved
//!    out of the boundary); the negative obstacles merged likewise into the separate
//!    robot-obstacle layer;
//! 5. the planes classified tether-free or tether-demand for the given friction
//!    ([`crate::plane_class`]);
//! 6. a suggested start near the top and goal near the bottom, in free space (or the given ones,
//!    checked).
//!
//! Unknown (NODATA) cells are never taken as ground: by default their clusters become tether
//! obstacles too, so that no plan crosses terrain nobody has seen ([`UnknownPolicy`]).

use nalgebra::{Point2, Vector2};
use serde::{Deserialize, Serialize};

use crate::frame::PlanningFrame;
use crate::grid::{GridGeometry, HeightGrid, Raster};
use crate::obstacle_detection::{
    ObstacleDetection, ObstacleError, ObstacleOptions, ReferencePlane, detect_obstacles,
};
use crate::plane_class::{PlaneClass, classify_plane};
use crate::plane_fit::{FittedPlane, PlaneFitError, PlaneFitOptions, fit_plane_series};
use crate::plane_series::{PlaneSeriesError, TerrainPlane, validate_planes};
use crate::slope::{FallLine, HillshadeOptions, SlopeError, SlopeField};
use rappel_geometry::map::{Map, MapError};
use rappel_geometry::normalize::{NormalizeOptions, NormalizeReport, normalize};
use rappel_geometry::polygon::{PointInPolygon, Polygon, convex_hull};

/// Default wheel-terrain friction `mu` (thesis §2.5.4, Fig. 2.36: `mu = 0.4`).
pub const DEFAULT_FRICTION: f64 = 0.4;

/// Suggested start and goal keep this many cells (of the larger cell size) of clearance from the
/// boundary and every obstacle; the search for them steps by one cell.
pub const START_GOAL_MARGIN_CELLS: f64 = 2.0;

/// What unknown (NODATA) regions become in the scenario.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum UnknownPolicy {
    /// Tether obstacles (and so robot obstacles too): no plan crosses them. The default.
    #[default]
    TetherObstacle,
    /// Robot obstacles only: the robot avoids them, the tether may pass over them.
    RobotObstacle,
    /// Neither: they are only reported in [`Ingested::unknown_regions`].
    Ignore,
}

/// Settings of [`ingest`]; every default is documented on its field.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct IngestOptions {
    /// Obstacle detection (defaults: the thesis' `H_min`, `H_max`, `theta_max`).
    pub obstacles: ObstacleOptions,
    /// Plane segmentation.
    pub planes: PlaneFitOptions,
    /// Wheel-terrain friction `mu` of every plane, `>= 0`. Default [`DEFAULT_FRICTION`].
    pub friction: f64,
    /// Compass azimuth (degrees clockwise from north) of the fall line, downhill; `None` (the
    /// default): measured as the mean downhill direction.
    pub fall_line_azimuth_deg: Option<f64>,
    /// What unknown regions become. Default [`UnknownPolicy::TetherObstacle`].
    pub unknown: UnknownPolicy,
    /// Start in the planning frame; `None` (the default): suggested near the top.
    pub start: Option<Point2<f64>>,
    /// Goal in the planning frame; `None` (the default): suggested near the bottom.
    pub goal: Option<Point2<f64>>,
    /// Lighting of the hillshade.
    pub hillshade: HillshadeOptions,
}

impl Default for IngestOptions {
    fn default() -> Self {
        IngestOptions {
            obstacles: ObstacleOptions::default(),
            planes: PlaneFitOptions::default(),
            friction: DEFAULT_FRICTION,
            fall_line_azimuth_deg: None,
            unknown: UnknownPolicy::default(),
            start: None,
            goal: None,
            hillshade: HillshadeOptions::default(),
        }
    }
}

/// Why a DEM could not be turned into a scenario. Each variant's source says how to fix it.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum IngestError {
    /// A friction that is negative or not finite.
    #[error("friction mu = {} must be finite and >= 0", rappel_geometry::compact::Compact(*.0))]
    BadFriction(f64),
    /// No fall line (flat terrain, or no known slope), or a bad fall-line azimuth.
    #[error(transparent)]
    Slope(#[from] SlopeError),
    /// No plane series could be fitted, or bad segmentation options.
    #[error(transparent)]
    PlaneFit(#[from] PlaneFitError),
    /// Bad obstacle-detection parameters.
    #[error(transparent)]
    Obstacles(#[from] ObstacleError),
    /// The plane series came out invalid (a bug: please report it with the DEM).
    #[error("internal error, the fitted plane series is invalid: {0}")]
    PlaneSeries(#[from] PlaneSeriesError),
    /// The map could not be built (obstacles cover the whole grid), or a given start or goal is
    /// not in free space.
    #[error(transparent)]
    Map(#[from] MapError),
    /// No free point with clearance found for a suggested start or goal. Fix: give it explicitly,
    /// or relax obstacle detection.
    #[error(
        "no free {what} point with {margin_m} m of clearance found in the map; give one explicitly"
    )]
    NoFreeEndpoint {
        /// `start` or `goal`.
        what: &'static str,
        /// The clearance sought.
        margin_m: f64,
    },
    /// The grid's relief is implausible: a cell lies more than [`MAX_RELIEF_RATIO`] times the
    /// grid's horizontal extent from the median height (a spike or a corrupted value). Fix: repair
    /// or crop the DEM; mark the cell as no-data.
    #[error(
        "implausible relief: cell (row {row}, col {col}) is at {z:e} m, {offset:e} m from the \
         median height, over {MAX_RELIEF_RATIO} times the grid's extent of {extent_m:.3e} m; \
         bad data? mark it as no-data or crop the DEM"
    )]
    ImplausibleRelief {
        /// Row of the worst cell.
        row: usize,
        /// Column of the worst cell.
        col: usize,
        /// Its height.
        z: f64,
        /// Its distance from the median height.
        offset: f64,
        /// The grid's horizontal diagonal, m.
        extent_m: f64,
    },
}

/// Largest plausible ratio of a height's distance from the grid's median height to the grid's
/// horizontal diagonal. The steepest real walls rise a few times their base; 100 times is
/// unphysical for any DEM and catches spikes (a flipped exponent bit, a 1e12 cell) before the
/// slope and obstacle searches, whose work grows with the relief.
pub const MAX_RELIEF_RATIO: f64 = 100.0;

/// Refuses a grid whose relief is implausible (see [`IngestError::ImplausibleRelief`]).
///
/// ```
/// use rappel_terrain::grid::{GridGeometry, HeightGrid};
/// use rappel_terrain::ingest::{check_relief, IngestError};
/// let g = GridGeometry::new(10, 12, 1.0, 1.0, 0.0, 10.0).unwrap();
/// let mut v = vec![0.0; 120];
/// v[17] = 1e12;
/// let grid = HeightGrid::new(g, v).unwrap();
/// assert!(matches!(check_relief(&grid), Err(IngestError::ImplausibleRelief { row: 1, col: 5, .. })));
/// ```
pub fn check_relief(dem: &HeightGrid) -> Result<(), IngestError> {
    let g = dem.geometry();
    let extent_m =
        ((g.ncols as f64 * g.cell_x).powi(2) + (g.nrows as f64 * g.cell_y).powi(2)).sqrt();
    let mut finite: Vec<f64> = dem
        .heights()
        .iter()
        .copied()
        .filter(|z| z.is_finite())
        .collect();
    if finite.is_empty() {
        return Ok(());
    }
    let mid = finite.len() / 2;
    let (_, median, _) = finite.select_nth_unstable_by(mid, f64::total_cmp);
    let median = *median;
    let worst = dem
        .heights()
        .iter()
        .enumerate()
        .filter(|(_, z)| z.is_finite())
        .max_by(|a, b| (a.1 - median).abs().total_cmp(&(b.1 - median).abs()));
    if let Some((i, &z)) = worst {
        let offset = (z - median).abs();
        if offset > MAX_RELIEF_RATIO * extent_m {
            let (row, col) = g.row_col(i);
            return Err(IngestError::ImplausibleRelief {
                row,
                col,
                z,
                offset,
                extent_m,
            });
        }
    }
    Ok(())
}

/// Everything [`ingest`] makes of a DEM. Polygons and points are in the planning frame (`x` across
/// the slope, `y` up it, metres along the ground); rasters are in the grid's frame.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Ingested {
    /// The grid the rasters are on.
    pub grid: GridGeometry,
    /// The planning map: the unfolded sampled footprint of the grid (the rectangle through the
    /// outer cell centres) and the tether obstacles, normalised (valid: [`Map::validate`] passes).
    pub map: Map,
    /// The plane series, top first, with the friction given.
    pub planes: Vec<TerrainPlane>,
    /// The fitted planes behind [`Ingested::planes`], in the same order.
    pub plane_fits: Vec<FittedPlane>,
    /// Tether-free / tether-demand class of each plane, in the same order.
    pub plane_classes: Vec<PlaneClass>,
    /// Number of merges made to make the series convex.
    pub convexity_merges: usize,
    /// The robot-obstacle layer: hulls of negative obstacles (and of unknown regions under
    /// [`UnknownPolicy::RobotObstacle`]), merged where they overlap. Not clipped to the map.
    pub robot_obstacles: Vec<Polygon>,
    /// Hulls of unknown (NODATA) regions, merged where they overlap, whatever the policy.
    pub unknown_regions: Vec<Polygon>,
    /// Start (suggested or given).
    pub start: Point2<f64>,
    /// Goal (suggested or given).
    pub goal: Point2<f64>,
    /// The transform between world and planning coordinates.
    pub frame: PlanningFrame,
    /// The fall line used.
    pub fall_line: FallLine,
    /// Slope per cell, degrees.
    pub slope_deg: Raster,
    /// Aspect per cell (azimuth of the downhill direction), degrees.
    pub aspect_deg: Raster,
    /// Hillshade per cell, in `[0, 1]`.
    pub hillshade: Raster,
    /// Per-cell detection result and clusters.
    pub detection: ObstacleDetection,
    /// What normalisation of the tether obstacles changed.
    pub normalize_report: NormalizeReport,
}

/// The counts that summarise an ingestion (for tables and golden files).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct IngestSummary {
    /// Planes in the series.
    pub planes: usize,
    /// Tether-free planes.
    pub tether_free_planes: usize,
    /// Tether-demand planes.
    pub tether_demand_planes: usize,
    /// Obstacle points (cells with a compatible partner).
    pub obstacle_points: usize,
    /// Clusters of raised cells.
    pub tether_clusters: usize,
    /// Tether obstacles in the map, after merging and carving.
    pub tether_obstacles: usize,
    /// Clusters of sunken cells.
    pub robot_clusters: usize,
    /// Polygons of the robot-obstacle layer.
    pub robot_obstacles: usize,
    /// Unknown regions.
    pub unknown_regions: usize,
}

impl Ingested {
    /// The summary counts.
    pub fn summary(&self) -> IngestSummary {
        let free = self
            .plane_classes
            .iter()
            .filter(|&&c| c == PlaneClass::TetherFree)
            .count();
        IngestSummary {
            planes: self.planes.len(),
            tether_free_planes: free,
            tether_demand_planes: self.planes.len() - free,
            obstacle_points: self.detection.classes.len()
                - self
                    .detection
                    .count(crate::obstacle_detection::CellClass::Ground)
                - self
                    .detection
                    .count(crate::obstacle_detection::CellClass::Unknown),
            tether_clusters: self.detection.tether_clusters.len(),
            tether_obstacles: self.map.obstacles.len(),
            robot_clusters: self.detection.robot_clusters.len(),
            robot_obstacles: self.robot_obstacles.len(),
            unknown_regions: self.unknown_regions.len(),
        }
    }

    /// Fractional grid `(row, col)` of a planning-frame point (to draw over the rasters).
    pub fn planning_to_grid(&self, p: &Point2<f64>) -> (f64, f64) {
        self.grid.world_to_grid(&self.frame.to_world(p))
    }

    /// The edges between consecutive planes as world segments across the grid (to draw over the
    /// rasters), top first.
    pub fn plane_edges_world(&self) -> Vec<[Point2<f64>; 2]> {
        self.plane_fits
            .iter()
            .skip(1)
            .filter_map(|p| self.frame.level_line_in_grid(&self.grid, p.s_top))
            .collect()
    }
}

/// The convex hull, in the planning frame, of the corners of the given cells.
fn cluster_hull(g: &GridGeometry, frame: &PlanningFrame, cells: &[usize]) -> Polygon {
    let pts: Vec<Point2<f64>> = cells
        .iter()
        .flat_map(|&i| {
            let (r, c) = g.row_col(i);
            g.cell_corners(r, c)
        })
        .map(|w| frame.to_planning(&w))
        .collect();
    convex_hull(&pts)
}

/// Normalisation in hull mode (thesis §2.1.2: obstacles replaced by their convex hulls; overlapping
/// hulls merged into the hull of their union), carving hulls that touch the boundary out of it.
const HULL_MODE: NormalizeOptions = NormalizeOptions {
    convex_hulls: true,
    carve_boundary: true,
};

/// Merges overlapping polygons of a layer (hull mode), inside a frame that holds them all.
fn merge_layer(polys: Vec<Polygon>) -> Result<Vec<Polygon>, MapError> {
    if polys.is_empty() {
        return Ok(polys);
    }
    Ok(normalize(&Map::framing(polys), &HULL_MODE)?.0.obstacles)
}

/// `true` when `p` and the eight points at distance `margin` around it are in the map's free
/// space and outside every robot obstacle.
fn clear(map: &Map, robot: &[Polygon], p: Point2<f64>, margin: f64) -> bool {
    let around = (0..8).map(|k| {
        let a = f64::from(k) * std::f64::consts::FRAC_PI_4;
        p + Vector2::new(a.cos(), a.sin()) * margin
    });
    std::iter::once(p).chain(around).all(|q| {
        map.free_space_violation(&q).is_none()
            && robot
                .iter()
                .all(|o| !o.aabb().contains(&q) || o.locate(&q) == PointInPolygon::Outside)
    })
}

/// A clear point, searching along vertical lines from the middle of the map outwards, each from the
/// top down (`from_top`) or the bottom up.
fn suggest(
    map: &Map,
    robot: &[Polygon],
    from_top: bool,
    step: f64,
    margin: f64,
) -> Option<Point2<f64>> {
    let b = map.aabb();
    let xc = 0.5 * (b.min.x + b.max.x);
    let half = ((b.max.x - b.min.x) / (2.0 * step)).ceil() as i64;
    let rows = ((b.max.y - b.min.y - 2.0 * margin) / step).floor().max(0.0) as i64;
    for k in 0..=2 * half {
        let off = if k % 2 == 1 { (k + 1) / 2 } else { -(k / 2) };
        let x = xc + off as f64 * step;
        for j in 0..=rows {
            let y = if from_top {
                b.max.y - margin - j as f64 * step
            } else {
                b.min.y + margin + j as f64 * step
            };
            let p = Point2::new(x, y);
            if clear(map, robot, p, margin) {
                return Some(p);
            }
        }
    }
    None
}

/// Turns a DEM into the ingredients of a planning scenario (see the module docs).
///
/// ```
/// use rappel_terrain::grid::GridGeometry;
/// use rappel_terrain::ingest::{ingest, IngestOptions};
/// use rappel_terrain::plane_class::PlaneClass;
/// use rappel_terrain::slope::FallLine;
/// use rappel_terrain::synthetic::{plane_series_dem, with_box, ProfilePlane};
/// let g = GridGeometry::new(60, 40, 1.0, 1.0, 0.0, 60.0).unwrap();
/// let south = FallLine::from_azimuth(180.0).unwrap();
/// let wall = plane_series_dem(g, &south, 300.0, &[ProfilePlane::new(100.0, 45.0)]).unwrap();
/// let dem = with_box(&wall, 20..24, 18..22, 1.0).unwrap(); // a boulder
/// let out = ingest(&dem, &IngestOptions::default()).unwrap();
/// out.map.validate().unwrap();
/// assert_eq!(out.planes.len(), 1);
/// assert!((out.planes[0].slope_deg - 45.0).abs() < 0.5);
/// assert_eq!(out.plane_classes[0], PlaneClass::TetherDemand);
/// assert_eq!(out.map.obstacles.len(), 1);
/// assert!(out.start.y > out.goal.y);
/// ```
pub fn ingest(dem: &HeightGrid, options: &IngestOptions) -> Result<Ingested, IngestError> {
    if !(options.friction.is_finite() && options.friction >= 0.0) {
        return Err(IngestError::BadFriction(options.friction));
    }
    options.obstacles.validate()?;
    options.planes.validate()?;
    check_relief(dem)?;
    let g = *dem.geometry();

    // 1. Slopes and the fall line.
    let slope = SlopeField::horn(dem);
    let fall_line = match options.fall_line_azimuth_deg {
        Some(a) => FallLine::from_azimuth(a)?,
        None => slope.fall_line()?,
    };

    // 2. Planes and the unfolded frame.
    let flat_frame = PlanningFrame::for_grid(&g, &fall_line);
    let fit = fit_plane_series(dem, &flat_frame, &options.planes)?;
    let bottom_up: Vec<FittedPlane> = fit.planes.iter().rev().copied().collect();
    let frame = flat_frame.unfolded(
        &bottom_up
            .iter()
            .map(|p| (p.s_bottom, p.slope_deg()))
            .collect::<Vec<_>>(),
    );
    let planes: Vec<TerrainPlane> = fit
        .planes
        .iter()
        .map(|p| TerrainPlane {
            y_top: frame.unfold(p.s_top),
            y_bottom: frame.unfold(p.s_bottom),
            slope_deg: p.slope_deg(),
            friction: options.friction,
        })
        .collect();
    validate_planes(&planes)?;
    let plane_classes = planes
        .iter()
        .map(|p| classify_plane(p.slope_deg, p.friction))
        .collect();

    // 3. Obstacles, relative to the plane under each cell.
    let reference = |r: usize, c: usize| {
        let (t, s) = frame.horizontal(&g.cell_center(r, c));
        let p = &bottom_up[frame.piece_index(s)];
        ReferencePlane {
            gradient: frame.uphill * p.fall_line_gradient + frame.across * p.cross_gradient,
            height: p.height(t, s),
        }
    };
    let detection = detect_obstacles(dem, reference, &options.obstacles)?;

    // 4. Hulls, the map and the robot-obstacle layer.
    let hulls = |clusters: &[Vec<usize>]| -> Vec<Polygon> {
        clusters
            .iter()
            .map(|k| cluster_hull(&g, &frame, k))
            .collect()
    };
    let unknown = hulls(&detection.unknown_clusters);
    let mut tether = hulls(&detection.tether_clusters);
    let mut robot = hulls(&detection.robot_clusters);
    match options.unknown {
        UnknownPolicy::TetherObstacle => tether.extend(unknown.iter().cloned()),
        UnknownPolicy::RobotObstacle => robot.extend(unknown.iter().cloned()),
        UnknownPolicy::Ignore => {}
    }
    let raw = Map::new(Polygon::new(frame.footprint(&g)), tether);
    let (map, mut normalize_report) = normalize(&raw, &HULL_MODE)?;
    // A hull touching two edges of the boundary is listed twice.
    normalize_report.carved_into_boundary.dedup();
    let robot_obstacles = merge_layer(robot)?;
    let unknown_regions = merge_layer(unknown)?;

    // 6. Start and goal.
    let step = g.cell_size();
    let margin = START_GOAL_MARGIN_CELLS * step;
    let endpoint = |what: &'static str, given: Option<Point2<f64>>, from_top: bool| match given {
        Some(p) => map
            .validate_point(what, &p)
            .map(|_| p)
            .map_err(IngestError::from),
        None => suggest(&map, &robot_obstacles, from_top, step, margin).ok_or(
            IngestError::NoFreeEndpoint {
                what,
                margin_m: margin,
            },
        ),
    };
    let start = endpoint("start", options.start, true)?;
    let goal = endpoint("goal", options.goal, false)?;
    if options.goal.is_none() && goal.y >= start.y {
        return Err(IngestError::NoFreeEndpoint {
            what: "goal",
            margin_m: margin,
        });
    }

    Ok(Ingested {
        grid: g,
        map,
        planes,
        plane_fits: fit.planes,
        plane_classes,
        convexity_merges: fit.convexity_merges,
        robot_obstacles,
        unknown_regions,
        start,
        goal,
        frame,
        fall_line,
        slope_deg: slope.slope_deg(),
        aspect_deg: slope.aspect_deg(),
        hillshade: slope.hillshade(&options.hillshade),
        detection,
        normalize_report,
    })
}
