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
    buckets: Vec<Vec<u32>>,
}

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
            buckets: vec![Vec::new(); cols * rows],
        }
    }

    fn col_row(&self, p: &Point2<f64>) -> (usize, usize) {
        let c = ((p.x - self.origin.x) / self.cell).floor();
        let r = ((p.y - self.origin.y) / self.cell).floor();
        let c = if c.is_nan() {
            0.0
        } else {
            c.clamp(0.0, (self.cols - 1) as f64)
        };
        let r = if r.is_nan() {
            0.0
        } else {
            r.clamp(0.0, (self.rows - 1) as f64)
        };
        (c as usize, r as usize)
    }

    /// The index of the cell holding `p` (points outside are clamped to the border cells).
    pub fn cell_of(&self, p: &Point2<f64>) -> usize {
        let (c, r) = self.col_row(p);
        r * self.cols + c
    }

    /// Adds `id` to every cell that `bounds` covers.
    pub fn insert(&mut self, bounds: &Aabb, id: u32) {
        let (c0, r0) = self.col_row(&bounds.min);
        let (c1, r1) = self.col_row(&bounds.max);
        for r in r0..=r1 {
            for c in c0..=c1 {
                self.buckets[r * self.cols + c].push(id);
            }
        }
    }

    /// The ids in the cell holding `p`.
    pub fn at(&self, p: &Point2<f64>) -> &[u32] {
        &self.buckets[self.cell_of(p)]
    }

    /// All buckets, for pairwise checks within cells.
    pub fn buckets(&self) -> impl Iterator<Item = &[u32]> {
        self.buckets.iter().map(Vec::as_slice)
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
                for &id in &self.buckets[rr as usize * self.cols + cc as usize] {
                    if let Some(found) = f(id) {
                        return Some(Some(found));
                    }
                }
            }
        }
        Some(None)
    }
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
}
