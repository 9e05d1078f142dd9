//! The terrain under the Chapter-2 planner (thesis §2.1.2, §2.4.4; Kumar's multi-surface
//! environment): a series of planes down the fall line, unfolded isometrically into the map frame
//! ([`rappel_terrain::plane_series`]: `x` across the slope, `y` up it, plane bands listed
//! top first and meeting edge to edge), with the tether limit of each plane from a traversability
//! model ([`AnchorTraversability`]).
//!
//! A plane is **tether-demand** when the robot needs the tether to hold on it, **tether-free**
//! otherwise (thesis §2.1.2; for the point robot, `mu cot eta >= 1`). Unfolding keeps distances, so
//! SHPs, sleeves and funnels are computed in the map frame unchanged; only the anchor reachable
//! sets depend on the plane (§2.4.4). The tether stays on the ground only over a **convex** series,
//! each plane at least as steep as the one above (`eta_k >= eta_{k-1}`); a shallower plane below a
//! steeper one is reported by [`PlaneSeries::concave_edges`], since the taut tether may lift off
//! there and the Chapter-2 model no longer holds.
//!
//! A point above the top band or below the bottom band belongs to the nearest band. A scenario
//! without planes is flat ground: one tether-free plane (thesis §2.2.4).

use nalgebra::Point2;
use rappel_mechanics::anchor_traversability::{AnchorTraversability, TetherLimit};
use rappel_mechanics::robot::{RobotError, SlopePlane};
use rappel_terrain::plane_series::{PlaneSeriesError, TerrainPlane, validate_planes};
use rappel_terrain::surface::Terrain;

/// Largest angle, radians, between a surface's unfolded fall line and the frame's `-y` that
/// [`PlaneSeries::from_terrain`] accepts (charts are built in floating point: a few ulps of a
/// unit vector); also the gravity component below which a surface counts as level.
pub const FALL_LINE_TOLERANCE: f64 = 1e-9;

/// Largest difference in `y` between the two ends of a shared edge, relative to the planning
/// range's height, that [`PlaneSeries::from_terrain`] accepts as a level line.
pub const EDGE_LEVEL_TOLERANCE: f64 = 1e-12;

/// Why a plane series cannot be used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TerrainError {
    /// The series is malformed (gap, empty band, slope or friction out of range).
    #[error(transparent)]
    Planes(#[from] PlaneSeriesError),
    /// A [`Terrain`] that is not a series of bands down one common fall line (see
    /// [`PlaneSeries::from_terrain`]): what is wrong and where.
    #[error(
        "surface {surface}: {problem} (the Chapter-2 planner needs planes down one common fall line, thesis §2.1.2)"
    )]
    NotABandSeries {
        /// The surface (or, for an edge problem, the surface after the edge).
        surface: usize,
        /// What is wrong.
        problem: String,
    },
    /// The traversability model refuses a plane (for example a slope above 89 degrees).
    #[error("plane {plane}: {source}")]
    Plane {
        /// Plane index (0 = top).
        plane: usize,
        /// The model's objection.
        source: RobotError,
    },
}

/// A validated plane series with each plane's tether limit.
///
/// ```
/// use nalgebra::Point2;
/// use rappel_terrain::plane_series::TerrainPlane;
/// use rappel_mechanics::friction_cone::TetherFrictionCone;
/// use rappel_planners::terrain::PlaneSeries;
/// let planes = [
///     TerrainPlane { y_top: 100.0, y_bottom: 50.0, slope_deg: 20.0, friction: 0.4 },
///     TerrainPlane { y_top: 50.0, y_bottom: 0.0, slope_deg: 45.0, friction: 0.4 },
/// ];
/// let series = PlaneSeries::new(&planes, &TetherFrictionCone).unwrap();
/// assert!(!series.limit_at(&Point2::new(0.0, 80.0)).is_tether_demand());
/// let lower = series.limit_at(&Point2::new(0.0, 10.0)).max_angle().unwrap();
/// assert!((lower - 0.4f64.asin()).abs() < 1e-12);
/// assert!(series.concave_edges().is_empty());
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct PlaneSeries {
    planes: Vec<TerrainPlane>,
    limits: Vec<TetherLimit>,
}

