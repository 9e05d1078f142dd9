//! Axel's boom in contact with real ground (Paton §IV-A, the *in-contact* configuration): the
//! boom, a segment of length `L_c` pivoting about the axle, is swept down from straight up in
//! the vertical plane of the robot frame toward the anchor until it first touches the ground
//! mesh; that first contact (on the boom's tip or on its shaft, e.g. resting on a ledge's lip)
//! is the boom's ground contact for the stability QP, and the boom's elevation sets its mass and
//! the tether exit at its tip.
//!
//! # Method (exact, no sampling)
//! The boom sweeps a half disc of radius `L_c` about the pivot in the sweep plane (spanned by the
//! horizontal direction toward the anchor, `azimuth`, and the robot's `up`). The ground it can
//! touch is the mesh's section by that plane: per triangle a point, a segment or (a triangle in
//! the plane) three segments. Each section segment is clipped to the half disc (convex, so the
//! clipped part is one segment or empty). The boom at elevation `e` touches a section point of
//! polar angle `e` about the pivot, so the first contact while sweeping down is the section
//! point of **largest** polar angle. Along a segment not through the pivot the polar angle is
//! monotone, so the largest angle is at a clipped segment's end: a triangle edge crossing the
//! plane, a vertex in it, or where the segment leaves the disc (the boom's tip). The answer is a
//! continuous function of the mesh (no topological decision is taken on it); the section points
//! are computed in floating point.
//!
//! # Contact normal
//! * tip on a triangle's interior: the triangle's normal;
//! * on a triangle edge (the boom's shaft on a lip, or the tip on an edge): the edge-on-line
//!   contact normal `edge x boom`, oriented to the air side of the boom (the side it was swept
//!   from);
//! * on a vertex, or an edge along the boom: the boom's perpendicular in the sweep plane on the
//!   air side.
//!
//! Cost: with an [`IndexedGround`] the triangles whose bounding boxes meet the swept disc's box
//! (parry's BVH), `O(log triangles + nearby)`; with a bare [`TriMesh`] every triangle (a box test
//! rejects those beyond the boom's reach), the brute force the tests compare against.

use nalgebra::{Point3, Rotation3, Unit, Vector3};
use rappel_terrain::mesh::TriMesh;
use rappel_terrain::parry_mesh::ParryMesh;
use rappel_terrain::surface::SignedDistance;

use crate::axel::{Axel, AxelParams, BoomMode};
use crate::robot::{ContactFrame, MIN_TETHER_LENGTH, PlacedRobot, RobotError};
use crate::settle::{GroundContacts, SettledPose, place_on_ground};

/// A contact counts as at the boom's tip when it is this fraction of the boom's length or less
/// from it (relative: rounding of the disc clipping).
pub const TIP_TOLERANCE_REL: f64 = 1e-9;

/// A section point closer to the pivot than this fraction of the boom's length makes the sweep
/// undefined (the ground through the axle).
pub const PIVOT_CLEARANCE_REL: f64 = 1e-9;

/// Where the swept boom first touches the ground.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoomContact {
    /// The boom's elevation at contact: radians above the plane through the pivot normal to
    /// `up`, toward `azimuth` (negative below it).
    pub elevation: f64,
    /// The contact point on the ground, world.
    pub point: Point3<f64>,
    /// Its distance from the pivot along the boom, metres (`L_c` at the tip).
    pub along: f64,
    /// The boom's tip at contact, world.
    pub tip: Point3<f64>,
    /// The contact normal (from the ground toward the boom), world.
    pub normal: Unit<Vector3<f64>>,
    /// The contact is at the boom's tip (else on its shaft).
    pub at_tip: bool,
}

