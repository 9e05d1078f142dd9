//! Multi-slope terrain (Kumar §II, Fig. 1): planar convex surfaces in 3D, each sharing an edge with
//! the one before it at any angle, developed into the frame of the first surface; obstacles are
//! prisms on a surface. Implements [`Terrain`].
//!
//! The development: surface 0 is laid flat with its first vertex at the frame origin and its first
//! edge along `+x`; each next surface is rotated about the edge it shares with the previous one
//! into that one's plane, on the far side of the edge (Kumar's rotatewrtAnchorSurface, composed).

use crate::surface::{Chart, EdgeKind, Prism, SharedEdge, Terrain};
use nalgebra::{Point2, Point3, Vector2, Vector3};
use rappel_geometry::polygon::Polygon;
use rappel_geometry::predicates::orient2d;
use serde::{Deserialize, Serialize};

/// Relative tolerance of the surface checks (planarity, shared vertices), times the terrain's
/// extent: surfaces are typed in by hand in metres, so 1e-9 of the extent is far below any
/// survey precision and far above f64 rounding.
pub const RELATIVE_TOLERANCE: f64 = 1e-9;

/// Most surfaces accepted (each query scans the surfaces): a bound on the work per query.
pub const MAX_SURFACES: usize = 10_000;

/// Most obstacle vertices accepted (the tracker scans them per step).
pub const MAX_OBSTACLE_VERTICES: usize = 1_000_000;

/// One surface as given: a convex planar polygon in the world.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SurfaceSpec {
    /// Vertices in the world, in order around the polygon.
    pub vertices: Vec<Point3<f64>>,
    /// Wheel-ground friction.
    pub friction: f64,
}

/// One obstacle as given: a base polygon in the world on surface `surface`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObstacleSpec {
    /// The surface the base lies on.
    pub surface: usize,
    /// Base vertices in the world (on the surface's plane), in order.
    pub base: Vec<Point3<f64>>,
    /// Height along the surface normal, metres (> 0).
    pub height: f64,
    /// Tether friction on its sides.
    pub friction: f64,
}

/// Why a multi-slope terrain is refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MultiSlopeError {
    /// No surfaces, or too many.
    #[error("a terrain needs 1 to {MAX_SURFACES} surfaces, got {0}")]
    SurfaceCount(usize),
    /// A number is NaN or infinite.
    #[error("surface {surface}: a coordinate or friction is not finite")]
    NonFinite {
        /// Surface index.
        surface: usize,
    },
    /// Fewer than three vertices, or zero area.
    #[error("surface {surface} is degenerate (fewer than 3 vertices or zero area)")]
    Degenerate {
        /// Surface index.
        surface: usize,
    },
    /// A vertex is off the plane of the first three.
    #[error("surface {surface}: vertex {vertex} is off the surface's plane")]
    NotPlanar {
        /// Surface index.
        surface: usize,
        /// Vertex index.
        vertex: usize,
    },
    /// The polygon is not convex.
    #[error("surface {surface} is not convex")]
    NotConvex {
        /// Surface index.
        surface: usize,
    },
    /// Surface `surface` shares no edge with surface `surface - 1`.
    #[error("surface {surface} shares no edge with surface {}", surface - 1)]
    NoSharedEdge {
        /// Surface index.
        surface: usize,
    },
    /// Friction out of range.
    #[error("surface {surface}: friction must be finite and >= 0")]
    Friction {
        /// Surface index.
        surface: usize,
    },
    /// An obstacle is malformed.
    #[error("obstacle {obstacle}: {reason}")]
    Obstacle {
        /// Obstacle index.
        obstacle: usize,
        /// What is wrong.
        reason: String,
    },
}

/// A developed chain of planar surfaces with prism obstacles.
///
/// ```
/// use nalgebra::{Point2, Point3};
/// use rappel_terrain::multi_slope::{MultiSlopeTerrain, SurfaceSpec};
/// use rappel_terrain::surface::{EdgeKind, Terrain};
/// let p = |x, y, z| Point3::new(x, y, z);
/// // A flat top and a 45 degree slope falling away from its edge y = 0.
/// let top = SurfaceSpec { vertices: vec![p(0., 0., 0.), p(10., 0., 0.), p(10., 10., 0.), p(0., 10., 0.)], friction: 0.4 };
/// let s = 10.0 / 2f64.sqrt();
/// let slope = SurfaceSpec { vertices: vec![p(0., 0., 0.), p(0., -s, -s), p(10., -s, -s), p(10., 0., 0.)], friction: 0.4 };
/// let t = MultiSlopeTerrain::new(vec![top, slope], vec![]).unwrap();
/// assert_eq!(t.edges()[0].kind, EdgeKind::Crest);
/// assert!((t.slope_rad(1) - std::f64::consts::FRAC_PI_4).abs() < 1e-12);
/// let q = t.world(&Point2::new(5.0, -5.0)).unwrap(); // 5 m down the slope, unfolded
/// assert!((q.z + 5.0 / 2f64.sqrt()).abs() < 1e-9);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct MultiSlopeTerrain {
    charts: Vec<Chart>,
    frame_polygons: Vec<Polygon>,
    frictions: Vec<f64>,
    edges: Vec<SharedEdge>,
    obstacles: Vec<Prism>,
}

