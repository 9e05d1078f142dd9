//! The taut tether of every pose of a stability map (Kumar Fig. 5 with the thesis's taut tether,
//! §2.1.2): the robot is placed on a grid over each terrain plane's band of the map, and at each
//! free pose the tether, anchored at the start, is taut along the shortest free-space path to it,
//! pulling the robot towards its **last anchor** (the start in open ground, or the last obstacle
//! vertex it wraps).
//!
//! [`plane_bands`] clips the terrain planes to the map's box ([`MapPlane`]s for
//! [`rappel_mechanics::stability_map::grid_positions`]); [`free_positions`] keeps the grid's
//! positions strictly in free space ([`is_strictly_free`], located in the BTM); a [`TetherTable`]
//! looks up every free position's last anchor and tether length once in one
//! [`ShortestPathMap`] from the start (in parallel, rayon) and is the [`AnchorSource`] of
//! [`rappel_mechanics::stability_map::stability_map`]. At the start itself no tether pulls.

use crate::shortest_path_map::ShortestPathMap;
use nalgebra::{Point2, Point3};
use rappel_geometry::btm::{Btm, Location};
use rappel_geometry::polygon::Aabb;
use rappel_mechanics::robot::{RobotError, SlopePlane, TetherSpec};
use rappel_mechanics::stability_map::{AnchorSource, MapPlane};
use rappel_terrain::plane_series::TerrainPlane;
use rayon::prelude::*;
use std::collections::HashMap;

/// Each terrain plane's band of the map box `bounds` (bands outside the box are left out), for
/// the stability map's pose grid; an error for a plane whose slope or friction the mechanics
/// refuses.
///
/// ```
/// use rappel_geometry::polygon::Aabb;
/// use rappel_planners::tether_anchors::plane_bands;
/// use rappel_terrain::plane_series::TerrainPlane;
/// let planes = [TerrainPlane::new(30.0, 10.0, 40.0, 0.6), TerrainPlane::new(10.0, -5.0, 20.0, 0.6)];
/// let bounds = Aabb { min: [0.0, 0.0].into(), max: [4.0, 20.0].into() };
/// let bands = plane_bands(&planes, &bounds).unwrap();
/// assert_eq!(bands[0].y_range, [10.0, 20.0]);
/// assert_eq!(bands[1].y_range, [0.0, 10.0]);
/// ```
pub fn plane_bands(planes: &[TerrainPlane], bounds: &Aabb) -> Result<Vec<MapPlane>, RobotError> {
    let mut bands = Vec::with_capacity(planes.len());
    for p in planes {
        let plane = SlopePlane::new(p.slope_rad(), p.friction)?;
        let (y0, y1) = (p.y_bottom.max(bounds.min.y), p.y_top.min(bounds.max.y));
        if y0 <= y1 {
            bands.push(MapPlane {
                plane,
                x_range: [bounds.min.x, bounds.max.x],
                y_range: [y0, y1],
            });
        }
    }
    Ok(bands)
}

/// Whether `p` lies strictly in the free space of `btm` (not on an obstacle's or the boundary's
/// ring), located in the BTM: logarithmic-ish per point instead of a scan over every obstacle.
pub fn is_strictly_free(btm: &Btm, p: &Point2<f64>) -> bool {
    match btm.locate(p) {
        Location::Triangle(_) => true,
        Location::Edge(h) => btm.dcel().twin(h).is_some(),
        Location::Vertex(_) | Location::Obstacle(_) | Location::Outside => false,
    }
}

/// The distinct positions of a pose grid (as [`rappel_mechanics::stability_map::grid_positions`]
/// makes it: plane index and position) strictly in free space, sorted by `x` then `y`.
pub fn free_positions(btm: &Btm, positions: &[(usize, Point2<f64>)]) -> Vec<Point2<f64>> {
    let mut free: Vec<Point2<f64>> = positions
        .iter()
        .map(|(_, p)| *p)
        .filter(|p| is_strictly_free(btm, p))
        .collect();
    free.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    free.dedup();
    free
}

