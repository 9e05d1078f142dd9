//! Funnels on the universal cover (thesis §2.3.2, Alg. 2; Guibas et al., Hershberger and
//! Snoeyink): the primitive a shortest-path-tree search drives.
//!
//! # Shortest path tree nodes
//! Every vertex a search reaches is a node of a shortest path tree rooted at the start `v_s`,
//! whose parent is its predecessor `pred(v)` (thesis §2.3.1): the node's path to the root,
//! reversed, is the shortest path to that lift of the vertex in the universal cover. Nodes live
//! in an append-only arena, the [`FunnelTree`]; a node also stores its path length
//! `g(v) = g(pred(v)) + |v - pred(v)|` (the cost of thesis eq. 2.5).
//!
//! The arena keeps what the sector scans read (point, length, parent, jump pointer) in 32-byte
//! records aligned to 32 bytes, two to a cache line and none across two, and the vertex id in a
//! second array: a first SHP on a 100,000-obstacle strip makes 16 million nodes, far beyond the
//! cache, and the scans' cost is their cache misses. A node's id is larger than its parent's (a
//! node is added after its parent, and only the last node is ever removed), so along a path to
//! the root ids decrease, and a scan stops at the apex by comparing ids.
//!
//! No depths are stored. Myers' rule for a new node's jump pointer compares the spans
//! `depth(x) - depth(jump(x))` of its parent and of its parent's jump, and in a skew-binary
//! scheme every span is `2^k - 1`: the record keeps the level `k` in the top bits of its jump
//! word, so adding a node reads the records of its parent and its parent's jump (which the
//! scans have usually just touched) and nothing else. Ids then have 27 bits in the
//! jump word; nodes from id `2^ID_BITS` on (a tree of 134 million nodes, about 4.8 GB) jump to
//! their parent (span 1), which keeps every scan exact and only makes scans through those
//! nodes linear.
//!
//! # Collection
//! A search holds a tree node only through the funnels and goal entries it has queued: a
//! funnel holds its two tips and, through their parents, its chains, its apex and the apex
//! chain to the root. Everything else is garbage once the search has moved on (on a
//! 1,000,000-obstacle strip, about nine nodes in ten). [`FunnelTree::collect`] drops it: the
//! caller marks what it holds ([`FunnelTree::begin_marking`], [`FunnelTree::mark`], which
//! marks a node and walks up to the first ancestor already marked), the tree keeps the marked
//! nodes in their order, and every id the caller holds is replaced by
//! [`TreeMarks::renumbered`] (the number of marked nodes before it, from one bit per node and
//! one count per 64). The kept set is closed under parents, so each kept node keeps its
//! parent, its depth and its jump target (an ancestor), and ids keep their order, so every
//! rule above (ids decrease towards the root; the spans of the jump words) still holds. A
//! collection reads the tree once and writes the kept nodes once.
//!
//! # Funnel states
//! A funnel (Fig. 2.12) is then six words, a [`FunnelState`]: the left tip node (on `alpha`),
//! the right tip node (on `beta`), the apex node (the cusp `c`, their lowest common ancestor),
//! the mouth (the half-edge `d` crossed next), and each chain's node next to the apex (the apex
//! itself for an empty chain). Its left chain is the tree path from the left tip
//! up to the apex, its right chain likewise, its apex chain the tree path from the apex to the
//! root. Funnel states are `Copy`; splitting one (Alg. 2) appends one node and returns two new
//! states sharing everything else, so a priority queue of thousands of funnels costs a few words
//! each and no funnel is ever copied or mutated.
//!
//! # Split (Alg. 2)
//! Across the mouth lies triangle `(alpha, beta, v)`. The predecessor of `v` is the node of the
//! sector containing `v`: scanning the left chain from its tip, the first node `x` with `v`
//! strictly left of the ray `parent(x) -> x`; otherwise, scanning the right chain from its tip,
//! the first node with `v` strictly right of its ray; otherwise the apex. Along a chain the test
//! is monotone (false near the tip, true towards the apex: the chains of a funnel turn by less
//! than pi), so a chain holds the predecessor exactly when its node next to the apex turns: that
//! one test chooses the chain (or the apex, in two tests), and the scan of the chosen chain
//! follows Myers' skew-binary jump pointers, stored in each node, in `O(log n)` tests. The two children are the funnels through the edges `alpha v` and
//! `v beta`; a child whose mouth is a map edge is dead (Alg. 2 line 3). The child on the side
//! where the predecessor was found gets it as its apex; the other keeps the old apex (Alg. 2
//! lines 10-13).
//!
//! Advancing a funnel along a given sleeve, child after child, reproduces the Funnel Algorithm
//! ([`crate::funnel::shortest_path_in_sleeve`]): both use the same exact sector tests with the
//! same tie rules.

use crate::funnel::{Side, TautPath};
use crate::geom::{in_closed_triangle, strictly_left, strictly_right};
use crate::kite::Kite;
use nalgebra::Point2;
use rappel_geometry::btm::Btm;
use rappel_geometry::dcel::{HalfEdgeId, TriangleId, VertexId};
use serde::{Deserialize, Serialize};

/// A node of a [`FunnelTree`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct NodeId(pub u32);

