//! Sparse Euclidean signed distance field of a [`TriMesh`] (Paton §IV; after Voxblox,
//! Oleynikova et al. 2017: a TSDF band of exact distances, then an ESDF wavefront beyond it up to
//! a `max_distance`, a default value beyond that): voxel blocks of [`BLOCK`]³ grid points
//! allocated only near the surface, exact signed distances in them up to the truncation distance
//! `T`, propagated distances from `T` to the propagation distance `D`, `±D` beyond (the sign
//! carried by a flood fill), trilinear distance and gradient queries with the same formulas as
//! the dense [`crate::sdf::Sdf`]. [`SparseSdfParams::truncated`] builds the field without
//! propagation (`D = T`).
//!
//! # Construction
//! 1. **Blocks**: block `b` (grid points `8 b .. 8 b + 7` on each axis) is allocated when some
//!    triangle lies within `T + r_b` of its centre (`r_b` the block's half-diagonal); that
//!    triangle joins the block's candidate list. Every triangle visits only the blocks whose
//!    centres lie in its bounding box grown by `T + r_b` (rayon over triangles).
//! 2. **Exact band**: every grid point of an allocated block takes the smallest
//!    [`TriMesh::closest_on_triangle`] distance over its block's candidates (rayon over blocks).
//!    A point within `T` of the mesh has its closest triangle among the candidates (it is within
//!    `r_b` of the centre), so every value `<= T` is exact; a larger value only proves `|d| > T`,
//!    and its pseudo-normal sign (from a triangle that need not be the closest) is not trusted.
//!    2a. **Propagation** (when `D > T`; Voxblox's `esdf_integrator` wavefront, here carrying
//!    sites as in Danielsson's vector propagation): the exact points next to a point beyond `T`
//!    are the seeds, each with its closest surface point as its *site*. A bucketed priority
//!    queue (buckets `h / 4` wide) processes points in increasing distance; a processed point
//!    offers its site to its 6-neighbours beyond `T`, which take it when it is closer than their
//!    own by more than [`RELAX_SLACK_VOXELS`] `h`, with the exact distance to that site and the
//!    processed point's sign. Blocks are allocated on demand where a point within `D` is reached
//!    (same block cap). Sign: two 6-adjacent points one of which is beyond `T >= 2 h` lie on one
//!    side of the surface, so the carried sign is exact. Single-threaded (the queue is
//!    sequential); at most [`MAX_RELAXATIONS_PER_POINT`] relaxations per grid point.
//! 3. **Sign beyond the reach**: first inside each block in parallel (a point still unknown
//!    takes the sign of a 6-neighbour in its block; a block with no known point lies wholly
//!    beyond the reach and is released), then across blocks: the remaining points and the
//!    unallocated blocks (every point of which is farther than `T`, with propagation farther
//!    than `D`, from the mesh) take the sign of a neighbour by a breadth-first flood from the
//!    known points (6-neighbours; an unallocated block is one node, adjacent to the facing points
//!    of an allocated neighbour). Two adjacent nodes with `|d| > T >= 2 h` everywhere between
//!    them lie on one side of the surface, so the flood is exact for a closed mesh and on the air
//!    side of a terrain patch; every node is reached because the grid is connected and holds
//!    exact points. They store `±D`.
//!
//! # Error bound
//! **Truncated** (`D = T`): every stored value is `clamp(d, -T, T)` at its grid point, `d` the
//! mesh's exact signed distance, up to `f32` rounding (`T * 2^-24`). `clamp ∘ d` is
//! 1-Lipschitz, so the trilinear interpolant `f` satisfies, at every query point in the grid's
//! box, `|f(q) - clamp(d(q), -T, T)| <= (sqrt 3 / 2) h + T 2^-24` ([`SparseSdf::error_bound`],
//! proven); hence where `|f(q)| < T - bound` the field is within the bound of the exact
//! distance, and where it reads `±T` the exact distance is at least `T - 2 bound` in magnitude,
//! with that sign.
//!
//! **Propagated** (`D > T`): values `<= T` are exact as above. A propagated value is the exact
//! distance from its grid point to a real surface point (its site, stored in `f32`), so it is
//! **never below** the exact distance (up to the site's `f32` rounding, a few micrometres on
//! scenes of tens of metres) and never above `D`; its sign is exact. How far above is **not
//! proven**: [`PROPAGATION_EXCESS_VOXELS`] `h` = 0.25 h is the empirical bound the property tests
//! assert (`crates/terrain/tests/sparse_sdf.rs`: seeded grid points in the band and out to `D`
//! on Paton's ledge and pole scenes against parry's exact distance, a closed box and a tilted
//! plane; the largest excess measured in a probe was 0.11 h at 10 cm and 0.07 h at 5 cm). So every grid
//! value lies in `[clamp(|d|, 0, D), clamp(|d|, 0, D) + 0.25 h]` in magnitude, and queries
//! satisfy `|f(q) - clamp(d(q), -D, D)| <= (sqrt 3 / 2) h + D 2^-24 + 0.25 h`
//! ([`SparseSdf::error_bound`], its last term empirical, [`SparseSdf::excess_bound`]).
//! Sphere tracing may step by the field's value minus the bound.
//!
//! As for the dense field, beyond an open mesh's boundary the signed distance itself jumps (a
//! convention, `docs/mesh.md`) and the flood may carry either side's sign there: crop queries to
//! the interior.
//!
//! # Bounds
//! The block index is dense over the grid's box (4 bytes per block cell, at most
//! `max_block_cells`); allocated blocks (2 KiB each, the band's and the wavefront's together) at
//! most `max_blocks`; candidate pairs at most [`MAX_CANDIDATES_PER_BLOCK`] per allowed block;
//! wavefront relaxations at most [`MAX_RELAXATIONS_PER_POINT`] per grid point. Each is a typed
//! [`SdfError`]. Build memory with propagation: 4 bytes of value, 4 of site index and 4 of
//! closest-triangle index per grid point, plus 12 bytes per seed.

