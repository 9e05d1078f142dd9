//! A small dense linear-program solver for the tension-limited stability check (Kumar §III-B):
//! the two-phase primal simplex method on a dense tableau (Dantzig's rule, Bland's rule after a
//! run of degenerate pivots so that it cannot cycle).
//!
//! ```text
//! min cᵀx   subject to   a_iᵀ x = b_i (equalities),   a_iᵀ x <= b_i (inequalities)
//! ```
//!
//! Kumar's LP has four contacts times three force components plus the tether tension (13
//! variables, 6 equalities, 22 inequalities; [`crate::tension_lp`] hands it over in generator
//! form, 17 non-negative variables and 7 rows). clarabel's sparse set-up and interior-point
//! iterations cost about 100 us per check (95 % of `rappel track`'s time per waypoint); the
//! dense simplex a few microseconds (`docs/mechanics.md`). clarabel stays the oracle it is
//! tested against ([`crate::tension_lp::TensionLimitedLp::check_clarabel`]).
//!
//! # Method
//! A bound row `-x_j <= 0` makes `x_j` a non-negative column; every other variable is split into
//! `x⁺ - x⁻`. Each inequality gets a slack; a row whose right-hand side is negative is negated,
//! and every row without a slack of coefficient `+1` gets an artificial variable. Phase 1
//! minimises the artificials' sum (a positive minimum proves **infeasibility**), then drives the
//! artificials left at zero out of the basis (a row where none can leave is redundant); phase 2
//! minimises `cᵀx` without them, and a column with a negative reduced cost and no positive entry
//! proves the program **unbounded**.
//!
//! # Tolerances (the statics normalise the data to unit size: forces in units of the weight)
//! * [`FEASIBILITY_TOL`]: phase 1 ending above it proves infeasibility (absolute: `1e-9 W`).
//! * [`OPTIMALITY_TOL`]: a reduced cost above `-OPTIMALITY_TOL` is not negative.
//! * [`PIVOT_TOL`]: an entry below it in magnitude is never a pivot; [`HARRIS_TOL`]: the ratio
//!   test takes the largest pivot among the rows within it of the smallest ratio (Harris 1973),
//!   so that no tiny pivot swamps the tableau. The reduced costs are updated by each pivot and
//!   recomputed from the tableau before any conclusion (optimal, unbounded).
//! * At most [`MAX_PIVOTS_PER_COLUMN`] times the tableau's columns pivots in all: a typed error
//!   beyond (it has not been seen).

/// Phase 1's optimum above this proves infeasibility (module docs).
pub const FEASIBILITY_TOL: f64 = 1e-9;
/// Reduced costs above `-OPTIMALITY_TOL` are taken as non-negative (module docs).
pub const OPTIMALITY_TOL: f64 = 1e-10;
/// Entries below this magnitude are never pivots (module docs).
pub const PIVOT_TOL: f64 = 1e-9;
/// Harris's ratio-test slack: rows whose ratio is within this (over the pivot) of the smallest
/// compete on pivot size (module docs).
pub const HARRIS_TOL: f64 = 1e-9;
/// The pivot bound per tableau column (module docs).
pub const MAX_PIVOTS_PER_COLUMN: usize = 50;
/// Consecutive degenerate pivots after which Bland's rule replaces Dantzig's.
const DEGENERATE_RUN: usize = 8;

/// A dense LP: rows stored sparsely as given, the objective dense.
#[derive(Clone, Debug, Default)]
pub struct DenseLp {
    n: usize,
    c: Vec<f64>,
    eq: Vec<(Vec<(usize, f64)>, f64)>,
    le: Vec<(Vec<(usize, f64)>, f64)>,
}

/// What the simplex concluded.
#[derive(Clone, Debug, PartialEq)]
pub enum LpOutcome {
    /// An optimal vertex.
    Optimal {
        /// The solution.
        x: Vec<f64>,
        /// `cᵀx`.
        objective: f64,
    },
    /// The constraints cannot be met.
    Infeasible,
    /// The objective decreases without bound on the feasible set.
    Unbounded,
}

