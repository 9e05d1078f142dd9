//! Height grids (thesis §2.1.2, §2.5.1): a regular grid of heights over a georeferenced
//! rectangle ([`GridGeometry`], [`HeightGrid`], and [`Raster`] for any per-cell value), with
//! unknown (NODATA) cells kept unknown, the checks a grid's shape must pass ([`GridError`]) and the
//! work cap a reader may take on ([`DemLimits`]). The readers ([`crate::esri_ascii`],
//! [`crate::geotiff`], [`crate::dem::read_dem`]) build on this module; it knows nothing of files.
//!
//! Conventions: rows run from north (row 0) to south, columns from west to east, as in both file
//! formats. World coordinates are `(east, north)` in metres; cell `(row, col)` covers
//! `[west + col * cell_x, west + (col + 1) * cell_x] x [north - (row + 1) * cell_y, north - row * cell_y]`
//! and its height is taken at the cell centre. An unknown height is stored as NaN and reported as
//! `None`: it is never zero, and every analysis downstream skips it.

use nalgebra::Point2;
use rappel_geometry::compact::Compact;
use rappel_geometry::domain::{DOMAIN_TEXT, in_domain};
use serde::{Deserialize, Serialize};

/// The largest grid accepted, in cells (2^27, about 134 million: one gigabyte of heights). Guards
/// against headers that announce absurd sizes; the most [`DemLimits::max_cells`] may be raised to.
pub const MAX_CELLS: usize = 1 << 27;

/// The readers' default work cap, in cells (2^24, about 16.8 million, e.g. 4096 x 4096).
///
/// Ingesting a grid costs time and memory in proportion to its cells: measured on a 2-core
/// machine, 0.53 s for a rough 1000 x 1000 grid (`benches/benches/terrain.rs`, the textured
/// wall with about 5,000 obstacles) and 216 MB peak for a whole `rappel dem` run on a smooth
/// 2000 x 2000 grid, so the default keeps `rappel dem` to about ten seconds and 1 GB. A larger grid is refused before its heights
/// are allocated, with the cap named; raise it with [`DemLimits::with_max_cells`] or
/// `rappel dem --max-cells N`, up to [`MAX_CELLS`].
pub const DEFAULT_MAX_CELLS: usize = 1 << 24;

/// Limits on the work a DEM reader may take on, checked against a file's declared size before
/// anything is allocated.
///
/// ```
/// use rappel_terrain::grid::{DemLimits, GridGeometry, DEFAULT_MAX_CELLS};
/// assert_eq!(DemLimits::default().max_cells, DEFAULT_MAX_CELLS);
/// let small = DemLimits::with_max_cells(100).unwrap();
/// assert!(small.check(&GridGeometry::new(10, 10, 1.0, 1.0, 0.0, 0.0).unwrap()).is_ok());
/// assert!(small.check(&GridGeometry::new(10, 11, 1.0, 1.0, 0.0, 0.0).unwrap()).is_err());
/// assert!(DemLimits::with_max_cells(0).is_err());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DemLimits {
    /// The most cells a grid may have (1 ..= [`MAX_CELLS`]).
    pub max_cells: usize,
}

impl Default for DemLimits {
    fn default() -> Self {
        DemLimits {
            max_cells: DEFAULT_MAX_CELLS,
        }
    }
}

impl DemLimits {
    /// Limits with a work cap of `max_cells` cells; refused outside `1 ..= MAX_CELLS`.
    pub fn with_max_cells(max_cells: usize) -> Result<Self, GridError> {
        if (1..=MAX_CELLS).contains(&max_cells) {
            Ok(DemLimits { max_cells })
        } else {
            Err(GridError::BadWorkCap { max_cells })
        }
    }

    /// Refuses a grid of more than [`DemLimits::max_cells`] cells.
    pub fn check(&self, geometry: &GridGeometry) -> Result<(), GridError> {
        let cells = geometry.nrows.saturating_mul(geometry.ncols);
        if cells > self.max_cells {
            return Err(GridError::OverWorkCap {
                nrows: geometry.nrows,
                ncols: geometry.ncols,
                max_cells: self.max_cells,
            });
        }
        Ok(())
    }
}

