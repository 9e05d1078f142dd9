//! Potential tether friction obstacles detected on a DEM (thesis §3.1.1 and §3.4: "in
//! preprocessing ... this step should also identify PTFOs, and label them as such. This simply
//! means finding any convex terrain, by analyzing the surface curvature as discussed in
//! Subsection 3.3.3").
//!
//! [`detect_ptfos`] takes a height grid, its planning frame and fitted planes (terrain
//! ingestion's) and the planning map (boundary and geometric obstacles), and returns one PTFO
//! outline and surface per patch of convex terrain:
//!
//! 1. The principal curvatures of every cell of the DEM by central differences
//!    ([`crate::curvature::analyze_height_field`]); cells next to unknown heights are not
//!    analysed. A cell is **convex** when both curvatures are below `-min_curvature` (default
//!    [`DEFAULT_CURVATURE_PER_CELL`] over the cell size) (convex in every direction: a hump or a
//!    ridge's crest with some bend along it). The class does not depend on the slope the hump
//!    sits on: the signs of the principal curvatures are those of the height's Hessian (the first
//!    fundamental form is positive definite), and a plane adds nothing to the Hessian.
//!    With [`DetectionOptions::saddles`] a **saddle** cell is a candidate too when the fall line
//!    lies in its convex directions ([`crate::curvature::ConvexDirections`], the re-derived
//!    eq. 3.31): a descending tether runs down the fall line between its anchors, so that is the
//!    direction in which it may press on the saddle; a saddle convex only across the fall line is
//!    left out. The planner then decides each PTFO on the tether's actual contact with the height
//!    patch (Alg. 9), whatever its direction there.
//! 2. Convex cells whose centre lies in free space (not in a geometric obstacle, not outside the
//!    map), 8-connected, make a patch; patches of fewer than `min_cells` cells are dropped.
//! 3. The patch's outline is the convex hull of its cells' corners in the planning frame (the
//!    taut tether only touches the hull, as for geometric obstacles, §2.1.2). A hull that would
//!    make the map invalid (touching a geometric obstacle, another PTFO or the boundary) is
//!    dropped and counted, never silently merged.
//! 4. The PTFO's surface is a height patch in the planning frame ([`HeightPatch`]): nodes at the
//!    DEM's cell size over the hull's box and two nodes beyond, each the DEM's height (bilinear
//!    between cell centres) above the fitted plane under it, measured along the plane's normal.
//!
//! The tether-terrain friction is a physical property the DEM cannot give: whoever turns the
//! detected patches into PTFOs supplies it (the facade's `rappel::dem_ptfo`).

use crate::curvature::{Convexity, CurvatureMap, analyze_height_field};
use crate::ptfo_surface::{HeightPatch, PtfoSurface};
use nalgebra::{DMatrix, Point2};
use rappel_geometry::map::Map;
use rappel_geometry::polygon::{PointInPolygon, Polygon, convex_hull};
use rappel_terrain::frame::PlanningFrame;
use rappel_terrain::grid::HeightGrid;
use rappel_terrain::plane_fit::FittedPlane;

/// Default flatness tolerance of the convexity test, in units of one over the DEM's cell size: a
/// hump must bend with a radius under ten cells in every direction (0.1 1/m on a 1 m HiRISE grid,
/// 0.01 1/m on a 10 m grid). Curvature is measured by differences over neighbouring cells, so the
/// grid resolves nothing much tighter, and the grid's noise bends it at larger radii. Whether a
/// detected patch holds a tether is decided later by the planner (Alg. 8-9), not here.
pub const DEFAULT_CURVATURE_PER_CELL: f64 = 0.1;
/// Default fewest cells of a patch: smaller patches are single-cell noise.
pub const DEFAULT_MIN_CELLS: usize = 4;
/// Most PTFOs detected in one DEM (the largest patches are kept; the rest are counted as
/// dropped): bounds the frictional planner's work.
pub const MAX_PTFOS: usize = 200;
/// Nodes of a PTFO's height patch beyond the hull's box on each side (so the curvature is
/// defined on the outline).
const PATCH_MARGIN_NODES: usize = 2;
/// Most nodes of one height patch (a patch larger than this is coarsened): bounds the scenario's
/// size.
const MAX_PATCH_NODES: usize = 250_000;

