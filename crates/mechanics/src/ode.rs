//! An adaptive Dormand-Prince 5(4) integrator ("RK45", the method behind Matlab's `ode45` that the
//! thesis §3.3.4 used) for systems `y' = f(s, y)` with `y` an `nalgebra` vector of any fixed size.
//!
//! # Method
//! Each step evaluates the seven Dormand-Prince stages (Hairer, Nørsett & Wanner, *Solving ODEs I*,
//! Table 5.2) and advances with the fifth-order solution; the embedded fourth-order solution gives
//! the local error estimate `err = ||(y5 - y4) / (atol + rtol * max(|y_n|, |y_{n+1}|))||_rms`.
//! A step is accepted when `err <= 1`; the next step size is `h * clamp(SAFETY * err^(-1/5),
//! MIN_FACTOR, MAX_FACTOR)`. The last stage of an accepted step is the first of the next (FSAL).
//! The initial step follows Hairer's heuristic (*Solving ODEs I*, §II.4).
//!
//! The right-hand side may fail (for example a rope that cannot stick at some arc length): its error
//! is returned as [`OdeError::Rhs`] together with the abscissa where it occurred.

use nalgebra::SVector;
use thiserror::Error;

/// Safety factor applied to the optimal step-size prediction.
pub const SAFETY: f64 = 0.9;
/// The smallest factor by which one step may shrink the step size.
pub const MIN_FACTOR: f64 = 0.2;
/// The largest factor by which one step may grow the step size.
pub const MAX_FACTOR: f64 = 5.0;

/// Settings of [`integrate`]; build with [`OdeSettings::new`] and the `with_*` methods, which
/// validate their input.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OdeSettings {
    rtol: f64,
    atol: f64,
    max_steps: usize,
    max_step: f64,
}

impl Default for OdeSettings {
    /// `rtol = 1e-9`, `atol = 1e-12`, at most 100 000 steps, no limit on the step size.
    fn default() -> Self {
        OdeSettings {
            rtol: 1e-9,
            atol: 1e-12,
            max_steps: 100_000,
            max_step: f64::INFINITY,
        }
    }
}

impl OdeSettings {
    /// The default settings (see [`Default`]).
    pub fn new() -> Self {
        Self::default()
    }

    /// Sets the relative and absolute tolerances of the local error. Both must be finite, `rtol`
    /// positive and `atol` non-negative.
    pub fn with_tolerances(mut self, rtol: f64, atol: f64) -> Result<Self, OdeError> {
        if !(rtol.is_finite() && rtol > 0.0 && atol.is_finite() && atol >= 0.0) {
            return Err(OdeError::InvalidSettings(
                "rtol must be finite and > 0, atol finite and >= 0",
            ));
        }
        self.rtol = rtol;
        self.atol = atol;
        Ok(self)
    }

    /// Sets the maximum number of attempted steps (at least 1).
    pub fn with_max_steps(mut self, max_steps: usize) -> Result<Self, OdeError> {
        if max_steps == 0 {
            return Err(OdeError::InvalidSettings("max_steps must be at least 1"));
        }
        self.max_steps = max_steps;
        Ok(self)
    }

    /// Sets an upper bound on the step size (positive; infinity for none).
    pub fn with_max_step(mut self, max_step: f64) -> Result<Self, OdeError> {
        if max_step.is_nan() || max_step <= 0.0 {
            return Err(OdeError::InvalidSettings("max_step must be positive"));
        }
        self.max_step = max_step;
        Ok(self)
    }

    /// The relative tolerance.
    pub fn rtol(&self) -> f64 {
        self.rtol
    }

    /// The absolute tolerance.
    pub fn atol(&self) -> f64 {
        self.atol
    }
}

