//! Transparent huge pages for the large arrays of a long search: a global allocator that asks
//! Linux to back every allocation of at least [`HUGE_PAGE_THRESHOLD`] bytes with 2 MiB pages.
//!
//! **Why.** The first SHP of a long map pops funnels in key order, and on a crater strip whose
//! shortest path is a few metres longer than the straight line the queue holds funnels all along
//! the strip at once: nearly every read of the funnel tree, the queue and the per-vertex and
//! per-triangle arrays misses the cache *and* the TLB (4 KiB pages: a few thousand TLB entries
//! cover a few MiB, against 3 GB of search state on the 1,000,000-obstacle strip). With 2 MiB
//! pages the same entries cover gigabytes and a miss costs one memory access instead of a page
//! walk and the access. Measured on the generated strips (`docs/planner.md`, "Huge pages"), the
//! same search, expansion for expansion.
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
//! This module and `crates/cli/src/closed_stdout.rs` are the workspace's audited `unsafe` code:
//! a [`GlobalAlloc`] is an unsafe trait, every method forwards to [`System`] with the caller's
//! own arguments, and the `madvise` call passes a range inside the block just returned.

#![allow(unsafe_code)]

use std::alloc::{GlobalAlloc, Layout, System};

/// Allocations of at least this many bytes (16 MiB, eight huge pages) are advised to use huge
/// pages. Below it the rounding to 2 MiB pages costs memory for little time: with a 4 MiB
/// threshold `rappel plan --classes 100` on the 10,000-obstacle strip peaked 1.5 MiB higher
/// (47.8 against 46.3 MiB, medians of 11) in the same time, while the arrays that make a long
/// search wait on the TLB are hundreds of MiB.
pub const HUGE_PAGE_THRESHOLD: usize = 16 << 20;

/// The system allocator, with every allocation of at least [`HUGE_PAGE_THRESHOLD`] bytes advised
/// to use transparent huge pages on Linux (module docs). Install it with `#[global_allocator]`.
#[derive(Debug, Clone, Copy, Default)]
pub struct HugePageAlloc;

// SAFETY: every method forwards to `System` with the caller's arguments and returns its result
// unchanged; `advise` only gives the kernel a hint about pages inside the block `System` returned.
unsafe impl GlobalAlloc for HugePageAlloc {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: the caller upholds `GlobalAlloc::alloc`'s contract, which `System` shares.
        let p = unsafe { System.alloc(layout) };
        advise(p, layout.size());
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        // SAFETY: as `alloc`.
        let p = unsafe { System.alloc_zeroed(layout) };
        advise(p, layout.size());
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: `ptr` came from `System` through this allocator with this layout.
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY: `ptr` came from `System` through this allocator with this layout.
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if new_size > layout.size() {
            advise(p, new_size);
        }
        p
    }
}

/// The whole 4 KiB pages of the block `[p, p + len)`: the range `madvise` may be given.
fn whole_pages(p: usize, len: usize) -> Option<(usize, usize)> {
    const PAGE: usize = 4096;
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

/// Other platforms: nothing to advise.
#[cfg(not(target_os = "linux"))]
fn advise(_p: *mut u8, _len: usize) {}

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
}
