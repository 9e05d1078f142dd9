//! Euclidean signed distance field of a [`TriMesh`] on a regular voxel grid (Paton §IV, after
//! Voxblox's ESDF, Oleynikova et al. 2017): exact signed distances at the grid points within a
//! band of the surface, a Dijkstra propagation of closest surface points beyond it, and
//! trilinear distance and gradient queries.
//!
//! # Error bound
//! The signed distance `d` is 1-Lipschitz, so trilinear interpolation of exact corner values
//! errs by at most `sum_i w_i |x - c_i| <= sqrt(sum_i w_i |x - c_i|^2) <= (sqrt 3 / 2) h`
//! ([`INTERPOLATION_BOUND`] times the resolution `h`). Every grid point within `band * h` of the
//! mesh is exact (it lies in the expanded bounding box of its closest triangle), so the bound is
//! proven for every query point whose distance is at most `(band - sqrt 3) h`. Beyond the band a
//! grid point holds the distance to the closest surface point of one of its neighbours (vector
//! propagation); that is an upper bound on the true distance, and its excess is measured in the
//! tests (the bound quoted for it in `docs/mesh.md` is empirical, labelled so).
//!
//! An open mesh (a terrain patch) has a boundary; beyond it the signed distance jumps from `+` to
//! `-` across the half-surface where the boundary faces' pseudo-normals disagree, so neither
//! bound holds within `band * h` of the mesh's open boundary. Crop queries to the interior.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use nalgebra::{Point3, Vector3};

use crate::mesh::TriMesh;
use crate::surface::DropError;

/// `sqrt(3) / 2`: the trilinear interpolation error of a 1-Lipschitz function, in voxels.
pub const INTERPOLATION_BOUND: f64 = 0.866_025_403_784_438_6;

/// The default cap on grid points (8 bytes distance + 24 bytes closest point each: 1.3 GB at
/// the cap). A larger grid is an [`SdfError::TooManyVoxels`].
pub const DEFAULT_MAX_VOXELS: usize = 40_000_000;

/// How to build a field.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SdfParams {
    /// Grid spacing `h`, metres (`> 0`).
    pub resolution: f64,
    /// Width of the exact band, in voxels (`>= 2`: the proven bound needs `band > sqrt 3`).
    pub band: usize,
    /// Margin added around the mesh's bounding box, metres (`>= 0`).
    pub margin: f64,
    /// Cap on grid points.
    pub max_voxels: usize,
}

impl SdfParams {
    /// Resolution `h`, a band of 3 voxels, a margin of `4 h`, the default cap.
    pub fn new(resolution: f64) -> Self {
        SdfParams {
            resolution,
            band: 3,
            margin: 4.0 * resolution,
            max_voxels: DEFAULT_MAX_VOXELS,
        }
    }
}

/// Why a field could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SdfError {
    /// A parameter out of its domain.
    #[error("invalid SDF parameter {name} = {value}: {why}")]
    BadParameter {
        /// The parameter.
        name: &'static str,
        /// Its value.
        value: f64,
        /// The domain.
        why: &'static str,
    },
    /// The grid would exceed the voxel cap.
    #[error(
        "SDF grid of {nx} x {ny} x {nz} points exceeds the cap of {cap} (coarsen the resolution or crop the mesh)"
    )]
    TooManyVoxels {
        /// Points along x.
        nx: usize,
        /// Along y.
        ny: usize,
        /// Along z.
        nz: usize,
        /// The cap.
        cap: usize,
    },
    /// A sparse field's block index over the box would exceed its cap (the counts are the
    /// index's top-level cells, pages of 8³ blocks).
    #[error(
        "SDF block index of {nx} x {ny} x {nz} pages of 8^3 blocks exceeds the cap of {cap} (coarsen the resolution or crop the mesh)"
    )]
    TooManyBlockCells {
        /// Pages along x.
        nx: usize,
        /// Along y.
        ny: usize,
        /// Along z.
        nz: usize,
        /// The cap.
        cap: usize,
    },
    /// A sparse field would allocate more blocks (or candidate pairs) than its cap allows.
    #[error(
        "sparse SDF needs {blocks} blocks near the surface, over the cap of {cap} (coarsen the resolution, lower the truncation or crop the mesh)"
    )]
    TooManyBlocks {
        /// Blocks needed (for too many candidate pairs: the pairs over the per-block allowance).
        blocks: usize,
        /// The cap.
        cap: usize,
    },
    /// The sparse field's wavefront beyond its exact band ran over its relaxation budget
    /// (`sparse_sdf::MAX_RELAXATIONS_PER_POINT` per grid point).
    #[error(
        "sparse SDF propagation made {relaxations} relaxations over {points} grid points, over its budget (lower max_distance)"
    )]
    PropagationBudget {
        /// Relaxations made when the budget ran out.
        relaxations: usize,
        /// Grid points of the allocated blocks.
        points: usize,
    },
}