/// Why the boom has no ground contact.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BoomContactError {
    /// No ground within the boom's reach in its sweep plane (a boom over a drop).
    #[error("the boom touches no ground within its reach of {0} m")]
    NoGround(f64),
    /// The ground passes through the pivot.
    #[error("the ground passes through the boom's pivot")]
    GroundAtPivot,
    /// Bad input: non-finite points, a non-positive length, or directions that are not
    /// orthonormal.
    #[error("invalid boom sweep: {0}")]
    Parameter(&'static str),
    /// The inline boom would pass through the ground (where the swept boom first touches it).
    #[error("the inline boom would pass through the ground at ({x:.3}, {y:.3}, {z:.3})")]
    InlineThroughGround {
        /// World x of the swept boom's first contact.
        x: f64,
        /// y.
        y: f64,
        /// z.
        z: f64,
    },
    /// The robot model or the tether refused the placement.
    #[error(transparent)]
    Robot(#[from] RobotError),
}

/// Ground a boom can be swept against: a triangle mesh, its distances (for the wheels' contact
/// frames) and the triangles that may meet a box. [`TriMesh`] lists every triangle (the
/// brute-force sweep, kept as the test oracle); [`IndexedGround`] asks parry's BVH.
pub trait BoomGround: SignedDistance {
    /// The mesh.
    fn mesh(&self) -> &TriMesh;
    /// Appends to `out`, in ascending order, a superset of the triangles meeting `[lo, hi]`.
    fn candidates(&self, lo: &Point3<f64>, hi: &Point3<f64>, out: &mut Vec<usize>);
}

impl BoomGround for TriMesh {
    fn mesh(&self) -> &TriMesh {
        self
    }
    fn candidates(&self, _lo: &Point3<f64>, _hi: &Point3<f64>, out: &mut Vec<usize>) {
        out.extend(0..self.triangles().len());
    }
}

/// A mesh with parry's BVH over it ([`ParryMesh`] built from the same mesh): the sweep tests
/// only the triangles whose bounding boxes meet the swept half disc's box, and the wheels'
/// contact frames take their distances from the BVH (equal to the exact mesh's to 1e-9,
/// `terrain::parry_mesh`).
#[derive(Debug, Clone, Copy)]
pub struct IndexedGround<'a> {
    /// The mesh.
    pub mesh: &'a TriMesh,
    /// Its BVH (built from `mesh`: the indices must match).
    pub bvh: &'a ParryMesh,
}

impl SignedDistance for IndexedGround<'_> {
    fn signed_distance(&self, q: &Point3<f64>) -> Option<f64> {
        self.bvh.signed_distance(q)
    }
    fn distance_gradient(&self, q: &Point3<f64>) -> Option<Vector3<f64>> {
        self.bvh.distance_gradient(q)
    }
}

impl BoomGround for IndexedGround<'_> {
    fn mesh(&self) -> &TriMesh {
        self.mesh
    }
    fn candidates(&self, lo: &Point3<f64>, hi: &Point3<f64>, out: &mut Vec<usize>) {
        self.bvh.triangles_in_box(lo, hi, out);
    }
}

/// Which ground feature a candidate contact lies on.
#[derive(Debug, Clone, Copy)]
enum Feature {
    /// Inside triangle `t` (the disc's rim cut the section inside it).
    Face(usize),
    /// On the edge of direction `d` (unnormalised).
    Edge(Vector3<f64>),
    /// On a vertex in the plane.
    Vertex,
}