/// The shape and georeference of a grid: how many cells, how large, and where.
///
/// ```
/// use rappel_terrain::grid::GridGeometry;
/// let g = GridGeometry::new(3, 2, 1.0, 1.0, 100.0, 50.0).unwrap();
/// assert_eq!(g.len(), 6);
/// assert_eq!(g.cell_center(0, 0), nalgebra::Point2::new(100.5, 49.5));
/// assert_eq!(g.south(), 47.0);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct GridGeometry {
    /// Number of rows (north to south).
    pub nrows: usize,
    /// Number of columns (west to east).
    pub ncols: usize,
    /// Cell size east-west, metres (`> 0`).
    pub cell_x: f64,
    /// Cell size north-south, metres (`> 0`).
    pub cell_y: f64,
    /// Easting of the grid's west edge.
    pub west: f64,
    /// Northing of the grid's north edge.
    pub north: f64,
}

/// A defect in a grid's shape or contents.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GridError {
    /// No rows or no columns. Fix: give a grid of at least one cell.
    #[error("the grid has {nrows} rows and {ncols} columns; it needs at least one of each")]
    Empty {
        /// Rows given.
        nrows: usize,
        /// Columns given.
        ncols: usize,
    },
    /// More than [`MAX_CELLS`] cells. Fix: crop or resample the grid.
    #[error("the grid has {nrows} x {ncols} cells, more than the {MAX_CELLS} accepted")]
    TooLarge {
        /// Rows given.
        nrows: usize,
        /// Columns given.
        ncols: usize,
    },
    /// More cells than the work cap of [`DemLimits`]. Fix: raise the cap (`--max-cells`), or crop
    /// or resample the grid.
    #[error(
        "the grid has {nrows} x {ncols} cells, more than the work cap of {max_cells} cells; raise it with --max-cells (at most {MAX_CELLS}) or crop the grid"
    )]
    OverWorkCap {
        /// Rows given.
        nrows: usize,
        /// Columns given.
        ncols: usize,
        /// The cap in force.
        max_cells: usize,
    },
    /// A work cap outside `1 ..= MAX_CELLS`.
    #[error("a work cap of {max_cells} cells is outside 1 ..= {MAX_CELLS}")]
    BadWorkCap {
        /// The cap asked for.
        max_cells: usize,
    },
    /// A cell size that is not a positive finite number. Fix: the header's cell size.
    #[error("cell size ({}, {}) must be positive and finite", Compact(*.cell_x), Compact(*.cell_y))]
    BadCellSize {
        /// East-west size given.
        cell_x: f64,
        /// North-south size given.
        cell_y: f64,
    },
    /// A georeference that is not finite. Fix: the header's corner coordinates.
    #[error("the grid corner ({}, {}) is not finite", Compact(*.west), Compact(*.north))]
    NonFiniteCorner {
        /// West edge given.
        west: f64,
        /// North edge given.
        north: f64,
    },
    /// A corner, far corner or cell size outside the coordinate domain
    /// ([`rappel_geometry::domain`]), or cells too small for their distance from the origin
    /// (below [`MIN_CELL_TO_CORNER`] of it, where neighbouring cell centres would round to one
    /// position). Fix: the header's corner, cell size or units.
    #[error("{what} = {}: {why}", Compact(*.value))]
    OutOfDomain {
        /// What: `west`, `north`, `east`, `south`, `cell size x`, `cell size y`.
        what: &'static str,
        /// The value.
        value: f64,
        /// The domain it left.
        why: String,
    },
    /// The number of heights differs from rows x columns.
    #[error("{found} heights given for a grid of {expected} cells")]
    LengthMismatch {
        /// Rows x columns.
        expected: usize,
        /// Heights given.
        found: usize,
    },
    /// An infinite height (NaN is accepted and means unknown).
    #[error("cell (row {row}, column {col}) has an infinite height")]
    InfiniteHeight {
        /// Its row.
        row: usize,
        /// Its column.
        col: usize,
    },
}

/// The smallest cell size, as a fraction of the grid's largest corner coordinate: `2^-36`
/// (about `1.5e-11`) leaves 16 of a double's 52 fraction bits to tell cells and positions within
/// a cell apart (a UTM grid with northings of 5e6 m admits cells down to 0.07 mm).
pub const MIN_CELL_TO_CORNER: f64 = 1.0 / 68_719_476_736.0;

impl GridGeometry {
    /// A checked grid geometry: at least one cell, at most [`MAX_CELLS`], positive finite cell
    /// sizes, finite corner.
    pub fn new(
        nrows: usize,
        ncols: usize,
        cell_x: f64,
        cell_y: f64,
        west: f64,
        north: f64,
    ) -> Result<Self, GridError> {
        let g = GridGeometry {
            nrows,
            ncols,
            cell_x,
            cell_y,
            west,
            north,
        };
        g.validate()?;
        Ok(g)
    }

