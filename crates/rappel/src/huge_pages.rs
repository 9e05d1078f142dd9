//! Transparent huge pages for the large arrays of a long search: a global allocator that asks
//! Linux to back every allocation of at least [`HUGE_PAGE_THRESHOLD`] bytes with 2 MiB pages.
//!
//! **Why.** A long search reads gigabytes of state. In the A* order the first SHP of a crater
//! strip pops funnels from all along the strip at once (their keys differ by less than the few
//! metres by which the shortest path beats the straight line), so nearly every read of the funnel
//! tree, the queue and the per-vertex and per-triangle arrays misses the cache *and* the TLB
//! (4 KiB pages: a few thousand TLB entries cover a few MiB, against 3 GB of search state on the
//! 1,000,000-obstacle strip). The one-class search now sweeps the map band by band instead
//! (`rappel_planners::spt`, "The wave order"), which makes most reads local, but the bands still
//! revisit the whole map and other searches (several classes, the shortest path map) keep the A*
//! order. With 2 MiB pages the same TLB entries cover gigabytes and a miss costs one memory
//! access instead of a page walk and the access. Measured on the generated strips
//! (`docs/planner.md`, "Huge pages"), the same search, expansion for expansion.
//!
//! **How.** Most Linux systems ship transparent huge pages in `madvise` mode
//! (`/sys/kernel/mm/transparent_hugepage/enabled` reads `always [madvise] never`): only memory
//! the process marks with `madvise(MADV_HUGEPAGE)` gets huge pages. [`HugePageAlloc`] wraps the
//! system allocator and marks the whole 4 KiB pages inside every allocation of at least
//! [`HUGE_PAGE_THRESHOLD`] bytes, on `alloc`, `alloc_zeroed` and a growing `realloc`. Smaller
//! allocations are passed through untouched, so the many small vectors of a plan cost nothing
//! extra. The advice is a hint: it changes no byte of any answer, and where the kernel has no
//! transparent huge pages (or another platform) the call fails or is skipped and the allocator
//! behaves exactly as [`System`]; its result is therefore not checked (there is nothing to report
//! and nothing to do differently).
//!
//! **Use.** The `rappel` command line and the benchmarks install it; a program that embeds the
//! library and plans on large maps installs it the same way, in its binary crate:
//!
//! ```
//! #[global_allocator]
//! static ALLOC: rappel::huge_pages::HugePageAlloc = rappel::huge_pages::HugePageAlloc;
//!
//! let v = vec![0u64; 1 << 22]; // 32 MiB: advised
//! assert_eq!(v.len(), 1 << 22);
//! ```
//!
//! The cost is memory: a huge page is faulted in whole, so an advised array rounds its resident
//! size up to 2 MiB boundaries (at most 2 MiB per allocation over the threshold, an eighth of the smallest).
//!
//! **Growing without copying.** On Linux the blocks over the threshold (with an alignment of at
//! most a page) are mapped by this allocator itself (`mmap`), and a growing vector's block is
//! moved by `mremap`, which moves the page tables instead of the bytes. The system allocator
//! (glibc 2.36 here) copied such a block into a new mapping: growing the search tree of the
//! 1,000,000-obstacle strip from 2.4 to 4.8 GB of capacity held both copies at once, about 1.6 GB
//! over the search's own peak for a moment, and spent the copy's time. Smaller blocks, and every
//! block elsewhere than Linux, stay with [`System`].
//!
//! This module and `crates/cli/src/closed_stdout.rs` are the workspace's audited `unsafe` code:
//! a [`GlobalAlloc`] is an unsafe trait; a block is mapped or left to [`System`] by its layout
//! alone ([`is_mapped`]), so every block is freed and resized by the side that made it; the
//! `madvise` call passes a range inside the block just returned.

#![allow(unsafe_code)]

use std::alloc::{GlobalAlloc, Layout, System};

/// Allocations of at least this many bytes (16 MiB, eight huge pages) are advised to use huge
/// pages. Below it the rounding to 2 MiB pages costs memory for little time: with a 4 MiB
/// threshold `rappel plan --classes 100` on the 10,000-obstacle strip peaked 1.5 MiB higher
/// (47.8 against 46.3 MiB, medians of 11) in the same time, while the arrays that make a long
/// search wait on the TLB are hundreds of MiB.
pub const HUGE_PAGE_THRESHOLD: usize = 16 << 20;

/// The system allocator, with every allocation of at least [`HUGE_PAGE_THRESHOLD`] bytes mapped
/// by itself and advised to use transparent huge pages on Linux (module docs). Install it with
/// `#[global_allocator]`.
#[derive(Debug, Clone, Copy, Default)]
pub struct HugePageAlloc;

/// The size of a page, the largest alignment a mapped block has.
const PAGE: usize = 4096;

