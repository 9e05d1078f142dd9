//! The one place that talks to the clarabel interior-point solver: assembling a conic program
//! `min ½ xᵀPx + qᵀx  s.t.  Ax + s = b, s ∈ K` with `K` a product of a zero cone (equalities) and
//! a non-negative cone (inequalities `a·x <= b`), running it, and mapping clarabel's statuses to
//! ours (GUIDE §3): `Solved`/`AlmostSolved` → [`ConicOutcome::Optimal`], `PrimalInfeasible` (and its
//! reduced-accuracy twin) → [`ConicOutcome::Infeasible`], everything else → a
//! [`StabilityError`]. `P` is passed as its upper triangle (here diagonal); `verbose` is off.
//!
//! Setting up (`DefaultSolver::new`: equilibration, KKT symbolic factorisation) and solving are
//! separate steps ([`ConicProblem::setup`], [`PreparedSolver::solve`]) so that benchmarks can time
//! them apart; clarabel has no warm start, so each check sets up afresh.

use crate::stability_error::StabilityError;
use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
};
use std::panic::{AssertUnwindSafe, catch_unwind};

/// clarabel's iteration limit used by default (clarabel's own default).
pub const DEFAULT_MAX_ITER: u32 = 200;

/// Settings passed to clarabel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolverSettings {
    max_iter: u32,
    time_limit: f64,
}

impl Default for SolverSettings {
    /// [`DEFAULT_MAX_ITER`] iterations, no time limit.
    fn default() -> Self {
        SolverSettings {
            max_iter: DEFAULT_MAX_ITER,
            time_limit: f64::INFINITY,
        }
    }
}

impl SolverSettings {
    /// Sets the iteration limit (at least 1).
    pub fn with_max_iter(mut self, max_iter: u32) -> Result<Self, StabilityError> {
        if max_iter == 0 {
            return Err(StabilityError::Input("max_iter must be at least 1"));
        }
        self.max_iter = max_iter;
        Ok(self)
    }

    /// Sets a time limit in seconds (positive; infinity for none). Results then depend on the
    /// machine's speed: prefer the iteration limit for reproducible runs.
    pub fn with_time_limit(mut self, seconds: f64) -> Result<Self, StabilityError> {
        if seconds.is_nan() || seconds <= 0.0 {
            return Err(StabilityError::Input("time_limit must be positive"));
        }
        self.time_limit = seconds;
        Ok(self)
    }
}

/// Accumulates rows of a conic program; equalities and inequalities are kept apart and stacked
/// (zero cone first) when built.
#[derive(Clone, Debug, Default)]
pub(crate) struct ConicBuilder {
    n: usize,
    p_diag: Vec<f64>,
    q: Vec<f64>,
    eq: Vec<(Vec<(usize, f64)>, f64)>,
    le: Vec<(Vec<(usize, f64)>, f64)>,
}

impl ConicBuilder {
    pub(crate) fn new(n: usize) -> Self {
        ConicBuilder {
            n,
            p_diag: vec![0.0; n],
            q: vec![0.0; n],
            eq: Vec::new(),
            le: Vec::new(),
        }
    }

    /// Adds `weight * x_i²` to the objective (so `P_ii += 2 weight`).
    pub(crate) fn add_square(&mut self, i: usize, weight: f64) {
        self.p_diag[i] += 2.0 * weight;
    }

    /// Adds `c * x_i` to the objective.
    pub(crate) fn add_linear(&mut self, i: usize, c: f64) {
        self.q[i] += c;
    }

    /// Adds the equality `Σ a_j x_j = rhs`.
    pub(crate) fn equal(&mut self, row: Vec<(usize, f64)>, rhs: f64) {
        self.eq.push((row, rhs));
    }

    /// Adds the inequality `Σ a_j x_j <= rhs`.
    pub(crate) fn at_most(&mut self, row: Vec<(usize, f64)>, rhs: f64) {
        self.le.push((row, rhs));
    }

    /// The same program for the dense active-set solver ([`crate::dense_qp`]); the linear
    /// objective must be zero (the stability QP has none).
    pub(crate) fn dense(&self) -> crate::dense_qp::DenseQp {
        debug_assert!(self.q.iter().all(|v| *v == 0.0));
        let mut d = crate::dense_qp::DenseQp::new(self.n);
        for (i, v) in self.p_diag.iter().enumerate() {
            d.add_square(i, 0.5 * v);
        }
        for (row, rhs) in &self.eq {
            d.equal(row, *rhs);
        }
        for (row, rhs) in &self.le {
            d.at_most(row, *rhs);
        }
        d
    }