impl NodeId {
    /// The id as an index into per-node arrays.
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// One node of the shortest path tree: a lift of a map vertex (or the root, or a goal), as
/// [`FunnelTree::node`] returns it (the tree stores its parts in two arrays, module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FunnelNode {
    /// Position.
    pub point: Point2<f64>,
    /// Length of the shortest path from the root, `g(v)`.
    pub length: f64,
    /// The map vertex it lifts, [`NO_VERTEX`] for the root and goal points.
    vertex: u32,
    /// The predecessor's id, [`NO_PARENT`] for the root.
    parent: u32,
}

/// The stored vertex id of a node that lifts no map vertex.
const NO_VERTEX: u32 = u32::MAX;

/// [`FunnelNode`]'s parent of the root.
const NO_PARENT: u32 = u32::MAX;

/// Bits of a node id in a record's jump word (module docs); the top bits hold the jump's span
/// level.
const ID_BITS: u32 = 27;

/// Nodes with an id below this keep their span level beside their jump pointer.
const PACKED_NODES: u32 = 1 << ID_BITS;

/// The id part of a packed jump word.
const ID_MASK: u32 = PACKED_NODES - 1;

impl FunnelNode {
    /// The map vertex it lifts (`None` for the root and for goal points).
    #[inline]
    pub fn vertex(&self) -> Option<VertexId> {
        (self.vertex != NO_VERTEX).then_some(VertexId(self.vertex))
    }

    /// The predecessor, `None` for the root.
    pub fn parent(&self) -> Option<NodeId> {
        (self.parent != NO_PARENT).then_some(NodeId(self.parent))
    }
}

/// What the sector scans read of a node: 32 bytes, aligned so that no record spans two cache
/// lines (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(C, align(32))]
struct Link {
    point: Point2<f64>,
    length: f64,
    parent: u32,
    /// The jump pointer; below id [`PACKED_NODES`] its low [`ID_BITS`] bits, with the level `k`
    /// of its span `2^k - 1` in the bits above (0 for the root), read with [`Link::jump`] and
    /// [`Link::level`].
    jump: u32,
}

impl Link {
    /// The jump pointer of node `id`, whose record this is.
    #[inline]
    fn jump(&self, id: u32) -> u32 {
        if id < PACKED_NODES {
            self.jump & ID_MASK
        } else {
            self.jump
        }
    }

    /// The level `k` of node `id`'s span `depth(id) - depth(jump(id)) = 2^k - 1`: 0 for the
    /// root, 1 beyond the packed ids (whose jump is their parent).
    #[inline]
    fn level(&self, id: u32) -> u32 {
        if id < PACKED_NODES {
            self.jump >> ID_BITS
        } else {
            1
        }
    }
}

/// The arena of shortest-path-tree nodes shared by all funnels of one search.
///
/// `FunnelTree::default()` is storage without a root, allocating nothing (for a placeholder left
/// where a tree was moved out): [`FunnelTree::reset`] gives it its root; until then its
/// [`FunnelTree::len`] is 0 and reading a node of it panics.
///
/// ```
/// use nalgebra::Point2;
/// use rappel_homotopy::funnel_state::FunnelTree;
/// let mut tree = FunnelTree::default();
/// assert_eq!(tree.len(), 0);
/// tree.reset(Point2::new(1.0, 2.0));
/// assert_eq!(tree.len(), 1);
/// assert_eq!(tree.point(tree.root()), Point2::new(1.0, 2.0));
/// ```
#[derive(Debug, Clone, Default)]
pub struct FunnelTree {
    links: Vec<Link>,
    /// Each node's map vertex ([`NO_VERTEX`] for none).
    vertices: Vec<u32>,
}

impl FunnelTree {
    /// A tree holding only the root `start`.
    pub fn new(start: Point2<f64>) -> FunnelTree {
        let mut tree = FunnelTree {
            links: Vec::new(),
            vertices: Vec::new(),
        };
        tree.reset(start);
        tree
    }

    /// Empties the tree down to a new root `start`, keeping its storage: a search that reuses one
    /// tree across queries allocates only when a query grows it beyond every earlier one.
    pub fn reset(&mut self, start: Point2<f64>) {
        self.links.clear();
        self.vertices.clear();
        // The root jumps to itself with span 0 (level 0).
        self.links.push(Link {
            point: start,
            length: 0.0,
            parent: 0,
            jump: 0,
        });
        self.vertices.push(NO_VERTEX);
    }

    /// Bytes of node storage held (capacity, not length).
    pub fn capacity_bytes(&self) -> usize {
        self.links.capacity() * std::mem::size_of::<Link>()
            + self.vertices.capacity() * std::mem::size_of::<u32>()
    }

    /// Bytes of storage per node (length, not capacity: multiply by [`FunnelTree::len`]).
    pub const NODE_BYTES: usize = std::mem::size_of::<Link>() + std::mem::size_of::<u32>();

    /// The root (the start point).
    pub fn root(&self) -> NodeId {
        NodeId(0)
    }

