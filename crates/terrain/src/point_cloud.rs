//! Lidar point clouds (ASPRS LAS and LAZ, through the `las` crate with its `laz` feature)
//! gridded to a height model (issue 34), for field tests with terrestrial lidar: `rappel dem
//! scan.laz --cell M [--statistic max|mean]`.
//!
//! The rule ([`grid_points`]):
//! - **grid**: square cells of the given size over the points' plan bounding box, the
//!   north-west corner at `(min x, max y)` (`x` east, `y` north, `z` up, as LAS stores them); a
//!   point on a cell's west or north edge belongs to that cell, the last column and row take the
//!   points on the box's east and south edges;
//! - **statistic**: each cell's height is the **max** of its points' `z` (the top of the surface
//!   the scan saw: vegetation and boulders stay, the default) or their **mean**;
//! - **holes**: a cell with no point is unknown (NODATA), never interpolated.
//!
//! Every point is used (no classification filter: a scan of bare rock has no vegetation to
//! drop; classify and filter ground points with PDAL first otherwise).
//!
//! The CRS ([`read_point_cloud`]): an OGC WKT record (LAS 1.4, `LASF_Projection` 2112), else the
//! GeoTIFF keys records (34735-34737) read as a GeoTIFF's ([`crate::crs::GeoKeyDirectory`],
//! unused keys reported); `None` when the file has neither.
//!
//! Bounds: the file within the input size cap ([`crate::input`]), the points read in batches up
//! to the header's count (at most [`MAX_POINTS`]), the grid within [`DemLimits`].

use crate::crs::GeoKeyDirectory;
use crate::grid::{DemLimits, GridError, GridGeometry, HeightGrid};
use nalgebra::Point3;
use std::path::{Path, PathBuf};

/// Most points read from one file: 2^31 (about 60 GB of LAS point records).
pub const MAX_POINTS: u64 = 1 << 31;
/// Points read per batch.
const BATCH: u64 = 1 << 16;

/// How a cell's points become its height.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Statistic {
    /// The highest point (the default).
    #[default]
    Max,
    /// The mean of the points' heights.
    Mean,
}

impl Statistic {
    /// `max` or `mean` (any case); `None` otherwise.
    ///
    /// ```
    /// use rappel_terrain::point_cloud::Statistic;
    /// assert_eq!(Statistic::parse("Mean"), Some(Statistic::Mean));
    /// assert_eq!(Statistic::parse("median"), None);
    /// ```
    pub fn parse(text: &str) -> Option<Statistic> {
        match text.to_ascii_lowercase().as_str() {
            "max" => Some(Statistic::Max),
            "mean" => Some(Statistic::Mean),
            _ => None,
        }
    }
}