use std::collections::VecDeque;

use nalgebra::{Point3, Vector3};
use rayon::prelude::*;

use crate::mesh::{TriMesh, closest_point_triangle};
use crate::sdf::{INTERPOLATION_BOUND, SdfError, interpolate, padded_grid, saturating_count};
use crate::surface::SignedDistance;

/// Grid points per block side.
pub const BLOCK: usize = 8;
const BLOCK_POINTS: usize = BLOCK * BLOCK * BLOCK;

/// Default truncation distance `T`, metres: Axel's body clearance (0.25 m) plus the interpolation
/// bound at 10 cm and a margin. [`SparseSdfParams::new`] takes at least `3 h`.
pub const DEFAULT_TRUNCATION: f64 = 0.4;

/// Default propagation distance `D`, metres ([`SparseSdfParams::max_distance`]): values beyond the
/// exact band are carried out to `D` by the wavefront, `±D` beyond. One metre covers Axel's boom
/// reach (`L_c` = 1 m) and keeps the ledge scene at 5 cm near 30 M grid points (about 120 MB of
/// `f32` values); larger `D` costs memory and build time in proportion to the volume within `D`
/// of the surface.
pub const DEFAULT_MAX_DISTANCE: f64 = 1.0;

/// **Empirical** bound on the excess of a propagated grid value over the exact distance, in grid
/// spacings: every propagated value is the exact distance to a real surface point (so never below
/// the exact distance), and the property tests (`crates/terrain/tests/sparse_sdf.rs`, Paton's
/// ledge scenes and closed forms) find it at most this many `h` above it. Not proven (the
/// wavefront hands each voxel the best site of the neighbour that reached it first, like
/// Danielsson's vector propagation, whose known errors are a fraction of a voxel).
pub const PROPAGATION_EXCESS_VOXELS: f64 = 0.25;

/// A site replaces a point's site only when it is closer by more than this many grid spacings
/// (near-equal sites of one surface patch would otherwise relax points many times over).
pub const RELAX_SLACK_VOXELS: f64 = 0.01;

/// Cap on wavefront relaxations per propagated grid point (each strictly lowers the point's
/// value or gives it its first one); over it is [`SdfError::PropagationBudget`].
pub const MAX_RELAXATIONS_PER_POINT: usize = 16;

/// Default cap on allocated blocks (2 KiB each: 512 MiB at the cap).
pub const DEFAULT_MAX_BLOCKS: usize = 262_144;

/// Default cap on block cells of the dense block index over the grid's box (4 bytes each:
/// 128 MiB at the cap).
pub const DEFAULT_MAX_BLOCK_CELLS: usize = 1 << 25;

/// Cap on (block, candidate triangle) pairs per allowed block: at most
/// `MAX_CANDIDATES_PER_BLOCK * max_blocks` pairs are kept.
pub const MAX_CANDIDATES_PER_BLOCK: usize = 64;

/// `2^-24`: the relative rounding of a stored `f32` value.
pub const F32_ROUNDING: f64 = 5.960_464_477_539_063e-8;

const AIR: u32 = u32::MAX;
const GROUND: u32 = u32::MAX - 1;
const UNKNOWN: u32 = u32::MAX - 2;

/// How to build a [`SparseSdf`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SparseSdfParams {
    /// Grid spacing `h`, metres (`> 0`, finite).
    pub resolution: f64,
    /// Truncation distance `T`, metres (`>= 2 h`: the sign flood needs `T > sqrt 3 h`): the exact
    /// band.
    pub truncation: f64,
    /// Propagation distance `D >= T`, metres: beyond the exact band the closest surface points
    /// are carried outward by a wavefront up to `D`; values beyond are `±D`. `D = T`: no
    /// propagation (a truncated field).
    pub max_distance: f64,
    /// Margin added around the mesh's bounding box, metres (`>= 0`).
    pub margin: f64,
    /// Cap on allocated blocks.
    pub max_blocks: usize,
    /// Cap on cells of the dense block index.
    pub max_block_cells: usize,
}