/// Sweeps a boom of length `length` about `pivot` down from straight `up` toward `azimuth`
/// (orthonormal world directions) until it first touches `ground` (module doc). Only the
/// triangles `ground` lists for the swept disc's bounding box are tested, in ascending index
/// order, so an [`IndexedGround`] finds the same contact as the brute-force [`TriMesh`].
pub fn sweep_boom<G: BoomGround + ?Sized>(
    ground: &G,
    pivot: &Point3<f64>,
    azimuth: &Unit<Vector3<f64>>,
    up: &Unit<Vector3<f64>>,
    length: f64,
) -> Result<BoomContact, BoomContactError> {
    if !(pivot.iter().all(|c| c.is_finite()) && length.is_finite() && length > 0.0) {
        return Err(BoomContactError::Parameter(
            "pivot must be finite and the length finite and > 0",
        ));
    }
    if azimuth.dot(up).abs() > 1e-9 || !azimuth.iter().chain(up.iter()).all(|c| c.is_finite()) {
        return Err(BoomContactError::Parameter(
            "azimuth and up must be finite and orthogonal",
        ));
    }
    let (az, upv) = (azimuth.into_inner(), up.into_inner());
    let side = az.cross(&upv);
    // Plane coordinates of a point: (along azimuth, along up); its offset from the plane.
    let coords = |q: &Point3<f64>| {
        let r = q - pivot;
        (r.dot(&az), r.dot(&upv), r.dot(&side))
    };
    let reach2 = length * length;
    let min_r = PIVOT_CLEARANCE_REL * length;
    // Best candidate: (elevation, point (a, b), feature).
    let mut best: Option<(f64, [f64; 2], Feature)> = None;
    let mut consider = |a: f64, b: f64, feature: Feature| -> Result<(), BoomContactError> {
        if a.hypot(b) < min_r {
            return Err(BoomContactError::GroundAtPivot);
        }
        let e = b.atan2(a);
        if best.is_none_or(|(be, _, _)| e > be) {
            best = Some((e, [a, b], feature));
        }
        Ok(())
    };
    let mesh = ground.mesh();
    // The bounding box of the disc of radius `length` about the pivot in the sweep plane: along
    // world axis k it reaches `length * hypot(az_k, up_k)`.
    let reach = Vector3::from_fn(|k, _| length * az[k].hypot(upv[k]));
    let mut candidates = Vec::new();
    ground.candidates(&(pivot - reach), &(pivot + reach), &mut candidates);
    for t in candidates {
        let c = mesh.triangles()[t].map(|i| mesh.vertices()[i]);
        // Box test: the triangle's box beyond the reach of the pivot cannot be touched.
        let lo = c[0].inf(&c[1]).inf(&c[2]);
        let hi = c[0].sup(&c[1]).sup(&c[2]);
        let gap = (lo - pivot).sup(&(pivot - hi)).sup(&Vector3::zeros());
        if gap.norm_squared() > reach2 {
            continue;
        }
        let p = c.map(|v| coords(&v));
        let s = [p[0].2, p[1].2, p[2].2];
        if s.iter().all(|v| *v > 0.0) || s.iter().all(|v| *v < 0.0) {
            continue;
        }
        // Section points: vertices in the plane, edges crossing it.
        let mut pts: Vec<([f64; 2], Feature)> = Vec::with_capacity(3);
        for k in 0..3 {
            if s[k] == 0.0 {
                pts.push(([p[k].0, p[k].1], Feature::Vertex));
            }
        }
        for k in 0..3 {
            let l = (k + 1) % 3;
            if (s[k] < 0.0 && s[l] > 0.0) || (s[k] > 0.0 && s[l] < 0.0) {
                let w = s[k] / (s[k] - s[l]);
                pts.push((
                    [
                        p[k].0 + w * (p[l].0 - p[k].0),
                        p[k].1 + w * (p[l].1 - p[k].1),
                    ],
                    Feature::Edge(c[l] - c[k]),
                ));
            }
        }
        // Segments of the section: one point, one segment, or the triangle in the plane
        // (three vertices: its three edges).
        let segments: Vec<(usize, usize)> = match pts.len() {
            1 => vec![(0, 0)],
            2 => vec![(0, 1)],
            3 => vec![(0, 1), (1, 2), (2, 0)],
            _ => Vec::new(),
        };
        for (i, j) in segments {
            let (p0, f0) = pts[i];
            let (p1, f1) = pts[j];
            let Some((t0, t1)) = clip_to_half_disc(p0, p1, length) else {
                continue;
            };
            let at = |u: f64| [p0[0] + u * (p1[0] - p0[0]), p0[1] + u * (p1[1] - p0[1])];
            // An end cut by the clipping lies inside the triangle; for a triangle in the
            // sweep plane its normal is across the boom, so the boom's perpendicular is used.
            let interior = |f: Feature| match (pts.len(), f) {
                (3, _) => Feature::Vertex,
                _ => Feature::Face(t),
            };
            let q0 = at(t0);
            consider(q0[0], q0[1], if t0 == 0.0 { f0 } else { interior(f0) })?;
            let q1 = at(t1);
            consider(q1[0], q1[1], if t1 == 1.0 { f1 } else { interior(f1) })?;
        }
    }
    let (elevation, [a, b], feature) = best.ok_or(BoomContactError::NoGround(length))?;
    let point = pivot + az * a + upv * b;
    let along = a.hypot(b);
    let dir = az * elevation.cos() + upv * elevation.sin();
    // The air side of the boom: the direction of increasing elevation.
    let perp = -az * elevation.sin() + upv * elevation.cos();
    let at_tip = along >= length * (1.0 - TIP_TOLERANCE_REL);
    let normal = match feature {
        Feature::Face(t) => {
            let n = mesh.face_normal(t);
            if n.dot(&perp) >= 0.0 { n } else { -n }
        }
        Feature::Edge(e) => match e.cross(&dir).try_normalize(1e-12) {
            Some(n) if n.dot(&perp) >= 0.0 => n,
            Some(n) => -n,
            None => perp,
        },
        Feature::Vertex => perp,
    };
    Ok(BoomContact {
        elevation,
        point,
        along,
        tip: pivot + dir * length,
        normal: Unit::new_normalize(normal),
        at_tip,
    })
}

