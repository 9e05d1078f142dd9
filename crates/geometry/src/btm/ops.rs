//! Local mutations of the DCEL: splitting a triangle or an edge at a new vertex, flipping an edge,
//! restoring the (constrained) Delaunay property with Lawson's flips, and replacing a cavity of
//! triangles by a new triangulation. Every mutation goes through [`Dcel::take_slot`], which in
//! update mode retires the old triangle id instead of rewriting it, so ids stay stable.

use crate::dcel::{Dcel, FaceKind, HalfEdgeId, NONE};
use crate::predicates::incircle;
use std::collections::HashMap;

impl Dcel {
    /// A slot for a new triangle, reusing `old` when ids need not be preserved. In update mode the
    /// old slot is retired (its face kind logged) and a fresh slot appended.
    pub(crate) fn take_slot(&mut self, old: Option<u32>) -> u32 {
        match old {
            Some(t) if !self.fresh_slots => t,
            _ => {
                if let Some(t) = old {
                    self.retire(t);
                }
                let t = self.face.len() as u32;
                self.origin.extend_from_slice(&[NONE, NONE, NONE]);
                self.twin.extend_from_slice(&[NONE, NONE, NONE]);
                self.constrained.extend_from_slice(&[false, false, false]);
                self.face.push(FaceKind::Dead);
                t
            }
        }
    }

    /// Marks slot `t` dead (logging its kind in update mode).
    pub(crate) fn retire(&mut self, t: u32) {
        let kind = self.face[t as usize];
        if kind != FaceKind::Dead {
            if self.fresh_slots {
                self.retired.push((t, kind));
            }
            self.face[t as usize] = FaceKind::Dead;
            for i in 0..3 {
                self.twin[3 * t as usize + i] = NONE;
            }
        }
    }

    /// The vertex opposite half-edge `h` in its triangle.
    #[inline]
    pub(crate) fn apex(&self, h: u32) -> u32 {
        self.origin[HalfEdgeId(h).prev().index()]
    }

    /// Splits triangle `t` at the new vertex `p` (inside it) into three. Returns the three
    /// half-edges opposite `p`.
    pub(crate) fn split_triangle(&mut self, t: u32, p: u32) -> [u32; 3] {
        let b = 3 * t as usize;
        let (va, vb, vc) = (self.origin[b], self.origin[b + 1], self.origin[b + 2]);
        let outer = [self.twin[b], self.twin[b + 1], self.twin[b + 2]];
        let cons = [
            self.constrained[b],
            self.constrained[b + 1],
            self.constrained[b + 2],
        ];
        let face = self.face[t as usize];
        let t0 = self.take_slot(Some(t));
        let t1 = self.take_slot(None);
        let t2 = self.take_slot(None);
        self.write_triangle(t0, va, vb, p, face);
        self.write_triangle(t1, vb, vc, p, face);
        self.write_triangle(t2, vc, va, p, face);
        let (e0, e1, e2) = (3 * t0, 3 * t1, 3 * t2);
        self.link(e0, outer[0]);
        self.link(e1, outer[1]);
        self.link(e2, outer[2]);
        self.constrained[e0 as usize] = cons[0];
        self.constrained[e1 as usize] = cons[1];
        self.constrained[e2 as usize] = cons[2];
        for e in [e0 + 1, e0 + 2, e1 + 1, e1 + 2, e2 + 1, e2 + 2] {
            self.constrained[e as usize] = false;
        }
        self.link(e0 + 1, e1 + 2);
        self.link(e1 + 1, e2 + 2);
        self.link(e2 + 1, e0 + 2);
        [e0, e1, e2]
    }