    /// Checks the conditions listed in [`GridGeometry::new`].
    pub fn validate(&self) -> Result<(), GridError> {
        if self.nrows == 0 || self.ncols == 0 {
            return Err(GridError::Empty {
                nrows: self.nrows,
                ncols: self.ncols,
            });
        }
        match self.nrows.checked_mul(self.ncols) {
            Some(n) if n <= MAX_CELLS => {}
            _ => {
                return Err(GridError::TooLarge {
                    nrows: self.nrows,
                    ncols: self.ncols,
                });
            }
        }
        let positive = |v: f64| v.is_finite() && v > 0.0;
        if !(positive(self.cell_x) && positive(self.cell_y)) {
            return Err(GridError::BadCellSize {
                cell_x: self.cell_x,
                cell_y: self.cell_y,
            });
        }
        if !(self.west.is_finite() && self.north.is_finite()) {
            return Err(GridError::NonFiniteCorner {
                west: self.west,
                north: self.north,
            });
        }
        let values = [
            ("west", self.west),
            ("north", self.north),
            ("east", self.east()),
            ("south", self.south()),
            ("cell size x", self.cell_x),
            ("cell size y", self.cell_y),
        ];
        for (what, value) in values {
            if !in_domain(value) {
                return Err(GridError::OutOfDomain {
                    what,
                    value,
                    why: DOMAIN_TEXT.to_string(),
                });
            }
        }
        let reach = [self.west, self.north, self.east(), self.south()]
            .into_iter()
            .fold(0.0f64, |m, v| m.max(v.abs()));
        for (what, value) in [("cell size x", self.cell_x), ("cell size y", self.cell_y)] {
            if value < MIN_CELL_TO_CORNER * reach {
                return Err(GridError::OutOfDomain {
                    what,
                    value,
                    why: format!(
                        "below 2^-36 of the grid's largest coordinate {}: neighbouring cells would round to one position; shift the origin or use larger cells",
                        rappel_geometry::compact::Rounded(reach, 3)
                    ),
                });
            }
        }
        Ok(())
    }

    /// Number of cells.
    pub fn len(&self) -> usize {
        self.nrows * self.ncols
    }

    /// `true` for a grid without cells (never, for a validated geometry).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Row-major index of cell `(row, col)`.
    pub fn index(&self, row: usize, col: usize) -> usize {
        row * self.ncols + col
    }

    /// `(row, col)` of a row-major index.
    pub fn row_col(&self, index: usize) -> (usize, usize) {
        (index / self.ncols, index % self.ncols)
    }

    /// Northing of the south edge.
    pub fn south(&self) -> f64 {
        self.north - self.nrows as f64 * self.cell_y
    }

    /// Easting of the east edge.
    pub fn east(&self) -> f64 {
        self.west + self.ncols as f64 * self.cell_x
    }

    /// World `(east, north)` of the centre of cell `(row, col)`.
    pub fn cell_center(&self, row: usize, col: usize) -> Point2<f64> {
        Point2::new(
            self.west + (col as f64 + 0.5) * self.cell_x,
            self.north - (row as f64 + 0.5) * self.cell_y,
        )
    }

    /// World corners of cell `(row, col)`, counter-clockwise from its south-west corner.
    pub fn cell_corners(&self, row: usize, col: usize) -> [Point2<f64>; 4] {
        let w = self.west + col as f64 * self.cell_x;
        let e = w + self.cell_x;
        let n = self.north - row as f64 * self.cell_y;
        let s = n - self.cell_y;
        [
            Point2::new(w, s),
            Point2::new(e, s),
            Point2::new(e, n),
            Point2::new(w, n),
        ]
    }

    /// World corners of the whole grid, counter-clockwise from the south-west corner.
    pub fn corners(&self) -> [Point2<f64>; 4] {
        let (w, e, s, n) = (self.west, self.east(), self.south(), self.north);
        [
            Point2::new(w, s),
            Point2::new(e, s),
            Point2::new(e, n),
            Point2::new(w, n),
        ]
    }

    /// World corners of the rectangle through the centres of the outer cells (the region where
    /// heights are sampled), counter-clockwise from the south-west.
    pub fn sample_corners(&self) -> [Point2<f64>; 4] {
        let (hx, hy) = (0.5 * self.cell_x, 0.5 * self.cell_y);
        let (w, e, s, n) = (
            self.west + hx,
            self.east() - hx,
            self.south() + hy,
            self.north - hy,
        );
        [
            Point2::new(w, s),
            Point2::new(e, s),
            Point2::new(e, n),
            Point2::new(w, n),
        ]
    }