/// A signed distance field on a regular grid of points `origin + (i, j, k) h`.
#[derive(Debug, Clone)]
pub struct Sdf {
    origin: Point3<f64>,
    h: f64,
    dims: [usize; 3],
    dist: Vec<f64>,
}

#[derive(PartialEq)]
struct Item(f64, usize);
impl Eq for Item {}
impl PartialOrd for Item {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Item {
    fn cmp(&self, other: &Self) -> Ordering {
        // Min-heap on distance (distances are finite, never NaN).
        other.0.total_cmp(&self.0).then(other.1.cmp(&self.1))
    }
}

impl Sdf {
    /// The field of `mesh`. Work: `O(triangles * (band + size)^3)` for the band plus
    /// `O(N log N)` for the propagation over the `N <= max_voxels` grid points.
    ///
    /// ```
    /// use nalgebra::Point3;
    /// use rappel_terrain::mesh::TriMesh;
    /// use rappel_terrain::sdf::{Sdf, SdfParams};
    /// let v = vec![Point3::new(0.0, 0.0, 0.0), Point3::new(1.0, 0.0, 0.0), Point3::new(0.0, 1.0, 0.0)];
    /// let m = TriMesh::new(v, vec![[0, 1, 2]]).unwrap();
    /// let f = Sdf::from_mesh(&m, &SdfParams::new(0.05)).unwrap();
    /// let d = f.distance(&Point3::new(0.2, 0.2, 0.1)).unwrap();
    /// assert!((d - 0.1).abs() < 0.05);
    /// ```
    pub fn from_mesh(mesh: &TriMesh, p: &SdfParams) -> Result<Self, SdfError> {
        if !(p.resolution > 0.0 && p.resolution.is_finite()) {
            return Err(SdfError::BadParameter {
                name: "resolution",
                value: p.resolution,
                why: "must be positive and finite",
            });
        }
        if p.band < 2 {
            return Err(SdfError::BadParameter {
                name: "band",
                value: p.band as f64,
                why: "must be at least 2 voxels",
            });
        }
        if !(p.margin >= 0.0 && p.margin.is_finite()) {
            return Err(SdfError::BadParameter {
                name: "margin",
                value: p.margin,
                why: "must be non-negative and finite",
            });
        }
        let h = p.resolution;
        let (origin, _, [fx, fy, fz]) = padded_grid(mesh, h, p.margin);
        let total = fx * fy * fz;
        if total.is_nan() || total > p.max_voxels as f64 {
            return Err(SdfError::TooManyVoxels {
                nx: saturating_count(fx),
                ny: saturating_count(fy),
                nz: saturating_count(fz),
                cap: p.max_voxels,
            });
        }
        let dims = [fx as usize, fy as usize, fz as usize];
        let len = dims[0] * dims[1] * dims[2];
        let mut dist = vec![f64::INFINITY; len];
        let mut closest = vec![Point3::origin(); len];
        let at =
            |i: usize, j: usize, k: usize| origin + Vector3::new(i as f64, j as f64, k as f64) * h;
        let idx = |i: usize, j: usize, k: usize| (k * dims[1] + j) * dims[0] + i;
        let reach = p.band as f64 * h;
        // Band: every grid point in each triangle's expanded box.
        for t in 0..mesh.triangles().len() {
            let c = mesh.corners(t);
            let tlo = c[0].inf(&c[1]).inf(&c[2]) - Vector3::repeat(reach);
            let thi = c[0].sup(&c[1]).sup(&c[2]) + Vector3::repeat(reach);
            let r0 =
                |a: f64, o: f64, d: usize| (((a - o) / h).floor().max(0.0) as usize).min(d - 1);
            let r1 = |a: f64, o: f64, d: usize| (((a - o) / h).ceil().max(0.0) as usize).min(d - 1);
            for k in r0(tlo.z, origin.z, dims[2])..=r1(thi.z, origin.z, dims[2]) {
                for j in r0(tlo.y, origin.y, dims[1])..=r1(thi.y, origin.y, dims[1]) {
                    for i in r0(tlo.x, origin.x, dims[0])..=r1(thi.x, origin.x, dims[0]) {
                        let q = at(i, j, k);
                        let cl = mesh.closest_on_triangle(t, &q);
                        let id = idx(i, j, k);
                        if cl.signed_distance.abs() < dist[id].abs() {
                            dist[id] = cl.signed_distance;
                            closest[id] = cl.point;
                        }
                    }
                }
            }
        }
        // Propagation: Dijkstra over the 26-neighbourhood, carrying the closest surface point and
        // the sign; each point is settled once (`len` pops at most once each, bounded by the cap).
        let mut heap: BinaryHeap<Item> = dist
            .iter()
            .enumerate()
            .filter(|(_, d)| d.is_finite())
            .map(|(i, d)| Item(d.abs(), i))
            .collect();
        let mut done = vec![false; len];
        while let Some(Item(d, id)) = heap.pop() {
            if done[id] || d > dist[id].abs() {
                continue;
            }
            done[id] = true;
            let (i, j, k) = (
                id % dims[0],
                (id / dims[0]) % dims[1],
                id / (dims[0] * dims[1]),
            );
            let sign = dist[id].signum();
            let cp = closest[id];
            for dk in -1i64..=1 {
                for dj in -1i64..=1 {
                    for di in -1i64..=1 {
                        let (ni, nj, nk) = (i as i64 + di, j as i64 + dj, k as i64 + dk);
                        if ni < 0
                            || nj < 0
                            || nk < 0
                            || ni >= dims[0] as i64
                            || nj >= dims[1] as i64
                            || nk >= dims[2] as i64
                        {
                            continue;
                        }
                        let nid = idx(ni as usize, nj as usize, nk as usize);
                        if done[nid] {
                            continue;
                        }
                        let nd = (at(ni as usize, nj as usize, nk as usize) - cp).norm();
                        if nd < dist[nid].abs() {
                            dist[nid] = sign * nd;
                            closest[nid] = cp;
                            heap.push(Item(nd, nid));
                        }
                    }
                }
            }
        }
        Ok(Sdf {
            origin,
            h,
            dims,
            dist,
        })
    }