/// Why the simplex gave no answer.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum DenseLpError {
    /// Non-finite data.
    #[error("non-finite LP data")]
    NonFinite,
    /// More than [`MAX_PIVOTS_PER_COLUMN`] pivots per column.
    #[error("the simplex did not finish within {0} pivots")]
    PivotLimit(usize),
}

impl DenseLp {
    /// An LP in `n` variables with a zero objective and no constraints.
    pub fn new(n: usize) -> Self {
        DenseLp {
            n,
            c: vec![0.0; n],
            ..Default::default()
        }
    }

    /// Adds `c * x_i` to the objective.
    pub fn add_linear(&mut self, i: usize, c: f64) {
        self.c[i] += c;
    }

    /// Adds the equality `Σ a_j x_j = rhs`.
    pub fn equal(&mut self, row: &[(usize, f64)], rhs: f64) {
        self.eq.push((row.to_vec(), rhs));
    }

    /// Adds the inequality `Σ a_j x_j <= rhs`.
    pub fn at_most(&mut self, row: &[(usize, f64)], rhs: f64) {
        self.le.push((row.to_vec(), rhs));
    }

    /// Solves the LP (module docs).
    ///
    /// ```
    /// use rappel_mechanics::dense_lp::{DenseLp, LpOutcome};
    /// // min -x - y  s.t.  x + 2y <= 4,  3x + y <= 6,  x, y >= 0  =>  (1.6, 1.2), -2.8.
    /// let mut lp = DenseLp::new(2);
    /// lp.add_linear(0, -1.0);
    /// lp.add_linear(1, -1.0);
    /// lp.at_most(&[(0, 1.0), (1, 2.0)], 4.0);
    /// lp.at_most(&[(0, 3.0), (1, 1.0)], 6.0);
    /// lp.at_most(&[(0, -1.0)], 0.0);
    /// lp.at_most(&[(1, -1.0)], 0.0);
    /// match lp.solve().unwrap() {
    ///     LpOutcome::Optimal { x, objective } => {
    ///         assert!((x[0] - 1.6).abs() < 1e-12 && (x[1] - 1.2).abs() < 1e-12);
    ///         assert!((objective + 2.8).abs() < 1e-12);
    ///     }
    ///     other => panic!("{other:?}"),
    /// }
    /// ```
    pub fn solve(&self) -> Result<LpOutcome, DenseLpError> {
        let finite = |rows: &[(Vec<(usize, f64)>, f64)]| {
            rows.iter()
                .all(|(r, b)| b.is_finite() && r.iter().all(|(_, v)| v.is_finite()))
        };
        if !(self.c.iter().all(|v| v.is_finite()) && finite(&self.eq) && finite(&self.le)) {
            return Err(DenseLpError::NonFinite);
        }
        // Sign bounds: `-x_j <= 0` rows.
        let mut nonneg = vec![false; self.n];
        let mut rows_le = Vec::new();
        for (row, rhs) in &self.le {
            match row.as_slice() {
                [(j, v)] if *v < 0.0 && *rhs == 0.0 => nonneg[*j] = true,
                _ => rows_le.push((row, *rhs)),
            }
        }
        // Structural columns: x_j (non-negative) or x_j⁺, x_j⁻.
        let mut col_of = Vec::with_capacity(self.n);
        let mut structural = 0;
        for &nn in &nonneg {
            col_of.push(structural);
            structural += if nn { 1 } else { 2 };
        }
        let m = self.eq.len() + rows_le.len();
        let slacks = rows_le.len();
        // Rows: (dense row over structural + slack columns, rhs, has a +1 slack).
        let width0 = structural + slacks;
        let mut rows: Vec<(Vec<f64>, f64, Option<usize>)> = Vec::with_capacity(m);
        let dense = |row: &[(usize, f64)]| {
            let mut d = vec![0.0; width0];
            for &(j, v) in row {
                d[col_of[j]] += v;
                if !nonneg[j] {
                    d[col_of[j] + 1] -= v;
                }
            }
            d
        };
        for (row, rhs) in &self.eq {
            rows.push((dense(row), *rhs, None));
        }
        for (k, (row, rhs)) in rows_le.iter().enumerate() {
            let mut d = dense(row);
            d[structural + k] = 1.0;
            rows.push((d, *rhs, Some(structural + k)));
        }
        for (d, b, slack) in &mut rows {
            if *b < 0.0 {
                d.iter_mut().for_each(|v| *v = -*v);
                *b = -*b;
                *slack = None;
            }
        }
        let artificials: Vec<usize> = (0..m).filter(|&i| rows[i].2.is_none()).collect();
        let width = width0 + artificials.len();
        // The tableau: m rows of `width` entries and the rhs.
        let mut t = vec![0.0; m * (width + 1)];
        let mut basis = vec![0usize; m];
        let mut a = 0;
        for (i, (d, b, slack)) in rows.iter().enumerate() {
            let r = &mut t[i * (width + 1)..(i + 1) * (width + 1)];
            r[..width0].copy_from_slice(d);
            r[width] = *b;
            basis[i] = match slack {
                Some(s) => *s,
                None => {
                    r[width0 + a] = 1.0;
                    a += 1;
                    width0 + a - 1
                }
            };
        }
        let mut tab = Tableau {
            t,
            m,
            width,
            basis,
            pivots: 0,
            limit: MAX_PIVOTS_PER_COLUMN * (width + 1),
        };
        // Phase 1: minimise the artificials' sum.
        if !artificials.is_empty() {
            let mut cost = vec![0.0; width];
            cost[width0..].iter_mut().for_each(|v| *v = 1.0);
            let sum = tab.optimise(&cost, width)?;
            if sum.is_none_or(|v| v > FEASIBILITY_TOL) {
                return Ok(LpOutcome::Infeasible);
            }
            tab.drive_out_artificials(width0);
        }
        // Phase 2: the objective over the structural columns.
        let mut cost = vec![0.0; width];
        for (j, &c) in self.c.iter().enumerate() {
            cost[col_of[j]] = c;
            if !nonneg[j] {
                cost[col_of[j] + 1] = -c;
            }
        }
        let Some(objective) = tab.optimise(&cost, width0)? else {
            return Ok(LpOutcome::Unbounded);
        };
        let mut column = vec![0.0; width];
        for (i, &b) in tab.basis.iter().enumerate() {
            column[b] = tab.t[i * (width + 1) + width];
        }
        let x = (0..self.n)
            .map(|j| {
                let p = column[col_of[j]];
                if nonneg[j] {
                    p
                } else {
                    p - column[col_of[j] + 1]
                }
            })
            .collect();
        Ok(LpOutcome::Optimal { x, objective })
    }
}