    /// Fractional `(row, col)` of a world point: cell `(r, c)` spans `[r, r + 1) x [c, c + 1)`.
    pub fn world_to_grid(&self, p: &Point2<f64>) -> (f64, f64) {
        (
            (self.north - p.y) / self.cell_y,
            (p.x - self.west) / self.cell_x,
        )
    }

    /// The larger of the two cell sizes.
    pub fn cell_size(&self) -> f64 {
        self.cell_x.max(self.cell_y)
    }
}

/// A raster of values over a grid (heights, slopes, hillshade...), row-major from the north-west
/// corner; NaN marks an unknown value. Two rasters are equal when they have the same geometry, the
/// same unknown cells and the same known values.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Raster {
    /// Shape and georeference.
    pub geometry: GridGeometry,
    /// `geometry.len()` values, row-major, NaN where unknown.
    pub values: Vec<f64>,
}

impl PartialEq for Raster {
    fn eq(&self, other: &Self) -> bool {
        self.geometry == other.geometry
            && self.values.len() == other.values.len()
            && self
                .values
                .iter()
                .zip(&other.values)
                .all(|(a, b)| a == b || (a.is_nan() && b.is_nan()))
    }
}

impl Raster {
    /// The value of cell `(row, col)`, `None` when unknown or outside the grid.
    pub fn get(&self, row: usize, col: usize) -> Option<f64> {
        if row >= self.geometry.nrows || col >= self.geometry.ncols {
            return None;
        }
        let v = self.values[self.geometry.index(row, col)];
        (!v.is_nan()).then_some(v)
    }

    /// Smallest and largest known values, `None` when every value is unknown.
    pub fn range(&self) -> Option<(f64, f64)> {
        self.values
            .iter()
            .filter(|v| !v.is_nan())
            .fold(None, |acc, &v| match acc {
                None => Some((v, v)),
                Some((lo, hi)) => Some((lo.min(v), hi.max(v))),
            })
    }

    /// Number of known values.
    pub fn known_count(&self) -> usize {
        self.values.iter().filter(|v| !v.is_nan()).count()
    }
}

/// A digital elevation model: heights (metres) over a [`GridGeometry`], unknown cells kept as
/// unknown. Construct with [`HeightGrid::new`], [`HeightGrid::from_fn`] or
/// [`crate::dem::read_dem`].
///
/// ```
/// use rappel_terrain::grid::{GridGeometry, HeightGrid};
/// let g = GridGeometry::new(2, 2, 1.0, 1.0, 0.0, 2.0).unwrap();
/// let dem = HeightGrid::new(g, vec![1.0, 2.0, f64::NAN, 4.0]).unwrap();
/// assert_eq!(dem.height(0, 1), Some(2.0));
/// assert_eq!(dem.height(1, 0), None); // unknown, not zero
/// assert_eq!(dem.unknown_count(), 1);
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HeightGrid {
    raster: Raster,
}

impl HeightGrid {
    /// A height grid from row-major heights (NaN = unknown). Checks the geometry, the length and
    /// that no height is infinite.
    pub fn new(geometry: GridGeometry, heights: Vec<f64>) -> Result<Self, GridError> {
        geometry.validate()?;
        if heights.len() != geometry.len() {
            return Err(GridError::LengthMismatch {
                expected: geometry.len(),
                found: heights.len(),
            });
        }
        if let Some(i) = heights.iter().position(|h| h.is_infinite()) {
            let (row, col) = geometry.row_col(i);
            return Err(GridError::InfiniteHeight { row, col });
        }
        Ok(HeightGrid {
            raster: Raster {
                geometry,
                values: heights,
            },
        })
    }

    /// A height grid whose cell `(row, col)` with centre `p` has height `f(row, col, p)`
    /// (`None` = unknown).
    ///
    /// ```
    /// use rappel_terrain::grid::{GridGeometry, HeightGrid};
    /// let g = GridGeometry::new(4, 4, 1.0, 1.0, 0.0, 4.0).unwrap();
    /// let dem = HeightGrid::from_fn(g, |_, _, p| Some(p.y)).unwrap();
    /// assert_eq!(dem.height(0, 0), Some(3.5));
    /// ```
    pub fn from_fn(
        geometry: GridGeometry,
        mut f: impl FnMut(usize, usize, Point2<f64>) -> Option<f64>,
    ) -> Result<Self, GridError> {
        geometry.validate()?;
        let mut heights = Vec::with_capacity(geometry.len());
        for row in 0..geometry.nrows {
            for col in 0..geometry.ncols {
                heights.push(f(row, col, geometry.cell_center(row, col)).unwrap_or(f64::NAN));
            }
        }
        HeightGrid::new(geometry, heights)
    }

