//! Shortest homotopic paths (thesis §2.3; Hershberger and Snoeyink): the taut tether of a path
//! is the shortest path homotopic to it with the same endpoints, the SHP `pi-bar`. It lies in the
//! sleeve of the path's reduced crossing sequence (a shortest path in the universal cover never
//! crosses a diagonal twice, so it crosses exactly the diagonals separating its endpoints' lifts),
//! where the Funnel Algorithm finds it. Total time: linear in the number of segments plus
//! crossings, `O(C_pi + Delta_pi)` (thesis §2.2.3).

use crate::crossing::CrossingSequence;
use crate::funnel::{TautPath, shortest_path_in_sleeve};
use crate::homotopy::HomotopyError;
use crate::path::Path;
use crate::sleeve::Sleeve;
use rappel_geometry::btm::Btm;
use serde::{Deserialize, Serialize};

/// A path's SHP with the structures that produced it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ShortestHomotopicPath {
    /// The taut tether: polyline, anchors, length.
    pub taut: TautPath,
    /// The reduced crossing sequence of the path (and of the SHP).
    pub crossings: CrossingSequence,
    /// The sleeve of the reduced sequence.
    pub sleeve: Sleeve,
}

/// The SHP of `path`: crossing sequence, reduction, sleeve, funnel.
///
/// Around a triangle obstacle, a loop-the-loop path tightens to the straight segment when it
/// does not enclose the obstacle:
/// ```
/// use nalgebra::Point2;
/// use rappel_geometry::{btm::Btm, map::Map, polygon::Polygon};
/// use rappel_homotopy::{path::Path, shp::shortest_homotopic_path};
/// let p = |x, y| Point2::new(x, y);
/// let map = Map::new(
///     Polygon::new(vec![p(0., 0.), p(10., 0.), p(10., 10.), p(0., 10.)]),
///     vec![Polygon::new(vec![p(4., 4.), p(6., 4.), p(5., 6.)])],
/// );
/// let btm = Btm::from_map(&map).unwrap();
/// let slack = Path::new(vec![p(1., 9.), p(3., 9.), p(3., 7.), p(1., 7.), p(2., 9.5), p(1., 1.)]).unwrap();
/// let shp = shortest_homotopic_path(&btm, &slack).unwrap();
/// assert_eq!(shp.taut.points, vec![p(1., 9.), p(1., 1.)]);
/// assert!(shp.taut.anchors.is_empty());
/// ```
pub fn shortest_homotopic_path(
    btm: &Btm,
    path: &Path,
) -> Result<ShortestHomotopicPath, HomotopyError> {
    let crossings = CrossingSequence::reduced_of_path(btm, path)?;
    let sleeve = Sleeve::from_crossing_sequence(btm, &crossings)?;
    let taut = shortest_path_in_sleeve(btm, &sleeve, path.start(), path.end())?;
    Ok(ShortestHomotopicPath {
        taut,
        crossings,
        sleeve,
    })
}