impl SparseSdfParams {
    /// Resolution `h`, truncation `T = max(DEFAULT_TRUNCATION, 3 h)`, propagation to
    /// `D = max(DEFAULT_MAX_DISTANCE, T)`, margin `D`, the default caps.
    pub fn new(resolution: f64) -> Self {
        let mut p = Self::truncated(resolution);
        p.max_distance = DEFAULT_MAX_DISTANCE.max(p.truncation);
        p.margin = p.max_distance;
        p
    }

    /// As [`SparseSdfParams::new`] without propagation: `D = T`, margin `T` (values beyond the
    /// exact band are `±T`, a truncated field).
    pub fn truncated(resolution: f64) -> Self {
        let truncation = DEFAULT_TRUNCATION.max(3.0 * resolution);
        SparseSdfParams {
            resolution,
            truncation,
            max_distance: truncation,
            margin: truncation,
            max_blocks: DEFAULT_MAX_BLOCKS,
            max_block_cells: DEFAULT_MAX_BLOCK_CELLS,
        }
    }
}

/// A sparse truncated signed distance field on the grid `origin + (i, j, k) h`.
#[derive(Debug, Clone)]
pub struct SparseSdf {
    origin: Point3<f64>,
    h: f64,
    truncation: f64,
    max_distance: f64,
    dims: [usize; 3],
    cells: [usize; 3],
    /// Per block cell: the allocated block's index, or [`AIR`] / [`GROUND`].
    index: Vec<u32>,
    /// [`BLOCK_POINTS`] values per allocated block, `x` fastest.
    values: Vec<f32>,
}

fn bad(name: &'static str, value: f64, why: &'static str) -> SdfError {
    SdfError::BadParameter { name, value, why }
}

/// A node of the sign flood: a grid point of an allocated block (`block * 512 + local`) or an
/// unallocated block cell.
#[derive(Clone, Copy)]
enum Node {
    Point(usize),
    Cell(usize),
}

