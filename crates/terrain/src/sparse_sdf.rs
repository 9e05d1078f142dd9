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
//!    triangle lies within `R` of its centre; that triangle joins the block's candidate list.
//!    Every triangle visits only the blocks whose centres lie in its bounding box grown by `R`
//!    (rayon over triangles). `R = T + r_b` (`r_b` the block's half-diagonal), or in **far
//!    mode** `R = D + r_b`: chosen when `D > T` and those grown boxes hold at most
//!    [`SparseSdfParams::max_far_pairs`] block centres in all (coarse meshes such as Paton's
//!    18-triangle ledge).
//! 2. **Exact values**: every grid point of an allocated block takes the smallest
//!    [`TriMesh::closest_on_triangle`] distance over candidates of its block (rayon over blocks).
//!    A point lies within `r_b` of its block's centre, so its closest triangle lies within
//!    `min + 2 r_b` of the centre (`min` the nearest candidate's distance to it). When that
//!    distance is within `R` (all those triangles are candidates; in far mode always enough: a
//!    point within `D` of the mesh has its closest triangle within `D + r_b` of the centre, and
//!    a value above `D` is not kept) and at most
//!    [`MAX_EXACT_CANDIDATES`] triangles lie that close, the block is **complete**: each point
//!    takes its exact distance from that list, kept out to `D` (NaN beyond `D`), the sign from
//!    its true closest feature's pseudo-normal. Otherwise the block takes the candidates within
//!    `T + r_b` of its centre: a point within `T` of the mesh has its closest triangle among them
//!    (it is within `r_b` of the centre), so every value `<= T` is exact; a larger value only
//!    proves `|d| > T`, and its pseudo-normal sign (from a triangle that need not be the
//!    closest) is not trusted: it is NaN. Values `<= T` are the same either way. Per point,
//!    the candidates whose face region (the prism over the triangle along its normal) holds it
//!    give their plane's signed distance (the triangle's exact one there); the others are
//!    skipped when a lower bound (`sqrt(pd^2 + e^2)`, `pd` off the plane and `e` beyond an edge's
//!    plane) exceeds the best so far, else take [`TriMesh::closest_on_triangle`]; a block lying
//!    wholly in a candidate's face region skips the per-point region test.
//!    2a. **Propagation** (when `D > T`, unless far mode left every block complete; Voxblox's
//!    `esdf_integrator` wavefront, here carrying sites as in Danielsson's vector propagation):
//!    the exact points next to a NaN point of a block that is not complete (or, outside far
//!    mode, next to an unallocated block; in far mode every point of one lies beyond `D`) are
//!    the seeds, each with its closest surface point as its *site*. A bucketed priority
//!    queue (buckets `h / 4` wide) processes points in increasing distance; a processed point
//!    offers its site to its 6-neighbours beyond `T`, which take it when it is closer than their
//!    own by more than [`RELAX_SLACK_VOXELS`] `h`, with the exact distance to that site and the
//!    processed point's sign. Outside far mode, blocks are allocated on demand where a point
//!    within `D` is reached (same block cap). Sign: two 6-adjacent points one of which is beyond `T >= 2 h` lie on one
//!    side of the surface, so the carried sign is exact. Each bucket is processed in rounds:
//!    the round's points compute their offers in parallel against the state at the round's
//!    start, then the offers are applied in a fixed order (ascending grid points), so the field
//!    is bit-identical whatever the thread count; every block keeps a table of the blocks across
//!    its six faces, so the inner loop reads no block index. At most
//!    [`MAX_RELAXATIONS_PER_POINT`] relaxations per grid point.
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
//! **Propagated** (`D > T`): values `<= T` are exact as above, and so is every value of a
//! complete block out to `D` (up to `f32` rounding; in far mode on a coarse mesh, most of the
//! field or all of it). A propagated value (wavefront) is the exact
//! distance from its grid point to a real surface point (its site, stored in `f32`), so it is
//! **never below** the exact distance (up to the site's `f32` rounding, a few micrometres on
//! scenes of tens of metres) and never above `D`; its sign is exact. How far above is **not
//! proven**: [`PROPAGATION_EXCESS_VOXELS`] `h` = 0.25 h is the empirical bound the property tests
//! assert (`crates/terrain/tests/all/sparse_sdf.rs`: seeded grid points in the band and out to `D`
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
//! The block index is a two-level page table (`block_index`): dense over pages of 8³ block
//! cells (4 bytes per page cell, at most `max_block_cells` of them: with the default 2^25, a box
//! of up to 2^34 block cells, about 1 km on each side at 5 cm), a page of 8³ entries (2 KiB)
//! only where a block is allocated; allocated blocks (2 KiB each, the band's and the wavefront's together) at
//! most `max_blocks`; candidate pairs at most [`MAX_CANDIDATES_PER_BLOCK`] per allowed block;
//! wavefront relaxations at most [`MAX_RELAXATIONS_PER_POINT`] per grid point. Each is a typed
//! [`SdfError`]. Far mode is taken only when its pairs (counted from the grown bounding boxes
//! before any is gathered) fit [`SparseSdfParams::max_far_pairs`], else the band's pairs are
//! gathered (no error). Build memory with propagation: 4 bytes of value, 4 of site index and 4 of
//! closest-triangle index per grid point, plus 12 bytes per seed (far mode on a coarse mesh:
//! 8 bytes per grid point, no wavefront).

use std::collections::VecDeque;

use nalgebra::{Point3, Vector3};
use rayon::prelude::*;

use crate::block_index::{AIR, BlockIndex, GROUND, PAGE, TopId, UNKNOWN};
use crate::mesh::{TriMesh, closest_point_triangle};
use crate::sdf::{
    GridField, INTERPOLATION_BOUND, SdfError, SignBox, interpolate, padded_grid, saturating_count,
};
use crate::surface::SignedDistance;

/// Grid points per block side.
pub const BLOCK: usize = 8;
const BLOCK_POINTS: usize = BLOCK * BLOCK * BLOCK;
/// Points per axis of a stored block: its [`BLOCK`] points and one more, a copy of the first
/// point of the next block (the apron), so that every cell whose lowest corner lies in the block
/// has its eight corners in it.
const PADDED: usize = BLOCK + 1;
/// Stored values per allocated block.
const PADDED_POINTS: usize = PADDED * PADDED * PADDED;
/// `log2 BLOCK`: the wavefront steps between points with shifts.
const BLOCK_BITS: usize = 3;
const _: () = assert!(BLOCK == 1 << BLOCK_BITS);

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
/// the exact distance), and the property tests (`crates/terrain/tests/all/sparse_sdf.rs`, Paton's
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

/// A block whose complete candidate list (the triangles within `min + 2 r_b` of its centre,
/// `min` the nearest one's distance and `r_b` the block's half-diagonal) holds at most this many
/// triangles takes exact distances at all its points out to `D` (a **complete** block: no
/// wavefront inside it). Each point costs one plane test per candidate and a closest point on
/// the few triangles that pass it; a longer list (fine meshes) leaves the block to the band and
/// the wavefront.
pub const MAX_EXACT_CANDIDATES: usize = 16;

