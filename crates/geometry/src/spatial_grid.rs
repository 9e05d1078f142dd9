//! A uniform grid over a bounding box that buckets items by the cells their bounding boxes cover:
//! the coarse index behind segment-intersection checks, obstacle containment queries and cold point
//! location. Cell size adapts to the item count so each cell holds a few items on average.

use crate::polygon::Aabb;
use nalgebra::Point2;

/// A uniform bucket grid of item ids.
#[derive(Debug, Clone)]
pub struct SpatialGrid {
    origin: Point2<f64>,
    cell: f64,
    cols: usize,
    rows: usize,
    buckets: Buckets,
}

/// The ids of each cell: grown item by item ([`SpatialGrid::insert`]), or packed in one array
/// when every item is known up front ([`SpatialGrid::packed`]: two allocations whatever the cell
/// count, where growing costs one per occupied cell).
#[derive(Debug, Clone)]
enum Buckets {
    Growing(Vec<Vec<u32>>),
    /// Cell `i` holds `items[start[i]..start[i + 1]]`.
    Packed {
        start: Vec<u32>,
        items: Vec<u32>,
    },
}

/// Relative slack (of the grid's coordinates' magnitude) added to the margin of
/// [`SpatialGrid::visit_near_convex`], so that rounding in its cell bounds never drops an item.
const GRID_SLACK: f64 = 1e-12;

/// Upper bound on the number of cells, whatever the item count: bounds memory for degenerate
/// inputs (a handful of huge items) while leaving ~1 cell per item for ordinary maps.
const MAX_CELLS: usize = 1 << 22;

impl SpatialGrid {
    /// An empty grid over `bounds`, sized for about `expected_items` items of typical extent.
    pub fn new(bounds: Aabb, expected_items: usize) -> Self {
        let (w, h) = bounds.size();
        let (w, h) = (w.max(f64::MIN_POSITIVE), h.max(f64::MIN_POSITIVE));
        let target = expected_items.clamp(1, MAX_CELLS) as f64;
        let mut cell = (w * h / target).sqrt();
        if !(cell.is_finite() && cell > 0.0) {
            cell = w.max(h);
        }
        let cols = ((w / cell).ceil() as usize).clamp(1, MAX_CELLS);
        let rows = ((h / cell).ceil() as usize).clamp(1, MAX_CELLS / cols);
        // Re-derive the cell size so that cols x rows really covers the box.
        let cell = (w / cols as f64).max(h / rows as f64) * (1.0 + 1e-12);
        SpatialGrid {
            origin: bounds.min,
            cell,
            cols,
            rows,
            // Allocated on the first insertion: a grid packed right away never needs it.
            buckets: Buckets::Growing(Vec::new()),
        }
    }

    /// A grid over `bounds`, sized for about `expected_items` items, holding item `i` (id `i`) in
    /// every cell that `boxes[i]` covers, each cell's ids in increasing order: the same grid as
    /// [`SpatialGrid::new`] followed by [`SpatialGrid::insert`] of every box in order, packed
    /// into one array (a counting pass, then a filling pass).
    ///
    /// ```
    /// use nalgebra::Point2;
    /// use rappel_geometry::{polygon::Aabb, spatial_grid::SpatialGrid};
    /// let b = |x0, y0, x1, y1| Aabb { min: Point2::new(x0, y0), max: Point2::new(x1, y1) };
    /// let boxes = [b(0., 0., 1., 1.), b(0.5, 0.5, 9., 9.), b(9., 9., 10., 10.)];
    /// let grid = SpatialGrid::packed(b(0., 0., 10., 10.), boxes.len(), &boxes);
    /// assert_eq!(grid.at(&Point2::new(0.2, 0.2)), &[0, 1]);
    /// assert_eq!(grid.at(&Point2::new(9.9, 9.9)), &[1, 2]);
    /// ```
    pub fn packed(bounds: Aabb, expected_items: usize, boxes: &[Aabb]) -> Self {
        SpatialGrid::new(bounds, expected_items).pack(boxes)
    }