    /// The program (linear objective, no squares) for the dense simplex ([`crate::dense_lp`])
    /// over new variables `y` (`n_new` of them): old variable `j` is `Σ v y_c` over `(c, v)` in
    /// `substitution[j]`, in the objective and in every row.
    pub(crate) fn dense_lp_substituted(
        &self,
        substitution: &[Vec<(usize, f64)>],
        n_new: usize,
    ) -> crate::dense_lp::DenseLp {
        debug_assert!(self.p_diag.iter().all(|v| *v == 0.0));
        debug_assert_eq!(substitution.len(), self.n);
        // One dense buffer for every row (the rows are short; the allocations were a fifth of
        // `rappel track`'s time).
        let mut dense = vec![0.0; n_new];
        let mut rewrite = |row: &[(usize, f64)]| -> Vec<(usize, f64)> {
            for &(j, a) in row {
                for &(c, v) in &substitution[j] {
                    dense[c] += a * v;
                }
            }
            let out = dense
                .iter()
                .enumerate()
                .filter(|(_, v)| **v != 0.0)
                .map(|(c, v)| (c, *v))
                .collect();
            dense.iter_mut().for_each(|v| *v = 0.0);
            out
        };
        let mut d = crate::dense_lp::DenseLp::new(n_new);
        let objective: Vec<(usize, f64)> = self.q.iter().copied().enumerate().collect();
        for (c, v) in rewrite(&objective) {
            d.add_linear(c, v);
        }
        for (row, rhs) in &self.eq {
            d.equal(&rewrite(row), *rhs);
        }
        for (row, rhs) in &self.le {
            d.at_most(&rewrite(row), *rhs);
        }
        d
    }

    pub(crate) fn build(self, settings: SolverSettings) -> ConicProblem {
        let n = self.n;
        let (mut ri, mut ci, mut vi, mut b) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for (r, (row, rhs)) in self.eq.iter().chain(self.le.iter()).enumerate() {
            for &(c, v) in row {
                if v != 0.0 {
                    ri.push(r);
                    ci.push(c);
                    vi.push(v);
                }
            }
            b.push(*rhs);
        }
        let m = b.len();
        let a = CscMatrix::new_from_triplets(m, n, ri, ci, vi);
        let (pi, pv): (Vec<usize>, Vec<f64>) = self
            .p_diag
            .iter()
            .enumerate()
            .filter(|(_, v)| **v != 0.0)
            .map(|(i, v)| (i, *v))
            .unzip();
        let p = CscMatrix::new_from_triplets(n, n, pi.clone(), pi, pv);
        let mut cones = Vec::new();
        if !self.eq.is_empty() {
            cones.push(SupportedConeT::ZeroConeT(self.eq.len()));
        }
        if !self.le.is_empty() {
            cones.push(SupportedConeT::NonnegativeConeT(self.le.len()));
        }
        ConicProblem {
            p,
            q: self.q,
            a,
            b,
            cones,
            settings,
        }
    }
}

/// An assembled conic program, ready for clarabel's setup.
#[derive(Debug)]
pub struct ConicProblem {
    p: CscMatrix<f64>,
    q: Vec<f64>,
    a: CscMatrix<f64>,
    b: Vec<f64>,
    cones: Vec<SupportedConeT<f64>>,
    settings: SolverSettings,
}

impl ConicProblem {
    /// Number of decision variables.
    pub fn num_variables(&self) -> usize {
        self.q.len()
    }

    /// Number of constraint rows (equalities and inequalities).
    pub fn num_constraints(&self) -> usize {
        self.b.len()
    }

    /// clarabel's setup: data checks, equilibration and the KKT system's symbolic factorisation.
    pub fn setup(&self) -> Result<PreparedSolver, StabilityError> {
        if !(self
            .q
            .iter()
            .chain(&self.b)
            .chain(&self.a.nzval)
            .chain(&self.p.nzval)
            .all(|v| v.is_finite()))
        {
            return Err(StabilityError::Input(
                "non-finite problem data (check poses, masses and anchors)",
            ));
        }
        let settings = DefaultSettingsBuilder::default()
            .verbose(false)
            .max_iter(self.settings.max_iter)
            .time_limit(self.settings.time_limit)
            .build()
            .map_err(|e| StabilityError::Setup(e.to_string()))?;
        let built = catch_unwind(AssertUnwindSafe(|| {
            DefaultSolver::new(&self.p, &self.q, &self.a, &self.b, &self.cones, settings)
        }))
        .map_err(|_| StabilityError::Setup("clarabel panicked during setup".into()))?;
        built
            .map(PreparedSolver)
            .map_err(|e| StabilityError::Setup(e.to_string()))
    }
}

