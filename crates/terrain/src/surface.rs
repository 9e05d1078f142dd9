//! The [`Terrain`] trait: what planners and mechanics may ask of the ground (Kumar §II; thesis
//! §2.1.2). A terrain is a chain of planar surfaces in 3D, developed isometrically into one planar
//! **frame** (the planning frame in which maps, paths and tethers live): every question is asked
//! with a frame point, and [`Terrain::fold`] / [`Terrain::unfold`] move between a surface's region
//! of the frame and the world.
//!
//! Two surfaces that share an edge meet at a [`EdgeKind::Crest`] (the lower surface falls away
//! below the upper one's plane: a taut tether crossing it rests on the edge and bends there, a
//! **ground anchor**; Kumar calls this a "concave" slope change, Fig. 3a, concave as seen from the
//! air side) or at a [`EdgeKind::Valley`] (the tether spans it through the air, Kumar's "convex"
//! case, Fig. 3b: no anchor). The thesis' "convex plane series" is a series of crests.
//!
//! Obstacles are [`Prism`]s: a base polygon on one surface (in frame coordinates), a height along
//! that surface's normal and the tether friction on their sides.

use nalgebra::{Point2, Point3, Unit, Vector2, Vector3};
use rappel_geometry::polygon::Polygon;
use serde::{Deserialize, Serialize};

/// An isometry between a surface's plane in the world and the frame: a point `o3 + s u3 + t w3`
/// of the plane is the frame point `o2 + s u2 + t w2` (`u`, `w` orthonormal in both).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Chart {
    /// A world point of the plane.
    pub o3: Point3<f64>,
    /// First in-plane unit vector (world).
    pub u3: Vector3<f64>,
    /// Second in-plane unit vector (world), orthogonal to `u3`.
    pub w3: Vector3<f64>,
    /// The frame image of `o3`.
    pub o2: Point2<f64>,
    /// The frame image of `u3`.
    pub u2: Vector2<f64>,
    /// The frame image of `w3`.
    pub w2: Vector2<f64>,
}

impl Chart {
    /// The world point of frame point `p` (on this chart's plane).
    ///
    /// ```
    /// use nalgebra::{Point2, Point3, Unit, Vector2, Vector3};
    /// use rappel_terrain::surface::Chart;
    /// let c = Chart { o3: Point3::origin(), u3: Vector3::x(), w3: Vector3::z(),
    ///                 o2: Point2::origin(), u2: Vector2::x(), w2: Vector2::y() };
    /// assert_eq!(c.fold(&Point2::new(1.0, 2.0)), Point3::new(1.0, 0.0, 2.0));
    /// assert_eq!(c.unfold(&Point3::new(1.0, 0.0, 2.0)), Point2::new(1.0, 2.0));
    /// ```
    pub fn fold(&self, p: &Point2<f64>) -> Point3<f64> {
        let d = p - self.o2;
        self.o3 + self.u3 * d.dot(&self.u2) + self.w3 * d.dot(&self.w2)
    }

    /// The frame point of world point `q`, projected onto this chart's plane.
    pub fn unfold(&self, q: &Point3<f64>) -> Point2<f64> {
        let d = q - self.o3;
        self.o2 + self.u2 * d.dot(&self.u3) + self.w2 * d.dot(&self.w3)
    }
}

/// How two surfaces meet along their shared edge.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum EdgeKind {
    /// The next surface falls away below the previous one's plane: the tether rests on the edge
    /// (a ground anchor; Kumar's "concave" case).
    Crest,
    /// The next surface rises above the previous one's plane: the tether spans the valley.
    Valley,
    /// The two surfaces are coplanar.
    Flat,
}

/// The edge shared by surfaces `from` and `to = from + 1`, in frame coordinates.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SharedEdge {
    /// The surface before the edge (in chain order).
    pub from: usize,
    /// The surface after it.
    pub to: usize,
    /// One end, in the frame.
    pub a: Point2<f64>,
    /// The other end, in the frame.
    pub b: Point2<f64>,
    /// Crest, valley or flat.
    pub kind: EdgeKind,
    /// The dihedral turn between the two surfaces, radians, `>= 0` (0 for coplanar).
    pub bend: f64,
}

/// An obstacle (Kumar's `O_k = (O_k^b, s_ok, h_ok, mu_ok)`): a prism standing on one surface.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Prism {
    /// The surface the base lies on.
    pub surface: usize,
    /// The base polygon, in frame coordinates (counter-clockwise once validated).
    pub base: Polygon,
    /// Height along the surface normal, metres.
    pub height: f64,
    /// Tether friction on its sides.
    pub friction: f64,
}