    /// A node.
    ///
    /// # Panics
    /// When `id` did not come from this tree.
    #[inline]
    pub fn node(&self, id: NodeId) -> FunnelNode {
        let l = &self.links[id.index()];
        FunnelNode {
            point: l.point,
            length: l.length,
            vertex: self.vertices[id.index()],
            parent: if id.0 == 0 { NO_PARENT } else { l.parent },
        }
    }

    /// A node's position (one array read, where [`FunnelTree::node`] reads two).
    ///
    /// # Panics
    /// When `id` did not come from this tree.
    #[inline]
    pub fn point(&self, id: NodeId) -> Point2<f64> {
        self.links[id.index()].point
    }

    /// A node's path length `g` from the root.
    ///
    /// # Panics
    /// When `id` did not come from this tree.
    #[inline]
    pub fn length(&self, id: NodeId) -> f64 {
        self.links[id.index()].length
    }

    /// The map vertex a node lifts (`None` for the root and goal points).
    ///
    /// # Panics
    /// When `id` did not come from this tree.
    #[inline]
    pub fn vertex(&self, id: NodeId) -> Option<VertexId> {
        let v = self.vertices[id.index()];
        (v != NO_VERTEX).then_some(VertexId(v))
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.links.len()
    }

    /// `true` only for storage without a root (`FunnelTree::default()` before its first
    /// [`FunnelTree::reset`]); a tree made by [`FunnelTree::new`] always holds its root.
    pub fn is_empty(&self) -> bool {
        self.links.is_empty()
    }

    /// Adds a node at `point` with predecessor `parent`; when `point` coincides with the parent's
    /// position no node is added and `parent` is returned.
    pub fn extend(
        &mut self,
        parent: NodeId,
        point: Point2<f64>,
        vertex: Option<VertexId>,
    ) -> NodeId {
        let p = self.links[parent.index()];
        if p.point == point {
            return parent;
        }
        // Myers' skew-binary jump pointers: level-ancestor and monotone searches in O(log n).
        // The parent's span and its jump's are equal exactly when their levels are (module
        // docs): then the new node jumps over both, with a span of twice theirs plus one.
        let id = u32::try_from(self.links.len()).expect("fewer than 2^32 tree nodes");
        let j = p.jump(parent.0);
        let (level_p, jl) = (p.level(parent.0), &self.links[j as usize]);
        let jump = if id >= PACKED_NODES {
            // Beyond the packed ids every node jumps to its parent (module docs).
            parent.0
        } else if level_p > 0 && level_p == jl.level(j) {
            jl.jump(j) | (level_p + 1) << ID_BITS
        } else {
            parent.0 | 1 << ID_BITS
        };
        self.links.push(Link {
            point,
            length: p.length + (point - p.point).norm(),
            parent: parent.0,
            jump,
        });
        self.vertices.push(vertex.map_or(NO_VERTEX, |v| v.0));
        NodeId(id)
    }

    /// Removes node `id` if it is the last node added and not the root, and returns whether it
    /// did. For a node nothing refers to any more (a split whose two children were both
    /// dropped): the arena then keeps only nodes a search may still need. The caller must hold
    /// no other reference to it (ids are reused by the next node added).
    pub fn discard_last(&mut self, id: NodeId) -> bool {
        if id.0 == 0 || id.index() + 1 != self.links.len() {
            return false;
        }
        self.links.pop();
        self.vertices.pop();
        true
    }

    /// Starts a collection of the tree (module docs, "Collection"): clears `marks` for this
    /// tree's nodes and marks the root.
    pub fn begin_marking(&self, marks: &mut TreeMarks) {
        let words = self.links.len().div_ceil(64);
        marks.bits.clear();
        marks.bits.resize(words, 0);
        marks.before.clear();
        if words > 0 {
            marks.bits[0] = 1;
        }
    }

    /// Marks node `id` and its ancestors as live (after [`FunnelTree::begin_marking`]). The walk
    /// up stops at the first node already marked, so marking every node a search holds costs
    /// the live nodes plus one step per node held.
    ///
    /// # Panics
    /// When `id` did not come from this tree, or marking was not begun on it.
    pub fn mark(&self, marks: &mut TreeMarks, id: NodeId) {
        let mut x = id.0;
        while !marks.is_marked(x) {
            marks.bits[x as usize / 64] |= 1 << (x % 64);
            x = self.links[x as usize].parent;
        }
    }

    /// Keeps only the marked nodes (module docs, "Collection"), in their order, and returns
    /// how many were dropped; afterwards [`TreeMarks::renumbered`] gives each kept node's new
    /// id, with which the caller must replace every id it holds.
    ///
    /// Every ancestor of a marked node is marked ([`FunnelTree::mark`]), so parents, jump
    /// targets (ancestors too) and depths are kept; ids keep their order, so a node's id stays
    /// larger than its ancestors'. A node that jumped to its parent beyond the packed ids and
    /// now has a packed id records that jump with its span level 1: jump words hold real spans,
    /// which is all Myers' rule reads.
    ///
    /// # Panics
    /// When marking was not begun on this tree ([`FunnelTree::begin_marking`]).
    pub fn collect(&mut self, marks: &mut TreeMarks) -> usize {
        let len = self.links.len();
        assert_eq!(
            marks.bits.len(),
            len.div_ceil(64),
            "marks begun on this tree"
        );
        marks.before.clear();
        let mut kept = 0u32;
        for w in &marks.bits {
            marks.before.push(kept);
            kept += w.count_ones();
        }
        let mut next = 0usize;
        for old in 0..len as u32 {
            if !marks.is_marked(old) {
                continue;
            }
            let l = self.links[old as usize];
            let new = next as u32;
            let parent = marks.renumbered(NodeId(l.parent)).0;
            let jump = if old >= PACKED_NODES {
                // Its jump was its parent (span 1).
                if new >= PACKED_NODES {
                    parent
                } else {
                    parent | 1 << ID_BITS
                }
            } else {
                marks.renumbered(NodeId(l.jump(old))).0 | l.level(old) << ID_BITS
            };
            self.links[next] = Link { parent, jump, ..l };
            self.vertices[next] = self.vertices[old as usize];
            next += 1;
        }
        self.links.truncate(next);
        self.vertices.truncate(next);
        len - next
    }