impl SparseSdf {
    /// The field of `mesh`. Work: every triangle against the blocks of its grown bounding box,
    /// then `BLOCK³` points per allocated block against its candidates (both in parallel), then
    /// a linear flood over the points beyond `T` and the unallocated cells.
    ///
    /// ```
    /// use nalgebra::Point3;
    /// use rappel_terrain::mesh::TriMesh;
    /// use rappel_terrain::sparse_sdf::{SparseSdf, SparseSdfParams};
    /// let v = vec![Point3::new(0.0, 0.0, 0.0), Point3::new(1.0, 0.0, 0.0), Point3::new(0.0, 1.0, 0.0)];
    /// let m = TriMesh::new(v, vec![[0, 1, 2]]).unwrap();
    /// let f = SparseSdf::from_mesh(&m, &SparseSdfParams::new(0.05)).unwrap();
    /// let d = f.distance(&Point3::new(0.2, 0.2, 0.1)).unwrap();
    /// assert!((d - 0.1).abs() <= f.error_bound());
    /// ```
    pub fn from_mesh(mesh: &TriMesh, p: &SparseSdfParams) -> Result<Self, SdfError> {
        let h = p.resolution;
        if !(h > 0.0 && h.is_finite()) {
            return Err(bad("resolution", h, "must be positive and finite"));
        }
        let t_max = p.truncation;
        if !(t_max.is_finite() && t_max >= 2.0 * h) {
            return Err(bad(
                "truncation",
                t_max,
                "must be finite and at least 2 resolutions",
            ));
        }
        let d_max = p.max_distance;
        if !(d_max.is_finite() && d_max >= t_max) {
            return Err(bad(
                "max_distance",
                d_max,
                "must be finite and at least the truncation",
            ));
        }
        if !(p.margin >= 0.0 && p.margin.is_finite()) {
            return Err(bad("margin", p.margin, "must be non-negative and finite"));
        }
        if p.max_blocks == 0 || p.max_blocks >= UNKNOWN as usize {
            return Err(bad(
                "max_blocks",
                p.max_blocks as f64,
                "must be in 1 ..= 2^32 - 4",
            ));
        }
        if p.max_block_cells == 0 || p.max_block_cells > u32::MAX as usize {
            return Err(bad(
                "max_block_cells",
                p.max_block_cells as f64,
                "must be in 1 ..= 2^32 - 1",
            ));
        }
        let (origin, ext, fp) = padded_grid(mesh, h, p.margin);
        let fc = fp.map(|n| (n / BLOCK as f64).ceil());
        let total = fc[0] * fc[1] * fc[2];
        if !(total.is_finite() && total <= p.max_block_cells as f64) {
            return Err(SdfError::TooManyBlockCells {
                nx: saturating_count(fc[0]),
                ny: saturating_count(fc[1]),
                nz: saturating_count(fc[2]),
                cap: p.max_block_cells,
            });
        }
        let dims = fp.map(|n| n as usize);
        let cells = fc.map(|n| n as usize);
        let cell_id = |c: [usize; 3]| (c[2] * cells[1] + c[1]) * cells[0] + c[0];
        let b = BLOCK as f64;
        let half = 0.5 * (b - 1.0);
        let r_b = half * h * 3f64.sqrt();
        // Rounding slack on the candidate test (relative to the reach).
        let reach = (t_max + r_b) * (1.0 + 1e-9);
        let centre =
            |c: [usize; 3]| origin + Vector3::from(c.map(|v| v as f64 * b + half)).scale(h);

        // 1. Candidate (block cell, triangle) pairs.
        let mut pairs: Vec<(u32, u32)> = (0..mesh.triangles().len())
            .into_par_iter()
            .flat_map_iter(|t| {
                let [a, bb, c] = mesh.corners(t);
                let tlo = a.inf(&bb).inf(&c) - Vector3::repeat(reach);
                let thi = a.sup(&bb).sup(&c) + Vector3::repeat(reach);
                let range = |axis: usize| {
                    let u0 = ((tlo[axis] - origin[axis]) / h - half) / b;
                    let u1 = ((thi[axis] - origin[axis]) / h - half) / b;
                    let top = cells[axis] as f64 - 1.0;
                    let lo = u0.ceil().clamp(0.0, top) as usize;
                    let hi = u1.floor().clamp(0.0, top) as usize;
                    // An empty range when the box ends before the first centre.
                    if u1 < 0.0 || u0 > top {
                        1..1
                    } else {
                        lo..hi + 1
                    }
                };
                let (rx, ry, rz) = (range(0), range(1), range(2));
                let mut out = Vec::new();
                for k in rz {
                    for j in ry.clone() {
                        for i in rx.clone() {
                            let q = centre([i, j, k]);
                            let (cp, _) = closest_point_triangle(&q, &a, &bb, &c);
                            if (q - cp).norm() <= reach {
                                out.push((cell_id([i, j, k]) as u32, t as u32));
                            }
                        }
                    }
                }
                out.into_iter()
            })
            .collect();
        pairs.par_sort_unstable();
        let mut starts = Vec::new();
        let mut block_cells: Vec<usize> = Vec::new();
        for (k, &(c, _)) in pairs.iter().enumerate() {
            if k == 0 || pairs[k - 1].0 != c {
                starts.push(k);
                block_cells.push(c as usize);
            }
        }
        starts.push(pairs.len());
        let nb = block_cells.len();
        if nb > p.max_blocks {
            return Err(SdfError::TooManyBlocks {
                blocks: nb,
                cap: p.max_blocks,
            });
        }
        if pairs.len() > MAX_CANDIDATES_PER_BLOCK.saturating_mul(p.max_blocks) {
            return Err(SdfError::TooManyBlocks {
                blocks: pairs.len().div_ceil(MAX_CANDIDATES_PER_BLOCK),
                cap: p.max_blocks,
            });
        }
        let mut index = vec![UNKNOWN; cells[0] * cells[1] * cells[2]];
        for (k, &c) in block_cells.iter().enumerate() {
            index[c] = k as u32;
        }
        let split = |c: usize| {
            [
                c % cells[0],
                (c / cells[0]) % cells[1],
                c / (cells[0] * cells[1]),
            ]
        };

        // 2. Exact values up to T; NaN marks "farther than T, sign unknown". The plane test's
        // slack covers the rounding of the unit normal (relative to the scene's size).
        let plane_slack = 1e-9 * (ext.norm() + t_max);
        let mut values = vec![0f32; nb * BLOCK_POINTS];
        // The closest triangle of every exact point (the wavefront's sites).
        let mut best_tri = vec![u32::MAX; nb * BLOCK_POINTS];
        values
            .par_chunks_mut(BLOCK_POINTS)
            .zip(best_tri.par_chunks_mut(BLOCK_POINTS))
            .enumerate()
            .for_each(|(k, (out, tri_out))| {
                let cc = split(block_cells[k]);
                // Each candidate with a point and the unit normal of its plane: the distance to
                // the plane is a lower bound on the distance to the triangle, so a candidate
                // whose plane is farther than the best so far (or than T) is skipped.
                let cand: Vec<(usize, Point3<f64>, Vector3<f64>)> = pairs[starts[k]..starts[k + 1]]
                    .iter()
                    .map(|&(_, t)| {
                        let t = t as usize;
                        (t, mesh.corners(t)[0], mesh.face_normal(t))
                    })
                    .collect();
                for (l, (slot, tri_slot)) in out.iter_mut().zip(tri_out.iter_mut()).enumerate() {
                    let g = [l % BLOCK, (l / BLOCK) % BLOCK, l / (BLOCK * BLOCK)];
                    let q = origin
                        + Vector3::from([0, 1, 2].map(|a| (cc[a] * BLOCK + g[a]) as f64)).scale(h);
                    let mut best = f64::INFINITY;
                    let mut best_t = u32::MAX;
                    for &(t, a, n) in &cand {
                        if (q - a).dot(&n).abs() > best.abs().min(t_max) + plane_slack {
                            continue;
                        }
                        let d = mesh.closest_on_triangle(t, &q).signed_distance;
                        if d.abs() < best.abs() {
                            best = d;
                            best_t = t as u32;
                        }
                    }
                    if best.abs() <= t_max {
                        *slot = best as f32;
                        *tri_slot = best_t;
                    } else {
                        *slot = f32::NAN;
                    }
                }
            });

        drop(pairs);
        // 2a. The wavefront beyond the exact band, out to D.
        if d_max > t_max {
            let grid = Grid { origin, h, cells };
            propagate(
                mesh,
                &grid,
                &mut index,
                &mut block_cells,
                &mut values,
                &best_tri,
                d_max,
                p.max_blocks,
            )?;
        }
        drop(best_tri);
        // 2b. The sign flood inside each block (in parallel): an exact point's sign carried to
        // its 6-neighbours beyond T. A block without an exact point lies wholly beyond T, on one
        // side of the surface: it is released and becomes one unallocated node of step 3.
        let tf = d_max as f32;
        let exact: Vec<bool> = values
            .par_chunks_mut(BLOCK_POINTS)
            .map(|v| local_flood(v, tf))
            .collect();
        if exact.iter().any(|e| !e) {
            let kept = exact.iter().filter(|e| **e).count();
            let mut kept_values = Vec::with_capacity(kept * BLOCK_POINTS);
            let mut kept_cells = Vec::with_capacity(kept);
            for (k, &keep) in exact.iter().enumerate() {
                let c = block_cells[k];
                if keep {
                    index[c] = kept_cells.len() as u32;
                    kept_cells.push(c);
                    kept_values
                        .extend_from_slice(&values[k * BLOCK_POINTS..(k + 1) * BLOCK_POINTS]);
                } else {
                    index[c] = UNKNOWN;
                }
            }
            values = kept_values;
            block_cells = kept_cells;
        }
        let block_cells = block_cells;

        // 3. The sign flood across blocks: the points step 2b did not reach (a region of a block
        // cut off from its exact points inside the block) and the unallocated cells.
        let neighbours = |index: &[u32], n: Node, f: &mut dyn FnMut(Node)| {
            let (cc, local) = match n {
                Node::Point(i) => {
                    let l = i % BLOCK_POINTS;
                    (
                        split(block_cells[i / BLOCK_POINTS]),
                        Some([l % BLOCK, (l / BLOCK) % BLOCK, l / (BLOCK * BLOCK)]),
                    )
                }
                Node::Cell(c) => (split(c), None),
            };
            for axis in 0..3 {
                for up in [false, true] {
                    if let Some(g) = local {
                        let inside = if up { g[axis] + 1 < BLOCK } else { g[axis] > 0 };
                        if inside {
                            let mut g2 = g;
                            g2[axis] = if up { g[axis] + 1 } else { g[axis] - 1 };
                            let l2 = (g2[2] * BLOCK + g2[1]) * BLOCK + g2[0];
                            if let Node::Point(i) = n {
                                f(Node::Point(i - i % BLOCK_POINTS + l2));
                            }
                            continue;
                        }
                    }
                    let mut c2 = cc;
                    if up {
                        if cc[axis] + 1 >= cells[axis] {
                            continue;
                        }
                        c2[axis] += 1;
                    } else {
                        if cc[axis] == 0 {
                            continue;
                        }
                        c2[axis] -= 1;
                    }
                    let id = cell_id(c2);
                    let blk = index[id];
                    if blk >= UNKNOWN {
                        // Unallocated (unknown, air or ground).
                        f(Node::Cell(id));
                        continue;
                    }
                    let base = blk as usize * BLOCK_POINTS;
                    let face = if up { 0 } else { BLOCK - 1 };
                    match local {
                        Some(g) => {
                            let mut g2 = g;
                            g2[axis] = face;
                            f(Node::Point(base + (g2[2] * BLOCK + g2[1]) * BLOCK + g2[0]));
                        }
                        None => {
                            for u in 0..BLOCK {
                                for v in 0..BLOCK {
                                    let mut g2 = [0; 3];
                                    g2[axis] = face;
                                    g2[(axis + 1) % 3] = u;
                                    g2[(axis + 2) % 3] = v;
                                    f(Node::Point(base + (g2[2] * BLOCK + g2[1]) * BLOCK + g2[0]));
                                }
                            }
                        }
                    }
                }
            }
        };
        // `Some(true)` air, `Some(false)` ground, `None` unknown.
        let sign = |index: &[u32], values: &[f32], n: Node| match n {
            Node::Point(i) => {
                let v = values[i];
                (!v.is_nan()).then_some(v >= 0.0)
            }
            Node::Cell(c) => match index[c] {
                AIR => Some(true),
                GROUND => Some(false),
                _ => None,
            },
        };
        let set = |index: &mut [u32], values: &mut [f32], n: Node, air: bool| match n {
            Node::Point(i) => values[i] = if air { tf } else { -tf },
            Node::Cell(c) => index[c] = if air { AIR } else { GROUND },
        };
        // Seeds: unknown nodes with a known neighbour in the initial state (assigned after the
        // scan, so that the fronts advance evenly from every exact point).
        let mut seeds: Vec<(Node, bool)> = Vec::new();
        let unknown_nodes = values
            .iter()
            .enumerate()
            .filter(|(_, v)| v.is_nan())
            .map(|(i, _)| Node::Point(i))
            .chain(
                index
                    .iter()
                    .enumerate()
                    .filter(|(_, b)| **b == UNKNOWN)
                    .map(|(c, _)| Node::Cell(c)),
            );
        for n in unknown_nodes {
            let mut found = None;
            neighbours(&index, n, &mut |m| {
                if found.is_none() {
                    found = sign(&index, &values, m);
                }
            });
            if let Some(air) = found {
                seeds.push((n, air));
            }
        }
        let mut queue = VecDeque::with_capacity(seeds.len());
        for (n, air) in seeds {
            if sign(&index, &values, n).is_none() {
                set(&mut index, &mut values, n, air);
                queue.push_back((n, air));
            }
        }
        // Each node enters the queue once (when its sign is set): bounded by the node count.
        while let Some((n, air)) = queue.pop_front() {
            let mut next = Vec::new();
            neighbours(&index, n, &mut |m| {
                if sign(&index, &values, m).is_none() {
                    next.push(m);
                }
            });
            for m in next {
                if sign(&index, &values, m).is_none() {
                    set(&mut index, &mut values, m, air);
                    queue.push_back((m, air));
                }
            }
        }
        // Unreached nodes cannot exist (the grid is connected and holds exact points); air if so.
        for v in values.iter_mut().filter(|v| v.is_nan()) {
            *v = tf;
        }
        for b in index.iter_mut().filter(|b| **b == UNKNOWN) {
            *b = AIR;
        }
        Ok(SparseSdf {
            origin,
            h,
            truncation: t_max as f32 as f64,
            max_distance: tf as f64,
            dims,
            cells,
            index,
            values,
        })
    }