    /// This grid's cells holding exactly `boxes` (item `i` with id `i`), packed as in
    /// [`SpatialGrid::packed`]; whatever it held before is dropped.
    pub fn pack(mut self, boxes: &[Aabb]) -> Self {
        let cells = BoxCells {
            ranges: boxes.iter().map(|b| self.cell_range(b)).collect(),
            cols: self.cols,
        };
        self.buckets = packed_buckets(self.cols * self.rows, &cells);
        self
    }

    /// This grid's cells holding point `i` (id `i`) for every `i` in `0..points.len()` that
    /// `keep` accepts, each in the one cell holding it ([`SpatialGrid::cell_of`]), each cell's
    /// ids in increasing order; whatever the grid held before is dropped. Packed as in
    /// [`SpatialGrid::packed`], with no per-item temporary beyond the cell counts: ids index
    /// the caller's own point array, so a sparse subset needs no id map.
    ///
    /// ```
    /// use nalgebra::Point2;
    /// use rappel_geometry::{polygon::Aabb, spatial_grid::SpatialGrid};
    /// let p = |x, y| Point2::new(x, y);
    /// let bounds = Aabb { min: p(0.0, 0.0), max: p(10.0, 10.0) };
    /// let points = [p(0.5, 0.5), p(9.5, 9.5), p(0.6, 0.4), p(9.6, 9.4)];
    /// let grid = SpatialGrid::new(bounds, 4).pack_points(&points, |i| i != 3);
    /// assert_eq!(grid.at(&p(0.1, 0.1)), &[0, 2]);
    /// assert_eq!(grid.at(&p(9.9, 9.9)), &[1]);
    /// ```
    pub fn pack_points(mut self, points: &[Point2<f64>], keep: impl Fn(usize) -> bool) -> Self {
        let buckets = packed_buckets(
            self.cols * self.rows,
            &PointCells {
                grid: &self,
                points,
                keep,
            },
        );
        self.buckets = buckets;
        self
    }

    /// This grid's cells holding segment `i` (id `i`) in every cell that the closed segment
    /// `segments[i]` meets, each cell's ids in increasing order; whatever it held before is
    /// dropped. The cells are those [`SpatialGrid::visit_near_convex`] visits for the segment
    /// with margin 0 (a superset, rounding covered), so two segments with a common point share
    /// the cell holding it, and `visit_near_convex` of a segment with margin 0 finds every
    /// segment that meets it. A long diagonal segment is listed in the cells along it, not in
    /// every cell of its bounding box as [`SpatialGrid::pack`] would list it.
    ///
    /// ```
    /// use nalgebra::Point2;
    /// use rappel_geometry::{polygon::Aabb, spatial_grid::SpatialGrid};
    /// let p = |x, y| Point2::new(x, y);
    /// let bounds = Aabb { min: p(0.0, 0.0), max: p(10.0, 10.0) };
    /// // The diagonal meets 10 to 28 of the 100 cells (its box covers all of them).
    /// let grid = SpatialGrid::new(bounds, 100).pack_segments(&[[p(0.0, 0.0), p(10.0, 10.0)]]);
    /// let listed = grid.buckets().filter(|b| !b.is_empty()).count();
    /// assert!((10..=28).contains(&listed), "{listed}");
    /// assert_eq!(grid.at(&p(5.5, 5.5)), &[0]);
    /// assert!(grid.at(&p(9.5, 0.5)).is_empty());
    /// ```
    pub fn pack_segments(mut self, segments: &[[Point2<f64>; 2]]) -> Self {
        let buckets = packed_buckets(
            self.cols * self.rows,
            &SegmentCells {
                grid: &self,
                segments,
            },
        );
        self.buckets = buckets;
        self
    }

