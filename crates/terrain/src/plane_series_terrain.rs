//! The plane series of thesis §2.1.2 ([`crate::plane_series`]) as a [`Terrain`]: bands of the frame
//! (`x` across the slope, `y` up it) folded down the fall line in closed form. The world has `X = x`,
//! `Y` horizontal (increasing uphill, `Y = y` on the top plane's upper edge) and `Z` up, `Z = 0` at
//! the top plane's upper edge.

use crate::plane_series::{PlaneSeriesError, TerrainPlane, validate_planes};
use crate::surface::{Chart, EdgeKind, Prism, SharedEdge, Terrain};
use nalgebra::{Point2, Point3, Vector2, Vector3};
use rappel_geometry::polygon::Polygon;

/// A validated plane series, `x` limited to `x_min..=x_max`, with prism obstacles.
///
/// ```
/// use nalgebra::Point2;
/// use rappel_terrain::plane_series::TerrainPlane;
/// use rappel_terrain::plane_series_terrain::PlaneSeriesTerrain;
/// use rappel_terrain::surface::{EdgeKind, Terrain};
/// let t = PlaneSeriesTerrain::new(
///     &[TerrainPlane::new(20.0, 10.0, 0.0, 0.4), TerrainPlane::new(10.0, 0.0, 30.0, 0.4)],
///     (0.0, 10.0), vec![]).unwrap();
/// assert_eq!(t.edges()[0].kind, EdgeKind::Crest);
/// assert!((t.height(&Point2::new(1.0, 0.0)).unwrap() + 5.0).abs() < 1e-12); // 10 m at 30 degrees
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct PlaneSeriesTerrain {
    planes: Vec<TerrainPlane>,
    x_range: (f64, f64),
    charts: Vec<Chart>,
    edges: Vec<SharedEdge>,
    obstacles: Vec<Prism>,
}

/// Why a plane-series terrain is refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PlaneSeriesTerrainError {
    /// The planes are malformed.
    #[error(transparent)]
    Planes(#[from] PlaneSeriesError),
    /// No planes, or an empty or non-finite `x` range.
    #[error("a plane-series terrain needs planes and a finite x range with x_min < x_max")]
    Extent,
    /// An obstacle is off the terrain or malformed.
    #[error("obstacle {0}: outside the terrain, on a plane edge, or with a bad height/friction")]
    Obstacle(usize),
}

impl PlaneSeriesTerrain {
    /// The series `planes` (top first) across `x_range`, with obstacles whose bases are given in
    /// the frame (`surface` is recomputed from the base and checked).
    pub fn new(
        planes: &[TerrainPlane],
        x_range: (f64, f64),
        obstacles: Vec<Prism>,
    ) -> Result<PlaneSeriesTerrain, PlaneSeriesTerrainError> {
        validate_planes(planes)?;
        if planes.is_empty()
            || !(x_range.0.is_finite() && x_range.1.is_finite() && x_range.0 < x_range.1)
        {
            return Err(PlaneSeriesTerrainError::Extent);
        }
        let mut charts = Vec::with_capacity(planes.len());
        let mut edges = Vec::new();
        let (mut wy, mut wz) = (planes[0].y_top, 0.0);
        for (i, p) in planes.iter().enumerate() {
            let (s, c) = p.slope_rad().sin_cos();
            charts.push(Chart {
                o3: Point3::new(0.0, wy, wz),
                u3: Vector3::x(),
                w3: Vector3::new(0.0, -c, -s),
                o2: Point2::new(0.0, p.y_top),
                u2: Vector2::x(),
                w2: -Vector2::y(),
            });
            let d = p.y_top - p.y_bottom;
            wy -= d * c;
            wz -= d * s;
            if i > 0 {
                let above = planes[i - 1].slope_deg;
                let bend = (p.slope_deg - above).abs().to_radians();
                let kind = if p.slope_deg > above {
                    EdgeKind::Crest
                } else if p.slope_deg < above {
                    EdgeKind::Valley
                } else {
                    EdgeKind::Flat
                };
                edges.push(SharedEdge {
                    from: i - 1,
                    to: i,
                    a: Point2::new(x_range.0, p.y_top),
                    b: Point2::new(x_range.1, p.y_top),
                    kind,
                    bend,
                });
            }
        }
        let mut t = PlaneSeriesTerrain {
            planes: planes.to_vec(),
            x_range,
            charts,
            edges,
            obstacles: Vec::with_capacity(obstacles.len()),
        };
        for (k, mut o) in obstacles.into_iter().enumerate() {
            let base: Polygon = o.base.to_counter_clockwise();
            let s = base.vertices.first().and_then(|v| t.surface_at(v));
            let ok = o.height.is_finite()
                && o.height > 0.0
                && o.friction.is_finite()
                && o.friction >= 0.0
                && base.area() > 0.0
                && s.is_some()
                && base.vertices.iter().all(|v| t.surface_at(v) == s);
            if !ok {
                return Err(PlaneSeriesTerrainError::Obstacle(k));
            }
            o.base = base;
            o.surface = s.unwrap_or_default();
            t.obstacles.push(o);
        }
        Ok(t)
    }

    /// The planes, top first.
    pub fn planes(&self) -> &[TerrainPlane] {
        &self.planes
    }
}

impl Terrain for PlaneSeriesTerrain {
    fn surface_count(&self) -> usize {
        self.planes.len()
    }
    fn surface_at(&self, p: &Point2<f64>) -> Option<usize> {
        if !(p.x >= self.x_range.0 && p.x <= self.x_range.1) {
            return None;
        }
        self.planes.iter().position(|pl| pl.contains_y(p.y))
    }
    fn chart(&self, s: usize) -> &Chart {
        &self.charts[s]
    }
    fn friction(&self, s: usize) -> f64 {
        self.planes[s].friction
    }
    fn edges(&self) -> &[SharedEdge] {
        &self.edges
    }
    fn obstacles(&self) -> &[Prism] {
        &self.obstacles
    }
}