    /// A copy with every height replaced by `f(row, col, height)` (`height` is `None` where
    /// unknown; return `None` to make a cell unknown).
    pub fn map(
        &self,
        mut f: impl FnMut(usize, usize, Option<f64>) -> Option<f64>,
    ) -> Result<Self, GridError> {
        let g = self.raster.geometry;
        HeightGrid::from_fn(g, |r, c, _| f(r, c, self.height(r, c)))
    }

    /// Shape and georeference.
    pub fn geometry(&self) -> &GridGeometry {
        &self.raster.geometry
    }

    /// The height of cell `(row, col)`; `None` when unknown (NODATA) or outside the grid.
    pub fn height(&self, row: usize, col: usize) -> Option<f64> {
        self.raster.get(row, col)
    }

    /// All heights, row-major, NaN where unknown.
    pub fn heights(&self) -> &[f64] {
        &self.raster.values
    }

    /// The heights as a raster.
    pub fn as_raster(&self) -> &Raster {
        &self.raster
    }

    /// Number of unknown cells.
    pub fn unknown_count(&self) -> usize {
        self.raster.geometry.len() - self.raster.known_count()
    }

    /// Lowest and highest known heights, `None` when every cell is unknown.
    pub fn height_range(&self) -> Option<(f64, f64)> {
        self.raster.range()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn geometry_rejects_each_defect() {
        assert!(matches!(
            GridGeometry::new(0, 3, 1., 1., 0., 0.),
            Err(GridError::Empty { .. })
        ));
        assert!(matches!(
            GridGeometry::new(1 << 20, 1 << 20, 1., 1., 0., 0.),
            Err(GridError::TooLarge { .. })
        ));
        assert!(matches!(
            GridGeometry::new(usize::MAX, 3, 1., 1., 0., 0.),
            Err(GridError::TooLarge { .. })
        ));
        assert!(matches!(
            GridGeometry::new(2, 3, 0., 1., 0., 0.),
            Err(GridError::BadCellSize { .. })
        ));
        assert!(matches!(
            GridGeometry::new(2, 3, 1., f64::NAN, 0., 0.),
            Err(GridError::BadCellSize { .. })
        ));
        assert!(matches!(
            GridGeometry::new(2, 3, 1., 1., f64::INFINITY, 0.),
            Err(GridError::NonFiniteCorner { .. })
        ));
    }

    #[test]
    fn heights_are_checked_and_unknown_stays_unknown() {
        let g = GridGeometry::new(2, 3, 2., 1., 10., 20.).unwrap();
        assert!(matches!(
            HeightGrid::new(g, vec![0.0; 5]),
            Err(GridError::LengthMismatch {
                expected: 6,
                found: 5
            })
        ));
        let mut h = vec![0.0; 6];
        h[4] = f64::NEG_INFINITY;
        assert_eq!(
            HeightGrid::new(g, h),
            Err(GridError::InfiniteHeight { row: 1, col: 1 })
        );
        let dem = HeightGrid::from_fn(g, |r, c, _| (r != c).then_some(5.0)).unwrap();
        assert_eq!(dem.height(0, 0), None);
        assert_eq!(dem.height(0, 1), Some(5.0));
        assert_eq!(dem.height(2, 0), None);
        assert_eq!(dem.unknown_count(), 2);
        assert_eq!(dem.height_range(), Some((5.0, 5.0)));
    }

    #[test]
    fn cell_geometry_round_trips() {
        let g = GridGeometry::new(5, 7, 2.0, 3.0, 100.0, 200.0).unwrap();
        for (r, c) in [(0, 0), (4, 6), (2, 3)] {
            let p = g.cell_center(r, c);
            let (fr, fc) = g.world_to_grid(&p);
            assert_eq!((fr, fc), (r as f64 + 0.5, c as f64 + 0.5));
            let k = g.cell_corners(r, c);
            assert_eq!(k[0].x, g.west + c as f64 * 2.0);
            assert_eq!(k[2].y, g.north - r as f64 * 3.0);
        }
        assert_eq!(g.corners()[0], Point2::new(100.0, 185.0));
        assert_eq!(g.corners()[2], Point2::new(114.0, 200.0));
    }
}