/// Whether a block of this layout is mapped by [`HugePageAlloc`] itself (Linux, at least
/// [`HUGE_PAGE_THRESHOLD`] bytes, aligned to at most a page) rather than left to [`System`]. A
/// block's layout decides it for its whole life: `dealloc` and `realloc` are given the layout
/// the block was made (or last resized) with.
pub fn is_mapped(layout: Layout) -> bool {
    cfg!(target_os = "linux") && layout.size() >= HUGE_PAGE_THRESHOLD && layout.align() <= PAGE
}

// SAFETY: a block is mapped (`map`, `unmap`, `remap`) or left to `System` by its layout alone
// (`is_mapped`), so each block is resized and freed by the side that made it, with the sizes it
// was made with; a mapped block is page-aligned (every alignment `is_mapped` admits) and zeroed;
// `advise` only gives the kernel a hint about pages inside a block just returned.
unsafe impl GlobalAlloc for HugePageAlloc {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if is_mapped(layout) {
            return map(layout.size());
        }
        // SAFETY: the caller upholds `GlobalAlloc::alloc`'s contract, which `System` shares.
        unsafe { System.alloc(layout) }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        if is_mapped(layout) {
            // Fresh anonymous mappings read as zeros.
            return map(layout.size());
        }
        // SAFETY: as `alloc`.
        unsafe { System.alloc_zeroed(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        if is_mapped(layout) {
            unmap(ptr, layout.size());
            return;
        }
        // SAFETY: `ptr` came from `System` through this allocator with this layout.
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // `GlobalAlloc::realloc`'s contract: the new layout is valid.
        let new_layout = Layout::from_size_align(new_size, layout.align());
        let Ok(new_layout) = new_layout else {
            return std::ptr::null_mut();
        };
        match (is_mapped(layout), is_mapped(new_layout)) {
            (true, true) => remap(ptr, layout.size(), new_size),
            // SAFETY: `ptr` came from `System` through this allocator with this layout.
            (false, false) => unsafe { System.realloc(ptr, layout, new_size) },
            _ => {
                // Across the threshold: a new block from the other side, the bytes copied.
                // SAFETY: `new_layout` has a non-zero size (the caller's contract).
                let q = unsafe { self.alloc(new_layout) };
                if !q.is_null() {
                    // SAFETY: both blocks are live, distinct and at least this long.
                    unsafe {
                        std::ptr::copy_nonoverlapping(ptr, q, layout.size().min(new_size));
                        self.dealloc(ptr, layout);
                    }
                }
                q
            }
        }
    }
}

/// `size` rounded up to whole pages: the length of a block's mapping. Mappings are made, resized,
/// advised and unmapped whole, so each stays one kernel mapping with one set of flags (`mremap`
/// refuses a range that spans two, and an advice on part of a mapping splits it).
#[cfg(target_os = "linux")]
fn whole(size: usize) -> usize {
    size.div_ceil(PAGE) * PAGE
}

/// A new zeroed mapping of `size` bytes, advised to use huge pages; null when the kernel
/// refuses (the allocator's way to report it).
#[cfg(target_os = "linux")]
fn map(size: usize) -> *mut u8 {
    let size = whole(size);
    // SAFETY: an anonymous private mapping at an address of the kernel's choosing touches no
    // existing memory.
    let p = unsafe {
        libc::mmap(
            std::ptr::null_mut(),
            size,
            libc::PROT_READ | libc::PROT_WRITE,
            libc::MAP_PRIVATE | libc::MAP_ANONYMOUS,
            -1,
            0,
        )
    };
    if p == libc::MAP_FAILED {
        return std::ptr::null_mut();
    }
    let p = p.cast::<u8>();
    advise(p, size);
    p
}

/// Unmaps a block [`map`] or [`remap`] made `size` bytes long.
#[cfg(target_os = "linux")]
fn unmap(p: *mut u8, size: usize) {
    let size = whole(size);
    // SAFETY: `[p, p + size)` is a whole mapping of ours (rounded up to pages by the kernel, as
    // when it was made); nothing refers to it any more (the caller's contract).
    let _ = unsafe { libc::munmap(p.cast(), size) };
}

/// Resizes a mapped block of `old` bytes to `new` bytes, moving its page tables (not its bytes)
/// when it cannot grow in place; null when the kernel refuses (the block is then unchanged).
#[cfg(target_os = "linux")]
fn remap(p: *mut u8, old: usize, new: usize) -> *mut u8 {
    let (old, new) = (whole(old), whole(new));
    if old == new {
        return p;
    }
    // SAFETY: `[p, p + old)` is a whole mapping of ours; MREMAP_MAYMOVE lets the kernel move it
    // to free address space, keeping its contents (and zeros beyond them).
    let q = unsafe { libc::mremap(p.cast(), old, new, libc::MREMAP_MAYMOVE) };
    if q == libc::MAP_FAILED {
        return std::ptr::null_mut();
    }
    let q = q.cast::<u8>();
    if new > old {
        advise(q, new);
    }
    q
}

/// Other platforms map nothing ([`is_mapped`] is false there).
#[cfg(not(target_os = "linux"))]
fn map(_size: usize) -> *mut u8 {
    std::ptr::null_mut()
}

/// Other platforms map nothing ([`is_mapped`] is false there).
#[cfg(not(target_os = "linux"))]
fn unmap(_p: *mut u8, _size: usize) {}

/// Other platforms map nothing ([`is_mapped`] is false there).
#[cfg(not(target_os = "linux"))]
fn remap(_p: *mut u8, _old: usize, _new: usize) -> *mut u8 {
    std::ptr::null_mut()
}

/// The whole 4 KiB pages of the block `[p, p + len)`: the range `madvise` may be given.
fn whole_pages(p: usize, len: usize) -> Option<(usize, usize)> {
    let start = p.checked_add(PAGE - 1)? & !(PAGE - 1);
    let end = p.checked_add(len)? & !(PAGE - 1);
    (end > start).then(|| (start, end - start))
}

/// Advises the whole pages of a block of `len` bytes at `p` to use huge pages, when the block is
/// at least [`HUGE_PAGE_THRESHOLD`] long (module docs: the result is a hint and is not checked).
#[cfg(target_os = "linux")]
fn advise(p: *mut u8, len: usize) {
    if p.is_null() || len < HUGE_PAGE_THRESHOLD {
        return;
    }
    if let Some((start, n)) = whole_pages(p as usize, len) {
        // SAFETY: `[start, start + n)` lies inside the block just allocated and is page-aligned;
        // MADV_HUGEPAGE changes only how the kernel backs those pages, never their contents.
        let _ = unsafe { libc::madvise(start as *mut libc::c_void, n, libc::MADV_HUGEPAGE) };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn whole_pages_lie_inside_the_block() {
        // Aligned block: all of it.
        assert_eq!(whole_pages(8192, 3 * 4096), Some((8192, 3 * 4096)));
        // Unaligned start and end: the pages strictly inside.
        assert_eq!(whole_pages(4096 + 16, 3 * 4096), Some((8192, 2 * 4096)));
        // Less than one whole page: nothing.
        assert_eq!(whole_pages(4096 + 16, 4096), None);
        // Near the top of the address space: no overflow.
        assert_eq!(whole_pages(usize::MAX - 10, 100), None);
    }

    #[test]
    fn the_allocator_round_trips_large_and_small_blocks() {
        let a = HugePageAlloc;
        for (size, align) in [
            (16, 8),
            (HUGE_PAGE_THRESHOLD, 4096),
            (HUGE_PAGE_THRESHOLD + 1, 8),
            // Beyond a page's alignment: left to the system allocator however large.
            (HUGE_PAGE_THRESHOLD, 8192),
        ] {
            let layout = Layout::from_size_align(size, align).expect("valid layout");
            // SAFETY: a non-zero size; the block is written within bounds and freed once with the
            // layout it was allocated with (after the realloc, the new size's layout).
            unsafe {
                let p = a.alloc_zeroed(layout);
                assert!(!p.is_null());
                assert_eq!(*p.add(size - 1), 0);
                *p.add(size - 1) = 7;
                let q = a.realloc(p, layout, 2 * size);
                assert!(!q.is_null());
                assert_eq!(*q.add(size - 1), 7, "realloc keeps the contents");
                a.dealloc(
                    q,
                    Layout::from_size_align(2 * size, align).expect("valid layout"),
                );
            }
        }
    }

    /// Blocks that cross the threshold either way, and mapped blocks that grow and shrink, keep
    /// their bytes (a pattern written over the whole of the smaller size is read back).
    #[test]
    fn resizing_across_the_threshold_keeps_the_contents() {
        let a = HugePageAlloc;
        let small = 1 << 20;
        let large = HUGE_PAGE_THRESHOLD + 12_345;
        let huge = 3 * HUGE_PAGE_THRESHOLD;
        let steps = [small, large, huge, large, small, huge, 64];
        let layout = |size| Layout::from_size_align(size, 8).expect("valid layout");
        let byte = |i: usize| (i.wrapping_mul(2_654_435_761) >> 7) as u8;
        assert!(!is_mapped(layout(small)));
        assert_eq!(is_mapped(layout(large)), cfg!(target_os = "linux"));
        // SAFETY: every block is written and read within its size, resized with the layout it
        // has, and freed once with its last layout.
        unsafe {
            let mut p = a.alloc(layout(small));
            assert!(!p.is_null());
            for i in 0..small {
                *p.add(i) = byte(i);
            }
            let mut size = small;
            for &next in &steps[1..] {
                p = a.realloc(p, layout(size), next);
                assert!(!p.is_null(), "{size} -> {next}");
                let kept = size.min(next).min(small);
                for i in (0..kept).step_by(4093) {
                    assert_eq!(*p.add(i), byte(i), "{size} -> {next}: byte {i}");
                }
                // Grown mapped blocks read as zeros beyond the old end.
                if next > size && is_mapped(layout(next)) && is_mapped(layout(size)) {
                    assert_eq!(*p.add(next - 1), 0);
                }
                for i in 0..next.min(small) {
                    *p.add(i) = byte(i);
                }
                size = next;
            }
            a.dealloc(p, layout(size));
        }
    }
}