/// How to detect PTFOs.
///
/// ```
/// use rappel_mechanics::ptfo_detection::{DetectionOptions, DEFAULT_MIN_CELLS};
/// let o = DetectionOptions::default();
/// assert_eq!(o.min_cells, DEFAULT_MIN_CELLS);
/// assert!(o.validate().is_ok());
/// assert!(DetectionOptions { min_cells: 0, ..o }.validate().is_err());
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DetectionOptions {
    /// Flatness tolerance of the convexity test, 1/m (> 0). Default (`None`):
    /// [`DEFAULT_CURVATURE_PER_CELL`] over the DEM's cell size.
    pub min_curvature: Option<f64>,
    /// Fewest cells of a patch (>= 1). Default [`DEFAULT_MIN_CELLS`].
    pub min_cells: usize,
    /// Also take saddle cells that are convex along the fall line (module docs, step 1).
    /// Default `false`.
    pub saddles: bool,
}

impl Default for DetectionOptions {
    fn default() -> Self {
        DetectionOptions {
            min_curvature: None,
            min_cells: DEFAULT_MIN_CELLS,
            saddles: false,
        }
    }
}

impl DetectionOptions {
    /// Checks the options' ranges: a positive finite tolerance, at least one cell per patch.
    pub fn validate(&self) -> Result<(), DetectionError> {
        if let Some(k) = self.min_curvature
            && !(k.is_finite() && k > 0.0)
        {
            return Err(DetectionError(format!(
                "the curvature tolerance {k} must be positive and finite"
            )));
        }
        if self.min_cells == 0 {
            return Err(DetectionError(
                "the fewest cells of a patch must be at least 1".into(),
            ));
        }
        Ok(())
    }
}

/// An option out of range (the message says which).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct DetectionError(pub String);

/// One detected PTFO: its outline and surface in the planning frame.
#[derive(Debug, Clone, PartialEq)]
pub struct DetectedPtfo {
    /// The convex hull of the patch's cell corners, valid as one more obstacle of the map (after
    /// the PTFOs before it).
    pub hull: Polygon,
    /// The terrain over the hull above the fitted plane (module docs, step 4).
    pub surface: HeightPatch,
    /// Cells of the patch.
    pub cells: usize,
    /// The patch's cells, row-major indices into the grid (what a PTFO label raster marks).
    pub patch: Vec<usize>,
}

/// What [`detect_ptfos`] found.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Detection {
    /// Convex cells in free space.
    pub convex_cells: usize,
    /// Saddle cells in free space convex along the fall line (counted only with
    /// [`DetectionOptions::saddles`]; they join the convex cells' patches).
    pub saddle_cells: usize,
    /// Patches of at least `min_cells` cells.
    pub patches: usize,
    /// The PTFOs, largest patch first; adding their hulls to the map in this order keeps it
    /// valid.
    pub ptfos: Vec<DetectedPtfo>,
    /// Patches dropped because their hull would make the map invalid, or beyond [`MAX_PTFOS`],
    /// or without a usable height patch; with the reason.
    pub dropped: Vec<String>,
}

/// Detects the convex patches of `grid` as PTFOs (module docs): `frame` and `planes` are the
/// planning frame and fitted planes terrain ingestion made of the grid, `map` the planning map
/// the PTFOs join (its boundary and geometric obstacles).
///
/// ```
/// use rappel_mechanics::ptfo_detection::{detect_ptfos, DetectionOptions};
/// use rappel_terrain::{dem::read_dem, ingest::{ingest, IngestOptions}};
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/terrain/mars_hirise_dteec_010228_1490_crop.asc");
/// let grid = read_dem(path).unwrap();
/// let i = ingest(&grid, &IngestOptions::default()).unwrap();
/// let found = detect_ptfos(&grid, &i.frame, &i.plane_fits, &i.map, &DetectionOptions::default()).unwrap();
/// let mut map = i.map.clone();
/// map.obstacles.extend(found.ptfos.iter().map(|p| p.hull.clone()));
/// map.validate().unwrap();
/// ```
pub fn detect_ptfos(
    grid: &HeightGrid,
    frame: &PlanningFrame,
    planes: &[FittedPlane],
    map: &Map,
    options: &DetectionOptions,
) -> Result<Detection, DetectionError> {
    options.validate()?;
    let mut found = Detection::default();
    let patches = convex_patches(grid, frame, map, options, &mut found);
    let mut trial = map.clone();
    for (k, cells) in patches.iter().enumerate() {
        if found.ptfos.len() == MAX_PTFOS {
            found.dropped.push(format!(
                "{} patches beyond the cap of {MAX_PTFOS} PTFOs",
                patches.len() - k
            ));
            break;
        }
        let hull = patch_hull(grid, frame, cells);
        trial.obstacles.push(hull.clone());
        if let Err(e) = trial.validate() {
            trial.obstacles.pop();
            found
                .dropped
                .push(format!("patch of {} cells: {e}", cells.len()));
            continue;
        }
        let Some(surface) = height_patch(grid, frame, planes, &hull) else {
            trial.obstacles.pop();
            found.dropped.push(format!(
                "patch of {} cells: unknown heights around it",
                cells.len()
            ));
            continue;
        };
        let g = grid.geometry();
        found.ptfos.push(DetectedPtfo {
            hull,
            surface,
            cells: cells.len(),
            patch: cells.iter().map(|&(r, c)| g.index(r, c)).collect(),
        });
    }
    Ok(found)
}