    /// Grid spacing, metres.
    pub fn resolution(&self) -> f64 {
        self.h
    }

    /// Truncation distance `T` (the parameter rounded to `f32`), metres: values are clamped to
    /// `[-T, T]`.
    pub fn truncation(&self) -> f64 {
        self.truncation
    }

    /// Propagation distance `D` (the parameter rounded to `f32`), metres: values are clamped to
    /// `[-D, D]`; equal to [`SparseSdf::truncation`] for a truncated field.
    pub fn max_distance(&self) -> f64 {
        self.max_distance
    }

    /// The **empirical** bound on how far a propagated grid value (between `T` and `D` in
    /// magnitude) lies above the exact distance: [`PROPAGATION_EXCESS_VOXELS`] `h`; zero for a
    /// truncated field (module doc).
    pub fn excess_bound(&self) -> f64 {
        if self.max_distance > self.truncation {
            PROPAGATION_EXCESS_VOXELS * self.h
        } else {
            0.0
        }
    }

    /// Allocated blocks.
    pub fn block_count(&self) -> usize {
        self.values.len() / BLOCK_POINTS
    }

    /// The bound on `|f(q) - clamp(d(q), -D, D)|` anywhere in the box (module doc):
    /// `(sqrt 3 / 2) h + D 2^-24` plus [`SparseSdf::excess_bound`] (zero without propagation,
    /// where the bound is proven; with it, the excess term is empirical).
    pub fn error_bound(&self) -> f64 {
        INTERPOLATION_BOUND * self.h + self.max_distance * F32_ROUNDING + self.excess_bound()
    }