    /// Grid spacing, metres.
    pub fn resolution(&self) -> f64 {
        self.h
    }

    /// Grid points along x, y, z.
    pub fn dims(&self) -> [usize; 3] {
        self.dims
    }

    /// The grid's box `(min, max)`.
    pub fn bounds(&self) -> (Point3<f64>, Point3<f64>) {
        let e = Vector3::new(
            (self.dims[0] - 1) as f64,
            (self.dims[1] - 1) as f64,
            (self.dims[2] - 1) as f64,
        ) * self.h;
        (self.origin, self.origin + e)
    }

    fn value(&self, i: usize, j: usize, k: usize) -> f64 {
        let at = |x: usize, d: usize| x.min(d - 1);
        self.dist[(at(k, self.dims[2]) * self.dims[1] + at(j, self.dims[1])) * self.dims[0]
            + at(i, self.dims[0])]
    }

    /// Trilinear signed distance at `q` (positive on the air side); `None` outside the grid.
    pub fn distance(&self, q: &Point3<f64>) -> Option<f64> {
        self.distance_and_gradient(q).map(|(d, _)| d)
    }

    /// Gradient of the trilinear distance at `q` (the derivative of the interpolant, not
    /// normalised); `None` outside the grid.
    pub fn gradient(&self, q: &Point3<f64>) -> Option<Vector3<f64>> {
        self.distance_and_gradient(q).map(|(_, g)| g)
    }