/// The curvature tolerance in force: `min_curvature`, else [`DEFAULT_CURVATURE_PER_CELL`] over
/// the grid's cell size.
pub fn tolerance(grid: &HeightGrid, min_curvature: Option<f64>) -> f64 {
    let g = grid.geometry();
    min_curvature.unwrap_or(DEFAULT_CURVATURE_PER_CELL / g.cell_x.max(g.cell_y))
}

/// The principal curvatures of every cell of `grid` and their convexity classes under the
/// tolerance in force (rows north to south, as the grid's); `None` for an unusable tolerance.
pub fn convexity(
    grid: &HeightGrid,
    min_curvature: Option<f64>,
) -> Option<(CurvatureMap, DMatrix<Option<Convexity>>)> {
    let g = grid.geometry();
    let heights = DMatrix::from_fn(g.nrows, g.ncols, |r, c| {
        grid.height(r, c).unwrap_or(f64::NAN)
    });
    let map = analyze_height_field(&heights, g.cell_x, g.cell_y).ok()?;
    let classes = map.classify(tolerance(grid, min_curvature)).ok()?;
    Some((map, classes))
}

/// The convex cells (and with [`DetectionOptions::saddles`] the saddle cells convex along the
/// fall line) in free space, grouped 8-connected into patches of at least `min_cells`,
/// largest first.
fn convex_patches(
    grid: &HeightGrid,
    frame: &PlanningFrame,
    scenario_map: &Map,
    options: &DetectionOptions,
    found: &mut Detection,
) -> Vec<Vec<(usize, usize)>> {
    let g = grid.geometry();
    let Some((map, classes)) = convexity(grid, options.min_curvature) else {
        return Vec::new();
    };
    let tol = tolerance(grid, options.min_curvature);
    // Downhill in the grid's (column, row) frame: rows run south, so north is -y.
    let downhill = {
        let w = frame.to_world(&Point2::new(0.0, 0.0)) - frame.to_world(&Point2::new(0.0, 1.0));
        nalgebra::Vector2::new(w.x, -w.y)
    };
    let saddle_along_fall_line = |r: usize, c: usize| {
        let Some(k) = map.get(r, c) else {
            return false;
        };
        let Ok(Some(dirs)) = k.convex_directions(tol) else {
            return false;
        };
        // The fall line lifted into the tangent plane: z = h_x dx + h_y dy, with the height's
        // gradient from the normal (-h_x, -h_y, 1).
        let n = k.normal.into_inner();
        let (hx, hy) = (-n.x / n.z, -n.y / n.z);
        let t = nalgebra::Vector3::new(downhill.x, downhill.y, hx * downhill.x + hy * downhill.y);
        dirs.contains(&t)
    };
    let free = |r: usize, c: usize| {
        let p = frame.to_planning(&g.cell_center(r, c));
        scenario_map.boundary.locate(&p) == PointInPolygon::Inside
            && scenario_map
                .obstacles
                .iter()
                .all(|o| o.locate(&p) == PointInPolygon::Outside)
    };
    let mut convex = vec![false; g.len()];
    for r in 0..g.nrows {
        for c in 0..g.ncols {
            let class = classes[(r, c)];
            if class == Some(Convexity::Convex) && free(r, c) {
                convex[g.index(r, c)] = true;
                found.convex_cells += 1;
            } else if options.saddles
                && class == Some(Convexity::Saddle)
                && saddle_along_fall_line(r, c)
                && free(r, c)
            {
                convex[g.index(r, c)] = true;
                found.saddle_cells += 1;
            }
        }
    }
    // 8-connected components; each cell is pushed at most once, so the loop is bounded by the
    // grid's size.
    let mut seen = vec![false; g.len()];
    let mut patches = Vec::new();
    for start in 0..g.len() {
        if !convex[start] || seen[start] {
            continue;
        }
        seen[start] = true;
        let mut stack = vec![start];
        let mut cells = Vec::new();
        while let Some(i) = stack.pop() {
            let (r, c) = g.row_col(i);
            cells.push((r, c));
            for dr in -1isize..=1 {
                for dc in -1isize..=1 {
                    let (Some(rr), Some(cc)) = (r.checked_add_signed(dr), c.checked_add_signed(dc))
                    else {
                        continue;
                    };
                    if rr < g.nrows && cc < g.ncols {
                        let j = g.index(rr, cc);
                        if convex[j] && !seen[j] {
                            seen[j] = true;
                            stack.push(j);
                        }
                    }
                }
            }
        }
        if cells.len() >= options.min_cells {
            patches.push(cells);
        }
    }
    found.patches = patches.len();
    patches.sort_by_key(|p| std::cmp::Reverse(p.len()));
    patches
}

