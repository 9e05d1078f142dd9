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

/// The order word of a queued entry: the key's bits made order-preserving (the order of
/// [`f64::total_cmp`]) in the high 64 bits, the rank in the next 32 and the arena index in the low
/// 32, so that one unsigned comparison decides `(key, rank, index)`.
fn order_word(key: f64, rank: u32, item: u32) -> u128 {
    let bits = key.to_bits();
    // Negative values (sign set) reverse their order; positive ones go above them.
    let ordered = if bits >> 63 == 1 {
        !bits
    } else {
        bits | 1 << 63
    };
    (u128::from(ordered) << 64) | (u128::from(rank) << 32) | u128::from(item)
}

/// The key of an order word ([`order_word`] inverted).
fn key_of(word: u128) -> f64 {
    let ordered = (word >> 64) as u64;
    f64::from_bits(if ordered >> 63 == 1 {
        ordered & !(1 << 63)
    } else {
        !ordered
    })
}

/// Children per heap node.
const ARITY: usize = 4;

/// No entry: above every real order word (whose arena index is below `u32::MAX`).
const VACANT: u128 = u128::MAX;

/// Four sibling entries, aligned to one 64-byte cache line.
#[derive(Debug, Clone, Copy)]
#[repr(C, align(64))]
struct Line([u128; ARITY]);

/// A min-priority queue of `(key, item)`, smallest key first and on equal keys smallest
/// [`Rank::rank`] first (as a [`BinaryHeap`](std::collections::BinaryHeap) of [`MinEntry`]);
/// equal `(key, rank)` pairs pop in the order of their arena index, so the order is a function of
/// the operations alone. The items live in an arena whose slots are reused through a free list;
/// the heap is 4-ary over 16-byte order words ([`order_word`]), laid out so that the four
/// children of a node fill one cache line: logical position `p` is slot `p + 3` of the lines,
/// so the children `4p + 1 ..= 4p + 4` are exactly line `p + 1`, and vacant slots hold
/// [`VACANT`] so that the smallest child is found without bounds tests. A pop moves the hole
/// from the root down along the smallest children to a leaf and the last entry up from there
/// (Floyd's bottom-up deletion: the last entry usually belongs near the bottom).
/// Memory: 20 bytes plus the item per entry at the peak, kept (cleared, not freed) for reuse.
#[derive(Debug, Clone)]
pub(crate) struct ArenaHeap<T> {
    lines: Vec<Line>,
    len: usize,
    items: Vec<T>,
    free: Vec<u32>,
}

impl<T> Default for ArenaHeap<T> {
    /// An empty queue, allocating nothing (no `T: Default` bound, unlike the derived one).
    fn default() -> Self {
        ArenaHeap {
            lines: Vec::new(),
            len: 0,
            items: Vec::new(),
            free: Vec::new(),
        }
    }
}

impl<T: Rank + Copy> ArenaHeap<T> {
    /// Number of queued items.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Empties the queue, keeping its storage.
    pub fn clear(&mut self) {
        self.lines.clear();
        self.len = 0;
        self.items.clear();
        self.free.clear();
    }

    /// Bytes held (capacities).
    pub fn held_bytes(&self) -> usize {
        self.lines.capacity() * std::mem::size_of::<Line>()
            + self.items.capacity() * std::mem::size_of::<T>()
            + self.free.capacity() * std::mem::size_of::<u32>()
    }

    /// Bytes in use: the queued entries and the arena's slots (free ones included).
    pub fn live_bytes(&self) -> usize {
        self.len * std::mem::size_of::<u128>()
            + self.items.len() * std::mem::size_of::<T>()
            + self.free.len() * std::mem::size_of::<u32>()
    }

    #[inline]
    fn get(&self, p: usize) -> u128 {
        self.lines[(p + 3) / ARITY].0[(p + 3) % ARITY]
    }

    #[inline]
    fn set(&mut self, p: usize, word: u128) {
        self.lines[(p + 3) / ARITY].0[(p + 3) % ARITY] = word;
    }

    /// Queues `item` with priority `key`.
    ///
    /// # Panics
    /// Beyond `u32::MAX - 1` items queued at once (the arena's index).
    pub fn push(&mut self, key: f64, item: T) {
        let index = match self.free.pop() {
            Some(i) => {
                self.items[i as usize] = item;
                i
            }
            None => {
                let i = u32::try_from(self.items.len())
                    .ok()
                    .filter(|&i| i < u32::MAX)
                    .expect("fewer than 2^32 - 1 queued items");
                self.items.push(item);
                i
            }
        };
        let word = order_word(key, item.rank() as u32, index);
        let at = self.len;
        if (at + 3) / ARITY == self.lines.len() {
            self.lines.push(Line([VACANT; ARITY]));
        }
        self.len += 1;
        self.sift_up(at, word);
    }

    /// Places `word` at the hole `at` or above it: its ancestors larger than it move down.
    #[inline]
    fn sift_up(&mut self, mut at: usize, word: u128) {
        while at > 0 {
            let parent = (at - 1) / ARITY;
            let above = self.get(parent);
            if word >= above {
                break;
            }
            self.set(at, above);
            at = parent;
        }
        self.set(at, word);
    }

    /// Removes and returns the first `(key, item)`.
    pub fn pop(&mut self) -> Option<(f64, T)> {
        if self.len == 0 {
            return None;
        }
        let top = self.get(0);
        self.len -= 1;
        let n = self.len;
        let last = self.get(n);
        self.set(n, VACANT);
        if n > 0 {
            // The hole goes down along the smallest children to a leaf...
            let mut at = 0;
            while let Some(line) = self.lines.get(at + 1) {
                let c = &line.0;
                let (i01, w01) = if c[0] <= c[1] { (0, c[0]) } else { (1, c[1]) };
                let (i23, w23) = if c[2] <= c[3] { (2, c[2]) } else { (3, c[3]) };
                let (i, w) = if w01 <= w23 { (i01, w01) } else { (i23, w23) };
                if w == VACANT {
                    break;
                }
                self.set(at, w);
                at = ARITY * at + 1 + i;
            }
            // ... and the last entry comes up from there.
            self.sift_up(at, last);
        }
        let index = top as u32;
        self.free.push(index);
        Some((key_of(top), self.items[index as usize]))
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

    /// The order words sort as `f64::total_cmp` sorts the keys (zeros of both signs,
    /// infinities, subnormals), and give the key back bit for bit.
    #[test]
    fn order_words_follow_total_cmp() {
        let keys = [
            f64::NEG_INFINITY,
            -1.5,
            -f64::MIN_POSITIVE / 4.0,
            -0.0,
            0.0,
            f64::MIN_POSITIVE / 4.0,
            1.0,
            1.0 + f64::EPSILON,
            f64::MAX,
            f64::INFINITY,
        ];
        for a in keys {
            assert_eq!(key_of(order_word(a, 1, 7)).to_bits(), a.to_bits());
            for b in keys {
                assert_eq!(
                    order_word(a, 0, 0).cmp(&order_word(b, 0, 0)),
                    a.total_cmp(&b)
                );
            }
        }
        // On equal keys the rank, then the index, decide.
        assert!(order_word(1.0, 0, 9) < order_word(1.0, 1, 0));
        assert!(order_word(1.0, 1, 2) < order_word(1.0, 1, 3));
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
            let mut ours = ArenaHeap::default();
            let mut oracle = BinaryHeap::new();
            let mut popped = Vec::new();
            let mut serial = 0u64;
            for _ in 0..(500 * (round + 1)) {
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
