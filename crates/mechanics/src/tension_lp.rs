//! Tension-limited static stability of a rappelling robot as a linear program (Kumar §III-B,
//! eqs. 3a-3e), solved with the dense simplex of [`crate::dense_lp`] ([`TensionLimitedLp::check`])
//! or with clarabel ([`TensionLimitedLp::check_clarabel`], the oracle it is tested against).
//!
//! # Formulation
//! The constraints are those of `statics` (the crate-internal module of shared constraints) with point contacts (no contact moments):
//! force and moment balance (3a-3b), friction pyramids and non-negative normal forces (3c-3d; the
//! paper's strict `F_Z > 0` is taken as `>= 0`, the tipping limit), and `0 <= T_2 <= T_2max`
//! (3e), `T_2max` being the tether's limit (see [`crate::tension_limit`]). Kumar solves a pure
//! feasibility problem; we add the objective `min T_2`, which leaves the feasible set (and so the
//! verdict) unchanged and returns the smallest tension that holds the robot. The margin is the
//! tension headroom `1 - T_2,required / T_2max` (1 without a tether). Kumar's pyramid is aligned
//! with the tether direction; ours with the robot's axes (the two agree when the robot faces away
//! from its anchor, the usual rappelling pose). Kumar's pyramid circumscribes the friction cone;
//! [`FrictionPyramid::Inscribed`] selects the conservative pyramid inside it.

use crate::conic::{ConicBuilder, ConicOutcome, ConicProblem};
use crate::dense_lp::{DenseLpError, LpOutcome};
use crate::robot::PlacedRobot;
use crate::stability_error::StabilityError;
use crate::statics::{Layout, add_equilibrium, add_friction_pyramids, add_tether_bounds, weight};
use crate::traversability::{Assessment, StabilityCriterion, StabilitySettings};

/// How the friction cone `sqrt(F_X² + F_Y²) <= μ F_Z` is linearised.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum FrictionPyramid {
    /// Kumar's eq. 3c: `|F_X|, |F_Y| <= μ F_Z`. It contains the cone, so along its diagonals it
    /// allows up to `sqrt(2) μ F_Z`: optimistic off-axis.
    #[default]
    Circumscribed,
    /// `|F_X|, |F_Y| <= μ F_Z / sqrt(2)`: inside the cone, so every verdict "stable" also holds
    /// for the exact cone (conservative).
    Inscribed,
}

impl FrictionPyramid {
    fn coefficient(self, mu: f64) -> f64 {
        match self {
            FrictionPyramid::Circumscribed => mu,
            FrictionPyramid::Inscribed => mu * std::f64::consts::FRAC_1_SQRT_2,
        }
    }
}

/// The LP's verdict.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LpReport {
    /// A static equilibrium exists within the tension limit.
    pub stable: bool,
    /// The smallest tether tension that holds the robot (N), if stable and tethered.
    pub required_tension: Option<f64>,
    /// `1 - required / limit` (1 when no tension is needed or there is no tether; 0 when not
    /// stable).
    pub headroom: f64,
    /// clarabel reported reduced accuracy (always `false` from the dense simplex of
    /// [`TensionLimitedLp::check`]).
    pub reduced_accuracy: bool,
}

/// Kumar's tension-limited stability LP.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TensionLimitedLp {
    settings: StabilitySettings,
    pyramid: FrictionPyramid,
}

impl TensionLimitedLp {
    /// An LP checker with `settings`.
    pub fn new(settings: StabilitySettings) -> Self {
        TensionLimitedLp {
            settings,
            pyramid: FrictionPyramid::default(),
        }
    }

    /// Uses `pyramid` to linearise the friction cone (default: Kumar's circumscribed pyramid).
    pub fn with_pyramid(mut self, pyramid: FrictionPyramid) -> Self {
        self.pyramid = pyramid;
        self
    }

    fn layout(robot: &PlacedRobot) -> Layout {
        Layout {
            contacts: robot.contacts.len(),
            with_moments: false,
            tether: robot.tether.is_some(),
        }
    }

    /// The LP's rows for `robot`, with the friction pyramids as rows when `pyramid_rows` (the
    /// clarabel form) or without them (the generator form of [`TensionLimitedLp::check`] adds
    /// them as the pyramids' edges). A tethered robot must have a tension limit (Kumar eq. 3e).
    fn builder(
        &self,
        robot: &PlacedRobot,
        pyramid_rows: bool,
    ) -> Result<ConicBuilder, StabilityError> {
        let w = weight(robot, self.settings.gravity())?;
        if robot.tether.is_some_and(|t| t.max_tension.is_none()) {
            return Err(StabilityError::Input(
                "the tension-limited LP needs a tether tension limit (T_2max)",
            ));
        }
        let layout = Self::layout(robot);
        let mut b = ConicBuilder::new(layout.len());
        if let Some(col) = layout.tether() {
            b.add_linear(col, 1.0);
        }
        add_equilibrium(&mut b, robot, &layout, self.settings.gravity(), w);
        if pyramid_rows {
            add_friction_pyramids(&mut b, &layout, |i| {
                self.pyramid.coefficient(robot.contact_friction(i))
            });
        }
        add_tether_bounds(&mut b, robot, &layout, w);
        Ok(b)
    }

    /// Builds the LP for `robot` as a clarabel program (exposed so that setup and solve can be
    /// timed apart). A tethered robot must have a tension limit (Kumar eq. 3e).
    pub fn assemble(&self, robot: &PlacedRobot) -> Result<ConicProblem, StabilityError> {
        Ok(self.builder(robot, true)?.build(self.settings.solver()))
    }