    /// Distance and gradient of the trilinear interpolant at `q`; `None` outside the grid.
    pub fn distance_and_gradient(&self, q: &Point3<f64>) -> Option<(f64, Vector3<f64>)> {
        interpolate(&self.origin, self.h, self.dims, q, |c| self.corners(c))
    }
}

impl GridField for Sdf {
    fn grid(&self) -> (&Point3<f64>, f64, [usize; 3]) {
        (&self.origin, self.h, self.dims)
    }
    fn corners(&self, c: [usize; 3]) -> [f64; 8] {
        corners_by_value(c, |i, j, k| self.value(i, j, k))
    }
}

/// Distance and gradient at `q` of the trilinear interpolant of the grid of `dims` points
/// `origin + (i, j, k) h` whose cells' corner values `corners([i, j, k])` gives (in the order of
/// [`trilinear`]); `None` outside the grid.
pub(crate) fn interpolate(
    origin: &Point3<f64>,
    h: f64,
    dims: [usize; 3],
    q: &Point3<f64>,
    corners: impl Fn([usize; 3]) -> [f64; 8],
) -> Option<(f64, Vector3<f64>)> {
    let (cell, t) = grid_cell(origin, h, dims, q)?;
    Some(trilinear(corners(cell), t, h))
}

/// The eight corner values of the cell whose lowest corner is `[i, j, k]`, read one by one
/// through `value`, in the order of [`trilinear`].
pub(crate) fn corners_by_value(
    [i, j, k]: [usize; 3],
    value: impl Fn(usize, usize, usize) -> f64,
) -> [f64; 8] {
    std::array::from_fn(|n| value(i + (n & 1), j + ((n >> 1) & 1), k + (n >> 2)))
}

/// The cell of the grid of `dims` points `origin + (i, j, k) h` holding `q` (its lowest corner,
/// at most `dims - 2` on each axis) and the fractional position in it; `None` outside the grid.
pub(crate) fn grid_cell(
    origin: &Point3<f64>,
    h: f64,
    dims: [usize; 3],
    q: &Point3<f64>,
) -> Option<([usize; 3], [f64; 3])> {
    let mut c = [0; 3];
    let mut f = [0.0; 3];
    for a in 0..3 {
        let u = (q[a] - origin[a]) / h;
        let top = (dims[a] - 1) as f64;
        if !(u >= 0.0 && u <= top) {
            return None;
        }
        // `u >= 0`, so the conversion's truncation is the floor (and no libm call).
        let i = (u as usize).min(dims[a].saturating_sub(2));
        c[a] = i;
        f[a] = u - i as f64;
    }
    Some((c, f))
}

/// Trilinear interpolation of the corner values `c` (`c[a + 2 b + 4 c]` at corner `(a, b, c)`)
/// of a cell of side `h` at fractional position `t`: the value and the gradient of the
/// interpolant (not normalised).
pub(crate) fn trilinear(c: [f64; 8], t: [f64; 3], h: f64) -> (f64, Vector3<f64>) {
    let [c000, c100, c010, c110, c001, c101, c011, c111] = c;
    let [x, y, z] = t;
    let lerp = |a: f64, b: f64, t: f64| a + (b - a) * t;
    let c00 = lerp(c000, c100, x);
    let c10 = lerp(c010, c110, x);
    let c01 = lerp(c001, c101, x);
    let c11 = lerp(c011, c111, x);
    let c0 = lerp(c00, c10, y);
    let c1 = lerp(c01, c11, y);
    let d = lerp(c0, c1, z);
    let dx = lerp(
        lerp(c100 - c000, c110 - c010, y),
        lerp(c101 - c001, c111 - c011, y),
        z,
    );
    let dy = lerp(c10 - c00, c11 - c01, z);
    let dz = c1 - c0;
    (d, Vector3::new(dx, dy, dz) / h)
}

impl crate::surface::SignedDistance for Sdf {
    fn signed_distance(&self, q: &Point3<f64>) -> Option<f64> {
        self.distance(q)
    }
    fn distance_gradient(&self, q: &Point3<f64>) -> Option<Vector3<f64>> {
        self.gradient(q)
    }
    /// The interpolant's exact first zero along the vertical (`ground_below_on_grid`).
    fn ground_below(&self, q: &Point3<f64>, _tolerance: f64) -> Result<Point3<f64>, DropError> {
        ground_below_on_grid(self, q)
    }
    /// The interpolant's exact first zero along the line (`first_zero_on_grid`).
    fn ground_along(
        &self,
        q: &Point3<f64>,
        dir: &nalgebra::Unit<Vector3<f64>>,
        reach: f64,
        _tolerance: f64,
    ) -> Result<Option<f64>, DropError> {
        first_zero_on_grid(self, q, dir, reach)
    }
}

/// A box of grid cells (lowest-corner indices `lo..=hi` on each axis) every corner value of
/// which is strictly positive (`positive`) or strictly negative: the trilinear interpolant, a
/// convex combination of a cell's corners, has no zero in it. The grid walks
/// ([`ground_below_on_grid`], [`first_zero_on_grid`]) ask a field for the box around a cell and
/// step through the cells inside it without reading their corners; a field without such
/// summaries answers `None`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct SignBox {
    /// The box's lowest cell.
    pub lo: [usize; 3],
    /// The box's highest cell (inclusive).
    pub hi: [usize; 3],
    /// The sign of every corner value in the box.
    pub positive: bool,
}

