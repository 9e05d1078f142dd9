//! Triangle-mesh terrain (Paton §IV): a validated triangle mesh of the ground in world
//! coordinates, built from a height field ([`TriMesh::from_height_grid`]), from procedural scenes
//! ([`crate::paton_scene`]) or from raw vertex / index arrays ([`TriMesh::new`]), with exact
//! closest-point and signed-distance queries.
//!
//! The sign follows the angle-weighted pseudo-normals of Bærentzen and Aanæs (2005): the sign of
//! `(q - c) . n` where `c` is the closest point and `n` the pseudo-normal of the feature (face,
//! edge or vertex) holding `c`. Positive is the air side (the side the faces' counter-clockwise
//! normals point to). The sign is exact for a closed or boundary-free-near-`c` manifold mesh; at
//! an open mesh's outer boundary it is the boundary face's side.
//!
//! Queries are exact but brute force (`O(triangles)` per query, a bound documented on each
//! method): the [`crate::sdf`] voxel field is the fast path for planners and the settler.

use std::collections::HashMap;

use nalgebra::{Point3, Vector3};
use rappel_geometry::compact::Compact;
use rappel_geometry::domain::{DOMAIN_TEXT, in_domain};

use crate::grid::HeightGrid;

/// The most triangles a mesh may have (memory bound: about 100 bytes per triangle with its
/// pseudo-normals, so 400 MB). Larger meshes are a [`MeshError::TooLarge`].
pub const MAX_TRIANGLES: usize = 4_000_000;

/// A triangle whose area is below this fraction of the squared bounding-box diagonal is
/// degenerate (its normal is numerically meaningless). Relative to the scene's scale.
pub const DEGENERATE_AREA_REL: f64 = 1e-14;

/// A defect in a mesh, with where it is.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MeshError {
    /// No vertices or no triangles. Fix: give at least one triangle.
    #[error("empty mesh: {vertices} vertices, {triangles} triangles (need at least one triangle)")]
    Empty {
        /// Vertex count given.
        vertices: usize,
        /// Triangle count given.
        triangles: usize,
    },
    /// More than [`MAX_TRIANGLES`] triangles. Fix: decimate or crop the mesh.
    #[error("mesh too large: {triangles} triangles, the limit is {limit}")]
    TooLarge {
        /// Triangle count given.
        triangles: usize,
        /// [`MAX_TRIANGLES`].
        limit: usize,
    },
    /// A vertex coordinate is NaN or infinite.
    #[error("vertex {vertex}: coordinate {axis} is not finite ({value})")]
    NonFiniteVertex {
        /// Vertex index.
        vertex: usize,
        /// `x`, `y` or `z`.
        axis: char,
        /// The value found.
        value: f64,
    },
    /// A finite vertex coordinate outside the coordinate domain
    /// ([`rappel_geometry::domain`]: 0 or a magnitude in `[2^-120, 2^120]`), where distances
    /// and areas would overflow or lose all precision. Fix: the mesh's units or origin.
    #[error("vertex {vertex}: coordinate {axis} = {}: {DOMAIN_TEXT}", Compact(*.value))]
    VertexOutOfDomain {
        /// Vertex index.
        vertex: usize,
        /// `x`, `y` or `z`.
        axis: char,
        /// The value found.
        value: f64,
    },
    /// A triangle names a vertex that does not exist.
    #[error(
        "triangle {triangle}: corner {corner} is vertex {index}, but there are only {vertices} vertices"
    )]
    IndexOutOfRange {
        /// Triangle index.
        triangle: usize,
        /// Corner `0..3`.
        corner: usize,
        /// The index found.
        index: usize,
        /// Vertex count.
        vertices: usize,
    },
    /// A triangle has (nearly) zero area or repeats a vertex.
    #[error("triangle {triangle} is degenerate: area {area:e} (minimum {min_area:e})")]
    DegenerateTriangle {
        /// Triangle index.
        triangle: usize,
        /// Its area.
        area: f64,
        /// The threshold, [`DEGENERATE_AREA_REL`] times the squared bounding-box diagonal.
        min_area: f64,
    },
    /// An edge is shared by more than two triangles.
    #[error("non-manifold edge ({a}, {b}): shared by triangles {first}, {second} and {third}")]
    NonManifoldEdge {
        /// One end (vertex index).
        a: usize,
        /// The other end.
        b: usize,
        /// First triangle holding it.
        first: usize,
        /// Second.
        second: usize,
        /// Third.
        third: usize,
    },
    /// Two triangles share an edge with the same direction (their normals disagree on the side).
    #[error(
        "triangles {first} and {second} traverse edge ({a}, {b}) in the same direction: inconsistent orientation"
    )]
    InconsistentOrientation {
        /// One end (vertex index).
        a: usize,
        /// The other end.
        b: usize,
        /// First triangle.
        first: usize,
        /// Second triangle.
        second: usize,
    },
}

