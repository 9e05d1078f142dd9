//! Obstacle detection on slopes (thesis §2.1.2-2.1.3 and §2.5.2, after Abad-Manterola's algorithm
//! for obstacle detection on a slope \[58\], itself built on the extreme-terrain algorithm of
//! Manduchi et al. \[97\]).
//!
//! **Manduchi's rule, measured in the slope's frame.** Two known cells `p` and `q` are *compatible*
//! (part of one obstacle) when, with `v` the 3D vector from `p` to `q` and `n` the unit normal of
//! the fitted plane of the series under `p` (Abad-Manterola: the slope, not gravity, is the
//! reference for a tethered rover),
//! - their height difference across the plane lies between the parameters:
//!   `H_min < |v . n| < H_max`, and
//! - the line joining them is steeper than `theta_max` relative to the plane:
//!   `|v . n| > |v| sin(theta_max)`.
//!
//! A cell with a compatible partner is an *obstacle point*. The search for partners only looks as
//! far as a compatible pair can be, `|v| < H_max / sin(theta_max)`. Defaults are the thesis' values
//! (§2.5.2): `H_min = 0.2 m`, `H_max = 2 m`, `theta_max = 40 deg`.
//!
//! *Unsampled faces.* Manduchi's range data sample the face of a tall obstacle, and chains of
//! compatible points climb it; a DEM has no samples between two neighbouring cells, so a step
//! taller than `H_max` between neighbours would go unseen. With
//! [`ObstacleOptions::bridge_unsampled_faces`] (default on), two 8-neighbours that pass the angle
//! and `H_min` tests are also compatible when their height difference exceeds `H_max`: the face
//! between them would have supplied the chain.
//!
//! **Positive and negative obstacles** (§2.1.2: "negative obstacles that sink below the plane of
//! the ground, such as potholes and craters ... pose no obstacle to the tether"). Each obstacle
//! point is compared with the local ground: the least-squares plane through the known cells of a
//! window around it that are neither obstacle points nor enclosed by them, like the flat top of a
//! boulder or the floor of a pit (window half-width
//! [`ObstacleOptions::ground_window_m`]; with fewer than [`MIN_GROUND_CELLS`] such cells, the plane
//! of the series is used instead). A point at least `RAISED_FRACTION_OF_H_MIN * H_min` above that
//! ground (measured perpendicular to it) *rises above the plane* ([`CellClass::Raised`]); as far
//! below, it is *sunken* ([`CellClass::Sunken`]); in between it is the foot of an obstacle, level
//! with the ground ([`CellClass::Foot`]), and belongs to neither.
//!
//! **Clusters.** Raised cells, 8-connected, form the tether obstacles; sunken cells, 8-connected,
//! the robot obstacles (the separate robot-obstacle layer); unknown (NODATA) cells, 8-connected,
//! the unknown regions. The planning map replaces each cluster by its convex hull (§2.1.2: the taut
//! tether only touches reflex vertices), see [`crate::ingest`].

use nalgebra::Vector2;
use serde::{Deserialize, Serialize};

use crate::grid::{GridGeometry, HeightGrid};
use crate::least_squares::PlaneStats;