    /// The grid's box `(min, max)`.
    pub fn bounds(&self) -> (Point3<f64>, Point3<f64>) {
        let e = Vector3::from(self.dims.map(|n| (n - 1) as f64)) * self.h;
        (self.origin, self.origin + e)
    }

    fn value(&self, i: usize, j: usize, k: usize) -> f64 {
        let c = (k / BLOCK * self.cells[1] + j / BLOCK) * self.cells[0] + i / BLOCK;
        match self.index[c] {
            AIR => self.max_distance,
            GROUND => -self.max_distance,
            b => {
                let l = ((k % BLOCK) * BLOCK + j % BLOCK) * BLOCK + i % BLOCK;
                self.values[b as usize * BLOCK_POINTS + l] as f64
            }
        }
    }

    /// Trilinear signed distance at `q`, clamped to `[-T, T]` (positive on the air side);
    /// `None` outside the grid.
    pub fn distance(&self, q: &Point3<f64>) -> Option<f64> {
        self.distance_and_gradient(q).map(|(d, _)| d)
    }

    /// Distance and gradient of the trilinear interpolant at `q` (zero gradient where every
    /// corner reads `±T`); `None` outside the grid.
    pub fn distance_and_gradient(&self, q: &Point3<f64>) -> Option<(f64, Vector3<f64>)> {
        interpolate(&self.origin, self.h, self.dims, q, |i, j, k| {
            self.value(i, j, k)
        })
    }
}

/// The block grid's geometry, for the wavefront.
struct Grid {
    origin: Point3<f64>,
    h: f64,
    cells: [usize; 3],
}

/// A grid point's 6-neighbour across one face.
enum Neighbour {
    /// A point of an allocated block (`block * 512 + local`).
    Point(usize),
    /// The neighbour lies in the unallocated block cell `cell` at local position `local`.
    Unallocated { cell: usize, local: usize },
    /// Outside the grid's box.
    Outside,
}

const STEP: [usize; 3] = [1, BLOCK, BLOCK * BLOCK];