    /// The nodes from the root to `id`.
    pub fn path(&self, id: NodeId) -> Vec<NodeId> {
        let ancestors = || {
            std::iter::successors(Some(id), |x| {
                (x.0 != 0).then(|| NodeId(self.links[x.index()].parent))
            })
        };
        // Counted first: one allocation of the exact size, filled from the back.
        let mut out = vec![NodeId(0); ancestors().count()];
        for (slot, x) in out.iter_mut().rev().zip(ancestors()) {
            *slot = x;
        }
        out
    }

    /// The taut path from the root to `id`, with its anchors.
    pub fn taut_path(&self, btm: &Btm, id: NodeId) -> TautPath {
        TautPath::from_corners(
            btm,
            self.path(id)
                .into_iter()
                .map(|n| (self.point(n), self.vertex(n))),
        )
    }

    /// Whether `p` lies strictly on `side` of node `x`'s incoming ray `parent(x) -> x` (the
    /// sector test of the module docs).
    #[inline]
    fn turns(&self, x: u32, p: &Point2<f64>, side: Side) -> bool {
        let n = &self.links[x as usize];
        let parent = &self.links[n.parent as usize].point;
        match side {
            Side::Left => strictly_left(parent, &n.point, p),
            Side::Right => strictly_right(parent, &n.point, p),
        }
    }

    /// Scans the chain from `tip` towards the apex for the first node that turns (`p` strictly
    /// on `side` of its incoming ray), when the chain's node next to the apex, `first`, is known
    /// to turn: returns that node `t` and its child on the chain towards the tip (`t` itself
    /// when `t` is the tip).
    ///
    /// The test is monotone along the chain (false near the tip, true towards the apex), so the
    /// scan follows the jump pointers keeping the lowest node known not to turn (`x`) and the
    /// highest known to turn (`floor`), and tests each node at most once. A chain's nodes are
    /// the tip's ancestors-or-self down to `first`, with ids above the apex's (module docs: ids
    /// decrease towards the root), so every bound is an id comparison.
    fn first_turn(
        &self,
        tip: NodeId,
        first: NodeId,
        p: &Point2<f64>,
        side: Side,
    ) -> (NodeId, NodeId) {
        let mut x = tip.0;
        if x == first.0 || self.turns(x, p, side) {
            return (tip, tip);
        }
        // Invariant: `x` does not turn, `floor` turns, and `floor` is a proper ancestor of `x`
        // on the chain: the first turn from the tip lies in `(x, floor]`.
        let mut floor = first.0;
        loop {
            let n = &self.links[x as usize];
            let j = n.jump(x);
            if j > floor {
                if self.turns(j, p, side) {
                    floor = j;
                } else {
                    x = j;
                    continue;
                }
            }
            let parent = n.parent;
            if parent == floor || self.turns(parent, p, side) {
                return (NodeId(parent), NodeId(x));
            }
            x = parent;
        }
    }
}

/// The live nodes of a [`FunnelTree`] being collected, and afterwards each kept node's new id
/// (module docs, "Collection"): one bit per node and one count per 64 nodes, so renumbering
/// an id is two loads and a population count, and the marks of a tree of `n` nodes take about
/// `n / 6` bytes.
///
/// ```
/// use nalgebra::Point2;
/// use rappel_homotopy::funnel_state::{FunnelTree, TreeMarks};
/// let mut tree = FunnelTree::new(Point2::new(0.0, 0.0));
/// let a = tree.extend(tree.root(), Point2::new(1.0, 0.0), None);
/// let b = tree.extend(tree.root(), Point2::new(0.0, 1.0), None);
/// let c = tree.extend(b, Point2::new(1.0, 1.0), None);
/// let mut marks = TreeMarks::default();
/// tree.begin_marking(&mut marks);
/// tree.mark(&mut marks, c); // `a` is held by nobody
/// assert!(!marks.is_live(a));
/// assert_eq!(tree.collect(&mut marks), 1);
/// let c = marks.renumbered(c);
/// assert_eq!(tree.len(), 3);
/// assert_eq!(tree.length(c), 2.0);
/// assert_eq!(tree.point(tree.node(c).parent().unwrap()), Point2::new(0.0, 1.0));
/// ```
#[derive(Debug, Clone, Default)]
pub struct TreeMarks {
    /// Bit `x % 64` of word `x / 64` set when node `x` is live.
    bits: Vec<u64>,
    /// Per word of `bits`, the live nodes before it ([`FunnelTree::collect`] fills it).
    before: Vec<u32>,
}

