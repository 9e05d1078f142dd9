//! The edge-implicit random geometric graph (RGG) of ABIT*: every sampled state, the search tree
//! laid over them (parent, children, cost-to-come, history), and k-nearest-neighbour queries
//! through a kd-tree (`kiddo`).
//!
//! Edges are never stored: the neighbours of a state are the states at its `k` nearest
//! locations, its own location among them, with `k = ceil(f (e + e/d) ln n)` fixed per batch
//! (Karaman & Frazzoli's k-nearest RGG as OMPL's BIT* and ABIT* compute it; `f` is OMPL's rewire
//! factor, `n` counted before the batch: `abit::rgg_k`).
//! Several graph states may share one location (the fresh goal copies of Paton §V-A), so the
//! kd-tree indexes locations and each location lists its states.
//!
//! Samples drawn from a bias distribution (`StateSpace::sample_biased`) are indexed a second
//! time apart: a second kd-tree holds only the *unbiased* locations (start, goal, uniform and
//! informed samples), and a neighbourhood is the `k` nearest of all locations together with the
//! `k` nearest unbiased ones. Biased samples add edges to the RGG; they never take the uniform
//! graph's edges away. Without that, a dense biased region (the pole's shadow on the rover) fills
//! the k nearest of every state near it with its own samples, and a class that reached the
//! region's rim never gets an edge out of it (`docs/sampler.md`, the shadow row's failing
//! seeds). Without biased samples the second query is skipped, so unbiased runs are unchanged.

use std::num::NonZero;

use kiddo::{MutableKdTree, SquaredEuclidean};

/// One state of the graph.
#[derive(Debug, Clone)]
pub struct Node<S, H> {
    /// The state.
    pub state: S,
    /// Its history: `None` while undetermined (a fresh sample or goal copy), fixed once set.
    pub history: Option<H>,
    /// Cost-to-come through the tree, `f64::INFINITY` while not in the tree.
    pub g: f64,
    /// Parent in the tree.
    pub parent: Option<u32>,
    /// Children in the tree.
    pub children: Vec<u32>,
    /// Whether this is a copy of the goal state.
    pub is_goal: bool,
    /// The kd-tree location this state sits at.
    pub location: u32,
}

impl<S, H> Node<S, H> {
    /// Whether the state is connected to the search tree.
    pub fn in_tree(&self) -> bool {
        self.g.is_finite()
    }
}

/// The RGG: states plus the nearest-neighbour index.
pub struct Graph<S, H, const K: usize> {
    /// All states, indexed by `u32` ids (bounded by `u32::MAX` states).
    pub nodes: Vec<Node<S, H>>,
    /// The states at each kd-tree location.
    locations: Vec<Vec<u32>>,
    kd: MutableKdTree<f64, K>,
    /// The unbiased locations only (module doc), built at the first biased sample.
    kd_unbiased: MutableKdTree<f64, K>,
    /// The key of every location (to build `kd_unbiased` when the first biased sample comes,
    /// so that unbiased runs pay one vector push per sample, not a second kd-tree).
    keys: Vec<[f64; K]>,
    /// Number of locations of biased samples (0: the second query is skipped).
    biased_locations: usize,
}

/// The kd-tree rejected a point (non-finite coordinates) or the graph is full.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("nearest-neighbour index: {0}")]
pub struct IndexError(pub String);

impl<S, H, const K: usize> Default for Graph<S, H, K> {
    fn default() -> Self {
        Self {
            nodes: Vec::new(),
            locations: Vec::new(),
            kd: MutableKdTree::default(),
            kd_unbiased: MutableKdTree::default(),
            keys: Vec::new(),
            biased_locations: 0,
        }
    }
}

impl<S, H, const K: usize> Graph<S, H, K> {
    /// Adds a state at a new location with key `key`; returns its id. `biased`: the state was
    /// drawn from the space's bias distribution (kept out of the unbiased index, module doc).
    pub fn add(
        &mut self,
        state: S,
        history: Option<H>,
        key: [f64; K],
        biased: bool,
    ) -> Result<u32, IndexError> {
        if key.iter().any(|c| !c.is_finite()) {
            return Err(IndexError(format!("non-finite key {key:?}")));
        }
        let loc = u32::try_from(self.locations.len())
            .map_err(|_| IndexError("more than u32::MAX locations".into()))?;
        self.kd
            .add(&key, loc)
            .map_err(|e| IndexError(format!("{e:?}")))?;
        let index = |kd: &mut MutableKdTree<f64, K>, key: &[f64; K], loc: u32| {
            kd.add(key, loc).map_err(|e| IndexError(format!("{e:?}")))
        };
        if biased {
            if self.biased_locations == 0 {
                // Every location so far is unbiased: index them all (once per graph).
                for (l, k) in self.keys.iter().enumerate() {
                    index(&mut self.kd_unbiased, k, l as u32)?;
                }
            }
            self.biased_locations += 1;
        } else if self.biased_locations > 0 {
            index(&mut self.kd_unbiased, &key, loc)?;
        }
        self.keys.push(key);
        self.locations.push(Vec::new());
        self.push_node(state, history, loc, false)
    }

    /// Adds a state at the location of state `twin` (a goal copy); returns its id.
    pub fn add_at(&mut self, twin: u32, state: S, is_goal: bool) -> Result<u32, IndexError> {
        let loc = self.nodes[twin as usize].location;
        self.push_node(state, None, loc, is_goal)
    }