impl PlaneSeries {
    /// The series `planes` (top first; may be empty for flat ground) under `model`.
    pub fn new(
        planes: &[TerrainPlane],
        model: &dyn AnchorTraversability,
    ) -> Result<PlaneSeries, TerrainError> {
        validate_planes(planes)?;
        let limits = planes
            .iter()
            .enumerate()
            .map(|(i, p)| {
                SlopePlane::new(p.slope_rad(), p.friction)
                    .map(|s| model.tether_limit(&s))
                    .map_err(|source| TerrainError::Plane { plane: i, source })
            })
            .collect::<Result<_, _>>()?;
        Ok(PlaneSeries {
            planes: planes.to_vec(),
            limits,
        })
    }

    /// The plane series of any [`Terrain`] whose surfaces are bands down one common fall line,
    /// the frame's `-y` (thesis §2.1.2: a plane series developed about its edges; the
    /// plane-series terrain and Kumar's multi-slope chains with a common fall line are such
    /// terrains), with each surface's tether limit under `model`. The top band reaches up to
    /// `y_range.1`, the bottom one down to `y_range.0` (the map's extent: the trait does not
    /// bound a terrain). Refused with [`TerrainError::NotABandSeries`] when a sloping surface's
    /// fall line, unfolded, is not `-y` within [`FALL_LINE_TOLERANCE`], or an edge is not a level
    /// line `y = const` within [`EDGE_LEVEL_TOLERANCE`] of the range, or the edges do not step
    /// down the frame in chain order.
    ///
    /// ```
    /// use rappel_terrain::plane_series::TerrainPlane;
    /// use rappel_terrain::plane_series_terrain::PlaneSeriesTerrain;
    /// use rappel_mechanics::friction_cone::TetherFrictionCone;
    /// use rappel_planners::terrain::PlaneSeries;
    /// let planes = [TerrainPlane::new(100.0, 50.0, 20.0, 0.4), TerrainPlane::new(50.0, 0.0, 45.0, 0.4)];
    /// let t = PlaneSeriesTerrain::new(&planes, (0.0, 40.0), vec![]).unwrap();
    /// let from_trait = PlaneSeries::from_terrain(&t, (0.0, 100.0), &TetherFrictionCone).unwrap();
    /// assert_eq!(from_trait.limits(), PlaneSeries::new(&planes, &TetherFrictionCone).unwrap().limits());
    /// ```
    pub fn from_terrain<T: Terrain + ?Sized>(
        terrain: &T,
        y_range: (f64, f64),
        model: &dyn AnchorTraversability,
    ) -> Result<PlaneSeries, TerrainError> {
        let n = terrain.surface_count();
        let bad =
            |surface: usize, problem: String| TerrainError::NotABandSeries { surface, problem };
        if n == 0 {
            return Err(bad(0, "the terrain has no surface".into()));
        }
        let span = y_range.1 - y_range.0;
        if !(span.is_finite() && span > 0.0) {
            return Err(bad(
                0,
                format!("the y range {y_range:?} is empty or not finite"),
            ));
        }
        for s in 0..n {
            let normal = terrain.normal(s);
            // Gravity's component in the surface's plane points down its fall line.
            let downhill = normal * normal.z - nalgebra::Vector3::z();
            if downhill.norm() <= FALL_LINE_TOLERANCE {
                continue; // level: no fall line
            }
            let c = terrain.chart(s);
            let d2 = c.u2 * downhill.dot(&c.u3) + c.w2 * downhill.dot(&c.w3);
            let off = d2.x.atan2(-d2.y).abs();
            if off.is_nan() || off > FALL_LINE_TOLERANCE {
                return Err(bad(
                    s,
                    format!(
                        "its fall line unfolds {:.6}° away from the frame's -y",
                        off.to_degrees()
                    ),
                ));
            }
        }
        let edges = terrain.edges();
        if edges.len() + 1 != n {
            return Err(bad(
                0,
                format!(
                    "{} surfaces but {} shared edges (a chain has one fewer)",
                    n,
                    edges.len()
                ),
            ));
        }
        let mut tops = vec![y_range.1];
        for (k, e) in edges.iter().enumerate() {
            if e.from != k || e.to != k + 1 {
                return Err(bad(
                    k + 1,
                    format!(
                        "edge {k} joins {} and {}, not {k} and {}",
                        e.from,
                        e.to,
                        k + 1
                    ),
                ));
            }
            if (e.a.y - e.b.y).abs() > EDGE_LEVEL_TOLERANCE * span {
                return Err(bad(
                    k + 1,
                    format!(
                        "its upper edge runs from y {} to y {}, not level",
                        e.a.y, e.b.y
                    ),
                ));
            }
            let y = 0.5 * (e.a.y + e.b.y);
            if !(y < *tops.last().unwrap_or(&f64::INFINITY) && y > y_range.0) {
                return Err(bad(
                    k + 1,
                    format!(
                        "its upper edge at y {y} is not below the one above and inside the range"
                    ),
                ));
            }
            tops.push(y);
        }
        let planes: Vec<TerrainPlane> = (0..n)
            .map(|s| TerrainPlane {
                y_top: tops[s],
                y_bottom: tops.get(s + 1).copied().unwrap_or(y_range.0),
                slope_deg: terrain.slope_rad(s).to_degrees(),
                friction: terrain.friction(s),
            })
            .collect();
        PlaneSeries::new(&planes, model)
    }