    /// The indices of `points` ordered by the cell holding each (row by row, stable within a
    /// cell): a counting sort, linear in the points and cells. Items numbered in this order lie
    /// near their neighbours in memory as in space, so a pass over the cells touches them in
    /// order.
    pub fn order_by_cell(&self, points: &[Point2<f64>]) -> Vec<u32> {
        let cells = self.cols * self.rows;
        let mut start = vec![0u32; cells + 1];
        let keys: Vec<usize> = points.iter().map(|p| self.cell_of(p)).collect();
        for &k in &keys {
            start[k + 1] += 1;
        }
        for i in 0..cells {
            start[i + 1] += start[i];
        }
        let mut order = vec![0u32; points.len()];
        for (i, &k) in keys.iter().enumerate() {
            order[start[k] as usize] = i as u32;
            start[k] += 1;
        }
        order
    }

    /// Column and row of the cell holding `p`, clamped to the grid (NaN to the first cell). The
    /// saturating float-to-integer conversion floors non-negative values and sends negative
    /// ones and NaN to 0, so no `floor` call is needed.
    fn col_row(&self, p: &Point2<f64>) -> (usize, usize) {
        let c = ((p.x - self.origin.x) / self.cell) as usize;
        let r = ((p.y - self.origin.y) / self.cell) as usize;
        (c.min(self.cols - 1), r.min(self.rows - 1))
    }

    /// `[c0, r0, c1, r1]`: the columns and rows of the cells a box covers.
    fn cell_range(&self, bounds: &Aabb) -> [usize; 4] {
        let (c0, r0) = self.col_row(&bounds.min);
        let (c1, r1) = self.col_row(&bounds.max);
        [c0, r0, c1, r1]
    }

    /// The index of the cell holding `p` (points outside are clamped to the border cells).
    pub fn cell_of(&self, p: &Point2<f64>) -> usize {
        let (c, r) = self.col_row(p);
        r * self.cols + c
    }

    /// Adds `id` to every cell that `bounds` covers (a packed grid is unpacked first).
    pub fn insert(&mut self, bounds: &Aabb, id: u32) {
        let [c0, r0, c1, r1] = self.cell_range(bounds);
        let cells = self.cols * self.rows;
        match &self.buckets {
            Buckets::Packed { .. } => {
                let unpacked = (0..cells).map(|i| self.bucket(i).to_vec()).collect();
                self.buckets = Buckets::Growing(unpacked);
            }
            Buckets::Growing(b) if b.is_empty() => {
                self.buckets = Buckets::Growing(vec![Vec::new(); cells]);
            }
            Buckets::Growing(_) => {}
        }
        let Buckets::Growing(buckets) = &mut self.buckets else {
            return;
        };
        for r in r0..=r1 {
            for c in c0..=c1 {
                buckets[r * self.cols + c].push(id);
            }
        }
    }

    /// The ids in cell `i`.
    fn bucket(&self, i: usize) -> &[u32] {
        match &self.buckets {
            Buckets::Growing(b) => b.get(i).map_or(&[], Vec::as_slice),
            Buckets::Packed { start, items } => &items[start[i] as usize..start[i + 1] as usize],
        }
    }

    /// The ids in the cell holding `p`.
    pub fn at(&self, p: &Point2<f64>) -> &[u32] {
        self.bucket(self.cell_of(p))
    }

    /// All buckets, for pairwise checks within cells.
    pub fn buckets(&self) -> impl Iterator<Item = &[u32]> {
        (0..self.cols * self.rows).map(|i| self.bucket(i))
    }

