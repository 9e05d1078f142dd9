//! The one adapter to `parry3d-f64` (pinned with `=` in the workspace): a [`TriMesh`] behind
//! parry's BVH for point projection and ray casts. Answers the same questions as
//! [`TriMesh::signed_distance`] and [`TriMesh::closest`] (which scan every triangle) in roughly
//! logarithmic time. Parry's types (glam vectors) stay inside this module.
//!
//! The sign comes from parry's `ORIENTED` flag (angle-weighted pseudo-normals, the same
//! Bærentzen-Aanæs construction as [`TriMesh`]), so on the air side and inside a closed mesh
//! the two agree (tested on Paton's scene); beyond an open mesh's boundary the sign is a
//! convention in both, see `docs/mesh.md`.

use nalgebra::{Point3, Vector3};
use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::math::Vector;
use parry3d_f64::query::{PointQuery, Ray, RayCast};
use parry3d_f64::shape::{TriMesh as ParryTriMesh, TriMeshFlags};

use crate::mesh::TriMesh;
use crate::surface::SignedDistance;

/// Why parry refused a mesh (cannot happen for a validated [`TriMesh`] under `u32::MAX`
/// vertices, kept typed all the same).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ParryMeshError {
    /// More vertices than parry's `u32` indices address.
    #[error("{0} vertices exceed parry's u32 indices")]
    TooManyVertices(usize),
    /// Parry's builder refused the mesh.
    #[error("parry refused the mesh: {0}")]
    Builder(String),
}

/// A validated mesh behind parry's BVH.
#[derive(Clone)]
pub struct ParryMesh {
    mesh: ParryTriMesh,
}

impl std::fmt::Debug for ParryMesh {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ParryMesh")
            .field("triangles", &self.mesh.indices().len())
            .finish()
    }
}

fn to_parry(p: &Point3<f64>) -> Vector {
    Vector::new(p.x, p.y, p.z)
}

fn from_parry(v: Vector) -> Point3<f64> {
    Point3::new(v.x, v.y, v.z)
}

impl ParryMesh {
    /// Builds parry's mesh (and its BVH and pseudo-normals) from a validated mesh.
    pub fn new(mesh: &TriMesh) -> Result<Self, ParryMeshError> {
        let n = mesh.vertices().len();
        if n > u32::MAX as usize {
            return Err(ParryMeshError::TooManyVertices(n));
        }
        let vertices = mesh.vertices().iter().map(to_parry).collect();
        let indices = mesh
            .triangles()
            .iter()
            .map(|t| t.map(|i| i as u32))
            .collect();
        let mesh = ParryTriMesh::with_flags(vertices, indices, TriMeshFlags::ORIENTED)
            .map_err(|e| ParryMeshError::Builder(format!("{e:?}")))?;
        Ok(ParryMesh { mesh })
    }

    /// The closest surface point to `q` and whether `q` is inside (below the ground).
    pub fn project(&self, q: &Point3<f64>) -> (Point3<f64>, bool) {
        let p = self.mesh.project_local_point(to_parry(q), false);
        (from_parry(p.point), p.is_inside)
    }

    /// The first hit of the ray `origin + t dir`, `0 <= t <= max_t`, with the surface: `t`
    /// (in units of `dir`'s length), or `None`.
    pub fn cast_ray(&self, origin: &Point3<f64>, dir: &Vector3<f64>, max_t: f64) -> Option<f64> {
        let ray = Ray::new(to_parry(origin), Vector::new(dir.x, dir.y, dir.z));
        self.mesh.cast_local_ray(&ray, max_t, false)
    }

    /// Appends to `out` the indices (into the [`TriMesh`] this was built from) of the triangles
    /// whose bounding boxes meet the box `[lo, hi]` (closed), in ascending order: the BVH's
    /// candidates for a query confined to that box.
    pub fn triangles_in_box(&self, lo: &Point3<f64>, hi: &Point3<f64>, out: &mut Vec<usize>) {
        let start = out.len();
        let aabb = Aabb::new(to_parry(lo), to_parry(hi));
        out.extend(self.mesh.bvh().intersect_aabb(&aabb).map(|i| i as usize));
        out[start..].sort_unstable();
    }

    fn closest(&self, q: &Point3<f64>) -> Option<(f64, Vector3<f64>)> {
        if !q.iter().all(|c| c.is_finite()) {
            return None;
        }
        let (p, inside) = self.project(q);
        let v = q - p;
        let d = v.norm();
        let sign = if inside { -1.0 } else { 1.0 };
        // At the surface itself the direction is undefined: no gradient there.
        let g = v
            .try_normalize(0.0)
            .map(|u| u * sign)
            .unwrap_or_else(Vector3::zeros);
        Some((sign * d, g))
    }
}

impl SignedDistance for ParryMesh {
    fn signed_distance(&self, q: &Point3<f64>) -> Option<f64> {
        self.closest(q).map(|(d, _)| d)
    }
    fn distance_gradient(&self, q: &Point3<f64>) -> Option<Vector3<f64>> {
        self.closest(q).map(|(_, g)| g)
    }
    /// The exact vertical ray ([`crate::mesh::vertical_hit`], the same test as [`TriMesh`]'s)
    /// against the triangles whose boxes meet the vertical (the BVH's candidates), so the answer
    /// is the brute force's.
    fn ground_below(
        &self,
        q: &Point3<f64>,
        _tolerance: f64,
    ) -> Result<Point3<f64>, crate::surface::DropError> {
        let (d, _) = self
            .closest(q)
            .ok_or(crate::surface::DropError::Undefined(*q))?;
        let aabb = self.mesh.local_aabb();
        let (lo, hi) = (from_parry(aabb.mins), from_parry(aabb.maxs));
        let mut tris = Vec::new();
        self.triangles_in_box(
            &Point3::new(q.x, q.y, lo.z),
            &Point3::new(q.x, q.y, hi.z),
            &mut tris,
        );
        let v = self.mesh.vertices();
        let idx = self.mesh.indices();
        crate::mesh::vertical_hit(q, d >= 0.0, tris, |t| {
            idx[t].map(|i| from_parry(v[i as usize]))
        })
        .map(|z| Point3::new(q.x, q.y, z))
        .ok_or(crate::surface::DropError::Missed(*q))
    }
    /// The exact segment-triangle test ([`crate::mesh::cast_along`], the same as [`TriMesh`]'s)
    /// against the triangles whose boxes meet the segment's box (the BVH's candidates), so the
    /// answer is the brute force's for a start on the same side of the ground.
    fn ground_along(
        &self,
        q: &Point3<f64>,
        dir: &nalgebra::Unit<Vector3<f64>>,
        reach: f64,
        _tolerance: f64,
    ) -> Result<Option<f64>, crate::surface::DropError> {
        let (d, _) = self
            .closest(q)
            .ok_or(crate::surface::DropError::Undefined(*q))?;
        let end = q + dir.as_ref() * (if d < 0.0 { -reach } else { reach });
        let mut tris = Vec::new();
        if end.iter().all(|c| c.is_finite()) {
            self.triangles_in_box(&q.inf(&end), &q.sup(&end), &mut tris);
        }
        let v = self.mesh.vertices();
        let idx = self.mesh.indices();
        Ok(crate::mesh::cast_along(q, dir, reach, d, tris, |t| {
            idx[t].map(|i| from_parry(v[i as usize]))
        }))
    }
}