/// The feature of a triangle that holds a closest point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Feature {
    /// The interior of the face.
    Face,
    /// Edge `k` (from corner `k` to corner `(k + 1) % 3`).
    Edge(usize),
    /// Corner `k`.
    Vertex(usize),
}

/// The closest point of a mesh to a query point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Closest {
    /// The closest point on the mesh.
    pub point: Point3<f64>,
    /// The triangle holding it.
    pub triangle: usize,
    /// The feature of that triangle.
    pub feature: Feature,
    /// Signed distance (positive on the air side).
    pub signed_distance: f64,
}

/// A validated triangle mesh: finite vertices, in-range indices, no degenerate triangle, every
/// edge on at most two consistently oriented triangles.
#[derive(Debug, Clone)]
pub struct TriMesh {
    vertices: Vec<Point3<f64>>,
    triangles: Vec<[usize; 3]>,
    face_normals: Vec<Vector3<f64>>,
    vertex_normals: Vec<Vector3<f64>>,
    /// Per triangle, per edge `k`: the edge pseudo-normal.
    edge_normals: Vec<[Vector3<f64>; 3]>,
}

impl TriMesh {
    /// A mesh from vertices and counter-clockwise (seen from the air side) triangles, validated.
    ///
    /// ```
    /// use nalgebra::Point3;
    /// use rappel_terrain::mesh::TriMesh;
    /// let v = vec![Point3::new(0.0, 0.0, 0.0), Point3::new(1.0, 0.0, 0.0), Point3::new(0.0, 1.0, 0.0)];
    /// let m = TriMesh::new(v, vec![[0, 1, 2]]).unwrap();
    /// assert!((m.signed_distance(&Point3::new(0.2, 0.2, 0.5)) - 0.5).abs() < 1e-12);
    /// assert!(TriMesh::new(vec![], vec![]).is_err());
    /// ```
    pub fn new(vertices: Vec<Point3<f64>>, triangles: Vec<[usize; 3]>) -> Result<Self, MeshError> {
        if vertices.is_empty() || triangles.is_empty() {
            return Err(MeshError::Empty {
                vertices: vertices.len(),
                triangles: triangles.len(),
            });
        }
        if triangles.len() > MAX_TRIANGLES {
            return Err(MeshError::TooLarge {
                triangles: triangles.len(),
                limit: MAX_TRIANGLES,
            });
        }
        for (i, v) in vertices.iter().enumerate() {
            for (axis, value) in [('x', v.x), ('y', v.y), ('z', v.z)] {
                if !value.is_finite() {
                    return Err(MeshError::NonFiniteVertex {
                        vertex: i,
                        axis,
                        value,
                    });
                }
                if !in_domain(value) {
                    return Err(MeshError::VertexOutOfDomain {
                        vertex: i,
                        axis,
                        value,
                    });
                }
            }
        }
        for (t, tri) in triangles.iter().enumerate() {
            for (corner, &index) in tri.iter().enumerate() {
                if index >= vertices.len() {
                    return Err(MeshError::IndexOutOfRange {
                        triangle: t,
                        corner,
                        index,
                        vertices: vertices.len(),
                    });
                }
            }
        }
        let (lo, hi) = bounds(&vertices);
        let diag2 = (hi - lo).norm_squared();
        let min_area = DEGENERATE_AREA_REL * diag2;
        let mut face_normals = Vec::with_capacity(triangles.len());
        for (t, tri) in triangles.iter().enumerate() {
            let [a, b, c] = tri.map(|i| vertices[i]);
            let cross = (b - a).cross(&(c - a));
            let area = 0.5 * cross.norm();
            // Not `area > min_area` also catches a zero-size mesh (min_area 0) and NaN.
            let big_enough = area.partial_cmp(&min_area) == Some(std::cmp::Ordering::Greater);
            if !big_enough || tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2] {
                return Err(MeshError::DegenerateTriangle {
                    triangle: t,
                    area,
                    min_area,
                });
            }
            face_normals.push(cross / (2.0 * area));
        }
        // Edge incidence: undirected edge -> the (triangle, directed?) list. Bounded by 3 per
        // triangle.
        let mut edges: HashMap<(usize, usize), Vec<(usize, bool)>> = HashMap::new();
        for (t, tri) in triangles.iter().enumerate() {
            for k in 0..3 {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                let key = (a.min(b), a.max(b));
                let list = edges.entry(key).or_default();
                if list.len() == 2 {
                    return Err(MeshError::NonManifoldEdge {
                        a: key.0,
                        b: key.1,
                        first: list[0].0,
                        second: list[1].0,
                        third: t,
                    });
                }
                if let Some(&(other, _)) = list.first().filter(|&&(_, fwd)| fwd == (a < b)) {
                    return Err(MeshError::InconsistentOrientation {
                        a: key.0,
                        b: key.1,
                        first: other,
                        second: t,
                    });
                }
                list.push((t, a < b));
            }
        }
        let mut vertex_normals = vec![Vector3::zeros(); vertices.len()];
        for (t, tri) in triangles.iter().enumerate() {
            for k in 0..3 {
                let p = vertices[tri[k]];
                let e1 = (vertices[tri[(k + 1) % 3]] - p).normalize();
                let e2 = (vertices[tri[(k + 2) % 3]] - p).normalize();
                let angle = e1.dot(&e2).clamp(-1.0, 1.0).acos();
                vertex_normals[tri[k]] += face_normals[t] * angle;
            }
        }
        let mut edge_normals = Vec::with_capacity(triangles.len());
        for tri in &triangles {
            let mut en = [Vector3::zeros(); 3];
            for (k, n) in en.iter_mut().enumerate() {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                *n = edges[&(a.min(b), a.max(b))]
                    .iter()
                    .map(|&(s, _)| face_normals[s])
                    .sum();
            }
            edge_normals.push(en);
        }
        Ok(TriMesh {
            vertices,
            triangles,
            face_normals,
            vertex_normals,
            edge_normals,
        })
    }

    /// A mesh of a height grid: one vertex per known cell centre, two triangles per 2 x 2 block
    /// of known centres (split along the south-west / north-east diagonal); unknown cells leave
    /// holes. [`MeshError::Empty`] when no 2 x 2 block is fully known.
    ///
    /// ```
    /// use rappel_terrain::grid::{GridGeometry, HeightGrid};
    /// use rappel_terrain::mesh::TriMesh;
    /// let g = GridGeometry::new(3, 3, 1.0, 1.0, 0.0, 3.0).unwrap();
    /// let dem = HeightGrid::from_fn(g, |_, _, _| Some(2.0)).unwrap();
    /// let m = TriMesh::from_height_grid(&dem).unwrap();
    /// assert_eq!(m.triangles().len(), 8);
    /// ```
    pub fn from_height_grid(dem: &HeightGrid) -> Result<Self, MeshError> {
        let g = dem.geometry();
        let mut index = vec![usize::MAX; g.len()];
        let mut vertices = Vec::new();
        for row in 0..g.nrows {
            for col in 0..g.ncols {
                if let Some(h) = dem.height(row, col) {
                    let c = g.cell_center(row, col);
                    index[g.index(row, col)] = vertices.len();
                    vertices.push(Point3::new(c.x, c.y, h));
                }
            }
        }
        let mut triangles = Vec::new();
        for row in 0..g.nrows.saturating_sub(1) {
            for col in 0..g.ncols.saturating_sub(1) {
                // Rows run north to south: (row + 1) is south.
                let sw = index[g.index(row + 1, col)];
                let se = index[g.index(row + 1, col + 1)];
                let ne = index[g.index(row, col + 1)];
                let nw = index[g.index(row, col)];
                if [sw, se, ne, nw].contains(&usize::MAX) {
                    continue;
                }
                triangles.push([sw, se, ne]);
                triangles.push([sw, ne, nw]);
            }
        }
        TriMesh::new(vertices, triangles)
    }

    /// The vertices.
    pub fn vertices(&self) -> &[Point3<f64>] {
        &self.vertices
    }

    /// The triangles (vertex indices, counter-clockwise from the air side).
    pub fn triangles(&self) -> &[[usize; 3]] {
        &self.triangles
    }

    /// The unit normal of triangle `t` (air side).
    pub fn face_normal(&self, t: usize) -> Vector3<f64> {
        self.face_normals[t]
    }

    /// The corners of triangle `t`.
    pub fn corners(&self, t: usize) -> [Point3<f64>; 3] {
        self.triangles[t].map(|i| self.vertices[i])
    }

    /// The axis-aligned bounding box `(min, max)`.
    pub fn bounds(&self) -> (Point3<f64>, Point3<f64>) {
        bounds(&self.vertices)
    }

    /// The closest point of triangle `t` to `q`, with its signed distance (pseudo-normal sign).
    pub fn closest_on_triangle(&self, t: usize, q: &Point3<f64>) -> Closest {
        let [a, b, c] = self.corners(t);
        let (point, feature) = closest_point_triangle(q, &a, &b, &c);
        let n = match feature {
            Feature::Face => self.face_normals[t],
            Feature::Edge(k) => self.edge_normals[t][k],
            Feature::Vertex(k) => self.vertex_normals[self.triangles[t][k]],
        };
        let d = q - point;
        let dist = d.norm();
        let signed_distance = if d.dot(&n) < 0.0 { -dist } else { dist };
        Closest {
            point,
            triangle: t,
            feature,
            signed_distance,
        }
    }

    /// The closest point of the mesh to `q` (exact; a scan of every triangle, `O(triangles)`,
    /// bounded by [`MAX_TRIANGLES`]).
    pub fn closest(&self, q: &Point3<f64>) -> Closest {
        let mut best = self.closest_on_triangle(0, q);
        for t in 1..self.triangles.len() {
            let c = self.closest_on_triangle(t, q);
            if c.signed_distance.abs() < best.signed_distance.abs() {
                best = c;
            }
        }
        best
    }

    /// The exact signed distance from `q` to the mesh (positive on the air side), `O(triangles)`.
    pub fn signed_distance(&self, q: &Point3<f64>) -> f64 {
        self.closest(q).signed_distance
    }
}