/// Why an integration failed. `E` is the error type of the right-hand side.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum OdeError<E = std::convert::Infallible> {
    /// A setting is out of range; the message says which and how to fix it.
    #[error("invalid integrator settings: {0}")]
    InvalidSettings(&'static str),
    /// The interval end points or the initial state are not finite.
    #[error("the interval and the initial state must be finite")]
    NonFiniteInput,
    /// The step size fell below the floating-point resolution of the abscissa: the problem is too
    /// stiff or singular near `at`; loosen the tolerances or check the right-hand side.
    #[error("step size underflow at s = {at}")]
    StepSizeUnderflow {
        /// Where the integration stopped.
        at: f64,
    },
    /// More than the allowed number of steps were needed; raise `max_steps` or loosen tolerances.
    #[error("step limit {max_steps} reached at s = {at}")]
    TooManySteps {
        /// The limit that was reached.
        max_steps: usize,
        /// Where the integration stopped.
        at: f64,
    },
    /// The right-hand side produced a non-finite value at `at`.
    #[error("the right-hand side is not finite at s = {at}")]
    NonFiniteDerivative {
        /// The abscissa of the failing evaluation.
        at: f64,
    },
    /// The right-hand side reported an error at `at`.
    #[error("the right-hand side failed at s = {at}")]
    Rhs {
        /// The abscissa of the failing evaluation.
        at: f64,
        /// The right-hand side's own error.
        error: E,
    },
}

/// The accepted steps of an integration: abscissae and states, the first being the initial ones
/// and the last the requested end point.
#[derive(Clone, Debug, PartialEq)]
pub struct OdeSolution<const D: usize> {
    /// Abscissae of the accepted steps, monotone from the start to the end of the interval.
    pub s: Vec<f64>,
    /// States at those abscissae.
    pub y: Vec<SVector<f64, D>>,
    /// Number of rejected steps (for diagnostics).
    pub rejected: usize,
}

impl<const D: usize> OdeSolution<D> {
    /// The state at the end of the interval.
    pub fn last(&self) -> &SVector<f64, D> {
        // Invariant: `integrate` always stores the initial state, so `y` is never empty.
        &self.y[self.y.len() - 1]
    }
}

// Dormand-Prince 5(4) coefficients.
const C2: f64 = 1.0 / 5.0;
const C3: f64 = 3.0 / 10.0;
const C4: f64 = 4.0 / 5.0;
const C5: f64 = 8.0 / 9.0;
const A21: f64 = 1.0 / 5.0;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
const B1: f64 = 35.0 / 384.0;
const B3: f64 = 500.0 / 1113.0;
const B4: f64 = 125.0 / 192.0;
const B5: f64 = -2187.0 / 6784.0;
const B6: f64 = 11.0 / 84.0;
// Differences between the fifth- and fourth-order weights (the error estimator).
const E1: f64 = 71.0 / 57600.0;
const E3: f64 = -71.0 / 16695.0;
const E4: f64 = 71.0 / 1920.0;
const E5: f64 = -17253.0 / 339200.0;
const E6: f64 = 22.0 / 525.0;
const E7: f64 = -1.0 / 40.0;