    /// Calls `f` with the ids of every cell that meets the convex hull of `corners` (a point, a
    /// segment, a triangle, ..., in any order) grown by `margin` in `x` and in `y`: a superset
    /// of the items whose boxes come within `margin` of the hull (in any norm no larger than
    /// the maximum norm, the Euclidean one included), each cell visited once, column by column.
    /// The cells are found without rounding against the hull: a column's rows are those of the
    /// `y` range of the hull over the column's `x` range widened by `margin` (the hull's edges,
    /// i.e. the segments between every two corners, clipped to that range), then widened by
    /// `margin`; so the cost is the number of cells the grown hull meets, not the grid's size.
    /// Nothing is visited for no corners or a non-finite corner or margin.
    ///
    /// ```
    /// use nalgebra::Point2;
    /// use rappel_geometry::{polygon::Aabb, spatial_grid::SpatialGrid};
    /// let points: Vec<Point2<f64>> = (0..100).map(|i| Point2::new(i as f64, (i * i % 97) as f64)).collect();
    /// let boxes: Vec<Aabb> = points.iter().map(|p| Aabb { min: *p, max: *p }).collect();
    /// let grid = SpatialGrid::packed(Aabb::of_points(points.iter()), points.len(), &boxes);
    /// let mut near = Vec::new();
    /// grid.visit_near_convex(&[Point2::new(10.0, 0.0), Point2::new(60.0, 90.0)], 2.0, |id| near.push(id));
    /// assert!(near.contains(&50)); // (50, 75) lies 0.2 from the segment
    /// assert!(!near.contains(&99)); // (99, 4) lies far from it
    /// ```
    pub fn visit_near_convex(&self, corners: &[Point2<f64>], margin: f64, mut f: impl FnMut(u32)) {
        self.visit_cells_near_convex(corners, margin, |cell| {
            for &id in self.bucket(cell) {
                f(id);
            }
        });
    }

    /// Calls `f` with the index of every cell that meets the convex hull of `corners` grown by
    /// `margin` (plus [`GRID_SLACK`]), each once, column by column: the cells
    /// [`SpatialGrid::visit_near_convex`] reads. Nothing for no corners, a non-finite corner or
    /// margin.
    fn visit_cells_near_convex(
        &self,
        corners: &[Point2<f64>],
        margin: f64,
        mut f: impl FnMut(usize),
    ) {
        if corners.is_empty()
            || !margin.is_finite()
            || corners
                .iter()
                .any(|p| !(p.x.is_finite() && p.y.is_finite()))
        {
            return;
        }
        // Cell bounds recomputed here and the interpolated hull may differ from the division
        // that placed the items by a few ulps of the coordinates: widen by far more than that.
        let scale = self.origin.x.abs().max(self.origin.y.abs())
            + self.cell * (self.cols + self.rows) as f64;
        let margin = margin.abs() + GRID_SLACK * scale;
        let (x_min, x_max) = corners
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
                (a.min(p.x), b.max(p.x))
            });
        let col = |x: f64| self.col_row(&Point2::new(x, self.origin.y)).0;
        let (c0, c1) = (col(x_min - margin), col(x_max + margin));
        for c in c0..=c1 {
            // The column's x range (unbounded at the grid's first and last columns, which hold
            // every point clamped into them), widened by the margin.
            let xa = if c == 0 {
                f64::NEG_INFINITY
            } else {
                self.origin.x + self.cell * c as f64 - margin
            };
            let xb = if c + 1 == self.cols {
                f64::INFINITY
            } else {
                self.origin.x + self.cell * (c + 1) as f64 + margin
            };
            let (mut y_lo, mut y_hi) = (f64::INFINITY, f64::NEG_INFINITY);
            for (i, p) in corners.iter().enumerate() {
                for q in &corners[i..] {
                    if let Some((a, b)) = y_range_in_slab(p, q, xa, xb) {
                        y_lo = y_lo.min(a);
                        y_hi = y_hi.max(b);
                    }
                }
            }
            if y_lo > y_hi {
                continue;
            }
            let row = |y: f64| self.col_row(&Point2::new(self.origin.x, y)).1;
            for r in row(y_lo - margin)..=row(y_hi + margin) {
                f(r * self.cols + c);
            }
        }
    }

    /// Ids in cells at Chebyshev ring distance exactly `ring` around the cell of `p` (ring 0 is
    /// the cell itself), for searches that widen until something is found. `None` once the ring
    /// lies entirely outside the grid.
    pub fn ring_around(&self, p: &Point2<f64>, ring: usize) -> Option<Vec<u32>> {
        let mut out = Vec::new();
        self.find_in_ring(p, ring, |id| {
            out.push(id);
            None::<()>
        })?;
        Some(out)
    }

    /// The first `Some` that `f` returns for the ids of the cells at Chebyshev ring distance
    /// exactly `ring` around the cell of `p`, visited in the order of [`SpatialGrid::ring_around`],
    /// without collecting them: `Some(None)` when `f` answers `None` for all of them, `None` once
    /// the ring lies entirely outside the grid. At most `8 * ring + 1` cells are visited.
    pub fn find_in_ring<T>(
        &self,
        p: &Point2<f64>,
        ring: usize,
        mut f: impl FnMut(u32) -> Option<T>,
    ) -> Option<Option<T>> {
        let (c, r) = self.col_row(p);
        let (c, r, k) = (c as isize, r as isize, ring as isize);
        if c - k < 0 && r - k < 0 && c + k >= self.cols as isize && r + k >= self.rows as isize {
            return None;
        }
        for rr in (r - k).max(0)..=(r + k).min(self.rows as isize - 1) {
            let on_row_edge = (rr - r).abs() == k;
            for cc in (c - k).max(0)..=(c + k).min(self.cols as isize - 1) {
                if !on_row_edge && (cc - c).abs() != k {
                    continue;
                }
                for &id in self.bucket(rr as usize * self.cols + cc as usize) {
                    if let Some(found) = f(id) {
                        return Some(Some(found));
                    }
                }
            }
        }
        Some(None)
    }
}