impl crate::surface::SignedDistance for TriMesh {
    /// Exact, `O(triangles)`.
    fn signed_distance(&self, q: &Point3<f64>) -> Option<f64> {
        Some(TriMesh::signed_distance(self, q))
    }
    /// The unit vector from the closest point to `q`, signed; the feature's pseudo-normal on the
    /// surface.
    fn distance_gradient(&self, q: &Point3<f64>) -> Option<Vector3<f64>> {
        let c = self.closest(q);
        let v = q - c.point;
        let n = v.norm();
        Some(if n > 0.0 {
            v * (c.signed_distance.signum() / n)
        } else {
            self.face_normal(c.triangle)
        })
    }
    /// The exact vertical ray against every triangle ([`vertical_hit`]), `O(triangles)`.
    fn ground_below(
        &self,
        q: &Point3<f64>,
        _tolerance: f64,
    ) -> Result<Point3<f64>, crate::surface::DropError> {
        let down = TriMesh::signed_distance(self, q) >= 0.0;
        vertical_hit(q, down, 0..self.triangles.len(), |t| self.corners(t))
            .map(|z| Point3::new(q.x, q.y, z))
            .ok_or(crate::surface::DropError::Missed(*q))
    }
    /// The exact segment-triangle test against every triangle ([`segment_hit`]), `O(triangles)`:
    /// forward from `q` in the air (or on the ground), backward from `q` below it.
    fn ground_along(
        &self,
        q: &Point3<f64>,
        dir: &nalgebra::Unit<Vector3<f64>>,
        reach: f64,
        _tolerance: f64,
    ) -> Result<Option<f64>, crate::surface::DropError> {
        let d = TriMesh::signed_distance(self, q);
        Ok(cast_along(q, dir, reach, d, 0..self.triangles.len(), |t| {
            self.corners(t)
        }))
    }
}

