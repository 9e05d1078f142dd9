//! The entry of the planners' min-priority queues: `std`'s [`BinaryHeap`](std::collections::BinaryHeap)
//! is a max-heap, so the SPT search ([`crate::spt`]), the shortest path map
//! ([`crate::shortest_path_map`]) and the visibility-graph oracle ([`crate::visibility_graph`])
//! all queue a [`MinEntry`], ordered smallest key first and, on equal keys, smallest
//! [`Rank::rank`] first, written once here.
//!
//! The SPT search, whose queue holds up to about a million funnels on a 100,000-obstacle strip,
//! queues them in an [`ArenaHeap`] instead: the same order on `(key, rank)`, with the items kept
//! in an arena beside a radix heap of 16-byte entries over the keys' bits, which appends where a
//! binary heap would sift through levels far larger than the cache (the search's keys never fall
//! below the last key popped).

use std::cmp::{Ordering, Reverse};
use std::collections::BinaryHeap;

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
#[cfg(test)]
fn order_word(key: f64, rank: u32, item: u32) -> u128 {
    order_word_of(ordered_bits(key), rank, item)
}

/// [`order_word`] from a key's order-preserving bits.
fn order_word_of(ordered: u64, rank: u32, item: u32) -> u128 {
    (u128::from(ordered) << 64) | (u128::from(rank) << 32) | u128::from(item)
}

/// A key's bits made order-preserving: for any `a`, `b`,
/// `ordered_bits(a).cmp(&ordered_bits(b)) == a.total_cmp(&b)` (the high half of an
/// [`order_word`]).
pub(crate) fn ordered_bits(key: f64) -> u64 {
    let bits = key.to_bits();
    // Negative values (sign set) reverse their order; positive ones go above them.
    if bits >> 63 == 1 {
        !bits
    } else {
        bits | 1 << 63
    }
}

/// The key of an order word ([`order_word`] inverted).
#[cfg(test)]
fn key_of(word: u128) -> f64 {
    key_of_ordered((word >> 64) as u64)
}

/// The key of its order-preserving bits (the high half of an [`order_word`]; [`ordered_bits`]
/// inverted).
pub(crate) fn key_of_ordered(ordered: u64) -> f64 {
    f64::from_bits(if ordered >> 63 == 1 {
        ordered & !(1 << 63)
    } else {
        !ordered
    })
}

/// Buckets of [`ArenaHeap`] above the keys equal to the last one popped: one per bit of a key.
const BUCKETS: usize = 64;

/// A min-priority queue of `(key, item)`, smallest key first and on equal keys smallest
/// [`Rank::rank`] first (as a [`BinaryHeap`](std::collections::BinaryHeap) of [`MinEntry`]);
/// equal `(key, rank)` pairs pop in the order of their arena index, so the order is a function of
/// the operations alone. The items live in an arena whose slots are reused through a free list.
///
/// # A radix heap
/// The SPT search keys a child no lower than its parent (pathmax, [`crate::spt`]), so the keys it
/// pushes never fall below the last key popped. The queue exploits that as a radix heap over the
/// keys' order-preserving bits ([`order_word`]'s high half): an entry whose key differs from the
/// last popped key `last` first at bit `b` waits, unsorted, in bucket `b` (16 bytes appended to a
/// vector, no sifting through a heap far larger than the cache); entries whose key equals `last`
/// wait in a small binary heap on `(rank, index)`. A pop takes from that heap; when it is empty
/// the lowest non-empty bucket's smallest key becomes `last` and the bucket's entries move to
/// lower buckets or to the heap of equals. An entry only ever moves down, at most once per bit.
/// Keys below `last` (never pushed by the search, but any caller may) go to a binary heap of
/// whole order words popped before everything else, so the order is exact for any sequence.
/// Memory: 16 bytes plus the item per queued entry; each bucket keeps the capacity of its own
/// peak (cleared, not freed, for reuse), so the storage held can exceed the queue's peak (on the
/// 100,000-obstacle strip the process's peak grew by 8 MB over the 4-ary heap's, of 609 MB).
#[derive(Debug, Clone)]
pub(crate) struct ArenaHeap<T> {
    /// The order-preserving bits of the last key popped from the buckets (0 before the first).
    last: u64,
    /// Entries keyed `last`, by `(rank << 32) | index`.
    equal: BinaryHeap<Reverse<u64>>,
    /// `(key bits, (rank << 32) | index)` whose key differs from `last` first at bit `b`, in
    /// `buckets[b]`.
    buckets: Vec<Vec<(u64, u64)>>,
    /// Bit `b` set when `buckets[b]` is not empty.
    occupied: u64,
    /// Whole order words of entries keyed below `last`.
    below: BinaryHeap<Reverse<u128>>,
    len: usize,
    items: Vec<T>,
    free: Vec<u32>,
}