fn plane_basis(v: &[Point3<f64>]) -> Option<(Vector3<f64>, Vector3<f64>, Vector3<f64>)> {
    // Newell's normal: robust for any planar polygon.
    let mut n = Vector3::zeros();
    for i in 0..v.len() {
        let (a, b) = (v[i], v[(i + 1) % v.len()]);
        n += Vector3::new(
            (a.y - b.y) * (a.z + b.z),
            (a.z - b.z) * (a.x + b.x),
            (a.x - b.x) * (a.y + b.y),
        );
    }
    let n = n.try_normalize(0.0)?;
    let u = (v[1] - v[0]).try_normalize(0.0)?;
    let w = n.cross(&u);
    Some((u, w, n))
}

impl MultiSlopeTerrain {
    /// Develops `surfaces` (surface `i > 0` shares an edge with surface `i - 1`) and places the
    /// obstacles.
    pub fn new(
        surfaces: Vec<SurfaceSpec>,
        obstacles: Vec<ObstacleSpec>,
    ) -> Result<MultiSlopeTerrain, MultiSlopeError> {
        if surfaces.is_empty() || surfaces.len() > MAX_SURFACES {
            return Err(MultiSlopeError::SurfaceCount(surfaces.len()));
        }
        let mut extent: f64 = 0.0;
        for (i, s) in surfaces.iter().enumerate() {
            if s.vertices.iter().any(|p| !p.iter().all(|c| c.is_finite())) {
                return Err(MultiSlopeError::NonFinite { surface: i });
            }
            if !(s.friction.is_finite() && s.friction >= 0.0) {
                return Err(MultiSlopeError::Friction { surface: i });
            }
            for p in &s.vertices {
                extent = extent.max(p.coords.amax());
            }
        }
        let tol = RELATIVE_TOLERANCE * extent.max(f64::MIN_POSITIVE);
        let mut charts: Vec<Chart> = Vec::with_capacity(surfaces.len());
        let mut frame_polygons: Vec<Polygon> = Vec::with_capacity(surfaces.len());
        let mut edges = Vec::new();
        for (i, s) in surfaces.iter().enumerate() {
            let v = &s.vertices;
            let (u, w, n) = if v.len() >= 3 {
                plane_basis(v).ok_or(MultiSlopeError::Degenerate { surface: i })?
            } else {
                return Err(MultiSlopeError::Degenerate { surface: i });
            };
            if let Some(k) = v.iter().position(|p| (p - v[0]).dot(&n).abs() > tol) {
                return Err(MultiSlopeError::NotPlanar {
                    surface: i,
                    vertex: k,
                });
            }
            let chart = if i == 0 {
                Chart {
                    o3: v[0],
                    u3: u,
                    w3: w,
                    o2: Point2::origin(),
                    u2: Vector2::x(),
                    w2: Vector2::y(),
                }
            } else {
                let prev = &surfaces[i - 1].vertices;
                let shared: Vec<Point3<f64>> = v
                    .iter()
                    .filter(|p| prev.iter().any(|q| (*p - q).norm() <= tol))
                    .copied()
                    .collect();
                if shared.len() < 2 {
                    return Err(MultiSlopeError::NoSharedEdge { surface: i });
                }
                let (a, b) = (shared[0], shared[1]);
                let pc = &charts[i - 1];
                let (a2, b2) = (pc.unfold(&a), pc.unfold(&b));
                let eu3 = (b - a).normalize();
                let centroid3 =
                    Point3::from(v.iter().map(|p| p.coords).sum::<Vector3<f64>>() / v.len() as f64);
                let mut ew3 = n.cross(&eu3);
                if (centroid3 - a).dot(&ew3) < 0.0 {
                    ew3 = -ew3;
                }
                let eu2 = (b2 - a2).normalize();
                let prev_centroid2 = Point2::from(
                    frame_polygons[i - 1]
                        .vertices
                        .iter()
                        .map(|p| p.coords)
                        .sum::<Vector2<f64>>()
                        / frame_polygons[i - 1].len() as f64,
                );
                let mut ew2 = Vector2::new(-eu2.y, eu2.x);
                if (prev_centroid2 - a2).dot(&ew2) > 0.0 {
                    ew2 = -ew2;
                }
                // Crest or valley: does this surface fall below the previous surface's plane?
                let prev_n = {
                    let c = &charts[i - 1];
                    let m = c.u3.cross(&c.w3);
                    if m.z < 0.0 { -m } else { m }
                };
                let rise = prev_n.dot(&ew3);
                let up_n = if n.z < 0.0 { -n } else { n };
                let bend = prev_n.dot(&up_n).clamp(-1.0, 1.0).acos();
                let kind = if bend <= RELATIVE_TOLERANCE {
                    EdgeKind::Flat
                } else if rise < 0.0 {
                    EdgeKind::Crest
                } else {
                    EdgeKind::Valley
                };
                edges.push(SharedEdge {
                    from: i - 1,
                    to: i,
                    a: a2,
                    b: b2,
                    kind,
                    bend,
                });
                Chart {
                    o3: a,
                    u3: eu3,
                    w3: ew3,
                    o2: a2,
                    u2: eu2,
                    w2: ew2,
                }
            };
            let poly =
                Polygon::new(v.iter().map(|p| chart.unfold(p)).collect()).to_counter_clockwise();
            if poly.area() <= tol * tol {
                return Err(MultiSlopeError::Degenerate { surface: i });
            }
            if !poly.is_convex() {
                return Err(MultiSlopeError::NotConvex { surface: i });
            }
            charts.push(chart);
            frame_polygons.push(poly);
        }
        let frictions = surfaces.iter().map(|s| s.friction).collect();
        let mut t = MultiSlopeTerrain {
            charts,
            frame_polygons,
            frictions,
            edges,
            obstacles: Vec::new(),
        };
        let total: usize = obstacles.iter().map(|o| o.base.len()).sum();
        if total > MAX_OBSTACLE_VERTICES {
            return Err(MultiSlopeError::Obstacle {
                obstacle: 0,
                reason: format!(
                    "{total} obstacle vertices in all exceed the limit {MAX_OBSTACLE_VERTICES}"
                ),
            });
        }
        for (k, o) in obstacles.into_iter().enumerate() {
            let bad = |reason: String| MultiSlopeError::Obstacle {
                obstacle: k,
                reason,
            };
            if o.surface >= t.charts.len() {
                return Err(bad(format!("surface {} does not exist", o.surface)));
            }
            if !(o.height.is_finite() && o.height > 0.0) {
                return Err(bad("height must be finite and > 0".into()));
            }
            if !(o.friction.is_finite() && o.friction >= 0.0) {
                return Err(bad("friction must be finite and >= 0".into()));
            }
            if o.base.len() < 3 || o.base.iter().any(|p| !p.iter().all(|c| c.is_finite())) {
                return Err(bad("the base needs 3 or more finite vertices".into()));
            }
            let n = t.normal(o.surface);
            let c = t.charts[o.surface];
            if let Some(j) = o.base.iter().position(|p| (p - c.o3).dot(&n).abs() > tol) {
                return Err(bad(format!(
                    "base vertex {j} is off surface {}'s plane",
                    o.surface
                )));
            }
            let base =
                Polygon::new(o.base.iter().map(|p| c.unfold(p)).collect()).to_counter_clockwise();
            if base.area() <= tol * tol {
                return Err(bad("the base has zero area".into()));
            }
            let holder = &t.frame_polygons[o.surface];
            if let Some(j) = base
                .vertices
                .iter()
                .position(|p| !convex_contains(holder, p))
            {
                return Err(bad(format!(
                    "base vertex {j} is outside surface {}",
                    o.surface
                )));
            }
            t.obstacles.push(Prism {
                surface: o.surface,
                base,
                height: o.height,
                friction: o.friction,
            });
        }
        Ok(t)
    }

    /// The surfaces' polygons in the frame (counter-clockwise).
    pub fn frame_polygons(&self) -> &[Polygon] {
        &self.frame_polygons
    }
}

/// Exact closed containment in a counter-clockwise convex polygon.
pub fn convex_contains(poly: &Polygon, p: &Point2<f64>) -> bool {
    poly.edges().all(|(a, b)| orient2d(a, b, p) >= 0.0)
}

impl Terrain for MultiSlopeTerrain {
    fn surface_count(&self) -> usize {
        self.charts.len()
    }
    fn surface_at(&self, p: &Point2<f64>) -> Option<usize> {
        self.frame_polygons
            .iter()
            .position(|poly| convex_contains(poly, p))
    }
    fn chart(&self, s: usize) -> &Chart {
        &self.charts[s]
    }
    fn friction(&self, s: usize) -> f64 {
        self.frictions[s]
    }
    fn edges(&self) -> &[SharedEdge] {
        &self.edges
    }
    fn obstacles(&self) -> &[Prism] {
        &self.obstacles
    }
}