/// Default `H_min`, metres (thesis §2.5.2): smaller height differences are not obstacles.
pub const DEFAULT_H_MIN_M: f64 = 0.2;
/// Default `H_max`, metres (thesis §2.5.2): the height of Manduchi's truncated search cone.
pub const DEFAULT_H_MAX_M: f64 = 2.0;
/// Default `theta_max`, degrees (thesis §2.5.2): the steepest slant, relative to the slope, that
/// is not an obstacle.
pub const DEFAULT_THETA_MAX_DEG: f64 = 40.0;
/// Default half-width of the window of the local ground plane, metres.
pub const DEFAULT_GROUND_WINDOW_M: f64 = 10.0;
/// The ground window is at least this many cells each side of the cell, whatever the cell size.
pub const MIN_GROUND_WINDOW_CELLS: usize = 2;
/// Fewest ground cells (known, not obstacle points) in the window for a local ground plane; with
/// fewer, the plane of the series is the ground.
pub const MIN_GROUND_CELLS: usize = 6;
/// Largest radius, in cells, of the search for compatible partners (`H_max / sin(theta_max)` over
/// the cell size). A finer grid, or a larger `H_max`, is refused
/// ([`ObstacleError::SearchTooWide`]) rather than left to run for hours: resample the DEM or lower
/// `H_max`.
pub const MAX_SEARCH_RADIUS_CELLS: usize = 32;
/// Largest half-width, in cells, of the local ground window; wider windows are clamped to it.
pub const MAX_GROUND_WINDOW_CELLS: usize = 64;
/// An obstacle point rises above (sinks below) the ground when it is at least this fraction of
/// `H_min` above (below) it; closer, it is the foot of an obstacle.
pub const RAISED_FRACTION_OF_H_MIN: f64 = 0.5;

/// Parameters of obstacle detection (defaults: the thesis' values, §2.5.2).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ObstacleOptions {
    /// `H_min`, metres, `> 0`. Default [`DEFAULT_H_MIN_M`].
    pub h_min_m: f64,
    /// `H_max`, metres, `> H_min`. Default [`DEFAULT_H_MAX_M`].
    pub h_max_m: f64,
    /// `theta_max`, degrees in `(0, 90)`. Default [`DEFAULT_THETA_MAX_DEG`].
    pub theta_max_deg: f64,
    /// Treat steps taller than `H_max` between neighbouring cells as obstacles (see the module
    /// docs). Default `true`.
    pub bridge_unsampled_faces: bool,
    /// Half-width of the local ground window, metres, `> 0`. Default [`DEFAULT_GROUND_WINDOW_M`].
    pub ground_window_m: f64,
    /// Clusters of raised or sunken cells smaller than this are dropped. Default 1 (keep all).
    pub min_cluster_cells: usize,
}

impl Default for ObstacleOptions {
    fn default() -> Self {
        ObstacleOptions {
            h_min_m: DEFAULT_H_MIN_M,
            h_max_m: DEFAULT_H_MAX_M,
            theta_max_deg: DEFAULT_THETA_MAX_DEG,
            bridge_unsampled_faces: true,
            ground_window_m: DEFAULT_GROUND_WINDOW_M,
            min_cluster_cells: 1,
        }
    }
}

/// An unusable detection parameter.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ObstacleError {
    /// The compatibility cone spans too many cells (see [`MAX_SEARCH_RADIUS_CELLS`]).
    #[error(
        "H_max / sin(theta_max) = {reach_m:.3} m spans {cells} cells of the grid, more than {MAX_SEARCH_RADIUS_CELLS}: resample the DEM or lower H_max"
    )]
    SearchTooWide {
        /// The cone's reach, metres.
        reach_m: f64,
        /// Cells it spans.
        cells: usize,
    },
    /// A parameter outside its range.
    #[error("obstacle detection parameter {name} = {} must be {requirement}", rappel_geometry::compact::Compact(*.value))]
    BadParameter {
        /// The parameter.
        name: &'static str,
        /// Its value.
        value: f64,
        /// Its range.
        requirement: &'static str,
    },
}

impl ObstacleOptions {
    /// Checks the ranges documented on each field.
    pub fn validate(&self) -> Result<(), ObstacleError> {
        let bad = |name, value, requirement| {
            Err(ObstacleError::BadParameter {
                name,
                value,
                requirement,
            })
        };
        if !(self.h_min_m.is_finite() && self.h_min_m > 0.0) {
            return bad("H_min", self.h_min_m, "positive and finite");
        }
        if !(self.h_max_m.is_finite() && self.h_max_m > self.h_min_m) {
            return bad("H_max", self.h_max_m, "finite and larger than H_min");
        }
        if !(self.theta_max_deg > 0.0 && self.theta_max_deg < 90.0) {
            return bad("theta_max", self.theta_max_deg, "in (0, 90) degrees");
        }
        if !(self.ground_window_m.is_finite() && self.ground_window_m > 0.0) {
            return bad("ground_window", self.ground_window_m, "positive and finite");
        }
        Ok(())
    }
}

