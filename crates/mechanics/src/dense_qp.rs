//! A small dense convex QP solver for the stability checks: Goldfarb and Idnani's dual
//! active-set method (Math. Programming 27, 1983; the algorithm of `quadprog` / QuadProg++),
//! specialised to a **diagonal** Hessian.
//!
//! ```text
//! min ½ Σ_j d_j x_j²   subject to   a_iᵀ x = b_i (equalities),   a_iᵀ x <= b_i (inequalities)
//! ```
//!
//! The stability QP ([`crate::stability_qp`]) has a few contacts times 3 or 6 force and moment
//! components plus the tether tension (13 to 25 variables, 6 equalities, 11 to 40 inequalities):
//! clarabel's sparse set-up (equilibration, symbolic KKT factorisation, allocation) and its
//! interior-point iterations cost 100-200 us per check, the dense active-set method a few
//! microseconds (`docs/mesh.md`).
//!
//! # Method
//! Start at the unconstrained minimum `x = 0` and add the most violated constraint (equalities
//! first), each time moving along the step that keeps the active constraints satisfied and the
//! active multipliers feasible (dropping an active inequality whose multiplier would turn
//! negative). The active normals are kept in the factorisation `L⁻¹N = Q [R; 0]`, `J = L⁻ᵀ Q`
//! (`L = diag(√d)`), updated by Givens rotations. The iterates are dual feasible, so the method
//! stops at the optimum, or proves **primal infeasibility** when a violated constraint can be
//! satisfied neither by a primal step nor by dropping another one (its normal is a non-negative
//! combination of active normals that the others cannot offset).
//!
//! # Semidefinite objectives
//! Goldfarb-Idnani needs a positive definite Hessian. The stability QP weighs only tangential
//! forces and moments; normal forces and the tether tension have weight 0. Those diagonal
//! entries are raised to [`REGULARIZATION`] times the largest weight. The optimal value changes
//! by at most `½ REGULARIZATION d_max |x_free|²` (the unweighted variables' squared norm at the
//! optimum, O(1) in the weight-normalised statics), and where the original optimum is unique
//! (the stability QP's generic case: its unweighted columns are independent) the solution
//! converges to it; where the optimal face is not a point this picks its least-norm point in
//! the free variables, clarabel an interior point of it (the optimal value agrees).
//!
//! # Tolerances (the data is normalised to unit size by the statics)
//! * [`FEASIBILITY_TOL`]: a constraint violated by less is satisfied (absolute, in units of the
//!   weight: `1e-9 W`).
//! * [`DEPENDENCE_TOL`]: a step direction shorter than this (relative to the constraint's
//!   normal) means the constraint is linearly dependent on the active ones.
//! * At most [`MAX_ITERATIONS_PER_ROW`] times the number of rows of iterations: a typed error
//!   beyond (it has not been seen).

/// Diagonal entries below this fraction of the largest are raised to it (module docs).
pub const REGULARIZATION: f64 = 1e-9;
/// A constraint violated by at most this much counts as satisfied (module docs).
pub const FEASIBILITY_TOL: f64 = 1e-9;
/// Relative length below which a step direction is zero (linear dependence; module docs).
pub const DEPENDENCE_TOL: f64 = 1e-12;
/// The iteration bound per constraint row (module docs).
pub const MAX_ITERATIONS_PER_ROW: usize = 50;

/// A dense QP with a diagonal Hessian: rows stored densely, equalities and inequalities apart.
#[derive(Clone, Debug, Default)]
pub struct DenseQp {
    n: usize,
    /// Hessian diagonal (`½ Σ d_j x_j²`).
    d: Vec<f64>,
    /// Equality rows (`n` each) and right-hand sides.
    eq: Vec<f64>,
    eq_rhs: Vec<f64>,
    /// Inequality rows (`n` each, `a·x <= b`) and right-hand sides.
    le: Vec<f64>,
    le_rhs: Vec<f64>,
}

/// What the dense solver concluded.
#[derive(Clone, Debug, PartialEq)]
pub enum DenseOutcome {
    /// The optimum.
    Optimal {
        /// The primal solution.
        x: Vec<f64>,
        /// `½ Σ d_j x_j²` with the unregularised `d`.
        objective: f64,
    },
    /// The constraints cannot be met.
    Infeasible,
}

/// Why the dense solver gave no verdict.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum DenseQpError {
    /// Non-finite data, a negative Hessian entry or a row of the wrong length.
    #[error("invalid QP data: {0}")]
    Input(&'static str),
    /// The iteration bound ran out (module docs).
    #[error("the active-set method did not finish within {0} iterations")]
    IterationLimit(usize),
}

impl DenseQp {
    /// An empty problem in `n` variables (zero objective, no constraints).
    pub fn new(n: usize) -> Self {
        DenseQp {
            n,
            d: vec![0.0; n],
            ..Default::default()
        }
    }