/// What planners and mechanics may ask of the ground. Surfaces are numbered `0..surface_count()`;
/// points are frame points unless a name says world.
pub trait Terrain {
    /// How many surfaces.
    fn surface_count(&self) -> usize;
    /// The surface holding frame point `p` (the first in chain order on a shared edge); `None` off
    /// the terrain.
    fn surface_at(&self, p: &Point2<f64>) -> Option<usize>;
    /// The chart of surface `s` (panics when `s >= surface_count()`).
    fn chart(&self, s: usize) -> &Chart;
    /// Wheel-ground friction of surface `s`.
    fn friction(&self, s: usize) -> f64;
    /// The shared edges, in chain order.
    fn edges(&self) -> &[SharedEdge];
    /// The obstacles.
    fn obstacles(&self) -> &[Prism];

    /// Upward unit normal of surface `s` (world).
    fn normal(&self, s: usize) -> Vector3<f64> {
        let c = self.chart(s);
        let n = c.u3.cross(&c.w3).normalize();
        if n.z < 0.0 { -n } else { n }
    }
    /// Inclination of surface `s` from horizontal, radians.
    fn slope_rad(&self, s: usize) -> f64 {
        self.normal(s).z.clamp(-1.0, 1.0).acos()
    }
    /// The world point of frame point `p` on surface `s` (fold).
    fn fold(&self, s: usize, p: &Point2<f64>) -> Point3<f64> {
        self.chart(s).fold(p)
    }
    /// The frame point of world point `q` on surface `s` (unfold).
    fn unfold(&self, s: usize, q: &Point3<f64>) -> Point2<f64> {
        self.chart(s).unfold(q)
    }
    /// The world point of frame point `p` on whichever surface holds it.
    fn world(&self, p: &Point2<f64>) -> Option<Point3<f64>> {
        self.surface_at(p).map(|s| self.fold(s, p))
    }
    /// Height (world `z`) of the ground at frame point `p`.
    fn height(&self, p: &Point2<f64>) -> Option<f64> {
        self.world(p).map(|q| q.z)
    }
}

/// The closest point of a [`Terrain`]'s surfaces to a world point, with its signed distance
/// (see [`Terrain::signed_distance`]).
fn closest_on_terrain<T: Terrain + ?Sized>(t: &T, q: &Point3<f64>) -> Option<(f64, Vector3<f64>)> {
    let mut best: Option<(f64, Vector3<f64>)> = None;
    let mut consider = |d: f64, g: Vector3<f64>| {
        if best.is_none_or(|(b, _)| d.abs() < b.abs()) {
            best = Some((d, g));
        }
    };
    // Faces: the projection of q onto surface s's plane, when surface s holds it.
    for s in 0..t.surface_count() {
        let p = t.unfold(s, q);
        if t.surface_at(&p) == Some(s) {
            let n = t.normal(s);
            consider((q - t.fold(s, &p)).dot(&n), n);
        }
    }
    // Shared edges: the distance to the segment, signed by the earlier surface's plane (a point
    // nearest a crest lies above both planes, one nearest a valley below both).
    for e in t.edges() {
        let (a, b) = (t.fold(e.from, &e.a), t.fold(e.from, &e.b));
        let ab = b - a;
        let u = ((q - a).dot(&ab) / ab.norm_squared()).clamp(0.0, 1.0);
        let c = a + ab * u;
        let v = q - c;
        let dist = v.norm();
        if dist == 0.0 {
            consider(0.0, t.normal(e.from));
            continue;
        }
        let sign = if v.dot(&t.normal(e.from)) < 0.0 {
            -1.0
        } else {
            1.0
        };
        consider(sign * dist, sign * v / dist);
    }
    best
}

/// Most sphere-tracing steps of the default [`SignedDistance::ground_below`] and
/// [`SignedDistance::ground_along`] (analytic terrains; meshes and grid fields answer exactly).
pub const MAX_DROP_STEPS: usize = 200;

/// Why [`SignedDistance::ground_below`] found no ground point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DropError {
    /// The model has no distance at this point (off the terrain, outside a field's grid).
    Undefined(Point3<f64>),
    /// No ground within the default searches' bound ([`MAX_DROP_STEPS`] sphere-tracing steps).
    NotReached,
    /// The vertical through this point meets no ground at all (a mesh with no triangle over it).
    Missed(Point3<f64>),
}

