//! The scenario schema of frictional planning (thesis §3.4; `docs/scenario-format.md`,
//! "friction"): which obstacles are potential tether friction obstacles (PTFOs), the surface each
//! stands for, its tether-terrain friction (an interval allowed, §3.6.1), and the tension model
//! `T_min, T_max, T_d, ε` (§3.4.1) with defaults derived from the robot and the planes.
//!
//! # Derived tension defaults
//! With the boom along the tether, Axel's tension estimate (thesis eq. 3.32, re-derived in
//! `docs/mechanics.md` §4) is the whole along-slope weight `m g sin η`. So, for a robot of mass
//! `m` on the scenario's planes (slopes `η_1 .. η_k`, all required for the defaults):
//!
//! * `T_d = m g sin η_max`: the driving tension on the steepest plane;
//! * `ε = 0.1 T_d` ([`DEFAULT_EPSILON_FRACTION`]): the tension controller's deviation, an
//!   assumption to override with measured values;
//! * `T_max = 2 T_d` ([`SURGE_FACTOR`]): a load applied suddenly to an elastic tether (a slip
//!   caught, a wheel dropping) peaks at twice its static value (the undamped step response);
//! * `T_min = min(m g sin η_min, T_d - ε)`: the static tension on the shallowest plane, never
//!   above the driving band.

use rappel_mechanics::friction::FrictionInterval;
use rappel_mechanics::ptfo::TensionAssumptions;
use rappel_mechanics::ptfo_surface::PtfoSurface;
use rappel_mechanics::tension_limit::HoldingRobot;
use rappel_planners::frictional::{FrictionModel, Ptfo};
use rappel_terrain::plane_series::TerrainPlane;
use serde::{Deserialize, Serialize};

/// Standard gravity used by the derived defaults, m/s² (Earth; give tensions explicitly for Mars).
pub const GRAVITY: f64 = 9.81;
/// `ε / T_d` when `epsilon_n` is not given.
pub const DEFAULT_EPSILON_FRACTION: f64 = 0.1;
/// `T_max / T_d` when `t_max_n` is not given: the dynamic factor of a suddenly applied load.
pub const SURGE_FACTOR: f64 = 2.0;

/// The `friction` section of a scenario.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FrictionSpec {
    /// The PTFOs; every other obstacle is geometric.
    pub ptfos: Vec<PtfoSpec>,
    /// The tension model; missing values are derived (module docs).
    #[serde(default)]
    pub tensions: TensionSpec,
    /// Friction credited to geometric anchors in the capstan along the tether. Default 0 (none).
    #[serde(default)]
    pub geometric_friction: f64,
    /// The holding robot at the top anchor (Kumar eq. 1), for the tension limit of Kumar eq. 2.
    #[serde(default)]
    pub holding: Option<HoldingSpec>,
}

/// One PTFO.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PtfoSpec {
    /// Index of the obstacle in `map.obstacles`.
    pub obstacle: usize,
    /// The surface it stands for.
    #[schemars(with = "serde_json::Value")]
    pub surface: PtfoSurface,
    /// Tether-terrain friction coefficient range.
    pub friction: FrictionRange,
}

/// A friction coefficient range `lo <= hi` (equal for a known coefficient).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FrictionRange {
    /// Lowest coefficient (used for "will it hold").
    pub lo: f64,
    /// Highest coefficient (used for "will it slide").
    pub hi: f64,
}

/// The tension model; every value optional (module docs for the defaults).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct TensionSpec {
    /// `T_min`, N.
    pub t_min_n: Option<f64>,
    /// `T_max`, N.
    pub t_max_n: Option<f64>,
    /// `T_d`, N.
    pub t_d_n: Option<f64>,
    /// `ε`, N.
    pub epsilon_n: Option<f64>,
}

/// The holding robot of Kumar eq. 1.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct HoldingSpec {
    /// Extra pull of its wheels `F_0`, N.
    pub max_pull_n: f64,
    /// Friction of its ground `μ_s0`.
    pub friction: f64,
    /// Its mass, kg.
    pub mass_kg: f64,
}