    /// Number of variables.
    pub fn num_variables(&self) -> usize {
        self.n
    }

    /// Adds `weight * x_i²` to the objective.
    pub fn add_square(&mut self, i: usize, weight: f64) {
        self.d[i] += 2.0 * weight;
    }

    /// Adds the equality `Σ a_j x_j = rhs` given as sparse `(j, a_j)` pairs.
    pub fn equal(&mut self, row: &[(usize, f64)], rhs: f64) {
        push_row(&mut self.eq, self.n, row);
        self.eq_rhs.push(rhs);
    }

    /// Adds the inequality `Σ a_j x_j <= rhs` given as sparse `(j, a_j)` pairs.
    pub fn at_most(&mut self, row: &[(usize, f64)], rhs: f64) {
        push_row(&mut self.le, self.n, row);
        self.le_rhs.push(rhs);
    }

    /// Solves the problem (module docs) within [`MAX_ITERATIONS_PER_ROW`] iterations per row.
    pub fn solve(&self) -> Result<DenseOutcome, DenseQpError> {
        let rows = self.eq_rhs.len() + self.le_rhs.len();
        self.solve_within(MAX_ITERATIONS_PER_ROW * rows.max(1))
    }

    /// Solves the problem within `max_iter` active-set iterations (each adds or drops one
    /// inequality); [`DenseQpError::IterationLimit`] beyond.
    pub fn solve_within(&self, max_iter: usize) -> Result<DenseOutcome, DenseQpError> {
        let n = self.n;
        if !self
            .d
            .iter()
            .chain(&self.eq)
            .chain(&self.eq_rhs)
            .chain(&self.le)
            .chain(&self.le_rhs)
            .all(|v| v.is_finite())
        {
            return Err(DenseQpError::Input("non-finite problem data"));
        }
        if self.d.iter().any(|v| *v < 0.0) {
            return Err(DenseQpError::Input("negative Hessian entry"));
        }
        let n_eq = self.eq_rhs.len();
        let n_le = self.le_rhs.len();
        if n == 0 {
            let feasible = self.eq_rhs.iter().all(|b| b.abs() <= FEASIBILITY_TOL)
                && self.le_rhs.iter().all(|b| *b >= -FEASIBILITY_TOL);
            return Ok(if feasible {
                DenseOutcome::Optimal {
                    x: Vec::new(),
                    objective: 0.0,
                }
            } else {
                DenseOutcome::Infeasible
            });
        }
        let d_max = self.d.iter().cloned().fold(0.0, f64::max);
        let floor = if d_max > 0.0 {
            d_max * REGULARIZATION
        } else {
            1.0
        };
        let g: Vec<f64> = self.d.iter().map(|v| v.max(floor)).collect();
        let mut s = Solver::new(n, &g);
        // Row `k`: equalities first, then inequalities written as `-a·x >= -b`.
        let normal = |k: usize, out: &mut [f64]| {
            if k < n_eq {
                out.copy_from_slice(&self.eq[k * n..(k + 1) * n]);
            } else {
                let r = &self.le[(k - n_eq) * n..(k - n_eq + 1) * n];
                for (o, v) in out.iter_mut().zip(r) {
                    *o = -v;
                }
            }
        };
        let rhs = |k: usize| {
            if k < n_eq {
                self.eq_rhs[k]
            } else {
                -self.le_rhs[k - n_eq]
            }
        };
        let mut np = vec![0.0; n];
        // Equalities: full steps, both signs.
        for k in 0..n_eq {
            normal(k, &mut np);
            let slack = dot(&np, &s.x) - rhs(k);
            s.direction(&np);
            let znp = dot(&s.z, &np);
            if norm(&s.z) <= DEPENDENCE_TOL * norm(&np).max(f64::MIN_POSITIVE) {
                // Dependent on the equalities already active: consistent or not.
                if slack.abs() <= FEASIBILITY_TOL {
                    continue;
                }
                return Ok(DenseOutcome::Infeasible);
            }
            let t = -slack / znp;
            s.step(t);
            s.add(k);
            let last = s.u.len() - 1;
            s.u[last] = t;
        }
        let mut iterations = 0;
        loop {
            // The most violated inequality.
            let mut worst: Option<(usize, f64)> = None;
            for k in n_eq..n_eq + n_le {
                if s.is_active(k) {
                    continue;
                }
                normal(k, &mut np);
                let slack = dot(&np, &s.x) - rhs(k);
                if slack < -FEASIBILITY_TOL && worst.is_none_or(|(_, w)| slack < w) {
                    worst = Some((k, slack));
                }
            }
            let Some((p, _)) = worst else { break };
            normal(p, &mut np);
            let mut u_p = 0.0;
            loop {
                iterations += 1;
                if iterations > max_iter {
                    return Err(DenseQpError::IterationLimit(max_iter));
                }
                let slack = dot(&np, &s.x) - rhs(p);
                s.direction(&np);
                // Partial step: the first active inequality whose multiplier reaches 0.
                let mut t1 = f64::INFINITY;
                let mut drop = None;
                for (i, (&k, &r)) in s.active.iter().zip(&s.r).enumerate() {
                    if k >= n_eq && r > 0.0 {
                        let t = s.u[i] / r;
                        if t < t1 {
                            t1 = t;
                            drop = Some(i);
                        }
                    }
                }
                let z_norm = norm(&s.z);
                let t2 = if z_norm <= DEPENDENCE_TOL * norm(&np) {
                    f64::INFINITY
                } else {
                    -slack / dot(&s.z, &np)
                };
                if t1.is_infinite() && t2.is_infinite() {
                    return Ok(DenseOutcome::Infeasible);
                }
                if t2.is_infinite() {
                    // Dual step only: shift weight onto p, drop the blocking constraint.
                    s.dual_step(t1);
                    u_p += t1;
                    s.remove(drop.expect("t1 finite"));
                    continue;
                }
                let t = t1.min(t2);
                s.step(t);
                u_p += t;
                if t2 <= t1 {
                    s.add(p);
                    let last = s.u.len() - 1;
                    s.u[last] = u_p;
                    break;
                }
                s.remove(drop.expect("t1 finite"));
            }
        }
        let objective = 0.5 * self.d.iter().zip(&s.x).map(|(d, x)| d * x * x).sum::<f64>();
        Ok(DenseOutcome::Optimal { x: s.x, objective })
    }
}