/// [`crate::surface::SignedDistance::ground_along`] on triangles `candidates` (corners from
/// `corners`) for a start `q` of signed distance `d`: the segment from `q` to `q + reach dir`
/// when `d > 0`, to `q - reach dir` when `d < 0` (the signed parameter of the first hit by
/// [`segment_hit`]); `0` on the ground. Shared by [`TriMesh`] and the BVH adapter, so the two
/// answer bit for bit alike when the candidates hold every triangle the segment meets.
pub fn cast_along(
    q: &Point3<f64>,
    dir: &nalgebra::Unit<Vector3<f64>>,
    reach: f64,
    d: f64,
    candidates: impl IntoIterator<Item = usize>,
    corners: impl Fn(usize) -> [Point3<f64>; 3],
) -> Option<f64> {
    if d == 0.0 {
        return Some(0.0);
    }
    if !(reach >= 0.0 && reach.is_finite() && d.is_finite()) {
        return None;
    }
    let sign = if d > 0.0 { 1.0 } else { -1.0 };
    let end = q + dir.as_ref() * (sign * reach);
    segment_hit(q, &end, candidates, corners).map(|s| sign * s * reach)
}

/// The first point of the segment `p0 p1` on a triangle among `candidates` (corners from
/// `corners`), as its fraction `s` in `[0, 1]` of the way from `p0` to `p1`; `None` when the
/// segment meets none. The decisions are exact (Shewchuk's adaptive `orient3d`): the segment
/// meets triangle `abc` when `p0` and `p1` are not strictly on one side of its plane and the
/// line `p0 p1` passes through the closed triangle (the three orientations of `p0 p1` with its
/// edges agree in sign or vanish), so a segment through a shared edge or vertex always meets
/// the triangles around it. A segment lying in a triangle's plane is not counted for it (it
/// meets that plane's neighbours, if any, on their shared edges). The fraction is
/// `V0 / (V0 - V1)` from the two plane orientations (its rounding only). The smallest over the
/// candidates whatever their order, so any candidate superset of the triangles the segment
/// meets (a BVH's) gives the brute force's answer bit for bit.
pub fn segment_hit(
    p0: &Point3<f64>,
    p1: &Point3<f64>,
    candidates: impl IntoIterator<Item = usize>,
    corners: impl Fn(usize) -> [Point3<f64>; 3],
) -> Option<f64> {
    let c = |p: &Point3<f64>| robust::Coord3D {
        x: p.x,
        y: p.y,
        z: p.z,
    };
    let (q0, q1) = (c(p0), c(p1));
    let mut best: Option<f64> = None;
    for t in candidates {
        let [a, b, cc] = corners(t).map(|p| c(&p));
        let v0 = robust::orient3d(a, b, cc, q0);
        let v1 = robust::orient3d(a, b, cc, q1);
        if (v0 > 0.0 && v1 > 0.0) || (v0 < 0.0 && v1 < 0.0) || (v0 == 0.0 && v1 == 0.0) {
            continue;
        }
        let e = [
            robust::orient3d(q0, q1, a, b),
            robust::orient3d(q0, q1, b, cc),
            robust::orient3d(q0, q1, cc, a),
        ];
        if e.iter().any(|x| *x > 0.0) && e.iter().any(|x| *x < 0.0) {
            continue;
        }
        let s = (v0 / (v0 - v1)).clamp(0.0, 1.0);
        if best.is_none_or(|b| s < b) {
            best = Some(s);
        }
    }
    best
}