/// Default budget on the (block cell, triangle) pairs of **far mode**
/// ([`SparseSdfParams::max_far_pairs`]): when the triangles' bounding
/// boxes grown by `D + r_b` hold at most this many block centres in all (a coarse mesh such as
/// Paton's 18-triangle ledge), candidates are gathered out to `D + r_b` instead of `T + r_b`, so
/// that blocks beyond the band can be complete; above it (fine meshes, whose far blocks would
/// have long lists anyway) only the band's pairs are gathered. 16 bytes per pair: 64 MiB at the
/// budget.
pub const DEFAULT_MAX_FAR_PAIRS: usize = 1 << 22;

/// Default cap on allocated blocks (2 KiB each: 512 MiB at the cap).
pub const DEFAULT_MAX_BLOCKS: usize = 262_144;

/// Default cap on the top-level cells of the block index (each a page of 8³ block cells, 4 bytes
/// each: 128 MiB at the cap, a box of up to 2^34 block cells).
pub const DEFAULT_MAX_BLOCK_CELLS: usize = 1 << 25;

/// Cap on (block, candidate triangle) pairs per allowed block: at most
/// `MAX_CANDIDATES_PER_BLOCK * max_blocks` pairs are kept.
pub const MAX_CANDIDATES_PER_BLOCK: usize = 64;

/// `2^-24`: the relative rounding of a stored `f32` value.
pub const F32_ROUNDING: f64 = 5.960_464_477_539_063e-8;

/// How to build a [`SparseSdf`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SparseSdfParams {
    /// Grid spacing `h`, metres (`> 0`, finite).
    pub resolution: f64,
    /// Truncation distance `T`, metres (`>= 2 h`: the sign flood needs `T > sqrt 3 h`): the exact
    /// band.
    pub truncation: f64,
    /// Propagation distance `D >= T`, metres: beyond the exact band values are exact in the
    /// complete blocks of far mode, elsewhere the closest surface points are carried outward by
    /// a wavefront up to `D`; values beyond are `±D`. `D = T`: no propagation (a truncated
    /// field).
    pub max_distance: f64,
    /// Margin added around the mesh's bounding box, metres (`>= 0`).
    pub margin: f64,
    /// Cap on allocated blocks.
    pub max_blocks: usize,
    /// Cap on the top-level cells of the block index (pages of 8³ block cells over the grid's
    /// box, 4 bytes each): the only cap on the box's size.
    pub max_block_cells: usize,
    /// Budget of far mode's (block cell, triangle) pairs ([`DEFAULT_MAX_FAR_PAIRS`]; module
    /// doc, step 1): far mode is chosen when its pairs would not exceed it. `0` never chooses it
    /// (the band and the wavefront only, as for a fine mesh).
    pub max_far_pairs: usize,
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
            max_far_pairs: DEFAULT_MAX_FAR_PAIRS,
        }
    }
}

/// A sparse truncated signed distance field on the grid `origin + (i, j, k) h`. Two fields are
/// equal when their grids, block layouts and every stored value are bit-identical.
#[derive(Debug, Clone, PartialEq)]
pub struct SparseSdf {
    origin: Point3<f64>,
    h: f64,
    truncation: f64,
    max_distance: f64,
    dims: [usize; 3],
    /// Per block cell: the allocated block's number, or [`AIR`] / [`GROUND`].
    index: BlockIndex,
    /// [`PADDED_POINTS`] values per allocated block, `x` fastest: its points and its apron
    /// ([`PADDED`]).
    values: Vec<f32>,
    /// Per allocated block: the least and the greatest of its stored values, apron included
    /// (derived from `values`; the grid walks' [`SignBox`]es).
    ranges: Vec<[f32; 2]>,
}

fn bad(name: &'static str, value: f64, why: &'static str) -> SdfError {
    SdfError::BadParameter { name, value, why }
}

/// A node of the sign flood: a grid point of an allocated block (`block * 512 + local`), an
/// unallocated block cell of a page, or a uniform top-level cell of the block index.
#[derive(Clone, Copy)]
enum Node {
    Point(usize),
    Cell(usize),
    Top(TopId),
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
        // The cap is on the index's top level (pages of 8^3 block cells); block coordinates are
        // `u32` (at most 2^32 - 1 block cells per axis, far beyond any top level that fits).
        let ft = BlockIndex::top_counts(fc);
        let total = ft[0] * ft[1] * ft[2];
        if !(total.is_finite()
            && total <= p.max_block_cells as f64
            && fc.iter().all(|&n| n < u32::MAX as f64))
        {
            return Err(SdfError::TooManyBlockCells {
                nx: saturating_count(ft[0]),
                ny: saturating_count(ft[1]),
                nz: saturating_count(ft[2]),
                cap: p.max_block_cells,
            });
        }
        let dims = fp.map(|n| n as usize);
        let cells = fc.map(|n| n as usize);
        let cell_id = |c: [usize; 3]| (c[2] * cells[1] + c[1]) * cells[0] + c[0];
        let b = BLOCK as f64;
        let half = 0.5 * (b - 1.0);
        let r_b = half * h * 3f64.sqrt();
        // Rounding slack on the candidate tests (relative to the reach).
        let grow = 1.0 + 1e-9;
        let band_reach = (t_max + r_b) * grow;
        let centre =
            |c: [usize; 3]| origin + Vector3::from(c.map(|v| v as f64 * b + half)).scale(h);
        // The block cells whose centres lie in triangle `t`'s bounding box grown by `reach`.
        let block_ranges = |t: usize, reach: f64| {
            let [a, bb, c] = mesh.corners(t);
            let tlo = a.inf(&bb).inf(&c) - Vector3::repeat(reach);
            let thi = a.sup(&bb).sup(&c) + Vector3::repeat(reach);
            [0, 1, 2].map(|axis| {
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
            })
        };
        // Far mode (module doc, step 1): candidates out to `D + r_b` when their count stays
        // under the budget (a coarse mesh), so that short lists give exact values out to `D`.
        let far_reach = (d_max + r_b) * grow;
        let far = d_max > t_max && {
            let estimate: f64 = (0..mesh.triangles().len())
                .map(|t| {
                    block_ranges(t, far_reach)
                        .iter()
                        .map(|r| r.len() as f64)
                        .product::<f64>()
                })
                .sum();
            estimate <= p.max_far_pairs as f64
        };
        let reach = if far { far_reach } else { band_reach };

