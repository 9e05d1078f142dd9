//! Tension along a heavy rope lying on frictional ground (thesis §3.2.3, eq. 3.14), integrated
//! with the adaptive Dormand-Prince integrator of [`crate::ode`].
//!
//! # Math
//! A rope element in equilibrium satisfies `d(T t)/ds + F + W = 0`, with `F` the ground's force
//! per unit length (normal reaction `F_n >= 0` along the outward normal `n`, friction in the
//! tangent plane) and `W` the external load per unit length (weight `ρ g`). With the Darboux
//! frame of [`crate::darboux`] this splits into
//!
//! ```text
//! F_t = -(dT/ds + W_t),   F_n = -(κ_n T + W_n),   F_g = -(κ_g T + W_g),
//! ```
//!
//! and Coulomb's law `F_t² + F_g² <= μ² F_n²` becomes
//!
//! ```text
//! (dT/ds + W_t)² <= μ² (κ_n T + W_n)² - (κ_g T + W_g)²          (eq. 3.14')
//! ```
//!
//! This is the thesis' eq. 3.14 with `W` replaced by `-W`: the thesis writes the balance as
//! `dI/ds = E` (eq. 3.8), which gives the load the opposite sign (check: a frictionless chain
//! hanging straight down must have `dT/ds = -ρg` when `s` runs downward; eq. 3.14' gives that,
//! the printed form gives `+ρg`). For a weightless rope both reduce to eq. 3.16.
//!
//! Given the tension `T_0` at `s = 0`, the extreme tensions the rope can hold at each `s` follow
//! the limiting profiles `dT/ds = -W_t ± sqrt(D)`, `D = μ² F_n² - (κ_g T + W_g)²`
//! ([`TensionBranch::Growing`] takes `+`, [`TensionBranch::Decaying`] takes `-`). Where
//! `F_n < 0` the rope lifts off; where `D < 0` no tension distribution can hold it (it slips
//! sideways): both are reported as [`RopeOutcome::Slips`].

use crate::darboux::DarbouxError;
use crate::friction::{FrictionError, check_coefficient};
use crate::ode::{OdeError, OdeSettings, integrate};
use crate::surface_curve::SurfaceCurve;
use nalgebra::{Vector1, Vector3};
use thiserror::Error;

/// Relative tolerance on the contact force and the friction discriminant: `F_n` and `D` are
/// accepted down to `-CONE_TOLERANCE` times their natural scale (`|κ| T + |W|`, squared for `D`),
/// so that round-off at an exactly limiting configuration is not reported as a slip.
pub const CONE_TOLERANCE: f64 = 1e-10;

/// Which limiting tension profile to integrate (the two signs of eq. 3.14').
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TensionBranch {
    /// The largest tension the rope can hold at each `s` (friction opposing growth of `T`).
    Growing,
    /// The smallest tension the rope can hold at each `s`.
    Decaying,
}

/// Why the rope cannot stay in static equilibrium at some point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SlipReason {
    /// The contact force would be negative (`F_n < 0`): the rope lifts off the ground.
    LiftsOff,
    /// `D < 0`: the lateral load exceeds friction for any tension profile (the rope slides sideways).
    OutsideFrictionCone,
    /// The limiting tension dropped to zero or below: the rope goes slack.
    Slack,
}

/// The result of integrating a limiting tension profile.
#[derive(Clone, Debug, PartialEq)]
pub enum RopeOutcome {
    /// The rope holds over the whole curve; the profile is the limiting tension.
    Holds(TensionProfile),
    /// The rope cannot hold at (about) arc length `at` (accurate to one integration step).
    Slips {
        /// Arc length where the failure was detected.
        at: f64,
        /// Why.
        reason: SlipReason,
    },
}

/// A limiting tension profile: tensions at increasing arc lengths.
#[derive(Clone, Debug, PartialEq)]
pub struct TensionProfile {
    /// Arc lengths of the integrator's accepted steps, from 0 to the curve length.
    pub s: Vec<f64>,
    /// Tension at those arc lengths (N).
    pub tension: Vec<f64>,
}