    /// Splits the edge of half-edge `h` at the new vertex `p` (on its interior). Returns the
    /// half-edges opposite `p` (two or four).
    pub(crate) fn split_edge(&mut self, h: u32, p: u32) -> Vec<u32> {
        let g = self.twin[h as usize];
        let hh = HalfEdgeId(h);
        let (va, vb, vc) = (self.origin[h as usize], self.dest(h), self.apex(h));
        let out_bc = self.twin[hh.next().index()];
        let out_ca = self.twin[hh.prev().index()];
        let c_bc = self.constrained[hh.next().index()];
        let c_ca = self.constrained[hh.prev().index()];
        let c_ab = self.constrained[h as usize];
        let f0 = self.face[(h / 3) as usize];
        let t0 = self.take_slot(Some(h / 3));
        let t1 = self.take_slot(None);
        // (a, p, c) and (p, b, c)
        self.write_triangle(t0, va, p, vc, f0);
        self.write_triangle(t1, p, vb, vc, f0);
        self.link(3 * t0 + 2, out_ca);
        self.link(3 * t1 + 1, out_bc);
        self.constrained[(3 * t0 + 2) as usize] = c_ca;
        self.constrained[(3 * t1 + 1) as usize] = c_bc;
        self.link(3 * t0 + 1, 3 * t1 + 2);
        self.constrained[(3 * t0 + 1) as usize] = false;
        self.constrained[(3 * t1 + 2) as usize] = false;
        self.constrained[(3 * t0) as usize] = c_ab;
        self.constrained[(3 * t1) as usize] = c_ab;
        if g == NONE {
            self.twin[(3 * t0) as usize] = NONE;
            self.twin[(3 * t1) as usize] = NONE;
            return vec![3 * t0 + 2, 3 * t1 + 1];
        }
        let gg = HalfEdgeId(g);
        let vd = self.apex(g);
        let out_ad = self.twin[gg.next().index()];
        let out_db = self.twin[gg.prev().index()];
        let c_ad = self.constrained[gg.next().index()];
        let c_db = self.constrained[gg.prev().index()];
        let f1 = self.face[(g / 3) as usize];
        let t2 = self.take_slot(Some(g / 3));
        let t3 = self.take_slot(None);
        // (b, p, d) and (p, a, d)
        self.write_triangle(t2, vb, p, vd, f1);
        self.write_triangle(t3, p, va, vd, f1);
        self.link(3 * t2 + 2, out_db);
        self.link(3 * t3 + 1, out_ad);
        self.constrained[(3 * t2 + 2) as usize] = c_db;
        self.constrained[(3 * t3 + 1) as usize] = c_ad;
        self.link(3 * t2 + 1, 3 * t3 + 2);
        self.constrained[(3 * t2 + 1) as usize] = false;
        self.constrained[(3 * t3 + 2) as usize] = false;
        self.constrained[(3 * t2) as usize] = c_ab;
        self.constrained[(3 * t3) as usize] = c_ab;
        self.link(3 * t0, 3 * t3);
        self.link(3 * t1, 3 * t2);
        vec![3 * t0 + 2, 3 * t1 + 1, 3 * t2 + 2, 3 * t3 + 1]
    }

    /// Flips the edge of half-edge `h` (`a -> b` in `(a, b, c)`, twin in `(b, a, d)`) to `c - d`.
    /// Returns the new triangles `(d, c, a)` and `(c, d, b)` as slot ids.
    pub(crate) fn flip(&mut self, h: u32) -> (u32, u32) {
        let g = self.twin[h as usize];
        let (hh, gg) = (HalfEdgeId(h), HalfEdgeId(g));
        let (va, vb, vc) = (self.origin[h as usize], self.dest(h), self.apex(h));
        let vd = self.apex(g);
        let out_bc = self.twin[hh.next().index()];
        let out_ca = self.twin[hh.prev().index()];
        let out_ad = self.twin[gg.next().index()];
        let out_db = self.twin[gg.prev().index()];
        let c_bc = self.constrained[hh.next().index()];
        let c_ca = self.constrained[hh.prev().index()];
        let c_ad = self.constrained[gg.next().index()];
        let c_db = self.constrained[gg.prev().index()];
        let face = self.face[(h / 3) as usize];
        let t0 = self.take_slot(Some(h / 3));
        let t1 = self.take_slot(Some(g / 3));
        self.write_triangle(t0, vd, vc, va, face);
        self.write_triangle(t1, vc, vd, vb, face);
        let (e0, e1) = (3 * t0, 3 * t1);
        self.link(e0, e1);
        self.constrained[e0 as usize] = false;
        self.constrained[e1 as usize] = false;
        self.link(e0 + 1, out_ca);
        self.constrained[(e0 + 1) as usize] = c_ca;
        self.link(e0 + 2, out_ad);
        self.constrained[(e0 + 2) as usize] = c_ad;
        self.link(e1 + 1, out_db);
        self.constrained[(e1 + 1) as usize] = c_db;
        self.link(e1 + 2, out_bc);
        self.constrained[(e1 + 2) as usize] = c_bc;
        (t0, t1)
    }

    /// `true` when the unconstrained edge of `h` violates the empty-circumcircle test.
    #[inline]
    pub(crate) fn is_illegal(&self, h: u32) -> bool {
        if self.constrained[h as usize] {
            return false;
        }
        let g = self.twin[h as usize];
        if g == NONE {
            return false;
        }
        let (a, b, c) = (self.origin[h as usize], self.dest(h), self.apex(h));
        let d = self.apex(g);
        incircle(self.pt(a), self.pt(b), self.pt(c), self.pt(d)) > 0.0
    }

