//! The entry of the planners' min-priority queues: `std`'s [`BinaryHeap`](std::collections::BinaryHeap)
//! is a max-heap, so the SPT search ([`crate::spt`]), the shortest path map
//! ([`crate::shortest_path_map`]) and the visibility-graph oracle ([`crate::visibility_graph`])
//! all queue a [`MinEntry`], ordered smallest key first and, on equal keys, smallest
//! [`Rank::rank`] first, written once here.
//!
//! The SPT search, whose queue holds up to about a million funnels on a 100,000-obstacle strip,
//! queues them in an [`ArenaHeap`] instead: the same order on `(key, rank)`, with the items kept
//! in an arena beside a 4-ary heap of 16-byte entries, so that a pop sifts through about half as
//! many levels, each one cache line, instead of moving 32-byte items through a binary heap.

use std::cmp::Ordering;

/// How queued items of equal key are ordered: the smaller rank is popped first.
pub(crate) trait Rank {
    /// The tie-break rank (0 when the order of equal keys does not matter).
    fn rank(&self) -> usize;
}

/// A queued item with its key; [`Ord`] makes a [`BinaryHeap`](std::collections::BinaryHeap) of
/// them a min-heap by `(key, item.rank())` (keys compared by [`f64::total_cmp`]).
#[derive(Debug, Clone, Copy)]
pub(crate) struct MinEntry<T> {
    /// The priority: smallest first.
    pub key: f64,
    /// What is queued.
    pub item: T,
}

impl<T: Rank> PartialEq for MinEntry<T> {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl<T: Rank> Eq for MinEntry<T> {}

impl<T: Rank> PartialOrd for MinEntry<T> {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl<T: Rank> Ord for MinEntry<T> {
    /// Reversed, so that the max-heap pops the smallest key, then the smallest rank.
    fn cmp(&self, other: &Self) -> Ordering {
        other
            .key
            .total_cmp(&self.key)
            .then_with(|| other.item.rank().cmp(&self.item.rank()))
    }
}

/// One entry of an [`ArenaHeap`]: 16 bytes, four siblings to a 64-byte cache line.
#[derive(Debug, Clone, Copy)]
struct Slot {
    key: f64,
    rank: u32,
    /// The item's index in the arena.
    item: u32,
}

impl Slot {
    /// The heap order: smaller key ([`f64::total_cmp`]), then smaller rank, then smaller arena
    /// index (so the order of equal entries is a function of the operations alone).
    #[inline]
    fn before(&self, other: &Slot) -> bool {
        match self.key.total_cmp(&other.key) {
            Ordering::Less => true,
            Ordering::Greater => false,
            Ordering::Equal => (self.rank, self.item) < (other.rank, other.item),
        }
    }
}

/// Children per heap node.
const ARITY: usize = 4;

/// A min-priority queue of `(key, item)`, smallest key first and on equal keys smallest
/// [`Rank::rank`] first (as a [`BinaryHeap`](std::collections::BinaryHeap) of [`MinEntry`]);
/// equal `(key, rank)` pairs pop in the order of their arena index. The items live in an arena
/// whose slots are reused through a free list; the heap itself is 4-ary over 16-byte entries.
/// Memory: 20 bytes plus the item per entry at the peak, kept (cleared, not freed) for reuse.
#[derive(Debug, Clone, Default)]
pub(crate) struct ArenaHeap<T> {
    heap: Vec<Slot>,
    items: Vec<T>,
    free: Vec<u32>,
}

impl<T: Rank + Copy> ArenaHeap<T> {
    /// An empty queue.
    pub fn new() -> Self {
        ArenaHeap {
            heap: Vec::new(),
            items: Vec::new(),
            free: Vec::new(),
        }
    }

    /// Number of queued items.
    pub fn len(&self) -> usize {
        self.heap.len()
    }

    /// Empties the queue, keeping its storage.
    pub fn clear(&mut self) {
        self.heap.clear();
        self.items.clear();
        self.free.clear();
    }

    /// Bytes held (capacities).
    pub fn held_bytes(&self) -> usize {
        self.heap.capacity() * std::mem::size_of::<Slot>()
            + self.items.capacity() * std::mem::size_of::<T>()
            + self.free.capacity() * std::mem::size_of::<u32>()
    }

    /// Bytes in use: the queued entries and the arena's slots (free ones included).
    pub fn live_bytes(&self) -> usize {
        self.heap.len() * std::mem::size_of::<Slot>()
            + self.items.len() * std::mem::size_of::<T>()
            + self.free.len() * std::mem::size_of::<u32>()
    }

