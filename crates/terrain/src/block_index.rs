//! The block index of a sparse distance field ([`crate::sparse_sdf`]): a two-level page table
//! over the grid's block cells. The top level is dense over **pages** of [`PAGE`]³ block cells
//! and holds either a page number or one uniform entry for the whole page (air, ground, unknown);
//! a page, stored only where some of its cells differ from the others (an allocated block, in
//! practice), holds one entry per block cell: an allocated block's number or a uniform entry.
//! Memory: 4 bytes per top-level cell (`1 / 512` of a dense index over the block cells) plus
//! 2 KiB per page; a lookup is two dependent array reads, no hashing. The top level's cell count
//! is the remaining cap on the grid's box (checked by [`BlockIndex::new`]).

/// Block cells per page side.
pub(crate) const PAGE: usize = 8;
const PAGE_CELLS: usize = PAGE * PAGE * PAGE;

/// Entry of an unallocated cell wholly on the air side (values `+D`).
pub(crate) const AIR: u32 = u32::MAX;
/// Entry of an unallocated cell wholly on the ground side (values `-D`).
pub(crate) const GROUND: u32 = u32::MAX - 1;
/// Entry of an unallocated cell whose side is not known yet (during construction only).
pub(crate) const UNKNOWN: u32 = u32::MAX - 2;

/// A two-level index of block cells (module doc). Entries below [`UNKNOWN`] are block numbers.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct BlockIndex {
    /// Block cells per axis.
    cells: [usize; 3],
    /// Pages (top-level cells) per axis.
    tops: [usize; 3],
    /// Per top-level cell: a page number, or a uniform entry (`>= UNKNOWN`).
    top: Vec<u32>,
    /// [`PAGE_CELLS`] entries per page, `x` fastest.
    pages: Vec<u32>,
    /// The top-level cell of each page.
    page_top: Vec<usize>,
}

/// A node of the top level: a top-level cell index.
pub(crate) type TopId = usize;

impl BlockIndex {
    /// The top-level cell counts of a grid of `cells` block cells (in `f64`, before any check).
    pub(crate) fn top_counts(cells: [f64; 3]) -> [f64; 3] {
        cells.map(|n| (n / PAGE as f64).ceil())
    }

    /// An index over `cells` block cells, every entry `fill`. The caller has checked that the
    /// top level ([`BlockIndex::top_counts`]) fits its cap.
    pub(crate) fn new(cells: [usize; 3], fill: u32) -> Self {
        let tops = cells.map(|n| n.div_ceil(PAGE));
        BlockIndex {
            cells,
            tops,
            top: vec![fill; tops[0] * tops[1] * tops[2]],
            pages: Vec::new(),
            page_top: Vec::new(),
        }
    }

    /// Top-level cells per axis.
    pub(crate) fn tops(&self) -> [usize; 3] {
        self.tops
    }

    fn top_of(&self, c: [usize; 3]) -> TopId {
        ((c[2] / PAGE) * self.tops[1] + c[1] / PAGE) * self.tops[0] + c[0] / PAGE
    }

    fn in_page(c: [usize; 3]) -> usize {
        ((c[2] % PAGE) * PAGE + c[1] % PAGE) * PAGE + c[0] % PAGE
    }

    /// The entry of block cell `c` (inside the grid).
    #[inline]
    pub(crate) fn get(&self, c: [usize; 3]) -> u32 {
        let e = self.top[self.top_of(c)];
        if e >= UNKNOWN {
            e
        } else {
            self.pages[e as usize * PAGE_CELLS + Self::in_page(c)]
        }
    }

    /// Sets the entry of block cell `c`, creating its page when its top-level cell was uniform
    /// with another entry.
    pub(crate) fn set(&mut self, c: [usize; 3], v: u32) {
        let t = self.top_of(c);
        let mut e = self.top[t];
        if e >= UNKNOWN {
            if e == v {
                return;
            }
            let p = self.page_top.len();
            self.pages.resize((p + 1) * PAGE_CELLS, e);
            self.page_top.push(t);
            self.top[t] = p as u32;
            e = p as u32;
        }
        self.pages[e as usize * PAGE_CELLS + Self::in_page(c)] = v;
    }

    /// The uniform entry of top-level cell `t`, `None` when it has a page.
    pub(crate) fn uniform(&self, t: TopId) -> Option<u32> {
        let e = self.top[t];
        (e >= UNKNOWN).then_some(e)
    }

    /// Sets the uniform entry of top-level cell `t` (which has no page).
    pub(crate) fn set_uniform(&mut self, t: TopId, v: u32) {
        debug_assert!(self.top[t] >= UNKNOWN && v >= UNKNOWN);
        self.top[t] = v;
    }