impl TreeMarks {
    #[inline]
    fn is_marked(&self, x: u32) -> bool {
        self.bits[x as usize / 64] >> (x % 64) & 1 == 1
    }

    /// Whether node `id` is marked live.
    ///
    /// # Panics
    /// When `id` is beyond the tree whose marking was begun.
    pub fn is_live(&self, id: NodeId) -> bool {
        self.is_marked(id.0)
    }

    /// The id a live node has after [`FunnelTree::collect`]: the number of live nodes before it.
    ///
    /// # Panics
    /// When called before [`FunnelTree::collect`], or with an id beyond the collected tree.
    #[inline]
    pub fn renumbered(&self, id: NodeId) -> NodeId {
        let (w, b) = (id.index() / 64, id.0 % 64);
        debug_assert!(self.is_marked(id.0), "node {} was not kept", id.0);
        NodeId(self.before[w] + (self.bits[w] & ((1u64 << b) - 1)).count_ones())
    }

    /// Bytes held (capacities).
    pub fn held_bytes(&self) -> usize {
        self.bits.capacity() * 8 + self.before.capacity() * 4
    }
}

/// Which part of a funnel a predecessor was found on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Found {
    Left,
    Right,
    Apex,
}

/// Why a funnel operation is not possible.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum FunnelStateError {
    /// The mouth is a map edge: nothing lies beyond it.
    #[error("half-edge {0} is a map edge: no funnel can pass through it")]
    ClosedMouth(HalfEdgeId),
    /// The requested next mouth is not an edge of the triangle beyond the current mouth.
    #[error("half-edge {next} is not an exit of the triangle beyond mouth {mouth}")]
    NotAnExit {
        /// The current mouth.
        mouth: HalfEdgeId,
        /// The requested next mouth.
        next: HalfEdgeId,
    },
    /// The tree's root does not lie in the closed start triangle.
    #[error("the root does not lie in the closed triangle {0}")]
    RootNotInTriangle(TriangleId),
}

/// A funnel on the universal cover: left tip, right tip, apex and mouth, and each chain's node
/// next to the apex (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct FunnelState {
    left: NodeId,
    right: NodeId,
    apex: NodeId,
    mouth: HalfEdgeId,
    /// The left chain's node whose parent is the apex; the apex itself when the chain is empty
    /// (the left tip is the apex).
    left_first: NodeId,
    /// The right chain's node whose parent is the apex, or the apex (empty chain).
    right_first: NodeId,
}

/// The result of splitting a funnel at the vertex beyond its mouth (Alg. 2).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Split {
    /// The vertex `v` opposite the mouth.
    pub vertex: VertexId,
    /// Its new tree node.
    pub node: NodeId,
    /// Its predecessor `t = pred(v)`.
    pub predecessor: NodeId,
    /// The funnel through the edge `alpha v` (`None` when it is a map edge).
    pub left: Option<FunnelState>,
    /// The funnel through the edge `v beta` (`None` when it is a map edge).
    pub right: Option<FunnelState>,
}

impl FunnelState {
    /// The funnels from the tree's root through each non-map edge of `triangle`, which must
    /// contain the root (closed). This is the setup of Alg. 1 lines 2-5 and Alg. 3 lines 5-10.
    ///
    /// ```
    /// use nalgebra::Point2;
    /// use rappel_geometry::{btm::{Btm, Location}, map::Map, polygon::Polygon};
    /// use rappel_homotopy::funnel_state::{FunnelState, FunnelTree};
    /// let p = |x, y| Point2::new(x, y);
    /// let map = Map::new(
    ///     Polygon::new(vec![p(0., 0.), p(10., 0.), p(10., 10.), p(0., 10.)]),
    ///     vec![Polygon::new(vec![p(4., 4.), p(6., 4.), p(6., 6.), p(4., 6.)])],
    /// );
    /// let btm = Btm::from_map(&map).unwrap();
    /// let start = p(5., 9.);
    /// let Location::Triangle(t) = btm.locate(&start) else { unreachable!() };
    /// let mut tree = FunnelTree::new(start);
    /// let funnels = FunnelState::initial(&mut tree, &btm, t).unwrap();
    /// assert!(!funnels.is_empty());
    /// // Split the first funnel at the vertex beyond its mouth: two children at most.
    /// let split = funnels[0].split(&mut tree, &btm).unwrap();
    /// assert_eq!(tree.node(split.predecessor).point, start); // the start sees v directly
    /// ```
    pub fn initial(
        tree: &mut FunnelTree,
        btm: &Btm,
        triangle: TriangleId,
    ) -> Result<Vec<FunnelState>, FunnelStateError> {
        let root = tree.node(tree.root()).point;
        if !btm.is_free_triangle(triangle) || !in_closed_triangle(btm.dcel(), triangle, &root) {
            return Err(FunnelStateError::RootNotInTriangle(triangle));
        }
        Ok(triangle
            .half_edges()
            .into_iter()
            .filter_map(|h| FunnelState::through(tree, btm, h).ok())
            .collect())
    }