impl SignBox {
    /// Whether cell `c` lies in the box.
    fn holds(&self, c: [usize; 3]) -> bool {
        (0..3).all(|a| self.lo[a] <= c[a] && c[a] <= self.hi[a])
    }
}

/// A trilinear field on the grid of `dims` points `origin + (i, j, k) h`, as the grid walks
/// ([`ground_below_on_grid`], [`first_zero_on_grid`]) read it.
pub(crate) trait GridField {
    /// The grid: `(origin, h, dims)`.
    fn grid(&self) -> (&Point3<f64>, f64, [usize; 3]);
    /// The corner values of the cell whose lowest corner is `c`, in the order of [`trilinear`].
    fn corners(&self, c: [usize; 3]) -> [f64; 8];
    /// The [`SignBox`] around cell `c`, if the field knows one.
    fn sign_box(&self, c: [usize; 3]) -> Option<SignBox> {
        let _ = c;
        None
    }
}

/// The last [`SignBox`] a walk was given, asked anew only for a cell outside it: whether a cell
/// lies in a box of the sign `positive`.
struct BoxCache<'a, F: ?Sized> {
    field: &'a F,
    last: Option<SignBox>,
}

impl<'a, F: GridField + ?Sized> BoxCache<'a, F> {
    fn new(field: &'a F) -> Self {
        BoxCache { field, last: None }
    }
    fn zero_free(&mut self, cell: [usize; 3], positive: bool) -> bool {
        if !self.last.is_some_and(|b| b.holds(cell)) {
            self.last = self.field.sign_box(cell).filter(|b| b.holds(cell));
        }
        self.last.is_some_and(|b| b.positive == positive)
    }
}

/// The first zero along the vertical through `q` (down from `q` in the air, up from it below
/// the ground) of the trilinear field `field`:
/// within one cell the interpolant is linear along a vertical line (trilinear in `z` at fixed
/// `x, y`), so walking from grid plane to grid plane and solving the linear piece where the sign
/// changes gives the interpolant's exact first zero (no sphere-tracing convergence, no
/// tolerance). A piece whose cell lies in a [`SignBox`] of the start's sign
/// ([`GridField::sign_box`], asked once per box) holds no zero and is stepped over without
/// evaluating the field; the answer is the
/// same as without the boxes, bit for bit (the same planes bound the piece that crosses). At
/// most `dims[2] + 1` pieces. [`DropError::Undefined`] where the field has no value (outside the
/// grid, including leaving it without a zero).
pub(crate) fn ground_below_on_grid<F: GridField + ?Sized>(
    field: &F,
    q: &Point3<f64>,
) -> Result<Point3<f64>, DropError> {
    let (origin, h, dims) = field.grid();
    let (z0, nz) = (origin.z, dims[2]);
    let at = |z: f64| Point3::new(q.x, q.y, z);
    let value = |z: f64| {
        interpolate(origin, h, dims, &at(z), |c| field.corners(c))
            .map(|(v, _)| v)
            .ok_or(DropError::Undefined(at(z)))
    };
    let fq = value(q.z)?;
    if fq == 0.0 {
        return Ok(*q);
    }
    let down = fq > 0.0;
    let mut boxes = BoxCache::new(field);
    let u = (q.z - z0) / h;
    // The next grid plane in the direction of the search.
    let mut k = if down {
        u.ceil() - 1.0
    } else {
        u.floor() + 1.0
    };
    // The last plane (or `q`) and its value; the value is read only when a piece needs it: a
    // piece whose cell lies in a box of the start's sign holds no zero and is stepped over.
    let (mut z, mut fz) = (q.z, Some(fq));
    for _ in 0..=nz {
        if !(k >= 0.0 && k <= (nz - 1) as f64) {
            break;
        }
        let zn = z0 + k * h;
        let mid = at(0.5 * (z + zn));
        let free =
            grid_cell(origin, h, dims, &mid).is_some_and(|(cell, _)| boxes.zero_free(cell, down));
        if free {
            (z, fz) = (zn, None);
        } else {
            let fz_here = match fz {
                Some(v) => v,
                None => value(z)?,
            };
            let fnext = value(zn)?;
            if (down && fnext <= 0.0) || (!down && fnext >= 0.0) {
                // The linear piece between `z` and `zn` crosses zero (`fz_here` is non-zero).
                return Ok(at(z + (zn - z) * fz_here / (fz_here - fnext)));
            }
            (z, fz) = (zn, Some(fnext));
        }
        k += if down { -1.0 } else { 1.0 };
    }
    Err(DropError::Undefined(at(z)))
}