impl TensionProfile {
    /// Tension at the end of the curve.
    pub fn end_tension(&self) -> f64 {
        self.tension.last().copied().unwrap_or(f64::NAN)
    }
}

/// Why a heavy-rope problem could not be solved (as opposed to the rope slipping).
#[derive(Debug, Error, Clone, PartialEq)]
pub enum RopeError {
    /// The friction coefficient is invalid.
    #[error(transparent)]
    Friction(#[from] FrictionError),
    /// An input is not finite or out of range; the message names it.
    #[error("invalid heavy-rope input: {0}")]
    Input(&'static str),
    /// The curve has no Darboux frame at `at` (see [`DarbouxError`]).
    #[error("the curve has no Darboux frame at s = {at}: {error}")]
    Frame {
        /// Arc length.
        at: f64,
        /// The frame error.
        error: DarbouxError,
    },
    /// The integrator failed (step size underflow, step limit); loosen the tolerances.
    #[error("integration failed: {0}")]
    Integrator(OdeError),
}

/// A heavy rope on frictional ground: friction coefficient, load per unit length and integrator
/// settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeavyRope {
    mu: f64,
    load: Vector3<f64>,
    settings: OdeSettings,
}

enum RhsFailure {
    Slip(SlipReason),
    Frame(DarbouxError),
}

impl HeavyRope {
    /// A rope of linear density `kg_per_m` under gravity `gravity` (m/s², e.g. `(0, 0, -9.81)`)
    /// on ground with friction coefficient `mu`, integrated with `settings`.
    pub fn new(
        mu: f64,
        kg_per_m: f64,
        gravity: Vector3<f64>,
        settings: OdeSettings,
    ) -> Result<Self, RopeError> {
        check_coefficient(mu)?;
        if !(kg_per_m.is_finite() && kg_per_m >= 0.0) {
            return Err(RopeError::Input("linear density must be finite and >= 0"));
        }
        if !gravity.iter().all(|g| g.is_finite()) {
            return Err(RopeError::Input("gravity must be finite"));
        }
        Ok(HeavyRope {
            mu,
            load: gravity * kg_per_m,
            settings,
        })
    }

    /// A weightless rope (Konyukhov's model, eq. 3.16).
    pub fn weightless(mu: f64, settings: OdeSettings) -> Result<Self, RopeError> {
        Self::new(mu, 0.0, Vector3::zeros(), settings)
    }

    /// The derivative `dT/ds` of the limiting profile on `branch` at `s` with tension `t`.
    fn slope(
        &self,
        curve: &dyn SurfaceCurve,
        branch: TensionBranch,
        s: f64,
        t: f64,
    ) -> Result<f64, RhsFailure> {
        let f = curve.frame(s).map_err(RhsFailure::Frame)?;
        let (wt, wn, wg) = (
            self.load.dot(&f.tangent),
            self.load.dot(&f.normal),
            self.load.dot(&f.tangent_normal),
        );
        let scale = f.curvature * t.abs() + self.load.norm();
        let tol = CONE_TOLERANCE * scale.max(f64::MIN_POSITIVE);
        if t <= 0.0 {
            return Err(RhsFailure::Slip(SlipReason::Slack));
        }
        let f_n = -(f.normal_curvature * t + wn);
        if f_n < -tol {
            return Err(RhsFailure::Slip(SlipReason::LiftsOff));
        }
        let lateral = f.geodesic_curvature * t + wg;
        let d = self.mu * self.mu * f_n * f_n - lateral * lateral;
        if d < -tol * tol {
            return Err(RhsFailure::Slip(SlipReason::OutsideFrictionCone));
        }
        let root = d.max(0.0).sqrt();
        Ok(match branch {
            TensionBranch::Growing => -wt + root,
            TensionBranch::Decaying => -wt - root,
        })
    }