/// A settled Axel pose as the stability QP sees it with the boom **in contact with the mesh**
/// (Paton §IV-A): the boom swept toward the last anchor `anchor` (world, with its optional
/// tension limit) until it touches `mesh` ([`sweep_boom`]), the wheels' settled contacts as in
/// [`SettledPose::place`], the boom's contact as a third contact with its frame's `z` along the
/// contact normal and `x` along the boom, the boom's mass at its midpoint and the tether from its
/// tip toward the anchor. Replaces the planar in-contact approximation
/// ([`BoomMode::InContact`], the tip on the pose's plane) where the ground is a mesh.
pub fn place_boom_in_contact<G: BoomGround + ?Sized>(
    pose: &SettledPose,
    params: &AxelParams,
    mesh: &G,
    friction: f64,
    anchor: (&Point3<f64>, Option<f64>),
) -> Result<(PlacedRobot, BoomContact), BoomContactError> {
    let (pivot, azimuth, up) = boom_frame(pose, params, anchor.0)?;
    let contact = sweep_boom(mesh, &pivot, &azimuth, &up, params.boom_length)?;
    let mut placed = place_resting(pose, params, contact.elevation, mesh, friction, anchor)?;
    let z = contact.normal.into_inner();
    let boom = contact.tip - pivot;
    let x = (boom - z * boom.dot(&z))
        .try_normalize(1e-9)
        .ok_or(RobotError::Parameter("boom along its contact normal"))?;
    placed.contacts.push(ContactFrame {
        position: contact.point,
        rotation: Rotation3::from_basis_unchecked(&[x, z.cross(&x), z]),
        friction: Some(params.boom_friction),
        point: true,
    });
    Ok((placed, contact))
}

/// A unit world direction.
type UnitVector = Unit<Vector3<f64>>;

/// The boom's pivot (the axle centre) of a settled pose and its sweep directions toward
/// `anchor`: the horizontal (robot frame) direction toward it and the robot's up, world.
fn boom_frame(
    pose: &SettledPose,
    params: &AxelParams,
    anchor: &Point3<f64>,
) -> Result<(Point3<f64>, UnitVector, UnitVector), BoomContactError> {
    if !anchor.iter().all(|c| c.is_finite()) {
        return Err(RobotError::Parameter("anchor must be finite").into());
    }
    let r = pose.rotation;
    let local = r.inverse() * (anchor - pose.origin);
    let horizontal = Vector3::new(local.x, local.y, 0.0);
    if horizontal.norm() < MIN_TETHER_LENGTH {
        return Err(RobotError::Anchor("anchor straight above the axle").into());
    }
    let azimuth = Unit::new_normalize(r * horizontal);
    let up = Unit::new_normalize(r * Vector3::z());
    Ok((
        pose.origin + up.into_inner() * params.wheel_radius,
        azimuth,
        up,
    ))
}

/// The inline boom may sit this far (radians) below the swept boom's first contact (rounding).
pub const INLINE_CLEARANCE: f64 = 1e-9;

/// A settled Axel pose as the stability QP sees it with the boom **inline** with the tether
/// (Paton §IV-A) on a mesh: the boom along the line from the pivot to `anchor`, refused when the
/// anchor lies within the boom's reach or when the boom would pass through the mesh (the swept
/// boom's first contact, [`sweep_boom`], lies above the inline elevation; the planar model's
/// test against the pose's plane refuses booms that clear the real ground where it falls away
/// behind a lip). The wheels' contacts as in [`SettledPose::place`]; the tether from the tip.
pub fn place_boom_inline<G: BoomGround + ?Sized>(
    pose: &SettledPose,
    params: &AxelParams,
    mesh: &G,
    friction: f64,
    anchor: (&Point3<f64>, Option<f64>),
) -> Result<PlacedRobot, BoomContactError> {
    let (pivot, azimuth, up) = boom_frame(pose, params, anchor.0)?;
    let d = anchor.0 - pivot;
    if d.norm() <= params.boom_length {
        return Err(RobotError::Anchor("anchor within the boom's reach").into());
    }
    let inline = d.dot(&up).atan2(d.dot(&azimuth));
    match sweep_boom(mesh, &pivot, &azimuth, &up, params.boom_length) {
        Ok(c) if c.elevation > inline + INLINE_CLEARANCE => {
            return Err(BoomContactError::InlineThroughGround {
                x: c.point.x,
                y: c.point.y,
                z: c.point.z,
            });
        }
        Ok(_) | Err(BoomContactError::NoGround(_)) => {}
        Err(e) => return Err(e),
    }
    place_resting(pose, params, inline, mesh, friction, anchor)
}