/// [`crate::surface::SignedDistance::ground_along`] on the trilinear field `field`: the
/// interpolant's exact first zero on the line through `q` along the unit vector `dir`, forward
/// from `q` in the air, backward from `q` below the ground, within `reach`.
///
/// The line is cut where it crosses the grid planes; within one cell the interpolant along it is
/// a cubic in the line's parameter (trilinear in three coordinates that are each linear in it).
/// A cell whose eight corners all lie strictly on the start's side holds no zero (the
/// interpolant is their convex combination) and is skipped, without reading its corners when it
/// lies in a [`SignBox`] of that side ([`GridField::sign_box`], asked once per box); otherwise the cubic is split at its
/// critical points into monotone pieces and the first piece that reaches the other side is
/// bisected to full precision (at most [`MAX_BISECTIONS`] halvings). No sphere-tracing
/// convergence, no tolerance: the answer is the interpolant's first zero up to rounding.
/// At most `dims[0] + dims[1] + dims[2] + 1` cells (the line leaves the grid or the reach
/// before); [`DropError::Undefined`] where the line leaves the grid before a zero or the reach.
pub(crate) fn first_zero_on_grid<F: GridField + ?Sized>(
    field: &F,
    q: &Point3<f64>,
    dir: &nalgebra::Unit<Vector3<f64>>,
    reach: f64,
) -> Result<Option<f64>, DropError> {
    let (origin, h, dims) = field.grid();
    let corners = |c| field.corners(c);
    let f0 = interpolate(origin, h, dims, q, corners)
        .ok_or(DropError::Undefined(*q))?
        .0;
    if f0 == 0.0 {
        return Ok(Some(0.0));
    }
    if !(reach >= 0.0 && reach.is_finite()) {
        return Ok(None);
    }
    // Search along `s` from the start's side: the values times `sigma` start positive.
    let sigma = f0.signum();
    let mut boxes = BoxCache::new(field);
    let s = dir.as_ref() * sigma;
    let at = |tau: f64| q + s * tau;
    // The next grid-plane crossing per axis: (tau, tau step), or none along an axis `s` is
    // orthogonal to.
    let mut next = [(f64::INFINITY, 0.0); 3];
    for (a, nx) in next.iter_mut().enumerate() {
        if s[a] != 0.0 {
            let u = (q[a] - origin[a]) / h;
            let du = s[a] / h;
            let m = if du > 0.0 {
                u.floor() + 1.0
            } else {
                u.ceil() - 1.0
            };
            *nx = ((m - u) / du, 1.0 / du.abs());
        }
    }
    let mut tau = 0.0;
    for _ in 0..=dims[0] + dims[1] + dims[2] {
        // The cell interval [tau, end].
        let (axis, crossing) = next
            .iter()
            .enumerate()
            .map(|(a, n)| (a, n.0))
            .min_by(|x, y| x.1.total_cmp(&y.1))
            .expect("three axes");
        let end = crossing.min(reach);
        if end > tau {
            let mid = at(0.5 * (tau + end));
            let (cell, _) = grid_cell(origin, h, dims, &mid).ok_or(DropError::Undefined(mid))?;
            let [i, j, k] = cell;
            let c = if boxes.zero_free(cell, sigma > 0.0) {
                None
            } else {
                Some(corners(cell).map(|v| sigma * v))
            };
            if let Some(c) = c.filter(|c| c.iter().any(|v| *v <= 0.0)) {
                // The cubic along the line, in lambda = tau' - tau on [0, end - tau].
                let p = at(tau);
                let corner = origin + Vector3::new(i as f64, j as f64, k as f64) * h;
                let lin = |a: usize| [(p[a] - corner[a]) / h, s[a] / h];
                if let Some(l) = first_root(&cell_cubic(c, [lin(0), lin(1), lin(2)]), end - tau) {
                    return Ok(Some(sigma * (tau + l)));
                }
            }
        }
        if crossing >= reach {
            return Ok(None);
        }
        tau = crossing;
        next[axis].0 += next[axis].1;
    }
    Err(DropError::Undefined(at(tau)))
}

