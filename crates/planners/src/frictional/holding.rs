//! The capstan along the whole tether (thesis §3.2.5, §3.6; Kumar eq. 2): with the tether wrapped
//! over anchors `a_1 .. a_n`, a tension `T` at the robot needs only `T e^{-Σ I_j}` at the initial
//! anchor `a_0`, `I_j` being the friction exponent `∫ω ds` of anchor `j`'s wrap; so a weak top
//! anchor holds once the tether wraps (thesis §3.6). Friction anchors use their wrap's exponent
//! with the lowest friction (a "will it hold" question, §3.6.1); geometric anchors are credited
//! `μ_geo θ_j` (a sharp edge: the capstan with the radius dropped out), `μ_geo` = 0 by default.
//!
//! Given a holding limit `T_1max` at `a_0` (Kumar eq. 1), the largest tension the robot can load
//! the tether with is `T_1max e^{Σ I_j}` (Kumar eq. 2, [`rappel_mechanics::tension_limit`]) with
//! the effective coefficient `I_j/θ_j` per anchor.

use super::FrictionModel;
use super::anchor_check::{AnchorVerdict, PtfoCheck};
use rappel_mechanics::tension_limit::{TensionLimitError, tension_limit};
use serde::{Deserialize, Serialize};

/// Tensions along one class's tether.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct HoldingReport {
    /// `I_j` per anchor, in tether order (from `a_1`).
    pub exponents: Vec<f64>,
    /// `Σ I_j`.
    pub total_exponent: f64,
    /// The force `a_0` must hold when the robot pulls `T_max`: `T_max e^{-Σ I_j}`, N.
    pub holding_force_at_start_n: f64,
    /// Kumar eq. 2: the largest robot-side tension, when a holding limit is given, N.
    pub tension_limit_n: Option<f64>,
}

/// The capstan along the tether of `check` (module docs).
pub fn holding(
    check: &PtfoCheck,
    model: &FrictionModel,
    holding_limit: Option<f64>,
) -> Result<HoldingReport, TensionLimitError> {
    let exponents: Vec<f64> = check
        .anchors
        .iter()
        .map(|d| match d.verdict {
            AnchorVerdict::Geometric => model.geometric_friction * d.anchor.turning_angle,
            AnchorVerdict::Friction(_) => d.omega_integral_hold,
        })
        .collect();
    let total: f64 = exponents.iter().sum();
    let limit = holding_limit
        .map(|h| {
            let windings: Vec<(f64, f64)> = check
                .anchors
                .iter()
                .zip(&exponents)
                .map(|(d, i)| (i / d.anchor.turning_angle, d.anchor.turning_angle))
                .collect();
            tension_limit(h, &windings)
        })
        .transpose()?;
    Ok(HoldingReport {
        holding_force_at_start_n: model.tensions.t_max() * (-total).exp(),
        exponents,
        total_exponent: total,
        tension_limit_n: limit,
    })
}