    /// The top-level cell holding block cell `c`.
    pub(crate) fn top_id(&self, c: [usize; 3]) -> TopId {
        self.top_of(c)
    }

    /// Top-level cell `t`'s coordinates.
    pub(crate) fn top_coords(&self, t: TopId) -> [usize; 3] {
        let n = self.tops;
        [t % n[0], (t / n[0]) % n[1], t / (n[0] * n[1])]
    }

    /// Top-level cells with the uniform entry `v`.
    pub(crate) fn uniform_tops(&self, v: u32) -> impl Iterator<Item = TopId> + '_ {
        (0..self.top.len()).filter(move |&t| self.top[t] == v)
    }

    /// Block cells (inside the grid) of every page whose entry is `v`.
    pub(crate) fn paged_cells(&self, v: u32) -> impl Iterator<Item = [usize; 3]> + '_ {
        self.page_top.iter().enumerate().flat_map(move |(p, &t)| {
            let base = self.top_coords(t).map(|x| x * PAGE);
            (0..PAGE_CELLS).filter_map(move |l| {
                if self.pages[p * PAGE_CELLS + l] != v {
                    return None;
                }
                let c = [
                    base[0] + l % PAGE,
                    base[1] + (l / PAGE) % PAGE,
                    base[2] + l / (PAGE * PAGE),
                ];
                (c[0] < self.cells[0] && c[1] < self.cells[1] && c[2] < self.cells[2]).then_some(c)
            })
        })
    }

    /// The block cells of top-level cell `t` that lie inside the grid, on its face `f`
    /// (`2 axis + up`).
    pub(crate) fn face_cells(&self, t: TopId, f: usize) -> impl Iterator<Item = [usize; 3]> + '_ {
        let (axis, up) = (f / 2, f % 2 == 1);
        let base = self.top_coords(t).map(|x| x * PAGE);
        let (a1, a2) = ((axis + 1) % 3, (axis + 2) % 3);
        let mut fixed = base[axis] + if up { PAGE - 1 } else { 0 };
        // A top-level cell at the grid's upper end holds fewer block cells.
        fixed = fixed.min(self.cells[axis] - 1);
        (0..PAGE).flat_map(move |u| {
            (0..PAGE).filter_map(move |v| {
                let mut c = [0; 3];
                c[axis] = fixed;
                c[a1] = base[a1] + u;
                c[a2] = base[a2] + v;
                (c[a1] < self.cells[a1] && c[a2] < self.cells[a2]).then_some(c)
            })
        })
    }

    /// Replaces every [`UNKNOWN`] entry (page or top level) by `v`.
    pub(crate) fn replace_unknown(&mut self, v: u32) {
        for e in self.top.iter_mut().chain(self.pages.iter_mut()) {
            if *e == UNKNOWN {
                *e = v;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Entries written through `set` read back through `get`, and untouched cells keep the fill,
    /// against a dense array as the oracle; pages only where a cell differs from the fill.
    #[test]
    fn matches_a_dense_index() {
        let cells = [19, 9, 17];
        let mut idx = BlockIndex::new(cells, UNKNOWN);
        let mut dense = vec![UNKNOWN; cells[0] * cells[1] * cells[2]];
        let id = |c: [usize; 3]| (c[2] * cells[1] + c[1]) * cells[0] + c[0];
        let mut x = 12345u64;
        for n in 0..300u32 {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let c = [
                (x >> 33) as usize % cells[0],
                (x >> 40) as usize % cells[1],
                (x >> 47) as usize % cells[2],
            ];
            let v = if n % 7 == 0 { AIR } else { n };
            idx.set(c, v);
            dense[id(c)] = v;
        }
        for k in 0..cells[2] {
            for j in 0..cells[1] {
                for i in 0..cells[0] {
                    assert_eq!(idx.get([i, j, k]), dense[id([i, j, k])], "{i} {j} {k}");
                }
            }
        }
        assert!(idx.page_top.len() <= 18, "3 x 2 x 3 top-level cells");
        let unknown = idx.paged_cells(UNKNOWN).count()
            + idx
                .uniform_tops(UNKNOWN)
                .map(|t| {
                    let b = idx.top_coords(t).map(|x| x * PAGE);
                    (0..3)
                        .map(|a| (cells[a] - b[a]).min(PAGE))
                        .product::<usize>()
                })
                .sum::<usize>();
        assert_eq!(unknown, dense.iter().filter(|&&e| e == UNKNOWN).count());
        // Each face of a top-level cell inside the grid holds at most PAGE^2 cells, all on it.
        for t in 0..idx.top.len() {
            for f in 0..6 {
                for c in idx.face_cells(t, f) {
                    assert_eq!(idx.top_id(c), t);
                }
            }
        }
    }
}