/// A simplex tableau `[A | b]` in canonical form for `basis`.
struct Tableau {
    t: Vec<f64>,
    m: usize,
    width: usize,
    basis: Vec<usize>,
    pivots: usize,
    limit: usize,
}

impl Tableau {
    fn at(&self, i: usize, j: usize) -> f64 {
        self.t[i * (self.width + 1) + j]
    }

    fn rhs(&self, i: usize) -> f64 {
        self.t[i * (self.width + 1) + self.width]
    }

    /// Pivots on `(r, e)`: column `e` enters, row `r`'s basic variable leaves.
    fn pivot(&mut self, r: usize, e: usize) {
        let w = self.width + 1;
        let p = self.t[r * w + e];
        for v in &mut self.t[r * w..(r + 1) * w] {
            *v /= p;
        }
        let (before, rest) = self.t.split_at_mut(r * w);
        let (row, after) = rest.split_at_mut(w);
        for other in before.chunks_mut(w).chain(after.chunks_mut(w)) {
            let f = other[e];
            if f != 0.0 {
                for (o, &v) in other.iter_mut().zip(row.iter()) {
                    *o -= f * v;
                }
                other[e] = 0.0;
            }
        }
        self.basis[r] = e;
        self.pivots += 1;
    }

    /// Minimises `costᵀ column` over the columns `0..allowed` (the others never enter); `None`
    /// when unbounded, else the optimal value.
    fn optimise(&mut self, cost: &[f64], allowed: usize) -> Result<Option<f64>, DenseLpError> {
        let w = self.width + 1;
        // Reduced costs d_j = c_j - c_Bᵀ column_j: recomputed from the tableau before every
        // conclusion, updated by every pivot in between.
        let fresh = |tab: &Tableau| -> Vec<f64> {
            (0..tab.width)
                .map(|j| {
                    cost[j]
                        - (0..tab.m)
                            .map(|i| cost[tab.basis[i]] * tab.at(i, j))
                            .sum::<f64>()
                })
                .collect()
        };
        let mut d = fresh(self);
        let mut recomputed = true;
        let mut basic = vec![false; self.width];
        for &b in &self.basis {
            basic[b] = true;
        }
        let mut degenerate = 0;
        loop {
            if self.pivots > self.limit {
                return Err(DenseLpError::PivotLimit(self.limit));
            }
            let bland = degenerate >= DEGENERATE_RUN;
            let mut enter = None;
            let mut best = -OPTIMALITY_TOL;
            for j in (0..allowed).filter(|&j| !basic[j]) {
                if d[j] < best {
                    enter = Some(j);
                    if bland {
                        break;
                    }
                    best = d[j];
                }
            }
            let Some(e) = enter else {
                if !recomputed {
                    d = fresh(self);
                    recomputed = true;
                    continue;
                }
                let value = (0..self.m).map(|i| cost[self.basis[i]] * self.rhs(i)).sum();
                return Ok(Some(value));
            };
            // Harris's two-pass ratio test: the largest pivot among the rows whose ratio is
            // within HARRIS_TOL of the smallest (a tiny pivot would swamp the tableau).
            let bound = (0..self.m)
                .filter(|&i| self.at(i, e) > PIVOT_TOL)
                .map(|i| (self.rhs(i).max(0.0) + HARRIS_TOL) / self.at(i, e))
                .fold(f64::INFINITY, f64::min);
            let leave = (0..self.m)
                .filter(|&i| {
                    let a = self.at(i, e);
                    a > PIVOT_TOL && self.rhs(i).max(0.0) / a <= bound
                })
                .max_by(|&a, &b| {
                    self.at(a, e)
                        .total_cmp(&self.at(b, e))
                        .then(self.basis[b].cmp(&self.basis[a]))
                });
            let Some(r) = leave else {
                if !recomputed {
                    d = fresh(self);
                    recomputed = true;
                    continue;
                }
                return Ok(None);
            };
            let ratio = self.rhs(r).max(0.0) / self.at(r, e);
            degenerate = if ratio <= 0.0 { degenerate + 1 } else { 0 };
            basic[self.basis[r]] = false;
            basic[e] = true;
            self.pivot(r, e);
            let de = d[e];
            for (dj, &v) in d.iter_mut().zip(&self.t[r * w..r * w + self.width]) {
                *dj -= de * v;
            }
            d[e] = 0.0;
            recomputed = false;
        }
    }