/// The plane of the series under a cell: its world gradient `(dz/d east, dz/d north)` and its
/// height at the cell's centre.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReferencePlane {
    /// World gradient of the plane.
    pub gradient: Vector2<f64>,
    /// The plane's height at the cell centre.
    pub height: f64,
}

/// What detection made of a cell.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum CellClass {
    /// NODATA.
    Unknown,
    /// Known, not an obstacle point.
    Ground,
    /// An obstacle point level with the local ground (the foot of an obstacle).
    Foot,
    /// An obstacle point rising above the local ground: part of a tether obstacle.
    Raised,
    /// An obstacle point sunk below the local ground: part of a negative (robot) obstacle.
    Sunken,
}

/// The result of detection: a class per cell and the clusters, each a sorted list of row-major
/// cell indices, clusters in the row-major order of their first cell.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ObstacleDetection {
    /// The grid.
    pub geometry: GridGeometry,
    /// Row-major class of every cell.
    pub classes: Vec<CellClass>,
    /// Number of compatible pairs found.
    pub compatible_pairs: usize,
    /// Clusters of raised cells: the tether obstacles.
    pub tether_clusters: Vec<Vec<usize>>,
    /// Clusters of sunken cells: the negative obstacles, for the robot-obstacle layer.
    pub robot_clusters: Vec<Vec<usize>>,
    /// Clusters of unknown cells.
    pub unknown_clusters: Vec<Vec<usize>>,
}

impl ObstacleDetection {
    /// Number of cells of class `class`.
    pub fn count(&self, class: CellClass) -> usize {
        self.classes.iter().filter(|&&c| c == class).count()
    }
}

/// 8-connected components of the cells for which `member(index)` holds, each sorted, in the
/// row-major order of their first cell.
///
/// ```
/// use rappel_terrain::grid::GridGeometry;
/// use rappel_terrain::obstacle_detection::connected_components;
/// let g = GridGeometry::new(3, 4, 1.0, 1.0, 0.0, 3.0).unwrap();
/// // x . . x
/// // . x . x
/// // . . . .
/// let on = [0, 3, 5, 7];
/// let cc = connected_components(&g, |i| on.contains(&i));
/// assert_eq!(cc, vec![vec![0, 5], vec![3, 7]]);
/// ```
pub fn connected_components(g: &GridGeometry, member: impl Fn(usize) -> bool) -> Vec<Vec<usize>> {
    let mut seen = vec![false; g.len()];
    let mut out = Vec::new();
    let mut stack = Vec::new();
    for start in 0..g.len() {
        if seen[start] || !member(start) {
            continue;
        }
        seen[start] = true;
        stack.push(start);
        let mut comp = Vec::new();
        while let Some(i) = stack.pop() {
            comp.push(i);
            let (r, c) = g.row_col(i);
            for dr in -1isize..=1 {
                for dc in -1isize..=1 {
                    let (rr, cc) = (r as isize + dr, c as isize + dc);
                    if rr < 0 || cc < 0 || rr >= g.nrows as isize || cc >= g.ncols as isize {
                        continue;
                    }
                    let j = g.index(rr as usize, cc as usize);
                    if !seen[j] && member(j) {
                        seen[j] = true;
                        stack.push(j);
                    }
                }
            }
        }
        comp.sort_unstable();
        out.push(comp);
    }
    out
}

/// One neighbour offset of the compatibility search.
struct Offset {
    dr: usize,
    dc: isize,
    /// East and north components of the horizontal offset.
    dx: f64,
    dy: f64,
    adjacent: bool,
}

