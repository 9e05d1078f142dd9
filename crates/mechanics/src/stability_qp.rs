//! Wheel/tether static stability as a quadratic program (Paton §IV-C, eqs. 1-9), solved by the
//! dense active-set method of [`crate::dense_qp`] ([`StabilityQp::check`]) or with clarabel
//! ([`StabilityQp::check_clarabel`], the independent oracle it is tested against).
//!
//! # Formulation
//! The constraints are those of `statics` (the crate-internal module of shared constraints): each contact carries a full wrench
//! `(λ_i, M_i)` bounded by the friction pyramid and the moment bounds (eqs. 1-6), the two body
//! masses, the tether along the direction of the last anchor and the contact wrenches balance
//! (eqs. 7-8), and the tether tension is free (or bounded by the tether's limit).
//!
//! Paton's objective (eq. 9) is
//! `f = Σ_i (λ_ix² + λ_iy²)/μ² - 2 λ_iz² + (M_ix² + M_iy² + M_iz²)/μ_m² - 3 λ_iz²`, with `μ` the
//! contact's own coefficient (the wheels' `μ`; Axel's boom on the ground its `boom_friction`). Its Hessian is
//! indefinite (the `-2λ_iz²`, `-3λ_iz²` terms), so it is not a convex QP: clarabel (like any
//! interior-point QP solver) needs `P ⪰ 0`, and Paton used a general nonlinear solver (NLOPT).
//! Minimising the negative terms would only push normal load onto fewer contacts, which is not the
//! stated intent ("maximum margin on friction and moment cone utilisation"). We therefore minimise
//! the convex part,
//!
//! ```text
//! min  Σ_i (λ_ix² + λ_iy²)/μ² + |M_i|²/μ_m²        subject to eqs. 1-8,
//! ```
//!
//! which drives tangential forces and moments to the smallest share of their cones, and report
//! at the optimum:
//!
//! * the **margin** `-f / W²`: Paton's eq. 9 evaluated as printed, negated and normalised by the
//!   squared weight. Each contact's term `2λ_z² - (λ_x² + λ_y²)/μ²` is non-negative inside the
//!   pyramid (and likewise `3λ_z² - |M|²/μ_m²`), so a stable pose has margin `>= 0`, and it shrinks
//!   both as cones fill and as normal load is lost (steeper slopes);
//! * the **utilisation**: the largest of `max(|λ_x|, |λ_y|)/(μ λ_z)` and `max_k |M_k|/(μ_m λ_z)`
//!   over loaded contacts, in `[0, 1]` for a stable pose.
//!
//! Contacts without moment capacity (`μ_m = 0`) carry no moment variables and no moment term;
//! a point contact ([`crate::robot::ContactFrame::point`]: Axel's boom on the ground, which has
//! no grouser patch) carries no moment and has no moment term in the margin or utilisation.
//! Infeasibility (proven by the active-set method, or clarabel's `PrimalInfeasible`) means "not
//! stable".

use crate::conic::{ConicBuilder, ConicOutcome, ConicProblem};
use crate::dense_qp::{DenseOutcome, DenseQpError};
use crate::robot::PlacedRobot;
use crate::stability_error::StabilityError;
use crate::statics::{
    Layout, add_equilibrium, add_friction_pyramids, add_moment_bounds, add_tether_bounds, weight,
};
use crate::traversability::{Assessment, StabilityCriterion, StabilitySettings};
use nalgebra::Vector3;

/// Friction coefficients at or below this are treated as frictionless: their tangential forces
/// get objective weight 1 (the pyramid forces them to zero anyway) and no utilisation.
pub const MIN_FRICTION: f64 = 1e-9;
/// A contact whose normal force is below this fraction of the weight counts as unloaded and is
/// left out of the utilisation.
pub const UNLOADED_CONTACT: f64 = 1e-7;

