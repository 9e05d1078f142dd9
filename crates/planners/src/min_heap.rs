//! The entry of the planners' min-priority queues: `std`'s [`BinaryHeap`](std::collections::BinaryHeap)
//! is a max-heap, so the SPT search ([`crate::spt`]), the shortest path map
//! ([`crate::shortest_path_map`]) and the visibility-graph oracle ([`crate::visibility_graph`])
//! all queue a [`MinEntry`], ordered smallest key first and, on equal keys, smallest
//! [`Rank::rank`] first, written once here.

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
}