/// The settled pose's wheel contacts with the boom resting at `elevation` (radians above the
/// ground plane, toward the anchor: [`BoomMode::Resting`]) and the tether toward `anchor`: the
/// placement both boom configurations share, before the in-contact one adds its boom contact.
fn place_resting<G: BoomGround + ?Sized>(
    pose: &SettledPose,
    params: &AxelParams,
    elevation: f64,
    mesh: &G,
    friction: f64,
    anchor: (&Point3<f64>, Option<f64>),
) -> Result<PlacedRobot, BoomContactError> {
    let axel = Axel::new(AxelParams {
        boom: BoomMode::Resting(elevation),
        ..*params
    })?;
    Ok(place_on_ground(
        GroundContacts {
            origin: pose.origin,
            rotation: pose.rotation,
            contacts: &pose.contacts,
            replaces: 2,
        },
        &axel,
        mesh,
        friction,
        Some(anchor),
    )?)
}

/// The parameter interval `[t0, t1]` of the segment `p0 + t (p1 - p0)`, `t` in `[0, 1]`, inside
/// the half disc `|p| <= r`, `p.x >= 0`; `None` when empty.
fn clip_to_half_disc(p0: [f64; 2], p1: [f64; 2], r: f64) -> Option<(f64, f64)> {
    let d = [p1[0] - p0[0], p1[1] - p0[1]];
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    // Disc: |p0 + t d|^2 <= r^2.
    let qa = d[0] * d[0] + d[1] * d[1];
    let qb = 2.0 * (p0[0] * d[0] + p0[1] * d[1]);
    let qc = p0[0] * p0[0] + p0[1] * p0[1] - r * r;
    if qa == 0.0 {
        if qc > 0.0 {
            return None;
        }
    } else {
        let disc = qb * qb - 4.0 * qa * qc;
        if disc < 0.0 {
            return None;
        }
        let sq = disc.sqrt();
        // Stable roots.
        let sign = if qb >= 0.0 { 1.0 } else { -1.0 };
        let q = -0.5 * (qb + sign * sq);
        let (r1, r2) = if q == 0.0 {
            (0.0, 0.0)
        } else {
            let a = q / qa;
            let b = qc / q;
            (a.min(b), a.max(b))
        };
        lo = lo.max(r1);
        hi = hi.min(r2);
    }
    // Half plane x >= 0: p0.x + t d.x >= 0.
    if d[0] == 0.0 {
        if p0[0] < 0.0 {
            return None;
        }
    } else {
        let t = -p0[0] / d[0];
        if d[0] > 0.0 {
            lo = lo.max(t);
        } else {
            hi = hi.min(t);
        }
    }
    (lo <= hi).then_some((lo, hi))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clipping_matches_the_circle() {
        // A horizontal segment at height -0.5 across the unit disc: x from 0 to sqrt(0.75).
        let (t0, t1) = clip_to_half_disc([-2.0, -0.5], [2.0, -0.5], 1.0).unwrap();
        let x = |t: f64| -2.0 + 4.0 * t;
        assert!(x(t0).abs() < 1e-12 && (x(t1) - 0.75f64.sqrt()).abs() < 1e-12);
        assert!(clip_to_half_disc([-2.0, 1.5], [2.0, 1.5], 1.0).is_none());
        assert!(clip_to_half_disc([-0.5, 0.0], [-0.2, 0.1], 1.0).is_none());
        // Reversed direction, same set.
        let (u0, u1) = clip_to_half_disc([2.0, -0.5], [-2.0, -0.5], 1.0).unwrap();
        let y = |t: f64| 2.0 - 4.0 * t;
        assert!((y(u0) - 0.75f64.sqrt()).abs() < 1e-12 && y(u1).abs() < 1e-12);
    }
}