impl<T> Default for ArenaHeap<T> {
    /// An empty queue, allocating nothing (no `T: Default` bound, unlike the derived one).
    fn default() -> Self {
        ArenaHeap {
            last: 0,
            equal: BinaryHeap::new(),
            buckets: Vec::new(),
            occupied: 0,
            below: BinaryHeap::new(),
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
        self.last = 0;
        self.equal.clear();
        self.buckets.iter_mut().for_each(Vec::clear);
        self.occupied = 0;
        self.below.clear();
        self.len = 0;
        self.items.clear();
        self.free.clear();
    }

    /// Bytes held (capacities).
    pub fn held_bytes(&self) -> usize {
        self.equal.capacity() * std::mem::size_of::<u64>()
            + self
                .buckets
                .iter()
                .map(|b| b.capacity() * std::mem::size_of::<(u64, u64)>())
                .sum::<usize>()
            + self.below.capacity() * std::mem::size_of::<u128>()
            + self.items.capacity() * std::mem::size_of::<T>()
            + self.free.capacity() * std::mem::size_of::<u32>()
    }

    /// Bytes in use: the queued entries and the arena's slots (free ones included).
    pub fn live_bytes(&self) -> usize {
        self.len * std::mem::size_of::<(u64, u64)>()
            + self.items.len() * std::mem::size_of::<T>()
            + self.free.len() * std::mem::size_of::<u32>()
    }

    /// Files `(ordered, tie)` by its first bit differing from `last` (`ordered >= last`).
    #[inline]
    fn file(&mut self, ordered: u64, tie: u64) {
        if ordered == self.last {
            self.equal.push(Reverse(tie));
        } else {
            let b = (63 - (ordered ^ self.last).leading_zeros()) as usize;
            self.buckets[b].push((ordered, tie));
            self.occupied |= 1 << b;
        }
    }

    /// Queues `item` with priority `key` and its own [`Rank::rank`] (the tests' form, checked
    /// against `std`'s heap of [`MinEntry`]; the search pushes order words).
    ///
    /// # Panics
    /// Beyond `u32::MAX - 1` items queued at once (the arena's index).
    #[cfg(test)]
    pub fn push(&mut self, key: f64, item: T) {
        let rank = item.rank() as u32;
        self.push_ordered(ordered_bits(key), rank, item);
    }

    /// Queues `item` under an order-preserving key word (any `u64`: smaller pops first) and a
    /// tie-break `rank` of its own choosing in place of [`Rank::rank`]: the queue of a caller whose
    /// priority is not one `f64` (the one-class search's wave order, [`crate::spt`]). Keys pushed
    /// with [`ArenaHeap::push`] are the words [`ordered_bits`] gives; the two may be mixed.
    ///
    /// # Panics
    /// Beyond `u32::MAX - 1` items queued at once (the arena's index).
    pub fn push_ordered(&mut self, ordered: u64, rank: u32, item: T) {
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
        if self.buckets.is_empty() {
            self.buckets = vec![Vec::new(); BUCKETS];
        }
        let word = order_word_of(ordered, rank, index);
        self.len += 1;
        if ordered < self.last {
            self.below.push(Reverse(word));
        } else {
            self.file(ordered, word as u64);
        }
    }

    /// Removes and returns the first `(key, item)` (the tests' form of
    /// [`ArenaHeap::pop_ordered`]).
    #[cfg(test)]
    pub fn pop(&mut self) -> Option<(f64, T)> {
        self.pop_ordered()
            .map(|(ordered, item)| (key_of_ordered(ordered), item))
    }

    /// Calls `f` on every queued item, in the order of their arena slots (not the queue's),
    /// letting it rewrite the item in place (its key and place in the queue are unchanged): the
    /// SPT search renumbers the tree nodes its funnels hold after collecting the tree
    /// ([`crate::spt`], "Collecting the tree"). The arena is read front to back, skipping the
    /// slots on the free list, so a pass over a queue far beyond the cache streams.
    pub fn for_each_queued_mut(&mut self, mut f: impl FnMut(&mut T)) {
        let mut free = vec![0u64; self.items.len().div_ceil(64)];
        for &i in &self.free {
            free[i as usize / 64] |= 1 << (i % 64);
        }
        for (i, item) in self.items.iter_mut().enumerate() {
            if free[i / 64] >> (i % 64) & 1 == 0 {
                f(item);
            }
        }
    }

    /// Removes and returns the first item with its key word ([`ArenaHeap::push_ordered`]).
    pub fn pop_ordered(&mut self) -> Option<(u64, T)> {
        if self.len == 0 {
            return None;
        }
        self.len -= 1;
        let (key, index) = if let Some(Reverse(word)) = self.below.pop() {
            ((word >> 64) as u64, word as u32)
        } else {
            if self.equal.is_empty() {
                // The lowest non-empty bucket holds the next key: it becomes `last`, and the
                // bucket's entries move below it (each to a lower bucket, or to the equals).
                let b = self.occupied.trailing_zeros() as usize;
                if b >= BUCKETS {
                    // Unreachable: `len` counts the entries of the buckets and both heaps.
                    self.len += 1;
                    return None;
                }
                let mut bucket = std::mem::take(&mut self.buckets[b]);
                self.occupied &= !(1 << b);
                self.last = bucket.iter().map(|e| e.0).min().unwrap_or(self.last);
                for &(ordered, tie) in &bucket {
                    self.file(ordered, tie);
                }
                bucket.clear();
                self.buckets[b] = bucket;
            }
            let Reverse(tie) = self.equal.pop()?;
            (self.last, tie as u32)
        };
        self.free.push(index);
        Some((key, self.items[index as usize]))
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

    /// The tests' seeded xorshift64 generator from the nonzero seed `state`.
    fn xorshift(mut state: u64) -> impl FnMut() -> u64 {
        move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        }
    }

    /// An item whose rank is its own field, for the arena heap's tests.
    #[derive(Debug, Clone, Copy, PartialEq)]
    struct Ranked(usize, u64);

    impl Rank for Ranked {
        fn rank(&self) -> usize {
            self.0
        }
    }

    /// An [`ArenaHeap`] beside `std`'s binary heap of [`MinEntry`] as its oracle, each item
    /// numbered as it is pushed.
    #[derive(Default)]
    struct Checked {
        ours: ArenaHeap<Ranked>,
        oracle: BinaryHeap<MinEntry<usize>>,
        pushed: u64,
    }

    impl Checked {
        /// Pushes an item of rank `rank` with `key` onto both.
        fn push(&mut self, key: f64, rank: usize) {
            self.ours.push(key, Ranked(rank, self.pushed));
            self.oracle.push(MinEntry { key, item: rank });
            self.pushed += 1;
        }

        /// Pops both, checking that they agree on `(key, rank)`: the key and the item's number.
        fn pop(&mut self) -> Option<(f64, u64)> {
            let popped = self.ours.pop();
            let expected = self.oracle.pop();
            assert_eq!(
                popped.map(|(k, item)| (k, item.0)),
                expected.map(|e| (e.key, e.item))
            );
            assert_eq!(self.ours.len(), self.oracle.len());
            popped.map(|(k, item)| (k, item.1))
        }

        /// Checks that [`ArenaHeap::for_each_queued_mut`] visits exactly the items not yet
        /// popped (`popped` holds their numbers), each once, and that what it writes is what
        /// pops: every item is rewritten to its number plus `2^40`, and rewritten back.
        fn check_queued(&mut self, popped: &[u64]) {
            let mut seen = Vec::new();
            self.ours.for_each_queued_mut(|item| {
                seen.push(item.1);
                item.1 += 1 << 40;
            });
            seen.sort_unstable();
            let mut gone = popped.to_vec();
            gone.sort_unstable();
            let waiting: Vec<u64> = (0..self.pushed)
                .filter(|n| gone.binary_search(n).is_err())
                .collect();
            assert_eq!(seen, waiting, "every queued item once, no popped one");
            self.ours.for_each_queued_mut(|item| {
                assert!(item.1 >= 1 << 40, "the rewrite was kept");
                item.1 -= 1 << 40;
            });
        }

        /// Pops the rest, checking that every item pushed came out exactly once (`popped`
        /// holds the numbers popped before).
        fn drain(&mut self, mut popped: Vec<u64>) {
            while let Some((_, n)) = self.pop() {
                popped.push(n);
            }
            popped.sort_unstable();
            assert!(
                popped.iter().copied().eq(0..self.pushed),
                "every item exactly once"
            );
        }
    }

    /// The search's pattern: every key pushed at least the last key popped (equal ones common,
    /// others a few ulps to many binades above), as the radix buckets assume. Against `std`'s
    /// binary heap of [`MinEntry`]: the same `(key, rank)` sequence, every item once, nothing
    /// filed below the last key.
    #[test]
    fn arena_heap_pops_monotone_keys_in_min_entry_order() {
        let mut next = xorshift(0x2545_F491_4F6C_DD1D);
        let mut heap = Checked::default();
        let (mut last, mut popped) = (0.0f64, Vec::new());
        for _ in 0..20_000 {
            if next() % 5 < 3 || heap.ours.len() == 0 {
                let key = match next() % 4 {
                    0 => last,
                    1 => f64::from_bits(last.to_bits() + 1 + next() % 8),
                    2 => last + (next() % 1000) as f64 * 1e-3,
                    _ => last * (1.0 + (next() % 64) as f64) + 1.0,
                };
                heap.push(key, (next() % 2) as usize);
            } else if let Some((key, n)) = heap.pop() {
                assert!(key >= last);
                last = key;
                popped.push(n);
            }
            assert!(heap.ours.below.is_empty());
        }
        heap.check_queued(&popped);
        heap.drain(popped);
    }

    /// Against `std`'s binary heap of [`MinEntry`] as the oracle: seeded random pushes and pops
    /// (keys drawn from a few values so that ties are common, ranks 0 or 1) pop the same
    /// `(key, rank)` sequence, and every item pushed comes out once.
    #[test]
    fn arena_heap_pops_in_min_entry_order() {
        let mut next = xorshift(0x9E37_79B9_7F4A_7C15);
        for round in 0..20 {
            let mut heap = Checked::default();
            let mut popped = Vec::new();
            for _ in 0..(500 * (round + 1)) {
                if !next().is_multiple_of(3) || heap.ours.len() == 0 {
                    let key = (next() % (2 + round)) as f64 * 0.5;
                    heap.push(key, (next() % 2) as usize);
                } else if let Some((_, n)) = heap.pop() {
                    popped.push(n);
                }
            }
            heap.check_queued(&popped);
            heap.drain(popped);
            // Cleared, it starts over empty.
            heap.ours.clear();
            assert!(heap.ours.pop().is_none());
        }
    }
}