/// The forward half of the search window (each unordered pair visited once).
fn search_offsets(g: &GridGeometry, o: &ObstacleOptions) -> Result<Vec<Offset>, ObstacleError> {
    let reach = o.h_max_m / o.theta_max_deg.to_radians().sin();
    let cells = (reach / g.cell_x.min(g.cell_y)).floor();
    if cells > MAX_SEARCH_RADIUS_CELLS as f64 {
        return Err(ObstacleError::SearchTooWide {
            reach_m: reach,
            cells: cells as usize,
        });
    }
    let floor_cells =
        |cell: f64| ((reach / cell).floor() as usize).max(usize::from(o.bridge_unsampled_faces));
    let (rx, ry) = (
        floor_cells(g.cell_x).min(g.ncols) as isize,
        floor_cells(g.cell_y).min(g.nrows),
    );
    let mut out = Vec::new();
    for dr in 0..=ry {
        let first = if dr == 0 { 1 } else { -rx };
        for dc in first..=rx {
            let (dx, dy) = (dc as f64 * g.cell_x, -(dr as f64) * g.cell_y);
            let adjacent = dr <= 1 && dc.abs() <= 1;
            if dx * dx + dy * dy < reach * reach || (adjacent && o.bridge_unsampled_faces) {
                out.push(Offset {
                    dr,
                    dc,
                    dx,
                    dy,
                    adjacent,
                });
            }
        }
    }
    Ok(out)
}

/// Cells that are not ground for the local ground planes: obstacle points, and the cells they
/// enclose (the flat top of a boulder, the floor of a pit), i.e. those not reachable from the
/// grid's border by 4-connected steps through non-obstacle cells.
fn not_ground(g: &GridGeometry, point: &[bool]) -> Vec<bool> {
    let mut reached = vec![false; g.len()];
    let mut stack: Vec<usize> = Vec::new();
    let visit = |i: usize, reached: &mut Vec<bool>, stack: &mut Vec<usize>| {
        if !point[i] && !reached[i] {
            reached[i] = true;
            stack.push(i);
        }
    };
    for r in 0..g.nrows {
        visit(g.index(r, 0), &mut reached, &mut stack);
        visit(g.index(r, g.ncols - 1), &mut reached, &mut stack);
    }
    for c in 0..g.ncols {
        visit(g.index(0, c), &mut reached, &mut stack);
        visit(g.index(g.nrows - 1, c), &mut reached, &mut stack);
    }
    while let Some(i) = stack.pop() {
        let (r, c) = g.row_col(i);
        if r > 0 {
            visit(i - g.ncols, &mut reached, &mut stack);
        }
        if r + 1 < g.nrows {
            visit(i + g.ncols, &mut reached, &mut stack);
        }
        if c > 0 {
            visit(i - 1, &mut reached, &mut stack);
        }
        if c + 1 < g.ncols {
            visit(i + 1, &mut reached, &mut stack);
        }
    }
    reached.into_iter().map(|r| !r).collect()
}

/// Height of cell `(r, c)` above its local ground, perpendicular to the ground (see the module
/// docs), given which cells are not ground.
fn height_above_ground(
    dem: &HeightGrid,
    excluded: &[bool],
    r: usize,
    c: usize,
    (wx, wy): (usize, usize),
    reference: &impl Fn(usize, usize) -> ReferencePlane,
) -> f64 {
    let g = dem.geometry();
    let zp = dem.height(r, c).unwrap_or(0.0);
    let mut st = PlaneStats::default();
    for rr in r.saturating_sub(wy)..=(r + wy).min(g.nrows - 1) {
        for cc in c.saturating_sub(wx)..=(c + wx).min(g.ncols - 1) {
            if excluded[g.index(rr, cc)] {
                continue;
            }
            if let Some(z) = dem.height(rr, cc) {
                let dx = (cc as f64 - c as f64) * g.cell_x;
                let dy = (r as f64 - rr as f64) * g.cell_y;
                st.add(dx, dy, z - zp);
            }
        }
    }
    if st.count() >= MIN_GROUND_CELLS
        && let Some(ground) = st.fit()
    {
        let tilt = (1.0 + ground.grad_u.powi(2) + ground.grad_v.powi(2)).sqrt();
        return -ground.height(0.0, 0.0) / tilt;
    }
    let plane = reference(r, c);
    (zp - plane.height) / (1.0 + plane.gradient.norm_squared()).sqrt()
}