/// Most halvings of a bracket by `first_root` (a bracket of the cell's size reaches the
/// spacing of doubles well before).
pub const MAX_BISECTIONS: usize = 80;

/// The coefficients `[a0, a1, a2, a3]` of the trilinear interpolant of corner values `c`
/// (`c[a + 2 b + 4 c]` at corner `(a, b, c)`) along the line whose fractional cell coordinates
/// are `x_a = l[a][0] + l[a][1] lambda`, as a cubic in `lambda`.
fn cell_cubic(c: [f64; 8], l: [[f64; 2]; 3]) -> [f64; 4] {
    let [c000, c100, c010, c110, c001, c101, c011, c111] = c;
    // f = k0 + kx x + ky y + kz z + kxy x y + kxz x z + kyz y z + kxyz x y z.
    let k0 = c000;
    let kx = c100 - c000;
    let ky = c010 - c000;
    let kz = c001 - c000;
    let kxy = c110 - c100 - c010 + c000;
    let kxz = c101 - c100 - c001 + c000;
    let kyz = c011 - c010 - c001 + c000;
    let kxyz = c111 - c110 - c101 - c011 + c100 + c010 + c001 - c000;
    let mul2 = |a: [f64; 2], b: [f64; 2]| [a[0] * b[0], a[0] * b[1] + a[1] * b[0], a[1] * b[1]];
    let [x, y, z] = l;
    let (xy, xz, yz) = (mul2(x, y), mul2(x, z), mul2(y, z));
    let xyz = [
        xy[0] * z[0],
        xy[0] * z[1] + xy[1] * z[0],
        xy[1] * z[1] + xy[2] * z[0],
        xy[2] * z[1],
    ];
    [
        k0 + kx * x[0]
            + ky * y[0]
            + kz * z[0]
            + kxy * xy[0]
            + kxz * xz[0]
            + kyz * yz[0]
            + kxyz * xyz[0],
        kx * x[1] + ky * y[1] + kz * z[1] + kxy * xy[1] + kxz * xz[1] + kyz * yz[1] + kxyz * xyz[1],
        kxy * xy[2] + kxz * xz[2] + kyz * yz[2] + kxyz * xyz[2],
        kxyz * xyz[3],
    ]
}

/// The smallest `lambda` in `[0, len]` where the cubic `a` (coefficients from the constant up)
/// is `<= 0`, or `None` (module docs of [`first_zero_on_grid`]): split at the critical points,
/// the first monotone piece whose end is `<= 0` is bisected.
fn first_root(a: &[f64; 4], len: f64) -> Option<f64> {
    let f = |x: f64| ((a[3] * x + a[2]) * x + a[1]) * x + a[0];
    if f(0.0) <= 0.0 {
        return Some(0.0);
    }
    // Critical points: roots of 3 a3 x^2 + 2 a2 x + a1 inside (0, len).
    let (qa, qb, qc) = (3.0 * a[3], 2.0 * a[2], a[1]);
    let mut cuts = [len; 3];
    let mut n = 0;
    let mut push = |x: f64| {
        if x > 0.0 && x < len {
            cuts[n] = x;
            n += 1;
        }
    };
    if qa == 0.0 {
        if qb != 0.0 {
            push(-qc / qb);
        }
    } else {
        let disc = qb * qb - 4.0 * qa * qc;
        if disc >= 0.0 {
            let r = -0.5 * (qb + qb.signum() * disc.sqrt());
            if r != 0.0 {
                push(r / qa);
                push(qc / r);
            } else {
                push(0.0);
            }
        }
    }
    let (first, second) = (cuts[0].min(cuts[1]), cuts[0].max(cuts[1]));
    let mut lo = 0.0;
    for hi in [first, second, len] {
        if hi > lo && f(hi) <= 0.0 {
            // f(lo) > 0 >= f(hi) on a monotone piece: bisect.
            let (mut l, mut r) = (lo, hi);
            for _ in 0..MAX_BISECTIONS {
                let m = 0.5 * (l + r);
                if m <= l || m >= r {
                    break;
                }
                if f(m) <= 0.0 {
                    r = m;
                } else {
                    l = m;
                }
            }
            return Some(r);
        }
        lo = lo.max(hi);
    }
    None
}