/// What the tether search says about one pose: the last anchor and the tether's length, `None`
/// when no path reaches it (or at the start itself), or why the search could not tell.
pub type Taut = Result<Option<(Point2<f64>, f64)>, String>;

/// The taut tether of every free pose of a grid, looked up once per pose in a shortest path map
/// (in parallel, rayon) and then read both by the stability assessment (as its
/// [`AnchorSource`]: anchored at the last anchor, at the robot's tether exit height) and by the
/// caller's report ([`TetherTable::taut`]).
#[derive(Debug, Clone)]
pub struct TetherTable {
    /// Keyed by the pose's coordinates' bits (grid positions are produced by one function, so
    /// equal positions have equal bits).
    taut: HashMap<(u64, u64), Taut>,
    exit_height: f64,
    limit: Option<f64>,
}

fn key(p: &Point2<f64>) -> (u64, u64) {
    (p.x.to_bits(), p.y.to_bits())
}

impl TetherTable {
    /// Looks up the tether of every position in `positions` in `spm` (a map from the tether's
    /// anchor): its last anchor and length. `exit_height` is the height of the tether's exit
    /// above the robot's plane, `limit` the tether's tension limit of every [`TetherSpec`].
    /// `progress` is called with `1` after each position (from rayon's worker threads; e.g. to
    /// drive a progress bar); pass `&|_| {}` for none.
    ///
    /// ```
    /// use rappel_geometry::{btm::Btm, map::Map, polygon::Polygon};
    /// use rappel_planners::{shortest_path_map::ShortestPathMap, tether_anchors::TetherTable};
    /// use nalgebra::Point2;
    /// let boundary = Polygon::new(vec![[0.0, 0.0].into(), [4.0, 0.0].into(), [4.0, 4.0].into(), [0.0, 4.0].into()]);
    /// let map = Map { boundary, obstacles: vec![] };
    /// let btm = Btm::build(map.validate().unwrap()).unwrap();
    /// let start = Point2::new(2.0, 3.5);
    /// let spm = ShortestPathMap::build(&btm, start).unwrap();
    /// let poses = [Point2::new(2.0, 0.5), start];
    /// let table = TetherTable::new(&spm, &poses, 0.3, None, &|_| {});
    /// assert_eq!(table.taut(&poses[0]), Ok(Some((start, 3.0))));
    /// assert_eq!(table.taut(&start), Ok(None));
    /// ```
    pub fn new(
        spm: &ShortestPathMap<'_>,
        positions: &[Point2<f64>],
        exit_height: f64,
        limit: Option<f64>,
        progress: &(dyn Fn(u64) + Sync),
    ) -> Self {
        let taut = positions
            .par_iter()
            .map(|p| {
                // At the start itself there is no tether to pull (as when it was searched).
                let t = spm
                    .query(*p)
                    .map(|g| {
                        g.filter(|g| g.last_anchor != *p)
                            .map(|g| (g.last_anchor, g.length))
                    })
                    .map_err(|e| e.to_string());
                progress(1);
                (key(p), t)
            })
            .collect();
        TetherTable {
            taut,
            exit_height,
            limit,
        }
    }

    /// The searched tether at `position` (`Ok(None)` for a position not in the table: not free).
    pub fn taut(&self, position: &Point2<f64>) -> Taut {
        self.taut.get(&key(position)).cloned().unwrap_or(Ok(None))
    }
}

impl AnchorSource for TetherTable {
    fn tether_at(&self, _: usize, position: &Point2<f64>) -> Option<TetherSpec> {
        let (a, _) = self.taut(position).ok().flatten()?;
        Some(TetherSpec {
            anchor: Point3::new(a.x, a.y, self.exit_height),
            max_tension: self.limit,
        })
    }
}