impl Grid {
    fn split(&self, c: usize) -> [usize; 3] {
        let n = self.cells;
        [c % n[0], (c / n[0]) % n[1], c / (n[0] * n[1])]
    }
    fn cell_id(&self, c: [usize; 3]) -> usize {
        (c[2] * self.cells[1] + c[1]) * self.cells[0] + c[0]
    }
    /// The world position of point `l` of the block at block coordinates `cc`.
    fn point(&self, cc: [u32; 3], l: usize) -> Point3<f64> {
        let cc = cc.map(|c| c as usize);
        let g = [l % BLOCK, (l / BLOCK) % BLOCK, l / (BLOCK * BLOCK)];
        self.origin + Vector3::from([0, 1, 2].map(|a| (cc[a] * BLOCK + g[a]) as f64)).scale(self.h)
    }
    /// The neighbour of grid point `v` (`block * 512 + local`) one step along `axis` (`up`: in
    /// the positive direction).
    fn neighbour(
        &self,
        index: &[u32],
        coords: &[[u32; 3]],
        v: usize,
        axis: usize,
        up: bool,
    ) -> Neighbour {
        let (b, l) = (v / BLOCK_POINTS, v % BLOCK_POINTS);
        let g = (l / STEP[axis]) % BLOCK;
        if up && g + 1 < BLOCK {
            return Neighbour::Point(v + STEP[axis]);
        }
        if !up && g > 0 {
            return Neighbour::Point(v - STEP[axis]);
        }
        let mut cc = coords[b].map(|c| c as usize);
        if up {
            if cc[axis] + 1 >= self.cells[axis] {
                return Neighbour::Outside;
            }
            cc[axis] += 1;
        } else {
            if cc[axis] == 0 {
                return Neighbour::Outside;
            }
            cc[axis] -= 1;
        }
        let face = if up { 0 } else { BLOCK - 1 };
        let local = l - g * STEP[axis] + face * STEP[axis];
        let cell = self.cell_id(cc);
        match index[cell] {
            nb if nb < UNKNOWN => Neighbour::Point(nb as usize * BLOCK_POINTS + local),
            _ => Neighbour::Unallocated { cell, local },
        }
    }
}

/// Site marker of an exact point (its value stays).
const EXACT_SITE: u32 = u32::MAX;
/// Site marker of a point no site has reached yet.
const NO_SITE: u32 = u32::MAX - 1;