    /// The funnel from the tree's root through the edge `mouth` of the triangle holding the root.
    pub fn through(
        tree: &mut FunnelTree,
        btm: &Btm,
        mouth: HalfEdgeId,
    ) -> Result<FunnelState, FunnelStateError> {
        let d = btm.dcel();
        let root = tree.root();
        if !in_closed_triangle(d, mouth.triangle(), &tree.node(root).point) {
            return Err(FunnelStateError::RootNotInTriangle(mouth.triangle()));
        }
        d.twin(mouth).ok_or(FunnelStateError::ClosedMouth(mouth))?;
        let (a, b) = (d.destination(mouth), d.origin(mouth));
        let left = tree.extend(root, d.point(a), Some(a));
        let right = tree.extend(root, d.point(b), Some(b));
        Ok(FunnelState {
            left,
            right,
            apex: root,
            mouth,
            left_first: left,
            right_first: right,
        })
    }

    /// Marks the funnel's nodes live in a collection of its tree ([`FunnelTree::mark`]): its
    /// apex, its chains' nodes and everything up to the root are the ancestors of its two tips.
    pub fn mark(&self, tree: &FunnelTree, marks: &mut TreeMarks) {
        tree.mark(marks, self.left);
        tree.mark(marks, self.right);
    }

    /// The same funnel in its tree after [`FunnelTree::collect`] (every node id renumbered);
    /// the funnel must have been marked ([`FunnelState::mark`]).
    pub fn renumbered(&self, marks: &TreeMarks) -> FunnelState {
        let r = |x: NodeId| marks.renumbered(x);
        FunnelState {
            left: r(self.left),
            right: r(self.right),
            apex: r(self.apex),
            mouth: self.mouth,
            left_first: r(self.left_first),
            right_first: r(self.right_first),
        }
    }

    /// The left tip node (on the mouth's left endpoint `alpha`).
    pub fn left(&self) -> NodeId {
        self.left
    }

    /// The right tip node (on the mouth's right endpoint `beta`).
    pub fn right(&self) -> NodeId {
        self.right
    }

    /// The apex (cusp) node.
    pub fn apex(&self) -> NodeId {
        self.apex
    }

    /// The mouth: the half-edge, in the last triangle of the funnel, crossed next.
    pub fn mouth(&self) -> HalfEdgeId {
        self.mouth
    }

    /// The triangle beyond the mouth (`None` when the mouth is a map edge).
    pub fn next_triangle(&self, btm: &Btm) -> Option<TriangleId> {
        btm.dcel().twin(self.mouth).map(|g| g.triangle())
    }

    /// The predecessor of a point `p` beyond the mouth: the funnel node of the sector holding `p`
    /// (thesis Fig. 2.14). For the goal this is the `t_g` of thesis eq. 2.5.
    pub fn predecessor(&self, tree: &FunnelTree, p: &Point2<f64>) -> NodeId {
        self.locate(tree, p).0
    }

    /// The predecessor of `p`, the chain it was found on, and the predecessor's child on that
    /// chain towards the tip (the predecessor itself when it is the tip or the apex).
    ///
    /// Along a chain the sector test is monotone, so some node of the left chain turns exactly
    /// when its node next to the apex does: one test decides the chain (module docs, "Split").
    fn locate(&self, tree: &FunnelTree, p: &Point2<f64>) -> (NodeId, Found, NodeId) {
        if self.left_first != self.apex && tree.turns(self.left_first.0, p, Side::Left) {
            let (t, child) = tree.first_turn(self.left, self.left_first, p, Side::Left);
            (t, Found::Left, child)
        } else if self.right_first != self.apex && tree.turns(self.right_first.0, p, Side::Right) {
            let (t, child) = tree.first_turn(self.right, self.right_first, p, Side::Right);
            (t, Found::Right, child)
        } else {
            (self.apex, Found::Apex, self.apex)
        }
    }

    /// Adds the goal point `p` (beyond the mouth, in the closed triangle there) to the tree; the
    /// node's path is the shortest path to `p` through this funnel.
    pub fn reach(&self, tree: &mut FunnelTree, p: Point2<f64>) -> NodeId {
        let t = self.predecessor(tree, &p);
        tree.extend(t, p, None)
    }

    /// Splits the funnel at the vertex `v` opposite the mouth (Alg. 2): adds `v`'s node and
    /// returns the two child funnels.
    pub fn split(&self, tree: &mut FunnelTree, btm: &Btm) -> Result<Split, FunnelStateError> {
        self.split_across(tree, &Kite::across(btm, self.mouth))
    }

