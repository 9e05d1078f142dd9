//! Static equilibrium of a placed robot as linear constraints, shared by the wheel/tether QP
//! (Paton eqs. 1-8) and the tension-limited LP (Kumar eqs. 3a-3e).
//!
//! # Formulation
//! Decision variables, per contact `i`: the force `λ_i` in the contact frame (`z` along the
//! normal), and, when contacts carry moments, the moment `M_i` in the same frame; then the tether
//! tension `λ_t >= 0` if there is a tether. All are scaled by the robot's weight `W = Σ m_k g`
//! (forces in units of `W`, moments in `W·m`), which keeps the data near unit size.
//!
//! * force balance (Paton eq. 7, Kumar eq. 3a):
//!   `Σ_i R_i λ_i + d λ_t = -Σ_k m_k g / W = (0, 0, 1)`;
//! * moment balance about the robot origin `o` (Paton eq. 8, Kumar eq. 3b; any point gives the
//!   same set once forces balance):
//!   `Σ_i (r_i - o) × R_i λ_i + R_i M_i + (r_t - o) × d λ_t = -Σ_k (r_k - o) × m_k g / W`.
//!   Paton's printed eq. 8 omits the contact moments `R_i M_i`; without them eqs. 4-6 would
//!   constrain variables that act on nothing, so they are included;
//! * friction pyramid (Paton eqs. 1-3, Kumar eqs. 3c-3d): `λ_iz >= 0`, `|λ_ix|, |λ_iy| <= μ_i λ_iz`
//!   (`μ_i` the contact's own coefficient: the wheels' `μ`, Axel's boom its own);
//! * moment bounds (Paton eqs. 4-6): `|M_ix|, |M_iy|, |M_iz| <= μ_m λ_iz`; a point contact
//!   ([`crate::robot::ContactFrame::point`], Axel's boom on the ground) carries no moment: its
//!   moment variables appear in neither the balance nor the bounds, and the objective holds
//!   them at zero;
//! * tether (Kumar eq. 3e): `0 <= λ_t <= T_max / W`.

use crate::conic::ConicBuilder;
use crate::robot::PlacedRobot;
use crate::stability_error::StabilityError;
use nalgebra::{Matrix3, Vector3};

/// Index layout of the decision variables.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Layout {
    pub(crate) contacts: usize,
    pub(crate) with_moments: bool,
    pub(crate) tether: bool,
}

impl Layout {
    fn per_contact(&self) -> usize {
        if self.with_moments { 6 } else { 3 }
    }
    /// Index of component `k` (0 = x, 1 = y, 2 = z) of contact `i`'s force.
    pub(crate) fn force(&self, i: usize, k: usize) -> usize {
        i * self.per_contact() + k
    }
    /// Index of component `k` of contact `i`'s moment (only with moments).
    pub(crate) fn moment(&self, i: usize, k: usize) -> usize {
        i * self.per_contact() + 3 + k
    }
    /// Index of the tether tension.
    pub(crate) fn tether(&self) -> Option<usize> {
        self.tether.then(|| self.contacts * self.per_contact())
    }
    /// Number of variables.
    pub(crate) fn len(&self) -> usize {
        self.contacts * self.per_contact() + usize::from(self.tether)
    }
}

fn finite3(v: &Vector3<f64>) -> bool {
    v.iter().all(|c| c.is_finite())
}

/// Validates `robot` and returns its weight `W = Σ m_k g` (N).
pub(crate) fn weight(robot: &PlacedRobot, gravity: f64) -> Result<f64, StabilityError> {
    if !(gravity.is_finite() && gravity > 0.0) {
        return Err(StabilityError::Input("gravity must be finite and positive"));
    }
    if robot.contacts.is_empty() {
        return Err(StabilityError::Input("the robot has no ground contact"));
    }
    if !(robot.friction.is_finite() && robot.friction >= 0.0)
        || robot
            .contacts
            .iter()
            .any(|c| c.friction.is_some_and(|f| !(f.is_finite() && f >= 0.0)))
    {
        return Err(StabilityError::Input("friction must be finite and >= 0"));
    }
    if !(robot.moment_coefficient.is_finite() && robot.moment_coefficient >= 0.0) {
        return Err(StabilityError::Input(
            "moment coefficient must be finite and >= 0",
        ));
    }
    if !robot
        .masses
        .iter()
        .all(|m| m.mass.is_finite() && m.mass >= 0.0 && finite3(&m.position.coords))
    {
        return Err(StabilityError::Input(
            "masses must be finite and >= 0 at finite positions",
        ));
    }
    if !robot.contacts.iter().all(|c| finite3(&c.position.coords))
        || !finite3(&robot.reference.coords)
    {
        return Err(StabilityError::Input("contact points must be finite"));
    }
    if let Some(t) = &robot.tether
        && !(finite3(&t.exit.coords) && t.max_tension.is_none_or(|m| m.is_finite() && m >= 0.0))
    {
        return Err(StabilityError::Input(
            "tether exit and limit must be finite (limit >= 0)",
        ));
    }
    let w = robot.masses.iter().map(|m| m.mass).sum::<f64>() * gravity;
    if w > 0.0 {
        Ok(w)
    } else {
        Err(StabilityError::Input("the robot must have positive mass"))
    }
}