/// The height of the first mesh point on the vertical through `q` among triangles `candidates`
/// (corners from `corners`): the highest at or below `q` when `down`, else the lowest at or
/// above it. A triangle holds the vertical when its plan projection contains `(q.x, q.y)`,
/// edges and corners included, decided by exact orientation tests (`orient2d`), so a vertical
/// through a shared edge or vertex always meets the triangles around it; vertical triangles
/// (zero plan area) are skipped (the vertical meets them only on edges they share with
/// non-vertical triangles, or runs inside their plane). The height is the plane's, by the plan
/// barycentric weights.
pub fn vertical_hit(
    q: &Point3<f64>,
    down: bool,
    candidates: impl IntoIterator<Item = usize>,
    corners: impl Fn(usize) -> [Point3<f64>; 3],
) -> Option<f64> {
    use rappel_geometry::predicates::orient2d;
    let p = nalgebra::Point2::new(q.x, q.y);
    let mut best: Option<f64> = None;
    for t in candidates {
        let [a, b, c] = corners(t);
        let (a2, b2, c2) = (a.xy(), b.xy(), c.xy());
        let area = orient2d(&a2, &b2, &c2);
        if area == 0.0 {
            continue;
        }
        // Sub-areas opposite a, b and c: all of the area's sign (or zero) inside.
        let w = [
            orient2d(&b2, &c2, &p),
            orient2d(&c2, &a2, &p),
            orient2d(&a2, &b2, &p),
        ];
        if w.iter().any(|x| *x != 0.0 && x.signum() != area.signum()) {
            continue;
        }
        let z = (w[0] * a.z + w[1] * b.z + w[2] * c.z) / (w[0] + w[1] + w[2]);
        let beyond = if down { z <= q.z } else { z >= q.z };
        if beyond && best.is_none_or(|bz| if down { z > bz } else { z < bz }) {
            best = Some(z);
        }
    }
    best
}