/// A clarabel solver after setup.
pub struct PreparedSolver(DefaultSolver<f64>);

/// What clarabel concluded.
#[derive(Clone, Debug, PartialEq)]
pub enum ConicOutcome {
    /// An optimal point.
    Optimal {
        /// The primal solution.
        x: Vec<f64>,
        /// The objective value `½ xᵀPx + qᵀx`.
        objective: f64,
        /// clarabel reported `AlmostSolved` (reduced accuracy).
        reduced_accuracy: bool,
    },
    /// The constraints cannot be met.
    Infeasible {
        /// clarabel reported `AlmostPrimalInfeasible` (reduced accuracy).
        reduced_accuracy: bool,
    },
}

impl PreparedSolver {
    /// Runs the interior-point iterations and maps the status (see the module docs).
    pub fn solve(mut self) -> Result<ConicOutcome, StabilityError> {
        catch_unwind(AssertUnwindSafe(|| self.0.solve()))
            .map_err(|_| StabilityError::Trouble("clarabel panicked while solving".into()))?;
        let sol = &self.0.solution;
        match sol.status {
            SolverStatus::Solved | SolverStatus::AlmostSolved => {
                if sol.x.iter().all(|v| v.is_finite()) {
                    Ok(ConicOutcome::Optimal {
                        x: sol.x.clone(),
                        objective: sol.obj_val,
                        reduced_accuracy: sol.status == SolverStatus::AlmostSolved,
                    })
                } else {
                    Err(StabilityError::Trouble(
                        "clarabel returned a non-finite solution".into(),
                    ))
                }
            }
            SolverStatus::PrimalInfeasible => Ok(ConicOutcome::Infeasible {
                reduced_accuracy: false,
            }),
            SolverStatus::AlmostPrimalInfeasible => Ok(ConicOutcome::Infeasible {
                reduced_accuracy: true,
            }),
            other => Err(StabilityError::Trouble(format!("{other:?}"))),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn small_qp_and_infeasible_lp_map_to_outcomes() {
        // min x0² + x1² s.t. x0 + x1 = 2  ⇒ x = (1, 1), objective 2.
        let mut b = ConicBuilder::new(2);
        b.add_square(0, 1.0);
        b.add_square(1, 1.0);
        b.equal(vec![(0, 1.0), (1, 1.0)], 2.0);
        match b
            .build(SolverSettings::default())
            .setup()
            .unwrap()
            .solve()
            .unwrap()
        {
            ConicOutcome::Optimal { x, objective, .. } => {
                assert!(
                    (x[0] - 1.0).abs() < 1e-6
                        && (x[1] - 1.0).abs() < 1e-6
                        && (objective - 2.0).abs() < 1e-6
                )
            }
            other => panic!("{other:?}"),
        }
        // x <= -1 and x >= 0.
        let mut b = ConicBuilder::new(1);
        b.add_linear(0, 1.0);
        b.at_most(vec![(0, 1.0)], -1.0);
        b.at_most(vec![(0, -1.0)], 0.0);
        assert!(matches!(
            b.build(SolverSettings::default())
                .setup()
                .unwrap()
                .solve()
                .unwrap(),
            ConicOutcome::Infeasible { .. }
        ));
    }

    #[test]
    fn iteration_limit_is_a_typed_error_not_a_verdict() {
        let mut b = ConicBuilder::new(2);
        b.add_square(0, 1.0);
        b.add_linear(1, 1.0);
        b.equal(vec![(0, 1.0), (1, 1.0)], 2.0);
        b.at_most(vec![(1, -1.0)], 0.0);
        let settings = SolverSettings::default().with_max_iter(1).unwrap();
        assert!(matches!(
            b.build(settings).setup().unwrap().solve(),
            Err(StabilityError::Trouble(_))
        ));
        let mut b = ConicBuilder::new(1);
        b.equal(vec![(0, 1.0)], f64::NAN);
        assert!(matches!(
            b.build(SolverSettings::default()).setup(),
            Err(StabilityError::Input(_))
        ));
        assert!(SolverSettings::default().with_max_iter(0).is_err());
    }
}