/// The `y` range of the segment `p -> q` (a point when `p == q`) over `xa <= x <= xb`, if it
/// meets that slab. The interpolated ends may be off by an ulp or two; callers widen the range
/// by a margin. Bounds may be infinite.
fn y_range_in_slab(p: &Point2<f64>, q: &Point2<f64>, xa: f64, xb: f64) -> Option<(f64, f64)> {
    let (p, q) = if p.x <= q.x { (p, q) } else { (q, p) };
    if q.x < xa || p.x > xb {
        return None;
    }
    let at = |x: f64| {
        if x <= p.x {
            p.y
        } else if x >= q.x {
            q.y
        } else {
            p.y + (q.y - p.y) * ((x - p.x) / (q.x - p.x))
        }
    };
    let (ya, yb) = (at(xa.max(p.x)), at(xb.min(q.x)));
    Some((ya.min(yb), ya.max(yb)))
}

/// The cells of each item of a grid being packed ([`packed_buckets`]).
trait CellsOf {
    /// The number of items.
    fn count(&self) -> usize;
    /// Calls `f` with every cell item `id` goes in, each once.
    fn visit(&self, id: usize, f: impl FnMut(usize));
}

/// The cell of each kept point ([`SpatialGrid::pack_points`]).
struct PointCells<'a, K> {
    grid: &'a SpatialGrid,
    points: &'a [Point2<f64>],
    keep: K,
}

impl<K: Fn(usize) -> bool> CellsOf for PointCells<'_, K> {
    fn count(&self) -> usize {
        self.points.len()
    }

    #[inline]
    fn visit(&self, id: usize, mut f: impl FnMut(usize)) {
        if (self.keep)(id) {
            f(self.grid.cell_of(&self.points[id]));
        }
    }
}

/// The cells of bounding boxes, as cell ranges `[c0, r0, c1, r1]` ([`SpatialGrid::pack`]).
struct BoxCells {
    ranges: Vec<[usize; 4]>,
    cols: usize,
}

impl CellsOf for BoxCells {
    fn count(&self) -> usize {
        self.ranges.len()
    }

    #[inline]
    fn visit(&self, id: usize, mut f: impl FnMut(usize)) {
        let [c0, r0, c1, r1] = self.ranges[id];
        for r in r0..=r1 {
            for c in c0..=c1 {
                f(r * self.cols + c);
            }
        }
    }
}