fn bounds(vertices: &[Point3<f64>]) -> (Point3<f64>, Point3<f64>) {
    let mut lo = Point3::new(f64::INFINITY, f64::INFINITY, f64::INFINITY);
    let mut hi = Point3::new(f64::NEG_INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY);
    for v in vertices {
        lo = lo.inf(v);
        hi = hi.sup(v);
    }
    (lo, hi)
}

/// The closest point of triangle `abc` to `p` and the feature holding it (Ericson, Real-Time
/// Collision Detection §5.1.5, Voronoi regions of the triangle).
pub fn closest_point_triangle(
    p: &Point3<f64>,
    a: &Point3<f64>,
    b: &Point3<f64>,
    c: &Point3<f64>,
) -> (Point3<f64>, Feature) {
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let d1 = ab.dot(&ap);
    let d2 = ac.dot(&ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return (*a, Feature::Vertex(0));
    }
    let bp = p - b;
    let d3 = ab.dot(&bp);
    let d4 = ac.dot(&bp);
    if d3 >= 0.0 && d4 <= d3 {
        return (*b, Feature::Vertex(1));
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return (a + ab * v, Feature::Edge(0));
    }
    let cp = p - c;
    let d5 = ab.dot(&cp);
    let d6 = ac.dot(&cp);
    if d6 >= 0.0 && d5 <= d6 {
        return (*c, Feature::Vertex(2));
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return (a + ac * w, Feature::Edge(2));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (b + (c - b) * w, Feature::Edge(1));
    }
    let denom = 1.0 / (va + vb + vc);
    let v = vb * denom;
    let w = vc * denom;
    (a + ab * v + ac * w, Feature::Face)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::GridGeometry;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn tri() -> TriMesh {
        TriMesh::new(
            vec![
                Point3::new(0.0, 0.0, 0.0),
                Point3::new(1.0, 0.0, 0.0),
                Point3::new(0.0, 1.0, 0.0),
            ],
            vec![[0, 1, 2]],
        )
        .unwrap()
    }

    #[test]
    fn closest_point_matches_dense_sampling() {
        // Independent oracle: the minimum over a dense barycentric sample of the triangle.
        let m = tri();
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let [a, b, c] = m.corners(0);
        for _ in 0..50 {
            let q = Point3::new(
                rng.random_range(-1.0..2.0),
                rng.random_range(-1.0..2.0),
                rng.random_range(-1.0..1.0),
            );
            let exact = m.closest(&q).signed_distance.abs();
            let n = 200;
            let mut best = f64::INFINITY;
            for i in 0..=n {
                for j in 0..=(n - i) {
                    let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
                    let s = a + (b - a) * u + (c - a) * v;
                    best = best.min((q - s).norm());
                }
            }
            assert!(exact <= best + 1e-12, "{exact} > {best}");
            assert!(best - exact < 1.0 / n as f64, "{exact} vs {best}");
        }
    }

    #[test]
    fn sign_is_air_side_of_height_field() {
        let g = GridGeometry::new(6, 6, 1.0, 1.0, 0.0, 6.0).unwrap();
        let dem = HeightGrid::from_fn(g, |_, _, p| Some(0.3 * p.x + 0.1 * p.y)).unwrap();
        let m = TriMesh::from_height_grid(&dem).unwrap();
        let n = Vector3::new(-0.3, -0.1, 1.0).normalize();
        for (x, y, dz) in [(2.0, 3.0, 0.5), (3.3, 2.7, -0.4), (1.1, 4.2, 0.05)] {
            let z = 0.3 * x + 0.1 * y;
            let d = m.signed_distance(&Point3::new(x, y, z + dz));
            // Plane distance of a vertical offset dz: dz * n.z.
            assert!((d - dz * n.z).abs() < 1e-9, "{d} vs {}", dz * n.z);
        }
    }

    #[test]
    fn bad_meshes_are_positioned_errors() {
        let v = || {
            vec![
                Point3::new(0.0, 0.0, 0.0),
                Point3::new(1.0, 0.0, 0.0),
                Point3::new(0.0, 1.0, 0.0),
                Point3::new(0.0, 0.0, 1.0),
                Point3::new(1.0, 1.0, 1.0),
            ]
        };
        assert!(matches!(
            TriMesh::new(vec![], vec![[0, 1, 2]]),
            Err(MeshError::Empty { .. })
        ));
        let mut huge = v();
        huge[2].z = 1e300;
        let e = TriMesh::new(huge, vec![[0, 1, 2]]).unwrap_err();
        assert!(matches!(
            e,
            MeshError::VertexOutOfDomain {
                vertex: 2,
                axis: 'z',
                ..
            }
        ));
        assert!(
            e.to_string()
                .starts_with("vertex 2: coordinate z = 1e300: coordinates must be")
        );
        let mut nan = v();
        nan[3].y = f64::NAN;
        assert!(matches!(
            TriMesh::new(nan, vec![[0, 1, 3]]),
            Err(MeshError::NonFiniteVertex {
                vertex: 3,
                axis: 'y',
                ..
            })
        ));
        assert!(matches!(
            TriMesh::new(v(), vec![[0, 1, 2], [0, 1, 9]]),
            Err(MeshError::IndexOutOfRange {
                triangle: 1,
                corner: 2,
                index: 9,
                ..
            })
        ));
        assert!(matches!(
            TriMesh::new(v(), vec![[0, 1, 1]]),
            Err(MeshError::DegenerateTriangle { triangle: 0, .. })
        ));
        let mut collinear = v();
        collinear[2] = Point3::new(2.0, 0.0, 0.0);
        assert!(matches!(
            TriMesh::new(collinear, vec![[0, 1, 2]]),
            Err(MeshError::DegenerateTriangle { triangle: 0, .. })
        ));
        // Edge (0, 1) on three triangles.
        assert!(matches!(
            TriMesh::new(v(), vec![[0, 1, 2], [1, 0, 3], [1, 0, 4]]),
            Err(MeshError::NonManifoldEdge {
                a: 0,
                b: 1,
                third: 2,
                ..
            })
        ));
        assert!(matches!(
            TriMesh::new(v(), vec![[0, 1, 2], [0, 1, 3]]),
            Err(MeshError::InconsistentOrientation { .. })
        ));
    }

    #[test]
    fn random_garbage_never_panics() {
        // Fuzz-style: random vertex arrays (with NaN and huge values) and random indices.
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        for _ in 0..2000 {
            let nv = rng.random_range(0..6);
            let nt = rng.random_range(0..6);
            let vertices = (0..nv)
                .map(|_| {
                    let mut c = [0.0; 3];
                    for x in &mut c {
                        *x = match rng.random_range(0..10) {
                            0 => f64::NAN,
                            1 => f64::INFINITY,
                            2 => 1e300,
                            _ => rng.random_range(-1.0..1.0),
                        };
                    }
                    Point3::new(c[0], c[1], c[2])
                })
                .collect();
            let triangles = (0..nt)
                .map(|_| [0; 3].map(|_: usize| rng.random_range(0..7)))
                .collect();
            if let Ok(m) = TriMesh::new(vertices, triangles) {
                assert!(m.signed_distance(&Point3::origin()).is_finite());
            }
        }
    }
}