/// Integrates `y' = rhs(s, y)` from `s0` to `s1` (either direction) starting at `y0`, with
/// adaptive Dormand-Prince 5(4) steps under the error control of `settings`.
///
/// # Example
/// ```
/// use nalgebra::Vector1;
/// use rappel_mechanics::ode::{integrate, OdeSettings};
/// // y' = y, y(0) = 1: y(1) = e.
/// let sol = integrate(|_s, y: &Vector1<f64>| Ok::<_, ()>(*y), 0.0, Vector1::new(1.0), 1.0,
///     &OdeSettings::default()).unwrap();
/// assert!((sol.last()[0] - std::f64::consts::E).abs() < 1e-8);
/// ```
pub fn integrate<const D: usize, F, E>(
    mut rhs: F,
    s0: f64,
    y0: SVector<f64, D>,
    s1: f64,
    settings: &OdeSettings,
) -> Result<OdeSolution<D>, OdeError<E>>
where
    F: FnMut(f64, &SVector<f64, D>) -> Result<SVector<f64, D>, E>,
{
    if !(s0.is_finite() && s1.is_finite() && y0.iter().all(|v| v.is_finite())) {
        return Err(OdeError::NonFiniteInput);
    }
    let mut sol = OdeSolution {
        s: vec![s0],
        y: vec![y0],
        rejected: 0,
    };
    if s0 == s1 {
        return Ok(sol);
    }
    let direction = (s1 - s0).signum();
    let mut eval = |s: f64, y: &SVector<f64, D>| -> Result<SVector<f64, D>, OdeError<E>> {
        let dy = rhs(s, y).map_err(|error| OdeError::Rhs { at: s, error })?;
        if dy.iter().all(|v| v.is_finite()) {
            Ok(dy)
        } else {
            Err(OdeError::NonFiniteDerivative { at: s })
        }
    };
    let scale = |a: &SVector<f64, D>, b: &SVector<f64, D>| {
        a.zip_map(b, |x, y| {
            settings.atol + settings.rtol * x.abs().max(y.abs())
        })
    };
    let rms = |v: &SVector<f64, D>| (v.norm_squared() / D.max(1) as f64).sqrt();

    let mut s = s0;
    let mut y = y0;
    let mut k1 = eval(s, &y)?;
    let mut h = initial_step(&mut eval, s, &y, &k1, direction, settings, &scale, &rms)?;
    let mut steps = 0usize;
    loop {
        if steps >= settings.max_steps {
            return Err(OdeError::TooManySteps {
                max_steps: settings.max_steps,
                at: s,
            });
        }
        steps += 1;
        let remaining = s1 - s;
        let mut last = false;
        if h.abs() >= remaining.abs() {
            h = remaining;
            last = true;
        }
        if h.abs() <= 16.0 * f64::EPSILON * s.abs().max(1.0) {
            return Err(OdeError::StepSizeUnderflow { at: s });
        }
        let k2 = eval(s + C2 * h, &(y + k1 * (h * A21)))?;
        let k3 = eval(s + C3 * h, &(y + (k1 * A31 + k2 * A32) * h))?;
        let k4 = eval(s + C4 * h, &(y + (k1 * A41 + k2 * A42 + k3 * A43) * h))?;
        let k5 = eval(
            s + C5 * h,
            &(y + (k1 * A51 + k2 * A52 + k3 * A53 + k4 * A54) * h),
        )?;
        let k6 = eval(
            s + h,
            &(y + (k1 * A61 + k2 * A62 + k3 * A63 + k4 * A64 + k5 * A65) * h),
        )?;
        let y_new = y + (k1 * B1 + k3 * B3 + k4 * B4 + k5 * B5 + k6 * B6) * h;
        let k7 = eval(s + h, &y_new)?;
        let err_vec = (k1 * E1 + k3 * E3 + k4 * E4 + k5 * E5 + k6 * E6 + k7 * E7) * h;
        let err = rms(&err_vec.component_div(&scale(&y, &y_new)));
        let factor = if err == 0.0 {
            MAX_FACTOR
        } else {
            (SAFETY * err.powf(-0.2)).clamp(MIN_FACTOR, MAX_FACTOR)
        };
        if err <= 1.0 {
            s = if last { s1 } else { s + h };
            y = y_new;
            k1 = k7;
            sol.s.push(s);
            sol.y.push(y);
            if last {
                return Ok(sol);
            }
            h = direction * (h.abs() * factor).min(settings.max_step);
        } else {
            sol.rejected += 1;
            h *= factor.min(1.0);
        }
    }
}