/// Detects obstacles on `dem` (see the module docs); `reference(row, col)` gives the plane of the
/// series under each cell.
///
/// ```
/// use nalgebra::Vector2;
/// use rappel_terrain::grid::GridGeometry;
/// use rappel_terrain::obstacle_detection::{detect_obstacles, ObstacleOptions, ReferencePlane};
/// use rappel_terrain::slope::FallLine;
/// use rappel_terrain::synthetic::{plane_series_dem, with_box, ProfilePlane};
/// let g = GridGeometry::new(30, 30, 1.0, 1.0, 0.0, 30.0).unwrap();
/// let south = FallLine::from_azimuth(180.0).unwrap();
/// let slope = plane_series_dem(g, &south, 100.0, &[ProfilePlane::new(100.0, 30.0)]).unwrap();
/// let boulder = with_box(&slope, 10..14, 12..15, 1.0).unwrap();
/// let tan = 30f64.to_radians().tan();
/// let plane = |r: usize, c: usize| ReferencePlane {
///     gradient: Vector2::new(0.0, tan),
///     height: slope.height(r, c).unwrap(),
/// };
/// let found = detect_obstacles(&boulder, plane, &ObstacleOptions::default()).unwrap();
/// assert_eq!(found.tether_clusters.len(), 1);
/// assert!(found.robot_clusters.is_empty());
/// ```
pub fn detect_obstacles(
    dem: &HeightGrid,
    reference: impl Fn(usize, usize) -> ReferencePlane,
    options: &ObstacleOptions,
) -> Result<ObstacleDetection, ObstacleError> {
    options.validate()?;
    let g = *dem.geometry();
    let heights = dem.heights();
    let sin_t = options.theta_max_deg.to_radians().sin();
    let sin2 = sin_t * sin_t;
    let offsets = search_offsets(&g, options)?;
    let mut point = vec![false; g.len()];
    let mut compatible_pairs = 0usize;
    for r in 0..g.nrows {
        for c in 0..g.ncols {
            let ip = g.index(r, c);
            let zp = heights[ip];
            if zp.is_nan() {
                continue;
            }
            let grad = reference(r, c).gradient;
            let norm = (1.0 + grad.norm_squared()).sqrt();
            let (nx, ny, nz) = (-grad.x / norm, -grad.y / norm, 1.0 / norm);
            for o in &offsets {
                let (rq, cq) = (r + o.dr, c as isize + o.dc);
                if rq >= g.nrows || cq < 0 || cq >= g.ncols as isize {
                    continue;
                }
                let iq = g.index(rq, cq as usize);
                let zq = heights[iq];
                if zq.is_nan() {
                    continue;
                }
                let dz = zq - zp;
                let across = (nx * o.dx + ny * o.dy + nz * dz).abs();
                if across <= options.h_min_m {
                    continue;
                }
                let len2 = o.dx * o.dx + o.dy * o.dy + dz * dz;
                if across * across <= len2 * sin2 {
                    continue;
                }
                if across >= options.h_max_m && !(o.adjacent && options.bridge_unsampled_faces) {
                    continue;
                }
                compatible_pairs += 1;
                point[ip] = true;
                point[iq] = true;
            }
        }
    }

    let window = |cell: f64| {
        ((options.ground_window_m / cell)
            .ceil()
            .min(MAX_GROUND_WINDOW_CELLS as f64) as usize)
            .max(MIN_GROUND_WINDOW_CELLS)
    };
    let w = (window(g.cell_x), window(g.cell_y));
    let threshold = RAISED_FRACTION_OF_H_MIN * options.h_min_m;
    let excluded = not_ground(&g, &point);
    let classes: Vec<CellClass> = (0..g.len())
        .map(|i| {
            if heights[i].is_nan() {
                return CellClass::Unknown;
            }
            if !point[i] {
                return CellClass::Ground;
            }
            let (r, c) = g.row_col(i);
            let h = height_above_ground(dem, &excluded, r, c, w, &reference);
            if h >= threshold {
                CellClass::Raised
            } else if h <= -threshold {
                CellClass::Sunken
            } else {
                CellClass::Foot
            }
        })
        .collect();
    let clusters = |class: CellClass, min: usize| {
        let mut cc = connected_components(&g, |i| classes[i] == class);
        cc.retain(|k| k.len() >= min);
        cc
    };
    Ok(ObstacleDetection {
        geometry: g,
        tether_clusters: clusters(CellClass::Raised, options.min_cluster_cells),
        robot_clusters: clusters(CellClass::Sunken, options.min_cluster_cells),
        unknown_clusters: clusters(CellClass::Unknown, 1),
        classes,
        compatible_pairs,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn options_are_checked() {
        let ok = ObstacleOptions::default();
        assert!(ok.validate().is_ok());
        for (o, name) in [
            (ObstacleOptions { h_min_m: 0.0, ..ok }, "H_min"),
            (ObstacleOptions { h_max_m: 0.1, ..ok }, "H_max"),
            (
                ObstacleOptions {
                    theta_max_deg: 90.0,
                    ..ok
                },
                "theta_max",
            ),
            (
                ObstacleOptions {
                    ground_window_m: f64::NAN,
                    ..ok
                },
                "ground_window",
            ),
        ] {
            assert!(
                matches!(o.validate(), Err(ObstacleError::BadParameter { name: n, .. }) if n == name)
            );
        }
    }

    #[test]
    fn search_window_reaches_exactly_the_cone() {
        let g = GridGeometry::new(50, 50, 1.0, 1.0, 0.0, 50.0).unwrap();
        let o = ObstacleOptions::default();
        let reach = 2.0 / 40f64.to_radians().sin(); // 3.11 m
        let offs = search_offsets(&g, &o).unwrap();
        assert!(
            offs.iter()
                .all(|k| (k.dx * k.dx + k.dy * k.dy).sqrt() < reach)
        );
        // Every forward offset within the reach is there: the count of lattice points of the half
        // disc (excluding the centre).
        let mut n = 0;
        for dr in 0..=3i32 {
            for dc in -3i32..=3 {
                if (dr > 0 || dc > 0) && ((dr * dr + dc * dc) as f64) < reach * reach {
                    n += 1;
                }
            }
        }
        assert_eq!(offs.len(), n);
        // A 10 m grid cannot hold a compatible pair within the cone: only the bridging neighbours.
        let coarse = GridGeometry::new(5, 5, 10.0, 10.0, 0.0, 50.0).unwrap();
        assert_eq!(search_offsets(&coarse, &o).unwrap().len(), 4);
        let no_bridge = ObstacleOptions {
            bridge_unsampled_faces: false,
            ..o
        };
        assert_eq!(search_offsets(&coarse, &no_bridge).unwrap().len(), 0);
        // A 5 cm grid would need a window of 62 cells each way: refused.
        let fine = GridGeometry::new(5, 5, 0.05, 0.05, 0.0, 50.0).unwrap();
        assert!(matches!(
            search_offsets(&fine, &o),
            Err(ObstacleError::SearchTooWide { cells: 62, .. })
        ));
    }
}