/// The model the planner uses, with the holding limit and where each tension came from.
#[derive(Debug, Clone, PartialEq)]
pub struct ResolvedFriction {
    /// PTFOs and tensions.
    pub model: FrictionModel,
    /// `F_0 + μ_s0 m_1 g`, N, when a holding robot is given.
    pub holding_limit: Option<f64>,
    /// Notes on derived values (printed with the plan).
    pub notes: Vec<String>,
}

impl FrictionSpec {
    /// Resolves the section against its scenario (the robot's mass, the terrain planes and the
    /// number of obstacles): derived tensions, checked ranges, surfaces and obstacle indices.
    /// Errors name the offending entry.
    pub fn resolve(
        &self,
        mass_kg: f64,
        planes: &[TerrainPlane],
        obstacles: usize,
    ) -> Result<ResolvedFriction, String> {
        let mut notes = Vec::new();
        let mut ptfos = Vec::with_capacity(self.ptfos.len());
        for (i, p) in self.ptfos.iter().enumerate() {
            let friction = FrictionInterval::new(p.friction.lo, p.friction.hi)
                .map_err(|e| format!("friction.ptfos[{i}].friction: {e}"))?;
            let surface = p.surface.clone();
            surface
                .validate()
                .map_err(|e| format!("friction.ptfos[{i}].surface: {e}"))?;
            ptfos.push(Ptfo {
                obstacle: p.obstacle,
                surface,
                friction,
            });
        }
        let t = &self.tensions;
        let weight = mass_kg * GRAVITY;
        let slopes: Vec<f64> = planes.iter().map(|p| p.slope_deg.to_radians()).collect();
        let derive = |what: &str| {
            format!(
                "friction.tensions.{what}: no terrain planes to derive it from; give it explicitly"
            )
        };
        let t_d = match t.t_d_n {
            Some(v) => v,
            None => {
                let steep = slopes.iter().copied().fold(f64::NAN, f64::max);
                if steep.is_nan() {
                    return Err(derive("t_d_n"));
                }
                let v = weight * steep.sin();
                notes.push(format!(
                    "T_d = m g sin {:.1}° = {v:.1} N (steepest plane, eq. 3.32 with the boom along the tether)",
                    steep.to_degrees()
                ));
                v
            }
        };
        let epsilon = t.epsilon_n.unwrap_or_else(|| {
            notes.push(format!(
                "epsilon = {DEFAULT_EPSILON_FRACTION} T_d = {:.1} N (assumed)",
                DEFAULT_EPSILON_FRACTION * t_d
            ));
            DEFAULT_EPSILON_FRACTION * t_d
        });
        let t_max = t.t_max_n.unwrap_or_else(|| {
            notes.push(format!(
                "T_max = {SURGE_FACTOR} T_d = {:.1} N (suddenly applied load)",
                SURGE_FACTOR * t_d
            ));
            SURGE_FACTOR * t_d
        });
        let t_min = match t.t_min_n {
            Some(v) => v,
            None => {
                let shallow = slopes.iter().copied().fold(f64::NAN, f64::min);
                if shallow.is_nan() {
                    return Err(derive("t_min_n"));
                }
                let v = (weight * shallow.sin()).min(t_d - epsilon);
                notes.push(format!(
                    "T_min = min(m g sin {:.1}°, T_d - epsilon) = {v:.1} N",
                    shallow.to_degrees()
                ));
                v
            }
        };
        let tensions = TensionAssumptions::new(t_min, t_max, t_d, epsilon).map_err(|e| {
            format!(
                "friction.tensions: {e} (T_min {t_min:.3}, T_max {t_max:.3}, T_d {t_d:.3}, eps {epsilon:.3})"
            )
        })?;
        let holding_limit = self
            .holding
            .map(|h| {
                HoldingRobot {
                    max_pull: h.max_pull_n,
                    friction: h.friction,
                    mass: h.mass_kg,
                }
                .holding_limit(GRAVITY)
                .map_err(|e| format!("friction.holding: {e}"))
            })
            .transpose()?;
        let model = FrictionModel {
            ptfos,
            tensions,
            geometric_friction: self.geometric_friction,
        };
        rappel_planners::frictional::validate_model(&model, obstacles)
            .map_err(|e| format!("friction: {e}"))?;
        Ok(ResolvedFriction {
            model,
            holding_limit,
            notes,
        })
    }
}