/// The convex hull of the patch's cell corners in the planning frame.
fn patch_hull(grid: &HeightGrid, frame: &PlanningFrame, cells: &[(usize, usize)]) -> Polygon {
    let g = grid.geometry();
    let corners: Vec<Point2<f64>> = cells
        .iter()
        .flat_map(|&(r, c)| g.cell_corners(r, c))
        .map(|w| frame.to_planning(&w))
        .collect();
    convex_hull(&corners)
}

/// The fitted plane under horizontal position `s` up the fall line (the one whose range holds it,
/// else the nearest).
fn plane_under(planes: &[FittedPlane], s: f64) -> Option<&FittedPlane> {
    planes
        .iter()
        .find(|p| p.s_bottom <= s && s <= p.s_top)
        .or_else(|| {
            planes.iter().min_by(|a, b| {
                let da = (a.s_bottom - s).abs().min((a.s_top - s).abs());
                let db = (b.s_bottom - s).abs().min((b.s_top - s).abs());
                da.total_cmp(&db)
            })
        })
}

/// The DEM's height at world point `p`, bilinear between cell centres; `None` outside the grid's
/// centres or next to an unknown height.
fn bilinear(grid: &HeightGrid, p: &Point2<f64>) -> Option<f64> {
    let g = grid.geometry();
    let (fr, fc) = g.world_to_grid(p);
    let (y, x) = (fr - 0.5, fc - 0.5);
    if !(x >= 0.0 && y >= 0.0 && x <= (g.ncols - 1) as f64 && y <= (g.nrows - 1) as f64) {
        return None;
    }
    let (r0, c0) = (y.floor() as usize, x.floor() as usize);
    let (r1, c1) = ((r0 + 1).min(g.nrows - 1), (c0 + 1).min(g.ncols - 1));
    let (ty, tx) = (y - r0 as f64, x - c0 as f64);
    let h00 = grid.height(r0, c0)?;
    let h01 = grid.height(r0, c1)?;
    let h10 = grid.height(r1, c0)?;
    let h11 = grid.height(r1, c1)?;
    Some((h00 * (1.0 - tx) + h01 * tx) * (1.0 - ty) + (h10 * (1.0 - tx) + h11 * tx) * ty)
}

/// The height patch of a PTFO with outline `hull` (module docs, step 4).
fn height_patch(
    grid: &HeightGrid,
    frame: &PlanningFrame,
    planes: &[FittedPlane],
    hull: &Polygon,
) -> Option<HeightPatch> {
    let g = grid.geometry();
    let bb = hull.aabb();
    let (w, h) = bb.size();
    let mut spacing = g.cell_x.min(g.cell_y);
    let nodes = |spacing: f64| {
        (
            (w / spacing).ceil() as usize + 1 + 2 * PATCH_MARGIN_NODES,
            (h / spacing).ceil() as usize + 1 + 2 * PATCH_MARGIN_NODES,
        )
    };
    while {
        let (c, r) = nodes(spacing);
        c.saturating_mul(r) > MAX_PATCH_NODES
    } {
        spacing *= 2.0;
    }
    let (cols, rows) = nodes(spacing);
    let origin = Point2::new(
        bb.min.x - PATCH_MARGIN_NODES as f64 * spacing,
        bb.min.y - PATCH_MARGIN_NODES as f64 * spacing,
    );
    let mut heights = Vec::with_capacity(cols * rows);
    for r in 0..rows {
        for c in 0..cols {
            let p = Point2::new(origin.x + c as f64 * spacing, origin.y + r as f64 * spacing);
            let world = frame.to_world(&p);
            let z = bilinear(grid, &world)?;
            let (t, s) = frame.horizontal(&world);
            let plane = plane_under(planes, s)?;
            let grad2 = plane.fall_line_gradient.powi(2) + plane.cross_gradient.powi(2);
            heights.push((z - plane.height(t, s)) / (1.0 + grad2).sqrt());
        }
    }
    let patch = HeightPatch {
        origin,
        spacing,
        cols,
        heights,
    };
    PtfoSurface::HeightField(patch.clone())
        .validate()
        .ok()
        .map(|_| patch)
}