/// Adds the six balance equalities (see the module docs) for `robot` with weight `w`.
pub(crate) fn add_equilibrium(
    b: &mut ConicBuilder,
    robot: &PlacedRobot,
    layout: &Layout,
    gravity: f64,
    w: f64,
) {
    let o = robot.reference;
    // Columns of the force and moment rows, variable by variable.
    let mut force_rows: [Vec<(usize, f64)>; 3] = Default::default();
    let mut moment_rows: [Vec<(usize, f64)>; 3] = Default::default();
    let mut push = |col: usize, f: Vector3<f64>, m: Vector3<f64>| {
        for k in 0..3 {
            force_rows[k].push((col, f[k]));
            moment_rows[k].push((col, m[k]));
        }
    };
    for (i, c) in robot.contacts.iter().enumerate() {
        let r = c.position - o;
        let rot: Matrix3<f64> = *c.rotation.matrix();
        for k in 0..3 {
            let axis = rot.column(k).into_owned();
            push(layout.force(i, k), axis, r.cross(&axis));
            // A point contact's moment variables act on nothing (its objective term holds them
            // at zero): it carries no moment.
            if layout.with_moments && !c.point {
                push(layout.moment(i, k), Vector3::zeros(), axis);
            }
        }
    }
    if let (Some(col), Some(t)) = (layout.tether(), &robot.tether) {
        let d = t.direction.into_inner();
        push(col, d, (t.exit - o).cross(&d));
    }
    let g = Vector3::new(0.0, 0.0, -gravity);
    let mut f_rhs = Vector3::zeros();
    let mut m_rhs = Vector3::zeros();
    for m in &robot.masses {
        let fg = g * m.mass / w;
        f_rhs -= fg;
        m_rhs -= (m.position - o).cross(&fg);
    }
    for k in 0..3 {
        b.equal(std::mem::take(&mut force_rows[k]), f_rhs[k]);
    }
    for k in 0..3 {
        b.equal(std::mem::take(&mut moment_rows[k]), m_rhs[k]);
    }
}

/// Adds the friction pyramids `λ_z >= 0`, `|λ_x|, |λ_y| <= μ_i λ_z` of every contact, `μ_i =
/// mu(i)` (from the contact's own coefficient, [`PlacedRobot::contact_friction`]).
pub(crate) fn add_friction_pyramids(
    b: &mut ConicBuilder,
    layout: &Layout,
    mu: impl Fn(usize) -> f64,
) {
    for i in 0..layout.contacts {
        let mu = mu(i);
        let z = layout.force(i, 2);
        b.at_most(vec![(z, -1.0)], 0.0);
        for k in 0..2 {
            let t = layout.force(i, k);
            b.at_most(vec![(t, 1.0), (z, -mu)], 0.0);
            b.at_most(vec![(t, -1.0), (z, -mu)], 0.0);
        }
    }
}

/// Adds the moment bounds `|M_k| <= μ_m λ_z` of every contact that carries moments (Paton eqs.
/// 4-6; `point(i)`: contact `i` is a point contact, its moments act on nothing and stay free).
pub(crate) fn add_moment_bounds(
    b: &mut ConicBuilder,
    layout: &Layout,
    mu_m: f64,
    point: impl Fn(usize) -> bool,
) {
    if !layout.with_moments {
        return;
    }
    for i in (0..layout.contacts).filter(|&i| !point(i)) {
        let z = layout.force(i, 2);
        for k in 0..3 {
            let m = layout.moment(i, k);
            b.at_most(vec![(m, 1.0), (z, -mu_m)], 0.0);
            b.at_most(vec![(m, -1.0), (z, -mu_m)], 0.0);
        }
    }
}

/// Adds `0 <= λ_t <= T_max / W` (the upper bound only when the tether is limited).
pub(crate) fn add_tether_bounds(
    b: &mut ConicBuilder,
    robot: &PlacedRobot,
    layout: &Layout,
    w: f64,
) {
    if let (Some(col), Some(t)) = (layout.tether(), &robot.tether) {
        b.at_most(vec![(col, -1.0)], 0.0);
        if let Some(max) = t.max_tension {
            b.at_most(vec![(col, 1.0)], max / w);
        }
    }
}