/// Why a point cloud could not become a height grid.
#[derive(Debug, thiserror::Error)]
pub enum PointCloudError {
    /// The file could not be opened within the input limits.
    #[error(transparent)]
    Input(#[from] crate::input::InputError),
    /// The LAS/LAZ reader failed.
    #[error("{path}: LAS/LAZ: {why}")]
    Las {
        /// The file.
        path: PathBuf,
        /// The reader's message.
        why: String,
    },
    /// The cell size is not a positive finite number.
    #[error("cell size {0}: it must be a positive finite number of metres")]
    Cell(f64),
    /// No points, too many, or a point not finite or outside the header's bounds.
    #[error("{0}")]
    Points(String),
    /// The grid over the points is not a valid grid or is over the work cap.
    #[error("the grid over the points at this cell size: {0}")]
    Grid(#[from] GridError),
    /// The CRS records could not be read.
    #[error("{path}: CRS records: {source}")]
    Crs {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: crate::crs::CrsError,
    },
}

/// Points gridded to a height model by `statistic` over `cell` metre cells (module docs);
/// `points` must lie within `(min, max)`, their bounding box.
///
/// ```
/// use nalgebra::Point3;
/// use rappel_terrain::grid::DemLimits;
/// use rappel_terrain::point_cloud::{grid_points, Statistic};
/// let pts = [Point3::new(0.2, 0.2, 1.0), Point3::new(0.7, 0.4, 3.0), Point3::new(1.9, 1.9, 5.0)];
/// let (lo, hi) = (Point3::new(0.2, 0.2, 1.0), Point3::new(1.9, 1.9, 5.0));
/// let g = grid_points(&pts, (lo, hi), 1.0, Statistic::Mean, &DemLimits::default()).unwrap();
/// assert_eq!((g.geometry().nrows, g.geometry().ncols), (2, 2));
/// // The south-west cell holds the first two points; the north-west and south-east none.
/// assert_eq!(g.height(1, 0), Some(2.0));
/// assert_eq!(g.height(0, 0), None);
/// assert_eq!(g.height(0, 1), Some(5.0));
/// ```
pub fn grid_points(
    points: &[Point3<f64>],
    bounds: (Point3<f64>, Point3<f64>),
    cell: f64,
    statistic: Statistic,
    limits: &DemLimits,
) -> Result<HeightGrid, PointCloudError> {
    let mut g = Gridder::new(bounds, cell, statistic, limits)?;
    // One pass over the caller's points.
    for p in points {
        g.add(p)?;
    }
    g.finish()
}

/// The grid being filled, one point at a time.
struct Gridder {
    g: GridGeometry,
    lo: Point3<f64>,
    hi: Point3<f64>,
    statistic: Statistic,
    value: Vec<f64>,
    n: Vec<u32>,
    seen: u64,
}

impl Gridder {
    fn new(
        (lo, hi): (Point3<f64>, Point3<f64>),
        cell: f64,
        statistic: Statistic,
        limits: &DemLimits,
    ) -> Result<Gridder, PointCloudError> {
        if !(cell.is_finite() && cell > 0.0) {
            return Err(PointCloudError::Cell(cell));
        }
        if !(lo.iter().chain(hi.iter()).all(|v| v.is_finite()) && lo.x <= hi.x && lo.y <= hi.y) {
            return Err(PointCloudError::Points(format!(
                "the points' bounds ({}, {}) .. ({}, {}) are not a finite box",
                lo.x, lo.y, hi.x, hi.y
            )));
        }
        let count = |extent: f64| ((extent / cell).ceil() as usize).max(1);
        let g = GridGeometry::new(
            count(hi.y - lo.y),
            count(hi.x - lo.x),
            cell,
            cell,
            lo.x,
            hi.y,
        )?;
        limits.check(&g)?;
        Ok(Gridder {
            g,
            lo,
            hi,
            statistic,
            value: vec![f64::NAN; g.len()],
            n: vec![0; g.len()],
            seen: 0,
        })
    }

    fn add(&mut self, p: &Point3<f64>) -> Result<(), PointCloudError> {
        let (lo, hi, g) = (self.lo, self.hi, self.g);
        let inside = p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y;
        if !(p.z.is_finite() && inside) {
            return Err(PointCloudError::Points(format!(
                "point {} ({}, {}, {}) is not finite or lies outside the header's bounds",
                self.seen, p.x, p.y, p.z
            )));
        }
        self.seen += 1;
        let col = (((p.x - lo.x) / g.cell_x) as usize).min(g.ncols - 1);
        let row = (((hi.y - p.y) / g.cell_y) as usize).min(g.nrows - 1);
        let i = g.index(row, col);
        let v = &mut self.value[i];
        *v = match (self.statistic, self.n[i]) {
            (_, 0) => p.z,
            (Statistic::Max, _) => v.max(p.z),
            (Statistic::Mean, _) => *v + p.z,
        };
        self.n[i] = self.n[i].saturating_add(1);
        Ok(())
    }

    fn finish(mut self) -> Result<HeightGrid, PointCloudError> {
        if self.statistic == Statistic::Mean {
            for (v, c) in self.value.iter_mut().zip(&self.n) {
                if *c > 0 {
                    *v /= f64::from(*c);
                }
            }
        }
        if self.seen == 0 {
            return Err(PointCloudError::Points("the file holds no point".into()));
        }
        Ok(HeightGrid::new(self.g, self.value)?)
    }
}

/// A point cloud gridded, with what its file says of its CRS.
#[derive(Debug, Clone)]
pub struct PointCloudGrid {
    /// The height model.
    pub grid: HeightGrid,
    /// Points read.
    pub points: u64,
    /// The CRS of the file's records (`EPSG:n` or WKT), when it has one.
    pub crs: Option<String>,
    /// GeoKeys of the file's records not used by its CRS, one message each.
    pub ignored: Vec<String>,
}

/// Reads the LAS or LAZ file at `path` and grids it (module docs).
///
/// ```
/// use rappel_terrain::grid::DemLimits;
/// use rappel_terrain::point_cloud::{read_point_cloud, Statistic};
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/lidar/boulder_slope_utm10n.laz");
/// let pc = read_point_cloud(path.as_ref(), 0.5, Statistic::Max, &DemLimits::default()).unwrap();
/// assert_eq!(pc.crs.as_deref(), Some("EPSG:32610"));
/// assert_eq!(pc.points, 9504);
/// assert!(pc.grid.unknown_count() < pc.grid.geometry().len());
/// ```
pub fn read_point_cloud(
    path: &Path,
    cell: f64,
    statistic: Statistic,
    limits: &DemLimits,
) -> Result<PointCloudGrid, PointCloudError> {
    let las = |e: las::Error| PointCloudError::Las {
        path: path.to_path_buf(),
        why: e.to_string(),
    };
    let (file, _) = crate::input::open_input(path, crate::input::max_input_bytes()?)?;
    let mut reader = las::Reader::new(std::io::BufReader::new(file)).map_err(las)?;
    let header = reader.header().clone();
    let total = header.number_of_points();
    if total > MAX_POINTS {
        return Err(PointCloudError::Points(format!(
            "{}: {total} points, over the cap of {MAX_POINTS}",
            path.display()
        )));
    }
    let (crs, ignored) = crs_of(&header).map_err(|source| PointCloudError::Crs {
        path: path.to_path_buf(),
        source,
    })?;
    let b = header.bounds();
    let (lo, hi) = (
        Point3::new(b.min.x, b.min.y, b.min.z),
        Point3::new(b.max.x, b.max.y, b.max.z),
    );
    // The header's bounds are rounded to the records' scale: widen by half a unit of it.
    let tr = header.transforms();
    let slack = nalgebra::Vector3::new(tr.x.scale, tr.y.scale, tr.z.scale).abs() * 0.5;
    let named = |e: PointCloudError| match e {
        PointCloudError::Points(why) => {
            PointCloudError::Points(format!("{}: {why}", path.display()))
        }
        other => other,
    };
    let mut gridder =
        Gridder::new((lo - slack, hi + slack), cell, statistic, limits).map_err(named)?;
    let mut batch = las::PointDataBuilder::new().for_header(&header).build();
    let mut read = 0u64;
    // Batches up to the header's count (at most MAX_POINTS): the file cannot make it loop longer.
    while read < total {
        let n = reader
            .fill_points(BATCH.min(total - read), &mut batch)
            .map_err(las)?;
        if n == 0 {
            return Err(PointCloudError::Points(format!(
                "{}: the header counts {total} points, the file holds {read}",
                path.display()
            )));
        }
        read += n;
        for ((x, y), z) in batch.x().zip(batch.y()).zip(batch.z()) {
            gridder.add(&Point3::new(x, y, z)).map_err(named)?;
        }
    }
    let grid = gridder.finish().map_err(named)?;
    Ok(PointCloudGrid {
        grid,
        points: read,
        crs,
        ignored,
    })
}

/// The CRS of a LAS header's records and the GeoKeys it does not use (module docs).
fn crs_of(h: &las::Header) -> Result<(Option<String>, Vec<String>), crate::crs::CrsError> {
    let record = |id: u16| {
        h.all_vlrs()
            .find(|v| v.user_id == "LASF_Projection" && v.record_id == id)
            .map(|v| v.data.as_slice())
    };
    if let Some(wkt) = record(2112) {
        let text = String::from_utf8_lossy(wkt);
        let text = text.trim_end_matches('\0').trim();
        if let Some(crs) = crate::crs::Crs::parse(text) {
            return Ok((Some(crs.to_string()), Vec::new()));
        }
    }
    let Some(dir) = record(34735) else {
        return Ok((None, Vec::new()));
    };
    let shorts: Vec<u16> = dir
        .chunks_exact(2)
        .map(|b| u16::from_le_bytes([b[0], b[1]]))
        .collect();
    let doubles: Vec<f64> = record(34736)
        .unwrap_or_default()
        .chunks_exact(8)
        .map(|b| f64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]))
        .collect();
    let ascii = String::from_utf8_lossy(record(34737).unwrap_or_default()).into_owned();
    let keys = GeoKeyDirectory::parse(&shorts, &doubles, ascii.trim_end_matches('\0'))?;
    Ok((keys.to_crs()?.map(|c| c.to_string()), keys.ignored_keys()))
}