/// Hairer's starting step: balances the sizes of `y`, `f(y)` and a finite-difference estimate of
/// the second derivative.
#[allow(clippy::too_many_arguments)]
fn initial_step<const D: usize, G, E>(
    eval: &mut G,
    s: f64,
    y: &SVector<f64, D>,
    f0: &SVector<f64, D>,
    direction: f64,
    settings: &OdeSettings,
    scale: &impl Fn(&SVector<f64, D>, &SVector<f64, D>) -> SVector<f64, D>,
    rms: &impl Fn(&SVector<f64, D>) -> f64,
) -> Result<f64, OdeError<E>>
where
    G: FnMut(f64, &SVector<f64, D>) -> Result<SVector<f64, D>, OdeError<E>>,
{
    let sc = scale(y, y);
    let d0 = rms(&y.component_div(&sc));
    let d1 = rms(&f0.component_div(&sc));
    let h0 = if d0 < 1e-5 || d1 < 1e-5 {
        1e-6
    } else {
        0.01 * d0 / d1
    };
    let h0 = h0.min(settings.max_step);
    let f1 = eval(s + direction * h0, &(y + f0 * (direction * h0)))?;
    let d2 = rms(&(f1 - f0).component_div(&sc)) / h0;
    let h1 = if d1.max(d2) <= 1e-15 {
        (h0 * 1e-3).max(1e-6)
    } else {
        (0.01 / d1.max(d2)).powf(0.2)
    };
    Ok(direction * (100.0 * h0).min(h1).min(settings.max_step))
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Vector1, Vector2};

    fn ok<const D: usize>(v: SVector<f64, D>) -> Result<SVector<f64, D>, ()> {
        Ok(v)
    }

    #[test]
    fn exponential_growth_matches_closed_form() {
        let settings = OdeSettings::new().with_tolerances(1e-11, 1e-14).unwrap();
        let sol = integrate(
            |_, y: &Vector1<f64>| ok(*y * 0.7),
            0.0,
            Vector1::new(2.0),
            3.0,
            &settings,
        )
        .unwrap();
        let exact = 2.0 * (0.7f64 * 3.0).exp();
        assert!((sol.last()[0] - exact).abs() / exact < 1e-9);
        assert_eq!(*sol.s.last().unwrap(), 3.0);
    }

    #[test]
    fn harmonic_oscillator_backwards_returns_to_start() {
        let f = |_: f64, y: &Vector2<f64>| ok(Vector2::new(y[1], -y[0]));
        let settings = OdeSettings::new().with_tolerances(1e-10, 1e-12).unwrap();
        let fwd = integrate(f, 0.0, Vector2::new(1.0, 0.0), 10.0, &settings).unwrap();
        assert!((fwd.last()[0] - 10f64.cos()).abs() < 1e-7);
        let back = integrate(f, 10.0, *fwd.last(), 0.0, &settings).unwrap();
        assert!((back.last()[0] - 1.0).abs() < 1e-7 && back.last()[1].abs() < 1e-7);
        assert!(back.s.windows(2).all(|w| w[1] < w[0]));
    }

    #[test]
    fn tighter_tolerance_gives_smaller_error() {
        let f = |s: f64, y: &Vector1<f64>| ok(Vector1::new(-2.0 * s * y[0]));
        let exact = (-4.0f64).exp();
        let err = |rtol: f64| {
            let st = OdeSettings::new()
                .with_tolerances(rtol, rtol * 1e-3)
                .unwrap();
            (integrate(f, 0.0, Vector1::new(1.0), 2.0, &st)
                .unwrap()
                .last()[0]
                - exact)
                .abs()
        };
        assert!(err(1e-10) < err(1e-5));
        assert!(err(1e-10) < 1e-9);
    }

    #[test]
    fn failures_are_typed() {
        let st = OdeSettings::default();
        let r = integrate(
            |s, y: &Vector1<f64>| if s > 0.5 { Err("slip") } else { Ok(*y) },
            0.0,
            Vector1::new(1.0),
            1.0,
            &st,
        );
        assert!(matches!(r, Err(OdeError::Rhs { at, error: "slip" }) if at > 0.5));
        let r = integrate(
            |_, _: &Vector1<f64>| ok(Vector1::new(f64::NAN)),
            0.0,
            Vector1::new(1.0),
            1.0,
            &st,
        );
        assert!(matches!(r, Err(OdeError::NonFiniteDerivative { .. })));
        let st1 = OdeSettings::new()
            .with_max_steps(2)
            .unwrap()
            .with_tolerances(1e-12, 0.0)
            .unwrap();
        let r = integrate(
            |s, _: &Vector1<f64>| ok(Vector1::new((50.0 * s).sin())),
            0.0,
            Vector1::new(1.0),
            10.0,
            &st1,
        );
        assert!(matches!(
            r,
            Err(OdeError::TooManySteps { max_steps: 2, .. })
        ));
        assert!(OdeSettings::new().with_tolerances(0.0, 1.0).is_err());
        assert!(OdeSettings::new().with_max_step(-1.0).is_err());
        let r = integrate(
            |_, y: &Vector1<f64>| ok(*y),
            0.0,
            Vector1::new(f64::INFINITY),
            1.0,
            &st,
        );
        assert!(matches!(r, Err(OdeError::NonFiniteInput)));
    }
}