    /// Flat ground: no planes, tether-free everywhere.
    pub fn flat() -> PlaneSeries {
        PlaneSeries {
            planes: Vec::new(),
            limits: Vec::new(),
        }
    }

    /// The planes, top first.
    pub fn planes(&self) -> &[TerrainPlane] {
        &self.planes
    }

    /// Each plane's tether limit.
    pub fn limits(&self) -> &[TetherLimit] {
        &self.limits
    }

    /// The index of the plane holding map height `y`: the top-most band containing it, else the
    /// nearest band; `None` without planes.
    pub fn plane_index(&self, y: f64) -> Option<usize> {
        if self.planes.is_empty() {
            return None;
        }
        Some(self.planes.iter().position(|p| p.contains_y(y)).unwrap_or(
            if y > self.planes[0].y_top {
                0
            } else {
                self.planes.len() - 1
            },
        ))
    }

    /// The tether limit at map point `p` (tether-free without planes).
    pub fn limit_at(&self, p: &Point2<f64>) -> TetherLimit {
        self.plane_index(p.y)
            .map_or(TetherLimit::TetherFree, |i| self.limits[i])
    }

    /// `true` when every plane is tether-free (or there are none).
    pub fn all_tether_free(&self) -> bool {
        self.limits.iter().all(|l| !l.is_tether_demand())
    }

    /// Indices `k` where plane `k + 1` is shallower than plane `k` above it: a concave edge over
    /// which the taut tether may lift off the ground (module docs).
    pub fn concave_edges(&self) -> Vec<usize> {
        self.planes
            .windows(2)
            .enumerate()
            .filter(|(_, w)| w[1].slope_deg < w[0].slope_deg)
            .map(|(k, _)| k)
            .collect()
    }

    /// The segment `a -> b` cut at the band edges it crosses: consecutive pieces with the tether
    /// limit of the band each lies in.
    pub fn pieces(
        &self,
        a: Point2<f64>,
        b: Point2<f64>,
    ) -> Vec<(Point2<f64>, Point2<f64>, TetherLimit)> {
        let mut cuts: Vec<f64> = self
            .planes
            .iter()
            .skip(1)
            .map(|p| p.y_top)
            .filter(|&y| (y - a.y) * (y - b.y) < 0.0)
            .map(|y| (y - a.y) / (b.y - a.y))
            .collect();
        cuts.sort_by(f64::total_cmp);
        let mut out = Vec::with_capacity(cuts.len() + 1);
        let mut from = a;
        for t in cuts.into_iter().chain([1.0]) {
            let to = if t == 1.0 { b } else { a + (b - a) * t };
            let mid = Point2::from((from.coords + to.coords) / 2.0);
            out.push((from, to, self.limit_at(&mid)));
            from = to;
        }
        out
    }
}