    /// The report of an optimal LP point `x` (weight-normalised).
    fn report(robot: &PlacedRobot, x: &[f64], w: f64, reduced_accuracy: bool) -> LpReport {
        let required = Self::layout(robot).tether().map(|c| x[c].max(0.0) * w);
        let limit = robot.tether.and_then(|t| t.max_tension);
        let headroom = match (required, limit) {
            (Some(r), Some(l)) if l > 0.0 => (1.0 - r / l).clamp(0.0, 1.0),
            (Some(_), Some(_)) => 0.0,
            _ => 1.0,
        };
        LpReport {
            stable: true,
            required_tension: required,
            headroom,
            reduced_accuracy,
        }
    }

    /// The report of an infeasible LP.
    fn unstable(reduced_accuracy: bool) -> LpReport {
        LpReport {
            stable: false,
            required_tension: None,
            headroom: 0.0,
            reduced_accuracy,
        }
    }

    /// Checks whether `robot` is stable within its tether's tension limit.
    ///
    /// # Example
    /// ```
    /// use nalgebra::Point3;
    /// use rappel_mechanics::four_wheel::FourWheelRover;
    /// use rappel_mechanics::robot::{place, PlanarPose, SlopePlane, TetherSpec};
    /// use rappel_mechanics::tension_lp::TensionLimitedLp;
    /// // 35 kg on a 55° slope, μ = 0.4, tether straight up the fall line.
    /// let slope = SlopePlane::new(55f64.to_radians(), 0.4).unwrap();
    /// let pose = PlanarPose::new(0.0, 0.0, std::f64::consts::PI);
    /// let check = |limit| {
    ///     let tether = TetherSpec { anchor: Point3::new(0.0, 30.0, 0.35), max_tension: Some(limit) };
    ///     let robot = place(&FourWheelRover::default(), &pose, &slope, Some(&tether)).unwrap();
    ///     TensionLimitedLp::default().check(&robot).unwrap().stable
    /// };
    /// assert!(!check(200.0) && check(300.0));
    /// ```
    pub fn check(&self, robot: &PlacedRobot) -> Result<LpReport, StabilityError> {
        // The generator form: contact i's force is Σ_k λ_ik (s_k μ_i, t_k μ_i, 1) over the four
        // edges of its pyramid (s_k, t_k = ±1), λ_ik >= 0, which is exactly the pyramid (a
        // square pyramid is the cone of its edges). 6 equalities and the tension limit remain:
        // 7 rows instead of 23, so the tableau is an eighth of the row form's.
        let layout = Self::layout(robot);
        let edges = [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)];
        let n_new = 4 * layout.contacts + usize::from(layout.tether);
        let mut substitution = vec![Vec::new(); layout.len()];
        for i in 0..layout.contacts {
            let mu = self.pyramid.coefficient(robot.contact_friction(i));
            for (k, (s, t)) in edges.into_iter().enumerate() {
                let c = 4 * i + k;
                substitution[layout.force(i, 0)].push((c, s * mu));
                substitution[layout.force(i, 1)].push((c, t * mu));
                substitution[layout.force(i, 2)].push((c, 1.0));
            }
        }
        let tension = layout.tether().map(|t| {
            substitution[t].push((n_new - 1, 1.0));
            n_new - 1
        });
        let mut lp = self
            .builder(robot, false)?
            .dense_lp_substituted(&substitution, n_new);
        for c in 0..4 * layout.contacts {
            lp.at_most(&[(c, -1.0)], 0.0);
        }
        let w = weight(robot, self.settings.gravity())?;
        match lp.solve() {
            Ok(LpOutcome::Optimal { x, .. }) => {
                // The report reads the tension only: put it where the row form keeps it.
                let mut old = vec![0.0; layout.len()];
                if let (Some(t), Some(c)) = (layout.tether(), tension) {
                    old[t] = x[c];
                }
                Ok(Self::report(robot, &old, w, false))
            }
            Ok(LpOutcome::Infeasible) => Ok(Self::unstable(false)),
            // T is bounded below by 0 and every force by the equilibrium: never seen.
            Ok(LpOutcome::Unbounded) => Err(StabilityError::Trouble(
                "the tension LP is unbounded".into(),
            )),
            Err(DenseLpError::NonFinite) => Err(StabilityError::Input(
                "non-finite problem data (check poses, masses and anchors)",
            )),
            Err(e) => Err(StabilityError::Trouble(e.to_string())),
        }
    }

    /// Checks with clarabel (the interior-point oracle the dense simplex of
    /// [`TensionLimitedLp::check`] is tested against; same LP, same report).
    pub fn check_clarabel(&self, robot: &PlacedRobot) -> Result<LpReport, StabilityError> {
        let problem = self.assemble(robot)?;
        let w = weight(robot, self.settings.gravity())?;
        Ok(match problem.setup()?.solve()? {
            ConicOutcome::Infeasible { reduced_accuracy } => Self::unstable(reduced_accuracy),
            ConicOutcome::Optimal {
                x,
                reduced_accuracy,
                ..
            } => Self::report(robot, &x, w, reduced_accuracy),
        })
    }
}

impl StabilityCriterion for TensionLimitedLp {
    fn name(&self) -> &str {
        "tension-limited-lp"
    }

    fn assess(&self, robot: &PlacedRobot) -> Result<Assessment, StabilityError> {
        let r = self.check(robot)?;
        Ok(Assessment {
            stable: r.stable,
            margin: r.headroom,
            tether_tension: r.required_tension,
            reduced_accuracy: r.reduced_accuracy,
        })
    }
}