    /// After phase 1: pivots every artificial (columns `first..`) still basic at zero out of the
    /// basis on a structural or slack column; a row where every such entry is zero is redundant
    /// and keeps its artificial (at zero; it never enters again).
    fn drive_out_artificials(&mut self, first: usize) {
        for i in 0..self.m {
            if self.basis[i] >= first
                && let Some(e) = (0..first)
                    .filter(|j| !self.basis.contains(j))
                    .max_by(|&a, &b| self.at(i, a).abs().total_cmp(&self.at(i, b).abs()))
                    .filter(|&j| self.at(i, j).abs() > PIVOT_TOL)
            {
                self.pivot(i, e);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn optimal(lp: &DenseLp) -> (Vec<f64>, f64) {
        match lp.solve().unwrap() {
            LpOutcome::Optimal { x, objective } => (x, objective),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn equalities_free_variables_infeasibility_and_unboundedness() {
        // min x + y  s.t.  x - y = 1, y >= -2 (free x, y)  =>  y = -2, x = -1, objective -3.
        let mut lp = DenseLp::new(2);
        lp.add_linear(0, 1.0);
        lp.add_linear(1, 1.0);
        lp.equal(&[(0, 1.0), (1, -1.0)], 1.0);
        lp.at_most(&[(1, -1.0)], 2.0);
        let (x, v) = optimal(&lp);
        assert!(
            (x[0] + 1.0).abs() < 1e-12 && (x[1] + 2.0).abs() < 1e-12 && (v + 3.0).abs() < 1e-12
        );
        // x <= -1 and x >= 0.
        let mut lp = DenseLp::new(1);
        lp.at_most(&[(0, 1.0)], -1.0);
        lp.at_most(&[(0, -1.0)], 0.0);
        assert_eq!(lp.solve().unwrap(), LpOutcome::Infeasible);
        // min -x, x >= 0, no upper bound.
        let mut lp = DenseLp::new(1);
        lp.add_linear(0, -1.0);
        lp.at_most(&[(0, -1.0)], 0.0);
        assert_eq!(lp.solve().unwrap(), LpOutcome::Unbounded);
        // A redundant equality (twice the same row) is not infeasibility.
        let mut lp = DenseLp::new(2);
        lp.add_linear(0, 1.0);
        lp.equal(&[(0, 1.0), (1, 1.0)], 2.0);
        lp.equal(&[(0, 2.0), (1, 2.0)], 4.0);
        lp.at_most(&[(0, -1.0)], 0.0);
        lp.at_most(&[(1, -1.0)], 0.0);
        let (x, v) = optimal(&lp);
        assert!(v.abs() < 1e-12 && (x[1] - 2.0).abs() < 1e-12, "{x:?}");
        let mut bad = DenseLp::new(1);
        bad.equal(&[(0, f64::NAN)], 1.0);
        assert_eq!(bad.solve(), Err(DenseLpError::NonFinite));
    }

    /// Kumar's LP at a waypoint of `rappel track` where an earlier version of the simplex
    /// wrongly proved infeasibility (clarabel: stable, least tension 198.05 N = 0.5768 W).
    #[test]
    fn a_track_waypoint_found_infeasible_by_mistake() {
        let mut lp = DenseLp::new(13);
        lp.add_linear(12, 1.0);
        lp.equal(
            &[
                (0, -0.17685696947731555),
                (1, 0.9842365632038367),
                (2, 5.551115123125783e-17),
                (3, -0.17685696947731555),
                (4, 0.9842365632038367),
                (5, 5.551115123125783e-17),
                (6, -0.17685696947731555),
                (7, 0.9842365632038367),
                (8, 5.551115123125783e-17),
                (9, -0.17685696947731555),
                (10, 0.9842365632038367),
                (11, 5.551115123125783e-17),
                (12, 0.1768569694773149),
            ],
            0.0,
        );
        lp.equal(
            &[
                (0, -0.5645349004488237),
                (1, -0.10144099029663822),
                (2, -0.8191520442890161),
                (3, -0.5645349004488237),
                (4, -0.10144099029663822),
                (5, -0.8191520442890161),
                (6, -0.5645349004488237),
                (7, -0.10144099029663822),
                (8, -0.8191520442890161),
                (9, -0.5645349004488237),
                (10, -0.10144099029663822),
                (11, -0.8191520442890161),
                (12, 0.5645349004488237),
            ],
            0.0,
        );
        lp.equal(
            &[
                (0, -0.8062393928124183),
                (1, -0.14487274809410317),
                (2, 0.5735764363510114),
                (3, -0.8062393928124183),
                (4, -0.14487274809410317),
                (5, 0.5735764363510114),
                (6, -0.8062393928124183),
                (7, -0.14487274809410317),
                (8, 0.5735764363510114),
                (9, -0.8062393928124183),
                (10, -0.14487274809410317),
                (11, 0.5735764363510114),
                (12, 0.8062393928124182),
            ],
            1.0,
        );
        lp.equal(
            &[
                (0, -2.7755575615628914e-17),
                (1, 1.0408340855860843e-17),
                (2, -0.3439066355674128),
                (3, 1.3877787807814457e-17),
                (4, 1.0408340855860843e-17),
                (5, -0.24663530235488923),
                (6, -1.3877787807814457e-17),
                (7, -1.0408340855860843e-17),
                (8, 0.24663530235488923),
                (9, 2.7755575615628914e-17),
                (10, -1.0408340855860843e-17),
                (11, 0.3439066355674128),
                (12, -0.3444827971213429),
            ],
            -0.20478801107225403,
        );
        lp.equal(
            &[
                (0, 0.22526681217947944),
                (1, -0.24574561328670486),
                (2, -0.12481480053443503),
                (3, -0.22526681217947953),
                (4, -0.24574561328670488),
                (5, 0.185679394712418),
                (6, 0.22526681217947953),
                (7, 0.24574561328670488),
                (8, -0.185679394712418),
                (9, -0.22526681217947944),
                (10, 0.24574561328670486),
                (11, 0.12481480053443503),
                (12, 0.03550434660382306),
            ],
            -1.3877787807814457e-17,
        );
        lp.equal(
            &[
                (0, -0.15773351999652815),
                (1, 0.17207293090530346),
                (2, -0.17825400859518403),
                (3, 0.15773351999652818),
                (4, 0.17207293090530346),
                (5, 0.265177657451646),
                (6, -0.15773351999652818),
                (7, -0.17207293090530346),
                (8, -0.265177657451646),
                (9, 0.15773351999652815),
                (10, -0.17207293090530346),
                (11, 0.17825400859518403),
                (12, 0.05070546183293606),
            ],
            0.0,
        );
        lp.at_most(&[(2, -1.0)], 0.0);
        lp.at_most(&[(0, 1.0), (2, -0.4)], 0.0);
        lp.at_most(&[(0, -1.0), (2, -0.4)], 0.0);
        lp.at_most(&[(1, 1.0), (2, -0.4)], 0.0);
        lp.at_most(&[(1, -1.0), (2, -0.4)], 0.0);
        lp.at_most(&[(5, -1.0)], 0.0);
        lp.at_most(&[(3, 1.0), (5, -0.4)], 0.0);
        lp.at_most(&[(3, -1.0), (5, -0.4)], 0.0);
        lp.at_most(&[(4, 1.0), (5, -0.4)], 0.0);
        lp.at_most(&[(4, -1.0), (5, -0.4)], 0.0);
        lp.at_most(&[(8, -1.0)], 0.0);
        lp.at_most(&[(6, 1.0), (8, -0.4)], 0.0);
        lp.at_most(&[(6, -1.0), (8, -0.4)], 0.0);
        lp.at_most(&[(7, 1.0), (8, -0.4)], 0.0);
        lp.at_most(&[(7, -1.0), (8, -0.4)], 0.0);
        lp.at_most(&[(11, -1.0)], 0.0);
        lp.at_most(&[(9, 1.0), (11, -0.4)], 0.0);
        lp.at_most(&[(9, -1.0), (11, -0.4)], 0.0);
        lp.at_most(&[(10, 1.0), (11, -0.4)], 0.0);
        lp.at_most(&[(10, -1.0), (11, -0.4)], 0.0);
        lp.at_most(&[(12, -1.0)], 0.0);
        lp.at_most(&[(12, 1.0)], 0.7540525333099714);
        let (x, v) = optimal(&lp);
        // The scenario's gravity is 9.81 m/s²: W = 35 kg x 9.81.
        assert!(
            (v - 198.04730630289927 / (35.0 * 9.81)).abs() < 1e-7,
            "{v} {x:?}"
        );
    }

    #[test]
    fn a_degenerate_cycling_example_terminates() {
        // Beale's example, which cycles under Dantzig's rule with the textbook tie-breaking:
        // min -3/4 x4 + 150 x5 - 1/50 x6 + 6 x7, three rows, optimum -1/20.
        let mut lp = DenseLp::new(4);
        for (j, c) in [-0.75, 150.0, -0.02, 6.0].into_iter().enumerate() {
            lp.add_linear(j, c);
            lp.at_most(&[(j, -1.0)], 0.0);
        }
        lp.at_most(&[(0, 0.25), (1, -60.0), (2, -0.04), (3, 9.0)], 0.0);
        lp.at_most(&[(0, 0.5), (1, -90.0), (2, -0.02), (3, 3.0)], 0.0);
        lp.at_most(&[(2, 1.0)], 1.0);
        let (_, v) = optimal(&lp);
        assert!((v + 0.05).abs() < 1e-12, "{v}");
    }
}