    /// [`FunnelState::split`] with what lies across the mouth already known: `kite` must be the
    /// mouth's record ([`Kite::across`], or a [`crate::kite::KiteTable`] of the same BTM). The
    /// same split, read from one record instead of the DCEL.
    pub fn split_across(
        &self,
        tree: &mut FunnelTree,
        kite: &Kite,
    ) -> Result<Split, FunnelStateError> {
        let (vertex, vp) = kite
            .vertex()
            .ok_or(FunnelStateError::ClosedMouth(self.mouth))?;
        let (t, found, child) = self.locate(tree, &vp);
        let node = tree.extend(t, vp, Some(vertex));
        // The child on the predecessor's side has it as its apex, with the rest of that chain
        // (from `child` on) and `node` alone on the other side; the other child keeps the apex,
        // its chain on that side, and `node` ends its chain on the predecessor's side (next to
        // the apex only when the predecessor is the apex).
        let left = kite.left_exit().map(|mouth| FunnelState {
            left: self.left,
            right: node,
            apex: if found == Found::Left { t } else { self.apex },
            mouth,
            left_first: if found == Found::Left {
                child
            } else {
                self.left_first
            },
            right_first: if found == Found::Right {
                self.right_first
            } else {
                node
            },
        });
        let right = kite.right_exit().map(|mouth| FunnelState {
            left: node,
            right: self.right,
            apex: if found == Found::Right { t } else { self.apex },
            mouth,
            left_first: if found == Found::Left {
                self.left_first
            } else {
                node
            },
            right_first: if found == Found::Right {
                child
            } else {
                self.right_first
            },
        });
        Ok(Split {
            vertex,
            node,
            predecessor: t,
            left,
            right,
        })
    }

