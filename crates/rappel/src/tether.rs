//! Taut tethers for `rappel shp` and `rappel homotopic` (issue 3): path files, the shortest
//! homotopic path (SHP) of a path with its summary, and the picture layers for sleeves, SHPs and
//! anchors.
//!
//! A path file is a JSON array of `[x, y]` points in the map frame, for example
//! `[[100.0, 290.0], [80.0, 150.0], [100.0, 5.0]]`.

use nalgebra::Point2;
use rappel_geometry::btm::Btm;
use rappel_geometry::compact::Compact;
use rappel_geometry::domain::{DOMAIN_TEXT, in_domain};
use rappel_homotopy::crossing::CrossingSequence;
use rappel_homotopy::funnel::Anchor;
use rappel_homotopy::funnel::Side;
use rappel_homotopy::h_signature::{HSignature, Poles};
use rappel_homotopy::homotopy::HomotopyError;
use rappel_homotopy::path::{Path, PathError};
use rappel_homotopy::shp::{ShortestHomotopicPath, shortest_homotopic_path};
use serde::{Deserialize, Serialize};

/// Why a path file could not be used.
#[derive(Debug, thiserror::Error)]
pub enum PathFileError {
    /// The file was not read: not a regular file, over the input size cap, not text
    /// ([`rappel_terrain::input`]).
    #[error(transparent)]
    Input(#[from] rappel_terrain::input::InputError),
    /// The file could not be read.
    #[error("{file}: cannot read: {source}")]
    Read {
        /// The file.
        file: String,
        /// The I/O error.
        source: std::io::Error,
    },
    /// The file is not a JSON array of `[x, y]` points.
    #[error("{file}:{line}:{column}: not a JSON array of [x, y] points: {message}")]
    Parse {
        /// The file.
        file: String,
        /// Line of the problem (1-based).
        line: usize,
        /// Column of the problem (1-based).
        column: usize,
        /// What is wrong.
        message: String,
    },
    /// A point lies outside the coordinate domain ([`rappel_geometry::domain`]).
    #[error("{file}: point {index} ({}, {}) is outside the coordinate domain: {DOMAIN_TEXT}", Compact(point.x), Compact(point.y))]
    OutOfDomain {
        /// The file.
        file: String,
        /// The point's index (0-based).
        index: usize,
        /// The point.
        point: Point2<f64>,
    },
    /// The points do not make a path in the map's free space.
    #[error("{file}: {source}")]
    Invalid {
        /// The file.
        file: String,
        /// What is wrong, with the point or segment named.
        source: PathError,
    },
}

/// Reads a path file and checks it against the free space of `btm`.
pub fn load_path(file: &std::path::Path, btm: &Btm) -> Result<Path, PathFileError> {
    let name = file.display().to_string();
    let text = rappel_terrain::input::read_text(file)?;
    let points: Vec<Point2<f64>> =
        serde_json::from_str(&text).map_err(|e| PathFileError::Parse {
            file: name.clone(),
            line: e.line(),
            column: e.column(),
            message: crate::scenario::readable_message(&crate::scenario::strip_json_position(
                &e.to_string(),
            )),
        })?;
    if let Some((index, point)) = points
        .iter()
        .enumerate()
        .find(|(_, p)| p.x.is_finite() && p.y.is_finite() && !(in_domain(p.x) && in_domain(p.y)))
    {
        return Err(PathFileError::OutOfDomain {
            file: name,
            index,
            point: *point,
        });
    }
    let invalid = |source| PathFileError::Invalid {
        file: name.clone(),
        source,
    };
    let path = Path::new(points).map_err(invalid)?;
    path.validate(btm).map_err(invalid)?;
    Ok(path)
}

/// The H-signature in a report: its digest and the non-zero winding counts.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct HSignatureReport {
    /// [`HSignature::digest`] in hexadecimal.
    pub digest: String,
    /// `[obstacle id, winding count]` for every obstacle with a non-zero count.
    pub windings: Vec<(u32, i64)>,
}

/// An anchor of a taut tether in a report ([`Anchor`] with its angle in degrees).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct AnchorPoint {
    /// The map vertex.
    pub vertex: u32,
    /// Its position, `[x, y]`.
    #[schemars(with = "[f64; 2]")]
    pub point: Point2<f64>,
    /// The obstacle it belongs to; `None` for a (reflex) vertex of the map boundary.
    pub obstacle: Option<u32>,
    /// The side of the path the obstacle lies on.
    pub side: Side,
    /// The tether's turning angle at the anchor, degrees in `(0, 180)` (the wrap angle of the
    /// capstan equation).
    pub turning_angle_deg: f64,
}

impl From<&Anchor> for AnchorPoint {
    fn from(a: &Anchor) -> Self {
        AnchorPoint {
            vertex: a.vertex.0,
            point: a.point,
            obstacle: a.obstacle.map(|o| o.0),
            side: a.side,
            turning_angle_deg: crate::report::deg(a.turning_angle),
        }
    }
}

/// What `rappel shp` prints.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct ShpReport {
    /// Number of points of the input path.
    pub path_points: usize,
    /// Length of the input path, m.
    pub path_length_m: f64,
    /// The SHP polyline, `[x, y]` points.
    #[schemars(with = "Vec<[f64; 2]>")]
    pub points: Vec<Point2<f64>>,
    /// The SHP's length, m.
    pub length_m: f64,
    /// The anchors, in path order.
    pub anchors: Vec<AnchorPoint>,
    /// Length of the raw crossing sequence.
    pub crossings: usize,
    /// Length of the reduced crossing sequence (the homotopy class's word).
    pub reduced_crossings: usize,
    /// The H-signature of the path (and of its SHP).
    pub h_signature: HSignatureReport,
}

crate::report::report!(ShpReport, "shp");

/// The SHP of `path` with its report.
///
/// ```
/// use nalgebra::Point2;
/// use rappel::geometry::{btm::Btm, map::Map, polygon::Polygon};
/// use rappel::homotopy::path::Path;
/// let p = |x, y| Point2::new(x, y);
/// let map = Map::new(
///     Polygon::new(vec![p(0., 0.), p(10., 0.), p(10., 10.), p(0., 10.)]),
///     vec![Polygon::new(vec![p(4., 4.), p(6., 4.), p(6., 6.), p(4., 6.)])],
/// );
/// let btm = Btm::from_map(&map).unwrap();
/// let path = Path::new(vec![p(5., 9.), p(1., 5.), p(5., 1.)]).unwrap();
/// let (shp, report) = rappel::tether::shp_report(&btm, &path).unwrap();
/// assert_eq!(report.anchors.len(), 2);
/// assert_eq!(report.reduced_crossings, shp.crossings.len());
/// ```
pub fn shp_report(
    btm: &Btm,
    path: &Path,
) -> Result<(ShortestHomotopicPath, ShpReport), HomotopyError> {
    let shp = shortest_homotopic_path(btm, path)?;
    let raw = CrossingSequence::of_path(btm, path)?;
    let h = HSignature::of_path(&Poles::new(btm), path);
    let report = ShpReport {
        path_points: path.points().len(),
        path_length_m: path.length(),
        points: shp.taut.points.clone(),
        length_m: shp.taut.length,
        anchors: shp.taut.anchors.iter().map(AnchorPoint::from).collect(),
        crossings: raw.len(),
        reduced_crossings: shp.crossings.len(),
        h_signature: HSignatureReport {
            digest: format!("{:016x}", h.digest()),
            windings: h.windings().iter().map(|&(o, n)| (o.0, n)).collect(),
        },
    };
    Ok((shp, report))
}