        // 1. Candidate (block cell, triangle) pairs.
        let mut pairs: Vec<(usize, u32)> = (0..mesh.triangles().len())
            .into_par_iter()
            .flat_map_iter(|t| {
                let [a, bb, c] = mesh.corners(t);
                let [rx, ry, rz] = block_ranges(t, reach);
                let mut out = Vec::new();
                for k in rz {
                    for j in ry.clone() {
                        for i in rx.clone() {
                            let q = centre([i, j, k]);
                            let (cp, _) = closest_point_triangle(&q, &a, &bb, &c);
                            if (q - cp).norm() <= reach {
                                out.push((cell_id([i, j, k]), t as u32));
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
                block_cells.push(c);
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
        let split = |c: usize| {
            [
                c % cells[0],
                (c / cells[0]) % cells[1],
                c / (cells[0] * cells[1]),
            ]
        };
        let mut index = BlockIndex::new(cells, UNKNOWN);
        for (k, &c) in block_cells.iter().enumerate() {
            index.set(split(c), k as u32);
        }

        // 2. Exact values; NaN marks "farther than the block's exact reach, sign unknown" (`T`
        // in a block with the band's candidates, `D` in a complete block). The plane test's
        // slack covers the rounding of the unit normal (relative to the scene's size).
        let plane_slack = 1e-9 * (ext.norm() + d_max);
        // Margin of the face-region test: a block must lie this far inside each edge's plane.
        let prism_slack = 1e-9 * (ext.norm() + d_max);
        let mut values = vec![0f32; nb * BLOCK_POINTS];
        // The closest triangle of every exact point (the wavefront's sites).
        let mut best_tri = vec![u32::MAX; nb * BLOCK_POINTS];
        // Per block: whether its candidates are complete (every value exact out to `D`, NaN
        // only beyond `D`).
        let complete: Vec<bool> = values
            .par_chunks_mut(BLOCK_POINTS)
            .zip(best_tri.par_chunks_mut(BLOCK_POINTS))
            .enumerate()
            .map(|(k, (out, tri_out))| {
                let cc = split(block_cells[k]);
                // Each candidate with a point and the unit normal of its plane: the distance to
                // the plane is a lower bound on the distance to the triangle, so a candidate
                // whose plane is farther than the best so far (or than the reach) is skipped.
                // Nearest to the block's centre first (ties by triangle): the first candidate
                // is then usually a point's closest, and the plane test skips most others.
                let c0 = centre(cc);
                let mut cand: Vec<(f64, usize, Point3<f64>, Vector3<f64>)> = pairs
                    [starts[k]..starts[k + 1]]
                    .iter()
                    .map(|&(_, t)| {
                        let t = t as usize;
                        let [a, b, c] = mesh.corners(t);
                        let (cp, _) = closest_point_triangle(&c0, &a, &b, &c);
                        ((c0 - cp).norm(), t, a, mesh.face_normal(t))
                    })
                    .collect();
                cand.sort_unstable_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
                // Every point lies within `r_b` of the centre, so its closest triangle is within
                // `min + 2 r_b` of the centre: that prefix is complete when the pairs reached
                // that far; in far mode it is complete for every point within `D` of the mesh
                // anyway (that point's closest triangle lies within `D + r_b` of the centre).
                let full = (cand[0].0 + 2.0 * r_b) * grow;
                let n_full = cand.partition_point(|c| c.0 <= full);
                let (cand, reach_k, complete) =
                    if (far || full <= reach) && n_full <= MAX_EXACT_CANDIDATES {
                        (&cand[..n_full], d_max, true)
                    } else {
                        let n_band = cand.partition_point(|c| c.0 <= band_reach);
                        (&cand[..n_band], t_max, false)
                    };
                // Per candidate: its face region (the prism over it along its normal, where the
                // closest point on it is the projection and the signed distance is the plane's)
                // and whether the block's points all lie in it (then no per-point test).
                let lo = origin + Vector3::from(cc.map(|c| (c * BLOCK) as f64)).scale(h);
                let span = ((BLOCK - 1) as f64) * h;
                let corners: [Point3<f64>; 8] = std::array::from_fn(|k| {
                    lo + Vector3::new(
                        (k & 1) as f64 * span,
                        ((k >> 1) & 1) as f64 * span,
                        ((k >> 2) & 1) as f64 * span,
                    )
                });
                let regions: Vec<(Option<FaceRegion>, bool)> = cand
                    .iter()
                    .map(|&(_, t, _, n)| {
                        let r = FaceRegion::new(&mesh.corners(t), &n);
                        let whole =
                            r.is_some_and(|r| corners.iter().all(|c| r.margin(c) >= prism_slack));
                        (r, whole)
                    })
                    .collect();
                // Per candidate and point: a lower bound on the distance to the triangle, or
                // infinity when the point lies in its face region (its distance is then known).
                let mut lower = vec![0.0; cand.len()];
                // Per candidate: a lower bound on its distance from every point of the block
                // (a point lies within `r_b` of the centre), less the rounding slack. The
                // candidates are sorted by it, so once one exceeds the best distance so far
                // (which only falls), it and every later candidate can neither be closer nor
                // tie: the scans below stop there, with the same answer as a full scan.
                let block_lower: Vec<f64> = cand.iter().map(|c| c.0 - r_b - plane_slack).collect();
                for (l, (slot, tri_slot)) in out.iter_mut().zip(tri_out.iter_mut()).enumerate() {
                    let g = [l % BLOCK, (l / BLOCK) % BLOCK, l / (BLOCK * BLOCK)];
                    let q = origin
                        + Vector3::from([0, 1, 2].map(|a| (cc[a] * BLOCK + g[a]) as f64)).scale(h);
                    let mut best = f64::INFINITY;
                    let mut best_t = u32::MAX;
                    // First the face regions: there the plane's signed distance is the
                    // triangle's (its sign the face normal's, the pseudo-normal there). Outside,
                    // `q` lies a distance `e` beyond an edge's plane and `pd` off the triangle's
                    // plane, two orthogonal directions: the triangle is at least
                    // `sqrt(pd^2 + e^2)` away.
                    let mut stop = cand.len();
                    for (i, (((_, t, a, n), (region, whole)), lb)) in
                        cand.iter().zip(&regions).zip(lower.iter_mut()).enumerate()
                    {
                        if block_lower[i] > best.abs() + plane_slack {
                            stop = i;
                            break;
                        }
                        let pd = (q - a).dot(n);
                        let e = match region {
                            _ if *whole => 0.0,
                            Some(r) => r.margin(&q),
                            None => f64::NEG_INFINITY,
                        };
                        if e >= 0.0 {
                            *lb = f64::INFINITY;
                            if pd.abs() < best.abs() {
                                best = pd;
                                best_t = *t as u32;
                            }
                        } else if e.is_finite() {
                            *lb = (pd * pd + e * e).sqrt();
                        } else {
                            *lb = pd.abs();
                        }
                    }
                    // Then the edges and corners of the triangles that may still be closer.
                    for (((_, t, _, _), &lb), &lb_block) in
                        cand[..stop].iter().zip(&lower).zip(&block_lower)
                    {
                        if lb_block > best.abs().min(reach_k) + plane_slack {
                            break;
                        }
                        if lb > best.abs().min(reach_k) + plane_slack {
                            continue;
                        }
                        let d = mesh.closest_on_triangle(*t, &q).signed_distance;
                        if d.abs() < best.abs() {
                            best = d;
                            best_t = *t as u32;
                        }
                    }
                    if best.abs() <= reach_k {
                        *slot = best as f32;
                        *tri_slot = best_t;
                    } else {
                        *slot = f32::NAN;
                    }
                }
                complete
            })
            .collect();

        drop(pairs);
        // 2a. The wavefront beyond the exact values, out to D: needed unless every block is
        // complete in far mode (then no point within `D` lies outside a complete block).
        if d_max > t_max && !(far && complete.iter().all(|&c| c)) {
            let grid = Grid { origin, h, cells };
            propagate(
                mesh,
                &grid,
                &mut index,
                &mut block_cells,
                &mut values,
                &best_tri,
                &complete,
                far,
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
            // In place: block `k`'s values move down to the `kept`-th slot (`kept <= k`).
            let mut kept = 0;
            for (k, &keep) in exact.iter().enumerate() {
                let c = block_cells[k];
                if keep {
                    index.set(split(c), kept as u32);
                    block_cells[kept] = c;
                    if kept != k {
                        values.copy_within(
                            k * BLOCK_POINTS..(k + 1) * BLOCK_POINTS,
                            kept * BLOCK_POINTS,
                        );
                    }
                    kept += 1;
                } else {
                    index.set(split(c), UNKNOWN);
                }
            }
            values.truncate(kept * BLOCK_POINTS);
            block_cells.truncate(kept);
        }
        let block_cells = block_cells;

        // 3. The sign flood across blocks: the points step 2b did not reach (a region of a block
        // cut off from its exact points inside the block) and the unallocated cells.
        // The nodes behind block cell `c2` seen across face `(axis, up)`: the facing point of a
        // point at local position `local`, or all facing points for a whole cell's face, when
        // `c2` holds a block; else `c2` itself, or its uniform top-level cell.
        let behind = |index: &BlockIndex,
                      c2: [usize; 3],
                      axis: usize,
                      up: bool,
                      local: Option<[usize; 3]>,
                      f: &mut dyn FnMut(Node)| {
            let blk = index.get(c2);
            if blk >= UNKNOWN {
                let t = index.top_id(c2);
                if index.uniform(t).is_some() {
                    f(Node::Top(t));
                } else {
                    f(Node::Cell(cell_id(c2)));
                }
                return;
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
        };
        let neighbours = |index: &BlockIndex, n: Node, f: &mut dyn FnMut(Node)| {
            for axis in 0..3 {
                for up in [false, true] {
                    match n {
                        Node::Point(i) => {
                            let l = i % BLOCK_POINTS;
                            let g = [l % BLOCK, (l / BLOCK) % BLOCK, l / (BLOCK * BLOCK)];
                            if let Some(g2) = step_cell(g, [BLOCK; 3], axis, up) {
                                let l2 = (g2[2] * BLOCK + g2[1]) * BLOCK + g2[0];
                                f(Node::Point(i - l + l2));
                            } else if let Some(c2) =
                                step_cell(split(block_cells[i / BLOCK_POINTS]), cells, axis, up)
                            {
                                behind(index, c2, axis, up, Some(g), f);
                            }
                        }
                        Node::Cell(c) => {
                            if let Some(c2) = step_cell(split(c), cells, axis, up) {
                                behind(index, c2, axis, up, None, f);
                            }
                        }
                        Node::Top(t) => {
                            let Some(t2) = step_cell(index.top_coords(t), index.tops(), axis, up)
                            else {
                                continue;
                            };
                            let t2 = (t2[2] * index.tops()[1] + t2[1]) * index.tops()[0] + t2[0];
                            if index.uniform(t2).is_some() {
                                f(Node::Top(t2));
                                continue;
                            }
                            // The cells of page `t2` facing `t`, and what lies behind them.
                            let face = 2 * axis + usize::from(!up);
                            for c2 in index.face_cells(t2, face) {
                                behind(index, c2, axis, up, None, f);
                            }
                        }
                    }
                }
            }
        };
        // `Some(true)` air, `Some(false)` ground, `None` unknown.
        let sign = |index: &BlockIndex, values: &[f32], n: Node| {
            let e = match n {
                Node::Point(i) => {
                    let v = values[i];
                    return (!v.is_nan()).then_some(v >= 0.0);
                }
                Node::Cell(c) => index.get(split(c)),
                Node::Top(t) => index.uniform(t).unwrap_or(UNKNOWN),
            };
            match e {
                AIR => Some(true),
                GROUND => Some(false),
                _ => None,
            }
        };
        let set = |index: &mut BlockIndex, values: &mut [f32], n: Node, air: bool| {
            let e = if air { AIR } else { GROUND };
            match n {
                Node::Point(i) => values[i] = if air { tf } else { -tf },
                Node::Cell(c) => index.set(split(c), e),
                Node::Top(t) => index.set_uniform(t, e),
            }
        };
        // Seeds: unknown nodes with a known neighbour in the initial state (assigned after the
        // scan, so that the fronts advance evenly from every exact point).
        let mut seeds: Vec<(Node, bool)> = Vec::new();
        let mut unknown_nodes: Vec<Node> = values
            .par_iter()
            .enumerate()
            .filter(|(_, v)| v.is_nan())
            .map(|(i, _)| Node::Point(i))
            .collect();
        unknown_nodes.extend(index.paged_cells(UNKNOWN).map(|c| Node::Cell(cell_id(c))));
        unknown_nodes.extend(index.uniform_tops(UNKNOWN).map(Node::Top));
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
        values
            .par_iter_mut()
            .filter(|v| v.is_nan())
            .for_each(|v| *v = tf);
        index.replace_unknown(AIR);
        let values = pad_blocks(&index, cells, &block_cells, &values, tf);
        let value_ranges = stored_ranges(&values);
        Ok(SparseSdf {
            origin,
            h,
            truncation: t_max as f32 as f64,
            max_distance: tf as f64,
            dims,
            index,
            values,
            ranges: value_ranges,
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
        self.values.len() / PADDED_POINTS
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
        match self.index.get([i / BLOCK, j / BLOCK, k / BLOCK]) {
            AIR => self.max_distance,
            GROUND => -self.max_distance,
            b => {
                let l = ((k % BLOCK) * PADDED + j % BLOCK) * PADDED + i % BLOCK;
                self.values[b as usize * PADDED_POINTS + l] as f64
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
        interpolate(&self.origin, self.h, self.dims, q, |c| self.cell_corners(c))
    }

    /// The corner values of the cell whose lowest corner is `[i, j, k]`, in the order of
    /// `sdf::trilinear`: one index lookup in an allocated block (its apron holds the corners
    /// past its last point) and in the inside of an unallocated one, else one per corner.
    fn cell_corners(&self, [i, j, k]: [usize; 3]) -> [f64; 8] {
        let inner = i % BLOCK + 1 < BLOCK && j % BLOCK + 1 < BLOCK && k % BLOCK + 1 < BLOCK;
        match self.index.get([i / BLOCK, j / BLOCK, k / BLOCK]) {
            AIR if inner => [self.max_distance; 8],
            GROUND if inner => [-self.max_distance; 8],
            AIR | GROUND => crate::sdf::corners_by_value([i, j, k], |i, j, k| self.value(i, j, k)),
            b => {
                let l = ((k % BLOCK) * PADDED + j % BLOCK) * PADDED + i % BLOCK;
                let v = &self.values[b as usize * PADDED_POINTS + l..];
                let (y, z) = (PADDED, PADDED * PADDED);
                [0, 1, y, y + 1, z, z + 1, z + y, z + y + 1].map(|o| v[o] as f64)
            }
        }
    }

    /// The [`SignBox`] around cell `c`: the cells of `c`'s allocated block (their corners are
    /// its stored values, apron included), or those whose corners all lie in `c`'s unallocated
    /// block or uniform top-level page, when every value there has one strict sign; `None` for
    /// a cell of an unallocated block with corners beyond it and for a block holding both signs
    /// (or a zero).
    fn cell_sign_box(&self, c: [usize; 3]) -> Option<SignBox> {
        let b = c.map(|x| x / BLOCK);
        if let Some(e) = self.index.uniform(self.index.top_id(b)) {
            let span = PAGE * BLOCK;
            if let Some(bx) = self.uniform_box(c, span, e) {
                return Some(bx);
            }
        }
        match self.index.get(b) {
            e @ (AIR | GROUND) => self
                .uniform_box(c, BLOCK, e)
                .or_else(|| self.straddling_box(c, e == AIR)),
            n => {
                let positive = self.block_sign(n)?;
                // The apron holds the corners at local `BLOCK`: every cell of the block.
                let lo = c.map(|x| x - x % BLOCK);
                let hi = [0, 1, 2].map(|a| (lo[a] + BLOCK - 1).min(self.dims[a] - 2));
                Some(SignBox { lo, hi, positive })
            }
        }
    }

    /// The strict sign of every value of the block cell holding entry `e`, `None` when it holds
    /// both signs or a zero.
    fn block_sign(&self, e: u32) -> Option<bool> {
        match e {
            AIR => Some(true),
            GROUND => Some(false),
            n => {
                let [lo, hi] = self.ranges[n as usize];
                if lo > 0.0 {
                    Some(true)
                } else if hi < 0.0 {
                    Some(false)
                } else {
                    None
                }
            }
        }
    }

    /// Cell `c` of an unallocated block (of sign `positive`) whose corners reach into the next
    /// blocks: a box of that one cell when every block cell its corners lie in has the sign.
    fn straddling_box(&self, c: [usize; 3], positive: bool) -> Option<SignBox> {
        let far = c.map(|x| (x + 1) / BLOCK);
        let near = c.map(|x| x / BLOCK);
        for z in near[2]..=far[2] {
            for y in near[1]..=far[1] {
                for x in near[0]..=far[0] {
                    if self.block_sign(self.index.get([x, y, z])) != Some(positive) {
                        return None;
                    }
                }
            }
        }
        Some(SignBox {
            lo: c,
            hi: c,
            positive,
        })
    }

    /// The box of an unallocated block or page of side `span` cells with entry `e`.
    fn uniform_box(&self, c: [usize; 3], span: usize, e: u32) -> Option<SignBox> {
        // `D > 0`: air reads `+D`, ground `-D`.
        self.cell_box(c, span, e == AIR)
    }

    /// The cells of the aligned cube of `span` grid points holding cell `c` whose corners all
    /// lie in the cube, `None` when `c` is not one of them.
    fn cell_box(&self, c: [usize; 3], span: usize, positive: bool) -> Option<SignBox> {
        let lo = c.map(|x| x - x % span);
        let last = [0, 1, 2].map(|a| (lo[a] + span - 2).min(self.dims[a] - 2));
        (0..3).all(|a| c[a] <= last[a]).then_some(SignBox {
            lo,
            hi: last,
            positive,
        })
    }
}

/// The cell one step along `axis` (`up`: in the positive direction) from `c` in a grid of `n`
/// cells per axis; `None` past the grid's end.
fn step_cell(c: [usize; 3], n: [usize; 3], axis: usize, up: bool) -> Option<[usize; 3]> {
    let mut c2 = c;
    if up {
        if c[axis] + 1 >= n[axis] {
            return None;
        }
        c2[axis] += 1;
    } else {
        if c[axis] == 0 {
            return None;
        }
        c2[axis] -= 1;
    }
    Some(c2)
}

/// The block grid's geometry, for the wavefront.
struct Grid {
    origin: Point3<f64>,
    h: f64,
    cells: [usize; 3],
}

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
    /// The block cell across face `f` (`2 axis + up`) of the cell at `cc`; `None` outside the
    /// grid's box.
    fn across(&self, cc: [u32; 3], f: usize) -> Option<usize> {
        step_cell(cc.map(|x| x as usize), self.cells, f / 2, f % 2 == 1).map(|c| self.cell_id(c))
    }
}

/// Site marker of an exact point (its value stays).
const EXACT_SITE: u32 = u32::MAX;
/// Site marker of a point no site has reached yet.
const NO_SITE: u32 = u32::MAX - 1;
/// Face-table marker: the block cell across the face is unallocated.
const NO_BLOCK: u32 = u32::MAX;
/// Face-table marker: across the face lies the grid box's boundary.
const OUTSIDE: u32 = u32::MAX - 1;
/// Queue entries per parallel work item of a wavefront round (fixed, so that the rounds' output
/// order does not depend on the thread count).
const ROUND_CHUNK: usize = 2048;

/// The allocated blocks as the wavefront sees them: block coordinates and, per block and face
/// (`2 axis + up`), the block across it ([`NO_BLOCK`], [`OUTSIDE`]), kept current as blocks are
/// allocated, so that the inner loop never consults the block index.
struct Blocks {
    coords: Vec<[u32; 3]>,
    across: Vec<[u32; 6]>,
}

impl Blocks {
    /// The face table of the block at `cc` from the block index.
    fn faces(grid: &Grid, index: &BlockIndex, cc: [u32; 3]) -> [u32; 6] {
        std::array::from_fn(
            |f| match grid.across(cc, f).map(|c| index.get(grid.split(c))) {
                None => OUTSIDE,
                Some(b) if b < UNKNOWN => b,
                Some(_) => NO_BLOCK,
            },
        )
    }
}

/// A grid point's state in the wavefront: its value and its site (an index into the sites,
/// [`EXACT_SITE`] or [`NO_SITE`]).
#[derive(Clone, Copy)]
struct Pt {
    value: f32,
    site: u32,
}

/// A site offered to a grid point by a processed neighbour: the target (`block * 512 + local`
/// for an allocated block; for an unallocated one, the source block, the face and the local
/// position across it), the site and the signed exact distance to it.
#[derive(Clone, Copy)]
struct Offer {
    target: u32,
    face: u8,
    local: u16,
    site: u32,
    value: f64,
}

/// Step 2a (module doc): carries the closest surface points outward from the exact band. Each
/// point beyond `T` takes the exact distance to the site (the closest surface point of an exact
/// boundary point) of a neighbour that offers it a smaller distance (by more than the slack),
/// and that neighbour's sign; a bucketed queue (buckets `h / 4` wide, Voxblox's bucketed
/// priority queue) processes points in increasing distance. A bucket is processed in
/// **rounds**: every entry of the round computes its offers in parallel against the state at
/// the round's start (offers that cannot improve are dropped there), then the offers are applied
/// in the entries' order (sorted grid points), each re-checked against the current state;
/// improved points join their bucket (the current one at the earliest) for a later round. The
/// result is therefore independent of the thread count. A block cell is allocated when an offer
/// within `D` reaches one of its points (at most `max_blocks` blocks in all). Points no site
/// reaches within `D` stay NaN (the sign floods set them to `±D`).
#[allow(clippy::too_many_arguments)]
fn propagate(
    mesh: &TriMesh,
    grid: &Grid,
    index: &mut BlockIndex,
    block_cells: &mut Vec<usize>,
    field: &mut Vec<f32>,
    best_tri: &[u32],
    complete: &[bool],
    far: bool,
    d_max: f64,
    max_blocks: usize,
) -> Result<(), SdfError> {
    let h = grid.h;
    // Grid point indices are u32.
    let max_blocks = max_blocks.min(NO_SITE as usize / BLOCK_POINTS);
    let coords: Vec<[u32; 3]> = block_cells
        .iter()
        .map(|&c| grid.split(c).map(|x| x as u32))
        .collect();
    let across: Vec<[u32; 6]> = {
        let index = &*index;
        coords
            .par_iter()
            .map(|&cc| Blocks::faces(grid, index, cc))
            .collect()
    };
    let mut blocks = Blocks { coords, across };
    // Value and site side by side: the inner loop's reads of a point cost one cache line.
    // A complete block's points are final (NaN there: beyond `D`).
    let mut pts: Vec<Pt> = field
        .par_iter()
        .enumerate()
        .map(|(v, &value)| Pt {
            value,
            site: if value.is_nan() && !complete[v / BLOCK_POINTS] {
                NO_SITE
            } else {
                EXACT_SITE
            },
        })
        .collect();
    // The grid point across face `f` of point `v`: `Ok(u)` in an allocated block, `Err(Some(l))`
    // at local position `l` of an unallocated block, `Err(None)` outside the box.
    let step = |blocks: &Blocks, v: usize, f: usize| -> Result<usize, Option<usize>> {
        let (axis, up) = (f / 2, f % 2 == 1);
        let l = v % BLOCK_POINTS;
        // Shifts, not divisions by the axis's stride (the axis is known only at run time).
        let shift = BLOCK_BITS * axis;
        let stride = 1 << shift;
        let g = (l >> shift) & (BLOCK - 1);
        if up && g + 1 < BLOCK {
            return Ok(v + stride);
        }
        if !up && g > 0 {
            return Ok(v - stride);
        }
        let face = if up { 0 } else { BLOCK - 1 };
        let local = l - g * stride + face * stride;
        match blocks.across[v / BLOCK_POINTS][f] {
            OUTSIDE => Err(None),
            NO_BLOCK => Err(Some(local)),
            nb => Ok(nb as usize * BLOCK_POINTS + local),
        }
    };
    // Seeds: exact points with a neighbour that no site has reached (a NaN point of a block
    // that is not complete, or an unallocated cell unless in far mode, where every point of an
    // unallocated cell lies beyond `D`); their closest point is the site.
    let seeds: Vec<(u32, Point3<f32>)> = {
        let (blocks, pts) = (&blocks, &pts);
        (0..blocks.coords.len())
            .into_par_iter()
            .flat_map_iter(|b| {
                let mut out = Vec::new();
                for l in 0..BLOCK_POINTS {
                    let v = b * BLOCK_POINTS + l;
                    if pts[v].value.is_nan() {
                        continue;
                    }
                    let open = (0..6).any(|f| match step(blocks, v, f) {
                        Ok(u) => pts[u].site == NO_SITE,
                        Err(local) => local.is_some() && !far,
                    });
                    if open {
                        let q = grid.point(blocks.coords[b], l);
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
    // Queue entries: `point << 32 | site`.
    let mut buckets: Vec<Vec<u64>> = vec![Vec::new(); n_buckets];
    for (k, &(v, _)) in seeds.iter().enumerate() {
        buckets[bucket(pts[v as usize].value.abs() as f64)].push((v as u64) << 32 | k as u64);
    }
    let sites: Vec<Point3<f32>> = seeds.into_iter().map(|(_, s)| s).collect();
    let budget = MAX_RELAXATIONS_PER_POINT.saturating_mul(max_blocks * BLOCK_POINTS);
    // A new site must improve a point by more than this (so near-ties do not churn).
    let slack = RELAX_SLACK_VOXELS * h;
    let mut relaxations = 0usize;
    // Whether the distance `d` improves on point `u`'s current state.
    let improves = |pts: &[Pt], u: usize, d: f64| {
        let p = pts[u];
        p.site == NO_SITE || (p.site != EXACT_SITE && d < p.value.abs() as f64 - slack)
    };
    // The same on squared distances (no square root for the offers it rejects).
    let improves_sq = |pts: &[Pt], u: usize, d2: f64| {
        let p = pts[u];
        let lim = p.value.abs() as f64 - slack;
        p.site == NO_SITE || (p.site != EXACT_SITE && lim > 0.0 && d2 < lim * lim)
    };
    let d_max2 = d_max * d_max;
    for cur in 0..n_buckets {
        // Rounds: each round's entries are pushed by relaxations of the previous round, so the
        // rounds are bounded by the relaxation budget.
        loop {
            let mut entries = std::mem::take(&mut buckets[cur]);
            if entries.is_empty() {
                break;
            }
            // Ascending grid points (memory locality); equal entries are one.
            entries.par_sort_unstable();
            entries.dedup();
            let offers: Vec<Vec<Offer>> = {
                let (blocks, pts, sites) = (&blocks, &pts, &sites);
                entries
                    .par_chunks(ROUND_CHUNK)
                    .map(|chunk| {
                        let mut out = Vec::new();
                        for &e in chunk {
                            let (v, s) = ((e >> 32) as usize, e as u32);
                            // Stale: the point has taken a better site since (that entry is
                            // processed in its own right).
                            let pv = pts[v];
                            if pv.site != EXACT_SITE && pv.site != s {
                                continue;
                            }
                            let sp = sites[s as usize].cast::<f64>();
                            let sign = if pv.value >= 0.0 { 1.0 } else { -1.0 };
                            let b = v / BLOCK_POINTS;
                            let qv = grid.point(blocks.coords[b], v % BLOCK_POINTS);
                            for f in 0..6 {
                                let (axis, up) = (f / 2, f % 2 == 1);
                                let mut q = qv;
                                q[axis] += if up { h } else { -h };
                                let d2 = (q - sp).norm_squared();
                                if d2 > d_max2 {
                                    continue;
                                }
                                match step(blocks, v, f) {
                                    Ok(u) => {
                                        if improves_sq(pts, u, d2) {
                                            out.push(Offer {
                                                target: u as u32,
                                                face: u8::MAX,
                                                local: 0,
                                                site: s,
                                                value: sign * d2.sqrt(),
                                            });
                                        }
                                    }
                                    Err(Some(local)) if !far => out.push(Offer {
                                        target: b as u32,
                                        face: f as u8,
                                        local: local as u16,
                                        site: s,
                                        value: sign * d2.sqrt(),
                                    }),
                                    Err(_) => {}
                                }
                            }
                        }
                        out
                    })
                    .collect()
            };
            for o in offers.iter().flatten() {
                let u = if o.face == u8::MAX {
                    o.target as usize
                } else {
                    let (b, f) = (o.target as usize, o.face as usize);
                    let mut nb = blocks.across[b][f];
                    if nb == NO_BLOCK {
                        nb = allocate(grid, index, block_cells, &mut blocks, b, f, max_blocks)?;
                        if nb == OUTSIDE {
                            continue;
                        }
                        pts.resize(
                            blocks.coords.len() * BLOCK_POINTS,
                            Pt {
                                value: f32::NAN,
                                site: NO_SITE,
                            },
                        );
                    }
                    nb as usize * BLOCK_POINTS + o.local as usize
                };
                if !improves(&pts, u, o.value.abs()) {
                    continue;
                }
                relaxations += 1;
                if relaxations > budget {
                    return Err(SdfError::PropagationBudget {
                        relaxations,
                        points: pts.len(),
                    });
                }
                pts[u] = Pt {
                    value: o.value as f32,
                    site: o.site,
                };
                buckets[bucket(o.value.abs()).max(cur)].push((u as u64) << 32 | o.site as u64);
            }
        }
    }
    *field = pts.par_iter().map(|p| p.value).collect();
    Ok(())
}

/// Allocates the block cell across face `f` of block `b` for the wavefront (its index entry,
/// its face table and its neighbours' entries towards it); returns the new block's number.
fn allocate(
    grid: &Grid,
    index: &mut BlockIndex,
    block_cells: &mut Vec<usize>,
    blocks: &mut Blocks,
    b: usize,
    f: usize,
    max_blocks: usize,
) -> Result<u32, SdfError> {
    let nb = blocks.coords.len();
    if nb >= max_blocks {
        return Err(SdfError::TooManyBlocks {
            blocks: nb + 1,
            cap: max_blocks,
        });
    }
    // Block `b`'s face table marks the cell across `f` unallocated, not outside: it exists.
    let Some(cell) = grid.across(blocks.coords[b], f) else {
        return Ok(OUTSIDE);
    };
    index.set(grid.split(cell), nb as u32);
    block_cells.push(cell);
    let cc = grid.split(cell).map(|x| x as u32);
    let faces = Blocks::faces(grid, index, cc);
    for (g, &m) in faces.iter().enumerate() {
        if m < OUTSIDE {
            // The neighbour across face `g` sees the new block across the opposite face.
            blocks.across[m as usize][g ^ 1] = nb as u32;
        }
    }
    blocks.coords.push(cc);
    blocks.across.push(faces);
    Ok(nb as u32)
}

/// The blocks' values (`BLOCK_POINTS` per block, the block at block cell `block_cells[k]` of a
/// grid of `cells` block cells) with their aprons ([`PADDED`]): a point past the block's last
/// along some axis reads the next block's point there, `±d` where that block cell is air or
/// ground, and repeats the block's own last point past the grid's last block cell (no cell of
/// the grid has a corner there).
fn pad_blocks(
    index: &BlockIndex,
    cells: [usize; 3],
    block_cells: &[usize],
    values: &[f32],
    d: f32,
) -> Vec<f32> {
    let mut out = vec![0.0f32; block_cells.len() * PADDED_POINTS];
    out.par_chunks_mut(PADDED_POINTS)
        .enumerate()
        .for_each(|(k, o)| {
            let id = block_cells[k];
            let c = [
                id % cells[0],
                (id / cells[0]) % cells[1],
                id / (cells[0] * cells[1]),
            ];
            // What lies at each of the 8 block cells at offsets in {0, 1}³ (offset 0: the block).
            let block = |b: usize| &values[b * BLOCK_POINTS..(b + 1) * BLOCK_POINTS];
            let sources: [Apron<'_>; 8] = std::array::from_fn(|n| {
                let nc = [0, 1, 2].map(|a| c[a] + ((n >> a) & 1));
                if (0..3).any(|a| nc[a] >= cells[a]) {
                    return Apron::PastGrid;
                }
                match index.get(nc) {
                    AIR => Apron::Uniform(d),
                    GROUND => Apron::Uniform(-d),
                    b => Apron::Block(block(b as usize)),
                }
            });
            // Row by row: a row's first `BLOCK` values come from one source, its last from the
            // source one step up in `x`.
            for z in 0..PADDED {
                for y in 0..PADDED {
                    let n = usize::from(y == BLOCK) << 1 | usize::from(z == BLOCK) << 2;
                    let row = |yy: usize, zz: usize| (zz * BLOCK + yy) * BLOCK;
                    let out = &mut o[(z * PADDED + y) * PADDED..(z * PADDED + y + 1) * PADDED];
                    let (body, last) = out.split_at_mut(BLOCK);
                    match sources[n] {
                        Apron::Block(v) => {
                            let r = row(y % BLOCK, z % BLOCK);
                            body.copy_from_slice(&v[r..r + BLOCK]);
                        }
                        Apron::Uniform(u) => body.fill(u),
                        Apron::PastGrid => {
                            let v = block(k);
                            let r = row(y.min(BLOCK - 1), z.min(BLOCK - 1));
                            body.copy_from_slice(&v[r..r + BLOCK]);
                        }
                    }
                    last[0] = match sources[n | 1] {
                        Apron::Block(v) => v[row(y % BLOCK, z % BLOCK)],
                        Apron::Uniform(u) => u,
                        Apron::PastGrid => {
                            let v = block(k);
                            v[row(y.min(BLOCK - 1), z.min(BLOCK - 1)) + BLOCK - 1]
                        }
                    };
                }
            }
        });
    out
}

/// What a block's apron copies along one offset ([`pad_blocks`]).
#[derive(Clone, Copy)]
enum Apron<'a> {
    /// The values of the allocated block there.
    Block(&'a [f32]),
    /// An unallocated block's value (`±D`).
    Uniform(f32),
    /// Past the grid's last block cell.
    PastGrid,
}

/// The least and the greatest value of each stored block (no NaN left). Eight lanes per block
/// (vectorised; `min` and `max` are exact, so the lanes' order does not matter), blocks in
/// parallel.
fn stored_ranges(values: &[f32]) -> Vec<[f32; 2]> {
    const LANES: usize = 8;
    values
        .par_chunks(PADDED_POINTS)
        .map(|v| {
            let mut lo = [f32::INFINITY; LANES];
            let mut hi = [f32::NEG_INFINITY; LANES];
            let chunks = v.chunks_exact(LANES);
            let rest = chunks.remainder();
            for c in chunks {
                for k in 0..LANES {
                    lo[k] = if c[k] < lo[k] { c[k] } else { lo[k] };
                    hi[k] = if c[k] > hi[k] { c[k] } else { hi[k] };
                }
            }
            let fold = |a: f32, b: f32, less: bool| if (b < a) == less { b } else { a };
            let mut r = [f32::INFINITY, f32::NEG_INFINITY];
            for k in 0..LANES {
                r[0] = fold(r[0], lo[k], true);
                r[1] = fold(r[1], hi[k], false);
            }
            for &x in rest {
                r[0] = fold(r[0], x, true);
                r[1] = fold(r[1], x, false);
            }
            r
        })
        .collect()
}

/// The face region of a triangle: the prism of points whose projection on its plane falls in
/// the triangle, as three inward unit normals of the planes through its edges along its normal
/// and their offsets.
#[derive(Clone, Copy)]
struct FaceRegion {
    planes: [(Vector3<f64>, f64); 3],
}

impl FaceRegion {
    /// The face region of triangle `tri` with unit normal `n`; `None` when an edge is degenerate.
    fn new(tri: &[Point3<f64>; 3], n: &Vector3<f64>) -> Option<Self> {
        let mut planes = [(Vector3::zeros(), 0.0); 3];
        for (k, plane) in planes.iter_mut().enumerate() {
            let (p0, p1, p2) = (tri[k], tri[(k + 1) % 3], tri[(k + 2) % 3]);
            let mut m = n.cross(&(p1 - p0));
            let len = m.norm();
            if len.is_nan() || len <= 0.0 {
                return None;
            }
            m /= len;
            // Inward: towards the opposite corner.
            if m.dot(&(p2 - p0)) < 0.0 {
                m = -m;
            }
            *plane = (m, m.dot(&p0.coords));
        }
        Some(FaceRegion { planes })
    }

    /// How far `q` lies inside the region: the smallest signed distance to the edges' planes
    /// (negative outside).
    #[inline]
    fn margin(&self, q: &Point3<f64>) -> f64 {
        self.planes
            .iter()
            .map(|(m, o)| m.dot(&q.coords) - o)
            .fold(f64::INFINITY, f64::min)
    }
}

/// Step 2b for one block's values: every NaN point 6-connected inside the block to an exact
/// point takes that point's sign as `±tf`. `false` when the block has no exact point.
fn local_flood(v: &mut [f32], tf: f32) -> bool {
    // A block with no NaN point has nothing to flood (with propagation, most blocks).
    if !v.iter().any(|x| x.is_nan()) {
        return true;
    }
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

impl GridField for SparseSdf {
    fn grid(&self) -> (&Point3<f64>, f64, [usize; 3]) {
        (&self.origin, self.h, self.dims)
    }
    fn corners(&self, c: [usize; 3]) -> [f64; 8] {
        self.cell_corners(c)
    }
    fn sign_box(&self, c: [usize; 3]) -> Option<SignBox> {
        self.cell_sign_box(c)
    }
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
        crate::sdf::ground_below_on_grid(self, q)
    }
    /// The interpolant's exact first zero along the line (`sdf::first_zero_on_grid`).
    fn ground_along(
        &self,
        q: &Point3<f64>,
        dir: &nalgebra::Unit<Vector3<f64>>,
        reach: f64,
        _tolerance: f64,
    ) -> Result<Option<f64>, crate::surface::DropError> {
        crate::sdf::first_zero_on_grid(self, q, dir, reach)
    }
}

#[cfg(test)]
mod tests {
    //! The query-side structures against independent readings of the same field: the block
    //! aprons against the owning blocks' values, the sign boxes against the corners they
    //! summarise, and the grid walks with the boxes against the same walks without them.
    use super::*;
    use crate::paton_scene::PatonScene;
    use crate::sdf::{corners_by_value, first_zero_on_grid, ground_below_on_grid};

    /// The field read cell by cell: no sign boxes.
    struct NoBoxes<'a>(&'a SparseSdf);
    impl GridField for NoBoxes<'_> {
        fn grid(&self) -> (&Point3<f64>, f64, [usize; 3]) {
            self.0.grid()
        }
        fn corners(&self, c: [usize; 3]) -> [f64; 8] {
            self.0.corners(c)
        }
    }
    use nalgebra::Unit;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// Paton's ledge (with the pole) at 20 cm: propagated to the default `D`, and truncated.
    fn fields() -> Vec<SparseSdf> {
        let m = PatonScene::paper(true).mesh().expect("the scene meshes");
        let mut p = SparseSdfParams::new(0.2);
        p.margin = 1.0;
        let propagated = SparseSdf::from_mesh(&m, &p).expect("builds");
        p.max_distance = p.truncation;
        let truncated = SparseSdf::from_mesh(&m, &p).expect("builds");
        assert!(propagated.max_distance() > truncated.max_distance());
        vec![propagated, truncated]
    }

    /// Every cell's corners as the blocks' aprons give them equal the values of the blocks
    /// owning those points (or `±D` for unallocated ones).
    #[test]
    fn aprons_copy_the_owning_blocks() {
        for f in fields() {
            let d = f.dims;
            let mut checked = 0;
            for k in 0..d[2] - 1 {
                for j in 0..d[1] - 1 {
                    for i in 0..d[0] - 1 {
                        let c = [i, j, k];
                        let by_owner = corners_by_value(c, |i, j, k| f.value(i, j, k));
                        assert_eq!(f.corners(c), by_owner, "cell {c:?}");
                        checked += 1;
                    }
                }
            }
            assert!(checked > 100_000, "{checked} cells");
        }
    }

    /// A sign box holds only cells whose eight corners have its sign, strictly.
    #[test]
    fn sign_boxes_hold_what_they_claim() {
        for f in fields() {
            let d = f.dims;
            let (mut boxes, mut signs) = (0, [0, 0]);
            for k in 0..d[2] - 1 {
                for j in 0..d[1] - 1 {
                    for i in 0..d[0] - 1 {
                        let c = [i, j, k];
                        let Some(b) = f.sign_box(c) else { continue };
                        assert!(
                            b.lo.iter().zip(c).all(|(l, x)| *l <= x),
                            "{b:?} holds {c:?}"
                        );
                        assert!(
                            b.hi.iter().zip(c).all(|(h, x)| x <= *h),
                            "{b:?} holds {c:?}"
                        );
                        boxes += 1;
                        signs[usize::from(b.positive)] += 1;
                        // The claim for this cell, read corner by corner from the owners.
                        let v = corners_by_value(c, |i, j, k| f.value(i, j, k));
                        assert!(
                            v.iter().all(|x| (*x > 0.0) == b.positive && *x != 0.0),
                            "cell {c:?} in {b:?} has corners {v:?}"
                        );
                    }
                }
            }
            assert!(
                signs[0] > 1000 && signs[1] > 1000,
                "boxes {boxes}, signs {signs:?}"
            );
        }
    }

    /// The walks with the sign boxes give the answers of the walks reading every cell, bit for
    /// bit: 3,000 seeded lines and verticals per field, from the air and from below the ground.
    #[test]
    fn sign_boxes_do_not_change_the_walks() {
        let mut rng = ChaCha8Rng::seed_from_u64(14);
        for f in fields() {
            let (lo, hi) = f.bounds();
            let mut hits = 0;
            for _ in 0..3000 {
                let q = Point3::from(Vector3::from_fn(|a, _| rng.random_range(lo[a]..hi[a])));
                // Toward a point of the ground's height range (the floor at 0, the ledge's top
                // at 4 m), a little past it: most lines cross the ground, some stop short.
                let aim = Point3::new(
                    rng.random_range(lo.x..hi.x),
                    rng.random_range(lo.y..hi.y),
                    rng.random_range(-0.5..4.5),
                );
                let Some(dir) = Unit::try_new(aim - q, 1e-9) else {
                    continue;
                };
                let reach = (aim - q).norm() * rng.random_range(0.5..1.5);
                let with = f.ground_along(&q, &dir, reach, 0.0);
                let without = first_zero_on_grid(&NoBoxes(&f), &q, &dir, reach);
                assert_eq!(with, without, "line from {q:?} along {dir:?}");
                hits += usize::from(matches!(with, Ok(Some(_))));
                let below = f.ground_below(&q, 0.0);
                let plain = ground_below_on_grid(&NoBoxes(&f), &q);
                assert_eq!(below, plain, "vertical through {q:?}");
            }
            assert!(hits > 500, "{hits} lines met the ground");
        }
    }
}