    fn push_node(
        &mut self,
        state: S,
        history: Option<H>,
        loc: u32,
        is_goal: bool,
    ) -> Result<u32, IndexError> {
        let id = u32::try_from(self.nodes.len())
            .map_err(|_| IndexError("more than u32::MAX states".into()))?;
        self.nodes.push(Node {
            state,
            history,
            g: f64::INFINITY,
            parent: None,
            children: Vec::new(),
            is_goal,
            location: loc,
        });
        self.locations[loc as usize].push(id);
        Ok(id)
    }

    /// Marks state `id` as a goal copy.
    pub fn set_goal(&mut self, id: u32) {
        self.nodes[id as usize].is_goal = true;
    }

    /// The states at location `loc` (a sample and its history copies, or the goal copies).
    pub fn at_location(&self, loc: u32) -> &[u32] {
        &self.locations[loc as usize]
    }

    /// Number of distinct locations (the `n` of the RGG's k).
    pub fn location_count(&self) -> usize {
        self.locations.len()
    }

    /// The states at the `k` locations nearest to `key` (nearest first, the query location
    /// included), then, when biased samples exist, those at the `k` nearest unbiased locations
    /// not already listed (module doc); in a deterministic order.
    pub fn near(&self, key: &[f64; K], k: usize) -> Vec<u32> {
        let Some(k) = NonZero::new(k.min(self.locations.len())) else {
            return Vec::new();
        };
        let mut locs: Vec<u32> = self
            .kd
            .query(key)
            .nearest_n::<SquaredEuclidean<f64>>(k)
            .execute()
            .iter()
            .map(|r| r.item)
            .collect();
        if self.biased_locations > 0
            && let Some(ku) =
                NonZero::new(k.get().min(self.locations.len() - self.biased_locations))
        {
            // At most k extra locations, each checked against at most 2k: bounded by k².
            for r in self
                .kd_unbiased
                .query(key)
                .nearest_n::<SquaredEuclidean<f64>>(ku)
                .execute()
            {
                if !locs.contains(&r.item) {
                    locs.push(r.item);
                }
            }
        }
        locs.iter()
            .flat_map(|&l| self.locations[l as usize].iter().copied())
            .collect()
    }

    /// Attaches `child` to `parent` with cost-to-come `g`, detaching it from its old parent.
    /// Descendants' costs are shifted by the change (bounded by the number of states).
    pub fn attach(&mut self, child: u32, parent: u32, g: f64) {
        if let Some(old) = self.nodes[child as usize].parent {
            self.nodes[old as usize].children.retain(|&c| c != child);
        }
        let old_g = self.nodes[child as usize].g;
        self.nodes[child as usize].parent = Some(parent);
        self.nodes[child as usize].g = g;
        self.nodes[parent as usize].children.push(child);
        if old_g.is_finite() {
            let delta = g - old_g;
            let mut stack: Vec<u32> = self.nodes[child as usize].children.clone();
            while let Some(c) = stack.pop() {
                self.nodes[c as usize].g += delta;
                stack.extend(self.nodes[c as usize].children.iter().copied());
            }
        }
    }

    /// The path from the tree's root to `id` (root first); bounded by the number of states.
    pub fn path_to(&self, id: u32) -> Vec<u32> {
        let mut path = vec![id];
        let mut cur = id;
        while let Some(p) = self.nodes[cur as usize].parent {
            path.push(p);
            cur = p;
            if path.len() > self.nodes.len() {
                break;
            }
        }
        path.reverse();
        path
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn biased_samples_add_neighbours_and_take_none_away() {
        // 20 biased locations packed at x in [0, 0.095], three unbiased ones at x = 1, 2, 3.
        let build = |mark_biased: bool| {
            let mut g: Graph<(), (), 2> = Graph::default();
            for i in 0..20 {
                g.add((), None, [0.005 * f64::from(i), 0.0], mark_biased)
                    .unwrap();
            }
            for x in [1.0, 2.0, 3.0] {
                g.add((), None, [x, 0.0], false).unwrap();
            }
            g
        };
        let locs = |g: &Graph<(), (), 2>, ids: Vec<u32>| -> Vec<u32> {
            ids.iter().map(|&i| g.nodes[i as usize].location).collect()
        };
        // Unmarked: the 3 nearest of [0.05, 0] all lie in the cluster.
        let plain = build(false);
        let near = locs(&plain, plain.near(&[0.05, 0.0], 3));
        assert_eq!(near.len(), 3);
        assert!(near.iter().all(|&l| l < 20), "{near:?}");
        // Marked biased: the same 3 first, then the 3 nearest unbiased (x = 1, 2, 3).
        let marked = build(true);
        let near = locs(&marked, marked.near(&[0.05, 0.0], 3));
        assert_eq!(&near[..3], &locs(&plain, plain.near(&[0.05, 0.0], 3))[..]);
        assert_eq!(&near[3..], &[20, 21, 22]);
        // From x = 2.1 the unbiased nearest are also the nearest overall: no duplicates.
        let near = locs(&marked, marked.near(&[2.1, 0.0], 2));
        assert_eq!(near, vec![21, 22]);
        // Unbiased locations added before the first biased one are indexed when it comes.
        let mut late: Graph<(), (), 2> = Graph::default();
        for x in [1.0, 2.0, 3.0] {
            late.add((), None, [x, 0.0], false).unwrap();
        }
        for i in 0..20 {
            late.add((), None, [0.005 * f64::from(i), 0.0], true)
                .unwrap();
        }
        let near = locs(&late, late.near(&[0.05, 0.0], 3));
        assert_eq!(&near[3..], &[0, 1, 2]);
        assert!(near[..3].iter().all(|&l| l >= 3), "{near:?}");
    }
}