/// The cells along segments ([`SpatialGrid::pack_segments`]).
struct SegmentCells<'a> {
    grid: &'a SpatialGrid,
    segments: &'a [[Point2<f64>; 2]],
}

impl CellsOf for SegmentCells<'_> {
    fn count(&self) -> usize {
        self.segments.len()
    }

    #[inline]
    fn visit(&self, id: usize, f: impl FnMut(usize)) {
        self.grid
            .visit_cells_near_convex(&self.segments[id], 0.0, f);
    }
}

/// The packed buckets of `cells` cells holding the items of `of`, each cell's ids in increasing
/// order: a counting sort in two passes over the items (count, then fill), shared by
/// [`SpatialGrid::pack`] (cells of a box), [`SpatialGrid::pack_segments`] (cells along a
/// segment) and [`SpatialGrid::pack_points`] (the cell of a point).
fn packed_buckets(cells: usize, of: &impl CellsOf) -> Buckets {
    let mut start = vec![0u32; cells + 1];
    for id in 0..of.count() {
        of.visit(id, |cell| start[cell + 1] += 1);
    }
    for i in 0..cells {
        start[i + 1] += start[i];
    }
    let mut fill: Vec<u32> = start[..cells].to_vec();
    let mut items = vec![0u32; start[cells] as usize];
    for id in 0..of.count() {
        of.visit(id, |cell| {
            items[fill[cell] as usize] = id as u32;
            fill[cell] += 1;
        });
    }
    Buckets::Packed { start, items }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn items_are_found_in_the_cells_they_cover() {
        let bounds = Aabb {
            min: Point2::new(0.0, 0.0),
            max: Point2::new(10.0, 10.0),
        };
        let mut g = SpatialGrid::new(bounds, 100);
        let item = Aabb {
            min: Point2::new(2.0, 2.0),
            max: Point2::new(3.0, 3.0),
        };
        g.insert(&item, 7);
        assert!(g.at(&Point2::new(2.5, 2.5)).contains(&7));
        assert!(!g.at(&Point2::new(9.5, 9.5)).contains(&7));
        // Outside points clamp to the border instead of panicking.
        let _ = g.at(&Point2::new(-1e300, f64::NAN));
        let mut found = None;
        for k in 0.. {
            match g.ring_around(&Point2::new(9.9, 9.9), k) {
                Some(ids) if ids.contains(&7) => {
                    found = Some(k);
                    break;
                }
                Some(_) => {}
                None => break,
            }
        }
        assert!(found.is_some());
    }

    #[test]
    fn a_packed_grid_equals_the_grown_one_and_rings_match() {
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(10);
        for round in 0..20 {
            let bounds = Aabb {
                min: Point2::new(-5.0, 2.0),
                max: Point2::new(50.0, 2.0 + 5.0 * f64::from(round + 1)),
            };
            let boxes: Vec<Aabb> = (0..rng.random_range(1..300))
                .map(|_| {
                    let x = rng.random_range(-10.0..55.0);
                    let y = rng.random_range(-10.0..120.0);
                    let (w, h) = (rng.random_range(0.0..8.0), rng.random_range(0.0..8.0));
                    Aabb {
                        min: Point2::new(x, y),
                        max: Point2::new(x + w, y + h),
                    }
                })
                .collect();
            let expected = boxes.len() / (round as usize % 3 + 1);
            let packed = SpatialGrid::packed(bounds, expected, &boxes);
            let mut grown = SpatialGrid::new(bounds, expected);
            for (i, b) in boxes.iter().enumerate() {
                grown.insert(b, i as u32);
            }
            assert!(packed.buckets().eq(grown.buckets()));
            let q = Point2::new(rng.random_range(-5.0..50.0), rng.random_range(0.0..100.0));
            for ring in 0..4 {
                let mut visited = Vec::new();
                let first = packed.find_in_ring(&q, ring, |id| {
                    visited.push(id);
                    (id % 7 == 3).then_some(id)
                });
                let all = grown.ring_around(&q, ring);
                match (first, all) {
                    (None, None) => {}
                    (Some(f), Some(all)) => {
                        assert_eq!(f, all.iter().copied().find(|id| id % 7 == 3));
                        assert_eq!(visited[..], all[..visited.len()]);
                    }
                    (f, a) => panic!("ring {ring}: {f:?} vs {a:?}"),
                }
            }
            // Ordering by cell is a permutation with non-decreasing cells, stable within one.
            let points: Vec<Point2<f64>> = boxes.iter().map(|b| b.min).collect();
            let order = packed.order_by_cell(&points);
            let mut seen = order.clone();
            seen.sort_unstable();
            assert!(seen.iter().copied().eq(0..points.len() as u32));
            assert!(order.windows(2).all(|w| {
                let (a, b) = (w[0] as usize, w[1] as usize);
                let (ca, cb) = (packed.cell_of(&points[a]), packed.cell_of(&points[b]));
                ca < cb || (ca == cb && a < b)
            }));
            // Inserting into a packed grid unpacks it first and keeps every id.
            let mut more = packed.clone();
            more.insert(&boxes[0], 9999);
            grown.insert(&boxes[0], 9999);
            assert!(more.buckets().eq(grown.buckets()));
        }
    }

    #[test]
    fn visiting_near_a_hull_finds_every_point_within_the_margin_once() {
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        let dist_to_segment = |p: &Point2<f64>, a: &Point2<f64>, b: &Point2<f64>| {
            let d = b - a;
            let t = if d.norm_squared() > 0.0 {
                ((p - a).dot(&d) / d.norm_squared()).clamp(0.0, 1.0)
            } else {
                0.0
            };
            (a + d * t - p).norm()
        };
        let cross = |a: &Point2<f64>, b: &Point2<f64>, p: &Point2<f64>| {
            (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x)
        };
        for round in 0..40 {
            let n = rng.random_range(1..400);
            // Points on a thin arc (the anchors of a long obstacle) or scattered.
            let points: Vec<Point2<f64>> = (0..n)
                .map(|i| {
                    if round % 2 == 0 {
                        let a = 0.6 * i as f64 / n as f64;
                        Point2::new(50.0 + 20.0 * a.cos(), 55.0 + 20.0 * a.sin())
                    } else {
                        Point2::new(rng.random_range(0.0..100.0), rng.random_range(-10.0..30.0))
                    }
                })
                .collect();
            let boxes: Vec<Aabb> = points.iter().map(|p| Aabb { min: *p, max: *p }).collect();
            let grid = SpatialGrid::packed(Aabb::of_points(points.iter()), n, &boxes);
            for _ in 0..20 {
                let k = rng.random_range(1..4);
                let corners: Vec<Point2<f64>> = (0..k)
                    .map(|_| {
                        Point2::new(
                            rng.random_range(-10.0..110.0),
                            rng.random_range(-20.0..80.0),
                        )
                    })
                    .collect();
                let margin = rng.random_range(0.0..3.0);
                let mut seen = vec![0usize; n];
                grid.visit_near_convex(&corners, margin, |id| seen[id as usize] += 1);
                assert!(seen.iter().all(|&s| s <= 1), "a point visited twice");
                for (i, p) in points.iter().enumerate() {
                    let mut d = f64::INFINITY;
                    for a in &corners {
                        for b in &corners {
                            d = d.min(dist_to_segment(p, a, b));
                        }
                    }
                    if k == 3 {
                        let s: Vec<f64> = (0..3)
                            .map(|e| cross(&corners[e], &corners[(e + 1) % 3], p))
                            .collect();
                        if s.iter().all(|&x| x >= 0.0) || s.iter().all(|&x| x <= 0.0) {
                            d = 0.0;
                        }
                    }
                    assert!(
                        d > margin || seen[i] == 1,
                        "round {round}: point {i} at {d} within {margin} of {corners:?} not visited"
                    );
                }
            }
        }
    }
}