    /// Integrates the limiting tension profile on `branch` along `curve`, starting from tension
    /// `t0` (N) at `s = 0`.
    ///
    /// # Example
    /// ```
    /// use rappel_mechanics::heavy_rope::{HeavyRope, RopeOutcome, TensionBranch};
    /// use rappel_mechanics::ode::OdeSettings;
    /// use rappel_mechanics::surface_curve::Helix;
    /// // A weightless rope on a capstan of radius 0.5 m over a quarter turn, μ = 0.4.
    /// let capstan = Helix::new(0.5, 0.0, std::f64::consts::FRAC_PI_2).unwrap();
    /// let rope = HeavyRope::weightless(0.4, OdeSettings::default()).unwrap();
    /// let RopeOutcome::Holds(p) = rope.limit_tension(&capstan, 10.0, TensionBranch::Growing).unwrap()
    ///     else { panic!("a capstan holds") };
    /// assert!((p.end_tension() / 10.0 - (0.2 * std::f64::consts::PI).exp()).abs() < 1e-7);
    /// ```
    pub fn limit_tension(
        &self,
        curve: &dyn SurfaceCurve,
        t0: f64,
        branch: TensionBranch,
    ) -> Result<RopeOutcome, RopeError> {
        if !(t0.is_finite() && t0 > 0.0) {
            return Err(RopeError::Input(
                "start tension must be finite and positive",
            ));
        }
        let length = curve.length();
        if !(length.is_finite() && length >= 0.0) {
            return Err(RopeError::Input("curve length must be finite and >= 0"));
        }
        let rhs = |s: f64, y: &Vector1<f64>| self.slope(curve, branch, s, y[0]).map(Vector1::new);
        match integrate(rhs, 0.0, Vector1::new(t0), length, &self.settings) {
            Ok(sol) => Ok(RopeOutcome::Holds(TensionProfile {
                tension: sol.y.iter().map(|y| y[0]).collect(),
                s: sol.s,
            })),
            Err(OdeError::Rhs {
                at,
                error: RhsFailure::Slip(reason),
            }) => Ok(RopeOutcome::Slips { at, reason }),
            Err(OdeError::Rhs {
                at,
                error: RhsFailure::Frame(error),
            }) => Err(RopeError::Frame { at, error }),
            Err(OdeError::InvalidSettings(m)) => {
                Err(RopeError::Integrator(OdeError::InvalidSettings(m)))
            }
            Err(OdeError::NonFiniteInput) => Err(RopeError::Integrator(OdeError::NonFiniteInput)),
            Err(OdeError::StepSizeUnderflow { at }) => {
                Err(RopeError::Integrator(OdeError::StepSizeUnderflow { at }))
            }
            Err(OdeError::TooManySteps { max_steps, at }) => {
                Err(RopeError::Integrator(OdeError::TooManySteps {
                    max_steps,
                    at,
                }))
            }
            Err(OdeError::NonFiniteDerivative { at }) => {
                Err(RopeError::Integrator(OdeError::NonFiniteDerivative { at }))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface_curve::{CurveJet, Helix, PlaneLine};
    use nalgebra::Point3;

    fn settings() -> OdeSettings {
        OdeSettings::new().with_tolerances(1e-11, 1e-12).unwrap()
    }

    /// A rope over the top of a horizontal cylinder (axis `y`, radius `r`), from the apex down
    /// the `+x` side: `ρ(θ) = r (sin θ, 0, cos θ)`, `s = rθ`.
    struct OverCylinder {
        r: f64,
        angle: f64,
    }

    impl SurfaceCurve for OverCylinder {
        fn length(&self) -> f64 {
            self.r * self.angle
        }
        fn point(&self, s: f64) -> Point3<f64> {
            let th = s / self.r;
            Point3::new(self.r * th.sin(), 0.0, self.r * th.cos())
        }
        fn jet(&self, s: f64) -> CurveJet {
            let th = s / self.r;
            let n = Vector3::new(th.sin(), 0.0, th.cos());
            CurveJet {
                velocity: Vector3::new(th.cos(), 0.0, -th.sin()),
                acceleration: -n / self.r,
                surface_normal: n,
            }
        }
    }

    #[test]
    fn heavy_rope_over_cylinder_matches_closed_form() {
        // dT/dθ = μT + ρgR(μ cos θ - sin θ)  ⇒  T = (T0 - a) e^{μθ} + a cos θ + b sin θ,
        // a = ρgR(1-μ²)/(1+μ²), b = 2μρgR/(1+μ²).
        let (mu, rho, g, r, t0) = (0.4, 0.1, 9.81, 0.5, 5.0);
        let curve = OverCylinder { r, angle: 1.5 };
        let rope = HeavyRope::new(mu, rho, Vector3::new(0.0, 0.0, -g), settings()).unwrap();
        let RopeOutcome::Holds(p) = rope
            .limit_tension(&curve, t0, TensionBranch::Growing)
            .unwrap()
        else {
            panic!("rope over a cylinder top holds")
        };
        let w = rho * g * r;
        let (a, b) = (
            w * (1.0 - mu * mu) / (1.0 + mu * mu),
            2.0 * mu * w / (1.0 + mu * mu),
        );
        for (s, t) in p.s.iter().zip(&p.tension) {
            let th = s / r;
            let exact = (t0 - a) * (mu * th).exp() + a * th.cos() + b * th.sin();
            assert!((t - exact).abs() / exact < 1e-8, "{t} vs {exact}");
        }
    }

    #[test]
    fn branches_bracket_and_weight_lowers_tension_downhill() {
        let helix = Helix::new(1.0, 1.0, 1.0).unwrap();
        let rope = HeavyRope::weightless(0.4, settings()).unwrap();
        let end = |b| match rope.limit_tension(&helix, 45.0, b).unwrap() {
            RopeOutcome::Holds(p) => p.end_tension(),
            RopeOutcome::Slips { .. } => f64::NAN,
        };
        let (hi, lo) = (end(TensionBranch::Growing), end(TensionBranch::Decaying));
        assert!((hi * lo - 45.0 * 45.0).abs() < 1e-6 && hi > 45.0);
        // Frictionless chain straight down a vertical wall: dT/ds = -ρg.
        let wall = PlaneLine::new(Point3::origin(), -Vector3::z(), Vector3::x(), 10.0).unwrap();
        let chain = HeavyRope::new(0.0, 1.0, Vector3::new(0.0, 0.0, -9.81), settings()).unwrap();
        match chain
            .limit_tension(&wall, 200.0, TensionBranch::Growing)
            .unwrap()
        {
            RopeOutcome::Holds(p) => assert!((p.end_tension() - (200.0 - 98.1)).abs() < 1e-9),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn slips_are_reported_with_reason() {
        // A rope across a 60° slope with μ = 0.3: lateral weight exceeds friction.
        let (eta, mu) = (60f64.to_radians(), 0.3);
        let n = Vector3::new(0.0, -eta.sin(), eta.cos());
        let across = PlaneLine::new(Point3::origin(), Vector3::x(), n, 5.0).unwrap();
        let rope = HeavyRope::new(mu, 0.1, Vector3::new(0.0, 0.0, -9.81), settings()).unwrap();
        assert!(matches!(
            rope.limit_tension(&across, 100.0, TensionBranch::Growing)
                .unwrap(),
            RopeOutcome::Slips {
                reason: SlipReason::OutsideFrictionCone,
                ..
            }
        ));
        // Under an overhang (normal pointing down) a weighted straight rope lifts off.
        let ceiling = PlaneLine::new(Point3::origin(), Vector3::x(), -Vector3::z(), 5.0).unwrap();
        assert!(matches!(
            rope.limit_tension(&ceiling, 100.0, TensionBranch::Growing)
                .unwrap(),
            RopeOutcome::Slips {
                reason: SlipReason::LiftsOff,
                ..
            }
        ));
        assert!(matches!(
            rope.limit_tension(&ceiling, -1.0, TensionBranch::Growing),
            Err(RopeError::Input(_))
        ));
        assert!(HeavyRope::new(f64::NAN, 0.1, Vector3::zeros(), settings()).is_err());
    }
}