    /// Lawson's flips after inserting a vertex: `stack` holds half-edges opposite the new vertex.
    pub(crate) fn legalize_around_new_vertex(&mut self, stack: &mut Vec<u32>) {
        while let Some(h) = stack.pop() {
            if self.is_illegal(h) {
                let (t0, t1) = self.flip(h);
                // The new vertex is `c`; the edges opposite it are (a -> d) and (d -> b).
                stack.push(3 * t0 + 2);
                stack.push(3 * t1 + 1);
            }
        }
    }

    /// Lawson's flips from arbitrary suspect half-edges, until every unconstrained edge they lead
    /// to is locally Delaunay. Triangles retired meanwhile are skipped.
    pub(crate) fn legalize_edges(&mut self, stack: &mut Vec<u32>) {
        while let Some(h) = stack.pop() {
            if self.face[(h / 3) as usize] == FaceKind::Dead || self.origin[h as usize] == NONE {
                continue;
            }
            if self.is_illegal(h) {
                let (t0, t1) = self.flip(h);
                stack.extend_from_slice(&[3 * t0 + 1, 3 * t0 + 2, 3 * t1 + 1, 3 * t1 + 2]);
            }
        }
    }

    /// Replaces the triangles `dead` (a connected cavity) by `new` counter-clockwise triangles
    /// covering the same region, all of kind `face`. Edges on the cavity's rim keep their twins and
    /// map-edge flags; `constrain` names one new edge (either direction) to mark as a map edge.
    /// Returns the new slots.
    pub(crate) fn replace_cavity(
        &mut self,
        dead: &[u32],
        new: &[[u32; 3]],
        face: FaceKind,
        constrain: Option<(u32, u32)>,
    ) -> Vec<u32> {
        let dead_set: std::collections::HashSet<u32> = dead.iter().copied().collect();
        // Rim: (origin, dest) of each inner half-edge -> (outer twin, flag).
        let mut rim: HashMap<(u32, u32), (u32, bool)> = HashMap::new();
        for &t in dead {
            for i in 0..3 {
                let h = 3 * t + i;
                let g = self.twin[h as usize];
                if g == NONE || !dead_set.contains(&(g / 3)) {
                    rim.insert(
                        (self.origin[h as usize], self.dest(h)),
                        (g, self.constrained[h as usize]),
                    );
                }
            }
        }
        let mut slots = Vec::with_capacity(new.len());
        let mut reuse = dead.to_vec();
        reuse.reverse();
        for _ in new {
            let old = reuse.pop();
            slots.push(self.take_slot(old));
        }
        for t in reuse {
            self.retire(t);
        }
        let mut inner: HashMap<(u32, u32), u32> = HashMap::new();
        for (&t, tri) in slots.iter().zip(new) {
            self.write_triangle(t, tri[0], tri[1], tri[2], face);
        }
        for (&t, tri) in slots.iter().zip(new) {
            for i in 0..3u32 {
                let h = 3 * t + i;
                let (u, v) = (tri[i as usize], tri[((i + 1) % 3) as usize]);
                let is_constraint =
                    constrain.is_some_and(|(a, b)| (a, b) == (u, v) || (a, b) == (v, u));
                if let Some(&(g, flag)) = rim.get(&(u, v)) {
                    self.link(h, g);
                    self.constrained[h as usize] = flag || is_constraint;
                } else if let Some(g) = inner.remove(&(v, u)) {
                    self.link(h, g);
                    self.constrained[h as usize] = is_constraint;
                    self.constrained[g as usize] = is_constraint;
                } else {
                    inner.insert((u, v), h);
                    self.constrained[h as usize] = is_constraint;
                }
            }
        }
        debug_assert!(
            inner.is_empty(),
            "cavity retriangulation left unmatched edges"
        );
        slots
    }

    /// Changes the kind of triangle `t`, retiring and re-allocating it in update mode (a BTM
    /// triangle that becomes part of an obstacle leaves the BTM, so its id must go).
    pub(crate) fn set_face(&mut self, t: u32, face: FaceKind) -> u32 {
        if self.face[t as usize] == face {
            return t;
        }
        if !self.fresh_slots {
            self.face[t as usize] = face;
            return t;
        }
        let b = 3 * t as usize;
        let (va, vb, vc) = (self.origin[b], self.origin[b + 1], self.origin[b + 2]);
        let tw = [self.twin[b], self.twin[b + 1], self.twin[b + 2]];
        let cons = [
            self.constrained[b],
            self.constrained[b + 1],
            self.constrained[b + 2],
        ];
        let n = self.take_slot(Some(t));
        self.write_triangle(n, va, vb, vc, face);
        for i in 0..3 {
            self.link(3 * n + i as u32, tw[i]);
            self.constrained[3 * n as usize + i] = cons[i];
        }
        n
    }
}