fn push_row(rows: &mut Vec<f64>, n: usize, row: &[(usize, f64)]) {
    let start = rows.len();
    rows.resize(start + n, 0.0);
    for &(j, v) in row {
        rows[start + j] += v;
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn norm(a: &[f64]) -> f64 {
    dot(a, a).sqrt()
}

/// The active-set state: iterate, active rows with multipliers, and the factorisation.
struct Solver {
    n: usize,
    x: Vec<f64>,
    /// `J`, column-major (`n` columns of `n`).
    j: Vec<f64>,
    /// `R`, column-major upper triangular (column `i` = active row `i`), `n x n` storage.
    r_mat: Vec<f64>,
    active: Vec<usize>,
    u: Vec<f64>,
    /// Scratch: `Jᵀ n_p`, primal step `z`, dual step `r`.
    dv: Vec<f64>,
    z: Vec<f64>,
    r: Vec<f64>,
}

impl Solver {
    fn new(n: usize, g: &[f64]) -> Self {
        let mut j = vec![0.0; n * n];
        for (i, gi) in g.iter().enumerate() {
            j[i * n + i] = 1.0 / gi.sqrt();
        }
        Solver {
            n,
            x: vec![0.0; n],
            j,
            r_mat: vec![0.0; n * n],
            active: Vec::with_capacity(n),
            u: Vec::with_capacity(n),
            dv: vec![0.0; n],
            z: vec![0.0; n],
            r: Vec::with_capacity(n),
        }
    }

    fn is_active(&self, k: usize) -> bool {
        self.active.contains(&k)
    }

    fn col(&self, c: usize) -> &[f64] {
        &self.j[c * self.n..(c + 1) * self.n]
    }

    /// `dv = Jᵀ np`, `z = J₂ dv₂` (the primal step), `r = R⁻¹ dv₁` (the dual step).
    fn direction(&mut self, np: &[f64]) {
        let (n, q) = (self.n, self.active.len());
        for c in 0..n {
            self.dv[c] = dot(self.col(c), np);
        }
        self.z.iter_mut().for_each(|v| *v = 0.0);
        for c in q..n {
            let w = self.dv[c];
            for k in 0..n {
                self.z[k] += self.j[c * n + k] * w;
            }
        }
        self.r.clear();
        self.r.resize(q, 0.0);
        for i in (0..q).rev() {
            let mut v = self.dv[i];
            for k in i + 1..q {
                v -= self.r_mat[k * n + i] * self.r[k];
            }
            self.r[i] = v / self.r_mat[i * n + i];
        }
    }

    /// Primal and dual step of length `t` toward satisfying the row being added (its own
    /// multiplier is tracked by the caller).
    fn step(&mut self, t: f64) {
        for (x, z) in self.x.iter_mut().zip(&self.z) {
            *x += t * z;
        }
        self.dual_step(t);
    }

    fn dual_step(&mut self, t: f64) {
        for (u, r) in self.u.iter_mut().zip(&self.r) {
            *u -= t * r;
        }
    }

    /// Appends row `k` (its `dv = Jᵀ n_k` current) to the active set.
    fn add(&mut self, k: usize) {
        let (n, q) = (self.n, self.active.len());
        // Rotate columns q..n of J so that dv has zeros below position q.
        for c in (q + 1..n).rev() {
            let (a, b) = (self.dv[c - 1], self.dv[c]);
            if b == 0.0 {
                continue;
            }
            let h = a.hypot(b);
            let (cs, sn) = (a / h, b / h);
            self.dv[c - 1] = h;
            self.dv[c] = 0.0;
            rotate_columns(&mut self.j, n, c - 1, c, cs, sn);
        }
        for i in 0..=q {
            self.r_mat[q * n + i] = self.dv[i];
        }
        self.active.push(k);
        self.u.push(0.0);
    }

    /// Removes the active row at position `i`, restoring `R`'s triangle.
    fn remove(&mut self, i: usize) {
        let (n, q) = (self.n, self.active.len());
        self.active.remove(i);
        self.u.remove(i);
        // Shift R's columns left.
        for c in i..q - 1 {
            for k in 0..n {
                self.r_mat[c * n + k] = self.r_mat[(c + 1) * n + k];
            }
        }
        for k in 0..n {
            self.r_mat[(q - 1) * n + k] = 0.0;
        }
        // Upper Hessenberg from column i: rotate rows c, c + 1.
        for c in i..q - 1 {
            let (a, b) = (self.r_mat[c * n + c], self.r_mat[c * n + c + 1]);
            if b == 0.0 {
                continue;
            }
            let h = a.hypot(b);
            let (cs, sn) = (a / h, b / h);
            for col in c..q - 1 {
                let (ra, rb) = (self.r_mat[col * n + c], self.r_mat[col * n + c + 1]);
                self.r_mat[col * n + c] = cs * ra + sn * rb;
                self.r_mat[col * n + c + 1] = -sn * ra + cs * rb;
            }
            self.r_mat[c * n + c + 1] = 0.0;
            rotate_columns(&mut self.j, n, c, c + 1, cs, sn);
        }
    }
}

/// Columns `a`, `b` of the column-major `n x n` matrix `m` become `cs a + sn b`, `-sn a + cs b`.
fn rotate_columns(m: &mut [f64], n: usize, a: usize, b: usize, cs: f64, sn: f64) {
    for k in 0..n {
        let (x, y) = (m[a * n + k], m[b * n + k]);
        m[a * n + k] = cs * x + sn * y;
        m[b * n + k] = -sn * x + cs * y;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn approx(a: &[f64], b: &[f64]) -> bool {
        a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-9)
    }

    #[test]
    fn closed_form_optima_infeasibility_and_the_iteration_bound() {
        // min x0² + x1² s.t. x0 + x1 = 2: (1, 1), objective 2.
        let mut q = DenseQp::new(2);
        q.add_square(0, 1.0);
        q.add_square(1, 1.0);
        q.equal(&[(0, 1.0), (1, 1.0)], 2.0);
        match q.solve().unwrap() {
            DenseOutcome::Optimal { x, objective } => {
                assert!(approx(&x, &[1.0, 1.0]) && (objective - 2.0).abs() < 1e-9)
            }
            other => panic!("{other:?}"),
        }
        // Adding x0 >= 1.5 (written -x0 <= -1.5) and x1 >= 0.8: (1.5, 0.8) is infeasible with
        // the equality's 2 only if both bind; with x1 >= 0.4 the optimum is (1.5, 0.5).
        let mut r = q.clone();
        r.at_most(&[(0, -1.0)], -1.5);
        r.at_most(&[(1, -1.0)], -0.4);
        match r.solve().unwrap() {
            DenseOutcome::Optimal { x, .. } => assert!(approx(&x, &[1.5, 0.5]), "{x:?}"),
            other => panic!("{other:?}"),
        }
        r.at_most(&[(1, -1.0)], -0.8);
        assert_eq!(r.solve().unwrap(), DenseOutcome::Infeasible);
        // Two inequalities to add: one iteration is not enough.
        let mut s = DenseQp::new(2);
        s.add_square(0, 1.0);
        s.add_square(1, 1.0);
        s.at_most(&[(0, -1.0)], -1.0);
        s.at_most(&[(1, -1.0)], -1.0);
        assert_eq!(s.solve_within(1), Err(DenseQpError::IterationLimit(1)));
        assert!(matches!(s.solve(), Ok(DenseOutcome::Optimal { .. })));
        // Inconsistent dependent equalities; NaN data.
        let mut e = DenseQp::new(1);
        e.add_square(0, 1.0);
        e.equal(&[(0, 1.0)], 1.0);
        e.equal(&[(0, 2.0)], 3.0);
        assert_eq!(e.solve().unwrap(), DenseOutcome::Infeasible);
        e.equal(&[(0, f64::NAN)], 0.0);
        assert!(matches!(e.solve(), Err(DenseQpError::Input(_))));
    }
}