/// The grid box of a field over `mesh`: the mesh's bounds grown by `margin` on every side, as its
/// corner (the grid origin), its extent, and the number of grid points along each axis at
/// spacing `h`, as floats so that a caller can check its cap before any count overflows.
pub(crate) fn padded_grid(
    mesh: &TriMesh,
    h: f64,
    margin: f64,
) -> (Point3<f64>, Vector3<f64>, [f64; 3]) {
    let (lo, hi) = mesh.bounds();
    let origin = lo - Vector3::repeat(margin);
    let ext = (hi - lo) + Vector3::repeat(2.0 * margin);
    let n = |e: f64| (e / h).ceil() + 1.0;
    (origin, ext, [n(ext.x), n(ext.y), n(ext.z)])
}

/// A grid count held as a float, as a `usize` for an error message (saturating at `usize::MAX`).
pub(crate) fn saturating_count(f: f64) -> usize {
    if f < usize::MAX as f64 {
        f as usize
    } else {
        usize::MAX
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::{GridGeometry, HeightGrid};
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn bumpy() -> TriMesh {
        let g = GridGeometry::new(9, 9, 0.5, 0.5, 0.0, 4.5).unwrap();
        let dem = HeightGrid::from_fn(g, |r, c, p| {
            Some(0.4 * (p.x * 1.3).sin() + 0.3 * (p.y * 0.9).cos() + 0.05 * ((r * c) % 3) as f64)
        })
        .unwrap();
        TriMesh::from_height_grid(&dem).unwrap()
    }

    #[test]
    fn band_error_within_proven_bound_far_error_measured() {
        let m = bumpy();
        let h = 0.1;
        let f = Sdf::from_mesh(&m, &SdfParams::new(h)).unwrap();
        let (lo, hi) = f.bounds();
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let (mut near, mut far) = (0, 0);
        for _ in 0..600 {
            // Over the mesh's footprint shrunk by the band: beyond an open mesh's boundary the
            // signed distance jumps (see the module doc) and no bound holds.
            let (mlo, mhi) = m.bounds();
            let q = Point3::new(
                rng.random_range(mlo.x + 0.4..mhi.x - 0.4),
                rng.random_range(mlo.y + 0.4..mhi.y - 0.4),
                rng.random_range(lo.z..hi.z),
            );
            let exact = m.signed_distance(&q);
            let got = f.distance(&q).unwrap();
            if exact.abs() <= (3.0 - 3f64.sqrt()) * h {
                near += 1;
                assert!(
                    (got - exact).abs() <= INTERPOLATION_BOUND * h + 1e-12,
                    "near {q}: {got} vs {exact}"
                );
            } else {
                far += 1;
                // Empirical bound beyond the band (documented as such in docs/mesh.md).
                assert!((got - exact).abs() <= 1.0 * h, "far {q}: {got} vs {exact}");
                assert_eq!(got.signum(), exact.signum(), "sign at {q}");
            }
        }
        assert!(near > 20 && far > 100, "{near} near, {far} far");
    }

    #[test]
    fn plane_gradient_is_the_normal() {
        let g = GridGeometry::new(8, 8, 1.0, 1.0, 0.0, 8.0).unwrap();
        let dem = HeightGrid::from_fn(g, |_, _, p| Some(0.5 * p.x)).unwrap();
        let m = TriMesh::from_height_grid(&dem).unwrap();
        let f = Sdf::from_mesh(&m, &SdfParams::new(0.25)).unwrap();
        let n = Vector3::new(-0.5, 0.0, 1.0).normalize();
        let q = Point3::new(4.1, 3.9, 0.5 * 4.1 + 0.3);
        let g = f.gradient(&q).unwrap();
        assert!((g - n).norm() < 1e-6, "{g} vs {n}");
        assert!(f.distance(&Point3::new(100.0, 0.0, 0.0)).is_none());
    }

    #[test]
    fn bad_parameters_and_cap_are_errors() {
        let m = bumpy();
        assert!(matches!(
            Sdf::from_mesh(&m, &SdfParams::new(0.0)),
            Err(SdfError::BadParameter {
                name: "resolution",
                ..
            })
        ));
        assert!(matches!(
            Sdf::from_mesh(&m, &SdfParams::new(f64::NAN)),
            Err(SdfError::BadParameter { .. })
        ));
        let mut p = SdfParams::new(1e-6);
        p.max_voxels = 1000;
        assert!(matches!(
            Sdf::from_mesh(&m, &p),
            Err(SdfError::TooManyVoxels { cap: 1000, .. })
        ));
    }
}