    /// Queues `item` with priority `key`.
    ///
    /// # Panics
    /// Beyond `u32::MAX` items queued at once (the arena's index).
    pub fn push(&mut self, key: f64, item: T) {
        let index = match self.free.pop() {
            Some(i) => {
                self.items[i as usize] = item;
                i
            }
            None => {
                let i = u32::try_from(self.items.len()).expect("fewer than 2^32 queued items");
                self.items.push(item);
                i
            }
        };
        let slot = Slot {
            key,
            rank: item.rank() as u32,
            item: index,
        };
        // Sift up from a new leaf.
        let mut at = self.heap.len();
        self.heap.push(slot);
        while at > 0 {
            let parent = (at - 1) / ARITY;
            if !slot.before(&self.heap[parent]) {
                break;
            }
            self.heap[at] = self.heap[parent];
            at = parent;
        }
        self.heap[at] = slot;
    }

    /// Removes and returns the first `(key, item)`.
    pub fn pop(&mut self) -> Option<(f64, T)> {
        let last = self.heap.pop()?;
        let top = match self.heap.first_mut() {
            Some(first) => std::mem::replace(first, last),
            None => last,
        };
        let n = self.heap.len();
        if n > 1 {
            // Sift the moved last entry down from the root.
            let mut at = 0;
            loop {
                let first = ARITY * at + 1;
                if first >= n {
                    break;
                }
                let end = (first + ARITY).min(n);
                let mut best = first;
                for c in first + 1..end {
                    if self.heap[c].before(&self.heap[best]) {
                        best = c;
                    }
                }
                if !self.heap[best].before(&last) {
                    break;
                }
                self.heap[at] = self.heap[best];
                at = best;
            }
            self.heap[at] = last;
        }
        self.free.push(top.item);
        Some((top.key, self.items[top.item as usize]))
    }
}

impl Rank for usize {
    /// The value itself (the visibility graph's node index).
    fn rank(&self) -> usize {
        *self
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BinaryHeap;

    #[test]
    fn pops_smallest_key_then_smallest_rank() {
        let mut heap = BinaryHeap::new();
        for (key, item) in [(2.0, 1usize), (1.0, 7), (1.0, 3), (-0.5, 9), (2.0, 0)] {
            heap.push(MinEntry { key, item });
        }
        let order: Vec<(f64, usize)> = std::iter::from_fn(|| heap.pop())
            .map(|e| (e.key, e.item))
            .collect();
        assert_eq!(order, [(-0.5, 9), (1.0, 3), (1.0, 7), (2.0, 0), (2.0, 1)]);
    }

    /// An item whose rank is its own field, for the arena heap's tests.
    #[derive(Debug, Clone, Copy, PartialEq)]
    struct Ranked(usize, u64);

    impl Rank for Ranked {
        fn rank(&self) -> usize {
            self.0
        }
    }

    /// Against `std`'s binary heap of [`MinEntry`] as the oracle: seeded random pushes and pops
    /// (keys drawn from a few values so that ties are common, ranks 0 or 1) pop the same
    /// `(key, rank)` sequence, and every item pushed comes out once.
    #[test]
    fn arena_heap_pops_in_min_entry_order() {
        let mut state = 0x9E37_79B9_7F4A_7C15u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        for round in 0..20 {
            let mut ours = ArenaHeap::new();
            let mut oracle = BinaryHeap::new();
            let mut popped = Vec::new();
            let mut serial = 0u64;
            for _ in 0..2_000 {
                if next() % 3 != 0 || ours.len() == 0 {
                    let key = (next() % (2 + round)) as f64 * 0.5;
                    let item = Ranked((next() % 2) as usize, serial);
                    serial += 1;
                    ours.push(key, item);
                    oracle.push(MinEntry { key, item: item.0 });
                } else {
                    let (key, item) = ours.pop().unwrap();
                    let expected = oracle.pop().unwrap();
                    assert_eq!((key, item.0), (expected.key, expected.item));
                    popped.push(item.1);
                }
                assert_eq!(ours.len(), oracle.len());
            }
            while let Some((key, item)) = ours.pop() {
                let expected = oracle.pop().unwrap();
                assert_eq!((key, item.0), (expected.key, expected.item));
                popped.push(item.1);
            }
            assert!(oracle.pop().is_none());
            popped.sort_unstable();
            assert!(
                popped.iter().copied().eq(0..serial),
                "every item exactly once"
            );
            // Cleared, it starts over empty.
            ours.clear();
            assert!(ours.pop().is_none());
        }
    }
}
