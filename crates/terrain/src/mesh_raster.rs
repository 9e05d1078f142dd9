//! A triangle mesh rasterised to a height grid (issue 34: meshes into planning), so the OBJ, PLY
//! and STL terrain that `rappel settle` reads can become a DEM for `rappel dem`.
//!
//! The rule ([`rasterize_mesh`]):
//! - **grid**: square cells of the given size over the mesh's plan bounding box, the north-west
//!   corner at `(min x, max y)`; the mesh's `x` is east, `y` north, `z` up (as `settle` reads
//!   them), so the last column and row may reach past the mesh by less than a cell;
//! - **height**: at each cell's centre, the **highest surface** of the mesh on the vertical
//!   there ([`crate::mesh::vertical_hit`]: exact plan inclusion, edges and corners included,
//!   height by the triangle's plane); an overhang counts by its top;
//! - **holes**: a cell whose centre no triangle covers (outside the mesh's outline, a hole in it,
//!   or under vertical walls only) is unknown (NODATA), never zero or interpolated.
//!
//! The work is bounded before it starts: the grid within [`DemLimits`] and the triangles' box
//! visits within [`MAX_RASTER_VISITS`].

use crate::grid::{DemLimits, GridError, GridGeometry, HeightGrid};
use crate::mesh::{TriMesh, vertical_hit};
use nalgebra::Point3;

/// Most (triangle, cell) pairs visited (each triangle visits the cells whose centres lie in its
/// plan bounding box): 2^30, about a minute of work. A mesh of long thin triangles over a fine
/// grid goes beyond it; a coarser cell size brings it under.
pub const MAX_RASTER_VISITS: u64 = 1 << 30;

/// Why a mesh could not be rasterised.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MeshRasterError {
    /// The cell size is not a positive finite number.
    #[error("cell size {0}: it must be a positive finite number of metres")]
    Cell(f64),
    /// The grid over the mesh is not a valid grid or is over the work cap.
    #[error("the grid over the mesh at this cell size: {0}")]
    Grid(#[from] GridError),
    /// Too many (triangle, cell) visits.
    #[error(
        "rasterising visits {visits} (triangle, cell) pairs, over the cap of {MAX_RASTER_VISITS}; give a larger cell size"
    )]
    TooMuchWork {
        /// The visits the triangles' boxes need.
        visits: u64,
    },
    /// No cell centre is covered by the mesh.
    #[error(
        "no cell centre lies under the mesh at this cell size (a mesh of vertical walls only, or cells larger than the mesh); give a smaller cell size"
    )]
    NoHeights,
}

/// The mesh as a height grid of `cell` metre cells (module docs).
///
/// ```
/// use nalgebra::Point3;
/// use rappel_terrain::grid::DemLimits;
/// use rappel_terrain::mesh::TriMesh;
/// use rappel_terrain::mesh_raster::rasterize_mesh;
/// // A 4 m x 2 m ramp rising 0.5 m per metre eastwards.
/// let v = [(0.0, 0.0), (4.0, 0.0), (4.0, 2.0), (0.0, 2.0)]
///     .map(|(x, y)| Point3::new(x, y, 0.5 * x));
/// let ramp = TriMesh::new(v.to_vec(), vec![[0, 1, 2], [0, 2, 3]]).unwrap();
/// let g = rasterize_mesh(&ramp, 1.0, &DemLimits::default()).unwrap();
/// assert_eq!((g.geometry().nrows, g.geometry().ncols), (2, 4));
/// // Cell (0, 1) has its centre at x = 1.5: height 0.75.
/// assert_eq!(g.height(0, 1), Some(0.75));
/// assert!(rasterize_mesh(&ramp, 0.0, &DemLimits::default()).is_err());
/// ```
pub fn rasterize_mesh(
    mesh: &TriMesh,
    cell: f64,
    limits: &DemLimits,
) -> Result<HeightGrid, MeshRasterError> {
    if !(cell.is_finite() && cell > 0.0) {
        return Err(MeshRasterError::Cell(cell));
    }
    let (lo, hi) = mesh.bounds();
    let count = |extent: f64| ((extent / cell).ceil() as usize).max(1);
    let (ncols, nrows) = (count(hi.x - lo.x), count(hi.y - lo.y));
    let g = GridGeometry::new(nrows, ncols, cell, cell, lo.x, hi.y)?;
    limits.check(&g)?;
    // The cell centres in a triangle's plan box: columns and rows, clamped to the grid.
    let span = |a: f64, b: f64, n: usize| -> (usize, usize) {
        let first = (a / cell - 0.5).ceil().max(0.0) as usize;
        let last = ((b / cell - 0.5).floor().max(-1.0) + 1.0) as usize;
        (first.min(n), last.min(n))
    };
    let boxes = |t: usize| {
        let [a, b, c] = mesh.corners(t);
        let (x0, x1) = (a.x.min(b.x).min(c.x), a.x.max(b.x).max(c.x));
        let (y0, y1) = (a.y.min(b.y).min(c.y), a.y.max(b.y).max(c.y));
        // Rows count southwards from the north edge.
        (
            span(x0 - g.west, x1 - g.west, ncols),
            span(g.north - y1, g.north - y0, nrows),
        )
    };
    let triangles = mesh.triangles().len();
    // One pass to bound the work, one to do it; both over the mesh's triangles (at most
    // `mesh::MAX_TRIANGLES`).
    let visits: u64 = (0..triangles)
        .map(|t| {
            let ((c0, c1), (r0, r1)) = boxes(t);
            (c1.saturating_sub(c0) as u64) * (r1.saturating_sub(r0) as u64)
        })
        .sum();
    if visits > MAX_RASTER_VISITS {
        return Err(MeshRasterError::TooMuchWork { visits });
    }
    let top = hi.z + 1.0;
    let mut heights = vec![f64::NAN; g.len()];
    for t in 0..triangles {
        let ((c0, c1), (r0, r1)) = boxes(t);
        for r in r0..r1 {
            for c in c0..c1 {
                let p = g.cell_center(r, c);
                let q = Point3::new(p.x, p.y, top);
                if let Some(z) = vertical_hit(&q, true, [t], |t| mesh.corners(t)) {
                    let h = &mut heights[g.index(r, c)];
                    if h.is_nan() || z > *h {
                        *h = z;
                    }
                }
            }
        }
    }
    if heights.iter().all(|h| h.is_nan()) {
        return Err(MeshRasterError::NoHeights);
    }
    Ok(HeightGrid::new(g, heights)?)
}