/// One contact's wrench in its contact frame (`z` along the normal).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactWrench {
    /// Force `λ_i` (N).
    pub force: Vector3<f64>,
    /// Moment `M_i` (N·m); zero for point contacts.
    pub moment: Vector3<f64>,
}

/// The QP's verdict.
#[derive(Clone, Debug, PartialEq)]
pub struct QpReport {
    /// A static equilibrium exists.
    pub stable: bool,
    /// Negated, normalised eq. 9 at the optimum (module docs); 0 when not stable.
    pub margin: f64,
    /// Largest cone utilisation over loaded contacts (module docs); 0 when not stable.
    pub utilization: f64,
    /// Tether tension of the solution (N).
    pub tether_tension: Option<f64>,
    /// Contact wrenches of the solution (empty when not stable).
    pub wrenches: Vec<ContactWrench>,
    /// clarabel reported reduced accuracy.
    pub reduced_accuracy: bool,
}

/// The wheel/tether stability QP.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StabilityQp {
    settings: StabilitySettings,
}

impl StabilityQp {
    /// A QP checker with `settings`.
    pub fn new(settings: StabilitySettings) -> Self {
        StabilityQp { settings }
    }

    fn layout(robot: &PlacedRobot) -> Layout {
        Layout {
            contacts: robot.contacts.len(),
            with_moments: robot.moment_coefficient > 0.0,
            tether: robot.tether.is_some(),
        }
    }

    /// The QP's rows for `robot` (weight-normalised, see `statics`), its weight and layout.
    fn rows(&self, robot: &PlacedRobot) -> Result<(ConicBuilder, f64, Layout), StabilityError> {
        let w = weight(robot, self.settings.gravity())?;
        let layout = Self::layout(robot);
        let mut b = ConicBuilder::new(layout.len());
        for i in 0..layout.contacts {
            // A frictionless contact's pyramid holds its tangential forces at zero; weighting them
            // by 1 / MIN_FRICTION² (1e18) would wreck the problem's scaling (both solvers then
            // called feasible poses infeasible), so they get weight 1.
            let mu = robot.contact_friction(i);
            let wf = if mu > MIN_FRICTION {
                1.0 / (mu * mu)
            } else {
                1.0
            };
            b.add_square(layout.force(i, 0), wf);
            b.add_square(layout.force(i, 1), wf);
            if layout.with_moments {
                for k in 0..3 {
                    b.add_square(layout.moment(i, k), 1.0 / robot.moment_coefficient.powi(2));
                }
            }
        }
        add_equilibrium(&mut b, robot, &layout, self.settings.gravity(), w);
        add_friction_pyramids(&mut b, &layout, |i| robot.contact_friction(i));
        add_moment_bounds(&mut b, &layout, robot.moment_coefficient, |i| {
            robot.contacts[i].point
        });
        add_tether_bounds(&mut b, robot, &layout, w);
        Ok((b, w, layout))
    }

    /// Builds the QP for `robot` as a clarabel program (exposed so that setup and solve can be
    /// timed apart).
    pub fn assemble(&self, robot: &PlacedRobot) -> Result<ConicProblem, StabilityError> {
        Ok(self.rows(robot)?.0.build(self.settings.solver()))
    }

    /// Checks the static stability of `robot` with the dense active-set solver
    /// ([`crate::dense_qp`], Goldfarb-Idnani): the same QP as [`StabilityQp::check_clarabel`],
    /// a few microseconds instead of 100-200 (cross-checked against it on random and settled
    /// poses, `crates/mechanics/tests/all/dense_qp.rs`). `reduced_accuracy` is always `false`.
    ///
    /// # Example
    /// ```
    /// use rappel_mechanics::axel::Axel;
    /// use rappel_mechanics::robot::{place, PlanarPose, SlopePlane};
    /// use rappel_mechanics::stability_qp::StabilityQp;
    /// let flat = SlopePlane::new(0.0, 0.8).unwrap();
    /// let axel = place(&Axel::default(), &PlanarPose::new(0.0, 0.0, 0.0), &flat, None).unwrap();
    /// let report = StabilityQp::default().check(&axel).unwrap();
    /// assert!(report.stable && report.utilization < 1e-6);
    /// ```
    pub fn check(&self, robot: &PlacedRobot) -> Result<QpReport, StabilityError> {
        let (b, w, layout) = self.rows(robot)?;
        match b.dense().solve() {
            Ok(DenseOutcome::Infeasible) => Ok(Self::not_stable(false)),
            Ok(DenseOutcome::Optimal { x, .. }) => Ok(Self::report(robot, &layout, w, &x, false)),
            Err(DenseQpError::Input(_)) => Err(StabilityError::Input(
                "non-finite problem data (check poses, masses and anchors)",
            )),
            Err(e) => Err(StabilityError::Trouble(e.to_string())),
        }
    }