/// Step 2a (module doc): carries the closest surface points outward from the exact band. Each
/// point beyond `T` takes the exact distance to the site (the closest surface point of an exact
/// boundary point) of the neighbour that reached it with the smallest distance, and that
/// neighbour's sign; a bucketed queue (buckets `h / 4` wide, Voxblox's bucketed priority
/// queue) processes points in increasing distance. A block cell is allocated when the wavefront
/// first reaches one of its points within `D` (at most `max_blocks` blocks in all). Points no
/// site reaches within `D` stay NaN (the sign floods set them to `±D`).
#[allow(clippy::too_many_arguments)]
fn propagate(
    mesh: &TriMesh,
    grid: &Grid,
    index: &mut [u32],
    block_cells: &mut Vec<usize>,
    values: &mut Vec<f32>,
    best_tri: &[u32],
    d_max: f64,
    max_blocks: usize,
) -> Result<(), SdfError> {
    let h = grid.h;
    // Queue entries are grid point indices below `SEED_FLAG`.
    let max_blocks = max_blocks.min((SEED_FLAG as usize - 1) / BLOCK_POINTS);
    let mut coords: Vec<[u32; 3]> = block_cells
        .iter()
        .map(|&c| grid.split(c).map(|x| x as u32))
        .collect();
    let mut site = vec![NO_SITE; values.len()];
    for (v, s) in site.iter_mut().zip(values.iter()) {
        if !s.is_nan() {
            *v = EXACT_SITE;
        }
    }
    // Seeds: exact points with a neighbour that is NaN or unallocated; their closest point is
    // the site.
    let seeds: Vec<(u32, Point3<f32>)> = {
        let (index, coords, values) = (&*index, &coords, &*values);
        (0..coords.len())
            .into_par_iter()
            .flat_map_iter(|b| {
                let mut out = Vec::new();
                for l in 0..BLOCK_POINTS {
                    let v = b * BLOCK_POINTS + l;
                    if values[v].is_nan() {
                        continue;
                    }
                    let open =
                        (0..6).any(
                            |k| match grid.neighbour(index, coords, v, k / 2, k % 2 == 1) {
                                Neighbour::Point(u) => values[u].is_nan(),
                                Neighbour::Unallocated { .. } => true,
                                Neighbour::Outside => false,
                            },
                        );
                    if open {
                        let q = grid.point(coords[b], l);
                        let cp = mesh.closest_on_triangle(best_tri[v] as usize, &q).point;
                        out.push((v as u32, cp.cast::<f32>()));
                    }
                }
                out.into_iter()
            })
            .collect()
    };
    let width = 0.25 * h;
    let n_buckets = (d_max / width).ceil() as usize + 2;
    let bucket = |d: f64| ((d / width) as usize).min(n_buckets - 1);
    let mut buckets: Vec<Vec<u32>> = vec![Vec::new(); n_buckets];
    for (k, &(v, _)) in seeds.iter().enumerate() {
        buckets[bucket(values[v as usize].abs() as f64)].push(k as u32 | SEED_FLAG);
    }
    let (seed_points, sites): (Vec<u32>, Vec<Point3<f32>>) = seeds.into_iter().unzip();
    let budget = MAX_RELAXATIONS_PER_POINT.saturating_mul(max_blocks * BLOCK_POINTS);
    // A new site must improve a point by more than this (so near-ties do not churn).
    let slack = RELAX_SLACK_VOXELS * h;
    let mut relaxations = 0usize;
    let mut cur = 0;
    // Each bucket is sorted when it is reached (descending, popped from the end: ascending grid
    // point order, for memory locality); entries pushed into the current bucket are popped next.
    buckets[0].par_sort_unstable_by(|a, b| b.cmp(a));
    while cur < n_buckets {
        let Some(e) = buckets[cur].pop() else {
            cur += 1;
            if cur < n_buckets {
                buckets[cur].par_sort_unstable_by(|a, b| b.cmp(a));
            }
            continue;
        };
        let (v, s) = if e & SEED_FLAG != 0 {
            let k = e & !SEED_FLAG;
            (seed_points[k as usize] as usize, k)
        } else {
            (e as usize, site[e as usize])
        };
        let sp = sites[s as usize].cast::<f64>();
        let air = values[v] >= 0.0;
        let qv = grid.point(coords[v / BLOCK_POINTS], v % BLOCK_POINTS);
        for k in 0..6 {
            let (axis, up) = (k / 2, k % 2 == 1);
            let mut q = qv;
            q[axis] += if up { h } else { -h };
            let d = (q - sp).norm();
            if d > d_max {
                continue;
            }
            let u = match grid.neighbour(index, &coords, v, axis, up) {
                Neighbour::Point(u) => u,
                Neighbour::Outside => continue,
                Neighbour::Unallocated { cell, local } => {
                    let nb = block_cells.len();
                    if nb >= max_blocks {
                        return Err(SdfError::TooManyBlocks {
                            blocks: nb + 1,
                            cap: max_blocks,
                        });
                    }
                    index[cell] = nb as u32;
                    block_cells.push(cell);
                    coords.push(grid.split(cell).map(|x| x as u32));
                    values.resize((nb + 1) * BLOCK_POINTS, f32::NAN);
                    site.resize((nb + 1) * BLOCK_POINTS, NO_SITE);
                    nb * BLOCK_POINTS + local
                }
            };
            if site[u] == EXACT_SITE || (site[u] != NO_SITE && d >= values[u].abs() as f64 - slack)
            {
                continue;
            }
            relaxations += 1;
            if relaxations > budget {
                return Err(SdfError::PropagationBudget {
                    relaxations,
                    points: values.len(),
                });
            }
            values[u] = if air { d as f32 } else { -(d as f32) };
            site[u] = s;
            buckets[bucket(d).max(cur)].push(u as u32);
        }
    }
    Ok(())
}

/// Marks a queue entry as a seed (its value is the seed's index, not a grid point's).
const SEED_FLAG: u32 = 1 << 31;

/// Step 2b for one block's values: every NaN point 6-connected inside the block to an exact
/// point takes that point's sign as `±tf`. `false` when the block has no exact point.
fn local_flood(v: &mut [f32], tf: f32) -> bool {
    let mut stack: Vec<usize> = (0..BLOCK_POINTS).filter(|&l| !v[l].is_nan()).collect();
    if stack.is_empty() {
        return false;
    }
    // Each point is pushed at most twice (once exact, once when its sign is set): bounded.
    while let Some(l) = stack.pop() {
        let s = if v[l] >= 0.0 { tf } else { -tf };
        let g = [l % BLOCK, (l / BLOCK) % BLOCK, l / (BLOCK * BLOCK)];
        for (axis, step) in [1, BLOCK, BLOCK * BLOCK].into_iter().enumerate() {
            for m in [
                (g[axis] > 0).then(|| l - step),
                (g[axis] + 1 < BLOCK).then(|| l + step),
            ]
            .into_iter()
            .flatten()
            {
                if v[m].is_nan() {
                    v[m] = s;
                    stack.push(m);
                }
            }
        }
    }
    true
}

impl SignedDistance for SparseSdf {
    fn signed_distance(&self, q: &Point3<f64>) -> Option<f64> {
        self.distance(q)
    }
    fn distance_gradient(&self, q: &Point3<f64>) -> Option<Vector3<f64>> {
        self.distance_and_gradient(q).map(|(_, g)| g)
    }
    /// The interpolant's exact first zero along the vertical (`sdf::ground_below_on_grid`).
    fn ground_below(
        &self,
        q: &Point3<f64>,
        _tolerance: f64,
    ) -> Result<Point3<f64>, crate::surface::DropError> {
        crate::sdf::ground_below_on_grid(self.origin.z, self.h, self.dims[2], q, |p| {
            self.distance(p)
        })
    }
}