    /// Advances the funnel across the triangle beyond its mouth, leaving through `next` (one of
    /// that triangle's two other edges): the child of [`FunnelState::split`] on that side.
    pub fn advance(
        &self,
        tree: &mut FunnelTree,
        btm: &Btm,
        next: HalfEdgeId,
    ) -> Result<FunnelState, FunnelStateError> {
        let split = self.split(tree, btm)?;
        [split.left, split.right]
            .into_iter()
            .flatten()
            .find(|f| f.mouth == next)
            .ok_or(FunnelStateError::NotAnExit {
                mouth: self.mouth,
                next,
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The packed span levels give the jump pointers of Myers' rule computed from depths (the
    /// rule the tree used when it stored depths), on random trees with long paths and many
    /// branches: every jump is an ancestor, and its span is `2^level - 1`.
    #[test]
    fn packed_levels_follow_myers_rule() {
        let mut state = 0x2545_F491_4F6C_DD1Du64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        for round in 0..20u32 {
            let mut tree = FunnelTree::new(Point2::new(0.0, 0.0));
            let mut depth = vec![0u32];
            let mut myers_jump = vec![0u32];
            for i in 1..2_000u32 {
                // Mostly the last node (long paths), sometimes any earlier one (branches).
                let n = tree.len() as u32;
                let parent = if next() % (2 + u64::from(round)) == 0 {
                    (next() % u64::from(n)) as u32
                } else {
                    n - 1
                };
                let id = tree.extend(NodeId(parent), Point2::new(f64::from(i), 1.0), None);
                assert_eq!(id.index(), depth.len());
                let (p, j) = (parent as usize, myers_jump[parent as usize] as usize);
                let jj = myers_jump[j] as usize;
                let expected = if depth[p] > 0 && depth[p] - depth[j] == depth[j] - depth[jj] {
                    jj as u32
                } else {
                    parent
                };
                depth.push(depth[p] + 1);
                myers_jump.push(expected);
                let link = &tree.links[id.index()];
                assert_eq!(link.jump(id.0), expected);
                let span = depth[id.index()] - depth[expected as usize];
                assert_eq!(span, (1u32 << link.level(id.0)) - 1);
                // The jump is an ancestor.
                let mut x = id.0;
                while x > expected {
                    x = tree.links[x as usize].parent;
                }
                assert_eq!(x, expected);
            }
            assert_eq!(tree.node(tree.root()).parent(), None);
            assert_eq!(tree.links[0].level(0), 0);
        }
    }

    /// The chain's node next to the apex, found by walking up from the tip (independent of the
    /// state's own record).
    fn walked_first(tree: &FunnelTree, tip: NodeId, apex: NodeId) -> NodeId {
        let mut x = tip;
        while x != apex {
            let parent = NodeId(tree.links[x.index()].parent);
            if parent == apex {
                return x;
            }
            x = parent;
        }
        apex
    }

    /// The sector scan of the module docs node by node, without jump pointers or the recorded
    /// chain ends: the left chain from its tip, then the right chain, then the apex.
    fn linear_predecessor(tree: &FunnelTree, f: &FunnelState, p: &Point2<f64>) -> NodeId {
        for (tip, side) in [(f.left, Side::Left), (f.right, Side::Right)] {
            let mut x = tip;
            while x != f.apex {
                if tree.turns(x.0, p, side) {
                    return x;
                }
                x = NodeId(tree.links[x.index()].parent);
            }
        }
        f.apex
    }

    /// A generated crater strip of `obstacles` obstacles (seed `seed`), its BTM and the free
    /// triangle holding its start, where the explorations of its universal cover begin.
    fn strip_cover(
        obstacles: usize,
        seed: u64,
    ) -> (rappel_geometry::generate::GeneratedMap, Btm, TriangleId) {
        use rappel_geometry::btm::Location;
        use rappel_geometry::generate::{CraterStripOptions, crater_strip};
        let strip = crater_strip(&CraterStripOptions::new(obstacles, seed)).unwrap();
        let btm = Btm::from_map(&strip.map).unwrap();
        let Location::Triangle(t) = btm.locate(&strip.start) else {
            panic!("the start lies inside a free triangle");
        };
        (strip, btm, t)
    }

    /// Every funnel of a breadth-first exploration of a generated crater strip's universal cover
    /// (20,000 splits) records its chains' nodes next to the apex as walking the tree finds them,
    /// and locates the vertex beyond its mouth and far points beyond the mouth (the kind of
    /// target the A* bound uses) where the linear scan does.
    #[test]
    fn recorded_chain_ends_and_located_sectors_match_linear_scans() {
        use rappel_geometry::predicates::orient2d;
        let (strip, btm, t) = strip_cover(60, 3);
        let mut tree = FunnelTree::new(strip.start);
        let mut queue: std::collections::VecDeque<FunnelState> =
            FunnelState::initial(&mut tree, &btm, t).unwrap().into();
        let d = btm.dcel();
        let (mut splits, mut by_chain) = (0, [0usize; 3]);
        while let Some(f) = queue.pop_front() {
            if splits == 20_000 {
                break;
            }
            assert_eq!(f.left_first, walked_first(&tree, f.left, f.apex));
            assert_eq!(f.right_first, walked_first(&tree, f.right, f.apex));
            let Some((_, v)) = Kite::across(&btm, f.mouth).vertex() else {
                continue;
            };
            // Far points beyond the mouth: the goal, and points 1 km out along the mouth's
            // normal and either side of it.
            let (a, b) = (d.point(d.origin(f.mouth)), d.point(d.destination(f.mouth)));
            let (mid, along) = (nalgebra::center(&a, &b), (b - a).normalize());
            let out = nalgebra::Vector2::new(along.y, -along.x);
            let targets = [
                strip.goal,
                mid + 1e3 * out,
                mid + 1e3 * (out + along),
                mid + 1e3 * (out - along),
                v,
            ];
            for p in targets {
                if orient2d(&a, &b, &p) < 0.0 {
                    let (found, kind, _) = f.locate(&tree, &p);
                    assert_eq!(found, linear_predecessor(&tree, &f, &p));
                    by_chain[kind as usize] += 1;
                }
            }
            let split = f.split(&mut tree, &btm).unwrap();
            splits += 1;
            queue.extend(split.left);
            queue.extend(split.right);
        }
        assert_eq!(splits, 20_000);
        // All three outcomes occur.
        assert!(by_chain.iter().all(|&n| n > 100), "{by_chain:?}");
    }

    /// Collecting the tree (module docs, "Collection") in the middle of an exploration changes
    /// nothing the funnels compute: a breadth-first exploration of a crater strip's cover that
    /// collects every 500 splits (holding only its queued funnels) splits at the same
    /// predecessors and reaches the same points, lengths and taut paths, split for split, as
    /// one that never collects; and each collection keeps a tree in which every jump is an
    /// ancestor with the span its level says.
    #[test]
    fn collecting_mid_exploration_changes_no_split() {
        let (strip, btm, t) = strip_cover(40, 9);
        let explore = |collect: bool| {
            let mut tree = FunnelTree::new(strip.start);
            let mut marks = TreeMarks::default();
            let mut queue: std::collections::VecDeque<FunnelState> =
                FunnelState::initial(&mut tree, &btm, t).unwrap().into();
            let (mut seen, mut collected) = (Vec::new(), 0);
            for splits in 0..6_000 {
                if collect && splits % 500 == 499 {
                    tree.begin_marking(&mut marks);
                    queue.iter().for_each(|f| f.mark(&tree, &mut marks));
                    collected += tree.collect(&mut marks);
                    queue.iter_mut().for_each(|f| *f = f.renumbered(&marks));
                    check_jumps(&tree);
                }
                let Some(f) = queue.pop_front() else { break };
                let Ok(split) = f.split(&mut tree, &btm) else {
                    continue;
                };
                let n = tree.node(split.node);
                let taut = tree.taut_path(&btm, split.node);
                seen.push((
                    tree.point(split.predecessor),
                    n.point,
                    n.length,
                    taut.points,
                ));
                queue.extend(split.left);
                queue.extend(split.right);
            }
            (seen, collected)
        };
        let (plain, none) = explore(false);
        let (collecting, collected) = explore(true);
        assert_eq!(none, 0);
        assert!(collected > 1_000, "{collected} nodes collected");
        assert!(plain.len() > 5_000);
        assert!(plain == collecting, "the same splits, bit for bit");
    }

    /// Every jump of `tree` is an ancestor whose depth is `2^level - 1` less (depths from the
    /// parents, independently of the jump words).
    fn check_jumps(tree: &FunnelTree) {
        let mut depth = vec![0u32; tree.len()];
        for x in 1..tree.len() as u32 {
            let l = &tree.links[x as usize];
            assert!(l.parent < x, "ids decrease towards the root");
            depth[x as usize] = depth[l.parent as usize] + 1;
            let j = l.jump(x);
            let mut y = x;
            while y > j {
                y = tree.links[y as usize].parent;
            }
            assert_eq!(y, j, "the jump of {x} is an ancestor");
            assert_eq!(depth[x as usize] - depth[j as usize], (1 << l.level(x)) - 1);
        }
    }
}