    /// Checks the static stability of `robot` with clarabel (the interior-point oracle the dense
    /// solver of [`StabilityQp::check`] is tested against).
    pub fn check_clarabel(&self, robot: &PlacedRobot) -> Result<QpReport, StabilityError> {
        let (b, w, layout) = self.rows(robot)?;
        match b.build(self.settings.solver()).setup()?.solve()? {
            ConicOutcome::Infeasible { reduced_accuracy } => Ok(Self::not_stable(reduced_accuracy)),
            ConicOutcome::Optimal {
                x,
                reduced_accuracy,
                ..
            } => Ok(Self::report(robot, &layout, w, &x, reduced_accuracy)),
        }
    }

    fn not_stable(reduced_accuracy: bool) -> QpReport {
        QpReport {
            stable: false,
            margin: 0.0,
            utilization: 0.0,
            tether_tension: None,
            wrenches: Vec::new(),
            reduced_accuracy,
        }
    }

    /// The report of an optimal point `x` (weight-normalised).
    fn report(
        robot: &PlacedRobot,
        layout: &Layout,
        w: f64,
        x: &[f64],
        reduced_accuracy: bool,
    ) -> QpReport {
        let mu_m = robot.moment_coefficient;
        let mut margin = 0.0;
        let mut utilization: f64 = 0.0;
        let mut wrenches = Vec::with_capacity(layout.contacts);
        for i in 0..layout.contacts {
            let mu = robot.contact_friction(i);
            let f = Vector3::from_fn(|k, _| x[layout.force(i, k)]);
            let moments = layout.with_moments && !robot.contacts[i].point;
            let m = if moments {
                Vector3::from_fn(|k, _| x[layout.moment(i, k)])
            } else {
                Vector3::zeros()
            };
            let fz = f.z.max(0.0);
            let tangential = if mu > MIN_FRICTION {
                (f.x * f.x + f.y * f.y) / (mu * mu)
            } else {
                0.0
            };
            margin += 2.0 * fz * fz - tangential;
            if moments {
                margin += 3.0 * fz * fz - m.norm_squared() / (mu_m * mu_m);
            }
            if fz > UNLOADED_CONTACT {
                if mu > MIN_FRICTION {
                    utilization = utilization.max(f.x.abs().max(f.y.abs()) / (mu * fz));
                }
                if moments {
                    utilization = utilization.max(m.amax() / (mu_m * fz));
                }
            }
            wrenches.push(ContactWrench {
                force: f * w,
                moment: m * w,
            });
        }
        QpReport {
            stable: true,
            margin: margin.max(0.0),
            utilization,
            tether_tension: layout.tether().map(|c| x[c].max(0.0) * w),
            wrenches,
            reduced_accuracy,
        }
    }
}

impl StabilityCriterion for StabilityQp {
    fn name(&self) -> &str {
        "wheel-tether-qp"
    }

    fn assess(&self, robot: &PlacedRobot) -> Result<Assessment, StabilityError> {
        let r = self.check(robot)?;
        Ok(Assessment {
            stable: r.stable,
            margin: r.margin,
            tether_tension: r.tether_tension,
            reduced_accuracy: r.reduced_accuracy,
        })
    }
}