/// Signed distance to the ground (Paton §IV's distance queries, answered analytically for
/// planar-surface terrains): implemented for every [`Terrain`] and by the mesh distance field.
pub trait SignedDistance {
    /// Signed distance from world point `q` to the ground, metres, positive in the air; `None`
    /// where the model has no answer (off the terrain or outside a field's grid).
    fn signed_distance(&self, q: &Point3<f64>) -> Option<f64>;
    /// The gradient of the signed distance at `q` (a unit vector pointing away from the ground
    /// for exact distances); `None` where [`SignedDistance::signed_distance`] is.
    fn distance_gradient(&self, q: &Point3<f64>) -> Option<Vector3<f64>>;
    /// The ground point on the vertical through `q`: the first zero of the signed distance
    /// straight below `q` when `q` is in the air, straight above when it is below the ground.
    ///
    /// The default is sphere tracing (each step moves by the distance, so it never passes
    /// through the ground), stopping within `tolerance` of the ground, at most [`MAX_DROP_STEPS`]
    /// steps. It converges only at the rate `1 - s`, `s` the distance's slope along the
    /// vertical: slowly where the vertical runs beside a wall (exact distances) or where an
    /// interpolated field is nearly flat along it (a wall's top edge smeared over a cell), and
    /// the budget then runs out on ground that is there. Meshes (an exact vertical ray against
    /// the triangles) and the grid fields (the interpolant is linear along the vertical within a
    /// cell: its exact first zero, cell by cell) override it.
    fn ground_below(&self, q: &Point3<f64>, tolerance: f64) -> Result<Point3<f64>, DropError> {
        let mut q = *q;
        for _ in 0..MAX_DROP_STEPS {
            let d = self.signed_distance(&q).ok_or(DropError::Undefined(q))?;
            if d.abs() < tolerance {
                return Ok(q);
            }
            q.z -= d;
        }
        Err(DropError::NotReached)
    }
    /// The first ground point on the line through `q` along the unit vector `dir` (the settlers'
    /// drop along a footprint normal, Paton §IV-A): the signed parameter `t` of the first zero of
    /// the signed distance at `q + t dir`, searched forward (`0 <= t <= reach`) when `q` is in the
    /// air and backward (`-reach <= t <= 0`) when it is below the ground; `0` on the ground.
    /// `Ok(None)` when the line meets no ground within `reach`.
    ///
    /// The default is sphere tracing (each step moves by the distance, so it never passes the
    /// first zero), stopping within `tolerance` of the ground, at most [`MAX_DROP_STEPS`] steps
    /// ([`DropError::NotReached`] beyond them): slow where the line runs beside a wall, which is
    /// why meshes (an exact segment-triangle test, `mesh::segment_hit`) and the grid fields (the
    /// interpolant's exact first zero, cell by cell, `sdf::first_zero_on_grid`) override it.
    ///
    /// ```
    /// use nalgebra::{Point3, Unit, Vector3};
    /// use rappel_terrain::surface::SignedDistance;
    /// struct Floor;
    /// impl SignedDistance for Floor {
    ///     fn signed_distance(&self, q: &Point3<f64>) -> Option<f64> { Some(q.z) }
    ///     fn distance_gradient(&self, _: &Point3<f64>) -> Option<Vector3<f64>> { Some(Vector3::z()) }
    /// }
    /// // 45° down from 1 m above the floor: sqrt 2 m along the line.
    /// let dir = Unit::new_normalize(Vector3::new(1.0, 0.0, -1.0));
    /// let t = Floor.ground_along(&Point3::new(0.0, 0.0, 1.0), &dir, 5.0, 1e-9).unwrap().unwrap();
    /// assert!((t - 2f64.sqrt()).abs() < 1e-8);
    /// // Upward from the air: no ground within reach.
    /// assert_eq!(Floor.ground_along(&Point3::new(0.0, 0.0, 1.0), &Vector3::z_axis(), 5.0, 1e-9), Ok(None));
    /// ```
    fn ground_along(
        &self,
        q: &Point3<f64>,
        dir: &Unit<Vector3<f64>>,
        reach: f64,
        tolerance: f64,
    ) -> Result<Option<f64>, DropError> {
        let mut t = 0.0;
        for _ in 0..MAX_DROP_STEPS {
            let p = q + dir.as_ref() * t;
            let d = self.signed_distance(&p).ok_or(DropError::Undefined(p))?;
            if d.abs() < tolerance {
                return Ok(Some(t));
            }
            // Forward in the air, backward below the ground: toward the nearest zero either way.
            t += d;
            if t.abs() > reach {
                return Ok(None);
            }
        }
        Err(DropError::NotReached)
    }
}

/// Analytic distances of a chain of planar surfaces: the nearest of (a) each surface's plane where
/// the foot of the perpendicular lies on that surface and (b) each shared edge segment. Exact for
/// points whose closest ground point is inside a surface or on a shared edge; the terrain's outer
/// boundary and the obstacle prisms are not part of this distance (a point whose foot falls off
/// every surface and nearest no shared edge gets `None`).
///
/// ```
/// use nalgebra::{Point2, Point3};
/// use rappel_terrain::multi_slope::MultiSlopeTerrain;
/// use rappel_terrain::surface::SignedDistance;
/// # let _ = Point2::<f64>::origin();
/// fn height_above<T: SignedDistance>(t: &T, q: Point3<f64>) -> Option<f64> { t.signed_distance(&q) }
/// # let _ = height_above::<MultiSlopeTerrain>;
/// ```
impl<T: Terrain> SignedDistance for T {
    fn signed_distance(&self, q: &Point3<f64>) -> Option<f64> {
        closest_on_terrain(self, q).map(|(d, _)| d)
    }
    fn distance_gradient(&self, q: &Point3<f64>) -> Option<Vector3<f64>> {
        closest_on_terrain(self, q).map(|(_, g)| g)
    }
}
