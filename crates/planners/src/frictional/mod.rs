//! Frictional tether planning (thesis §3.4-3.5.5, Alg. 7-10 and 14): potential tether friction
//! obstacles (PTFOs) are searched as obstacles, and every SHP the search yields is checked against
//! the tether's friction on them.
//!
//! | module | algorithm |
//! |---|---|
//! | [`anchor_check`] | Alg. 8 `CheckPTFOs` with Alg. 9 `TetherSlips` on the wrap contact |
//! | [`slip`] | Alg. 14 `UpdateWithSlipped`: clip the vertex, local BTM update, retrace the SHP |
//! | [`feasibility2`] | Alg. 10 `CheckFeasibility2`: friction anchors over the ascent sweep |
//! | [`holding`] | capstan along the whole tether: holding force at `a_0`, Kumar eq. 2 |
//! | [`search`] | Alg. 7: the SPT search loop over classes |
//!
//! Obstacles of the map are identified by their index in [`rappel_geometry::map::Map::obstacles`],
//! which is their [`ObstacleId`] in a freshly built BTM; obstacles re-inserted after a clip get new
//! ids, tracked by [`slip::SlipState`].

pub mod anchor_check;
pub mod feasibility2;
pub mod holding;
pub mod search;
pub mod slip;

use rappel_geometry::btm::BtmError;
use rappel_geometry::dcel::ObstacleId;
use rappel_homotopy::homotopy::HomotopyError;
use rappel_mechanics::friction::FrictionInterval;
use rappel_mechanics::ptfo::{PtfoError, TensionAssumptions};
use rappel_mechanics::ptfo_surface::{PtfoSurface, WrapError};
use thiserror::Error;

/// A potential tether friction obstacle: the surface an obstacle of the map stands for and the
/// tether-terrain friction on it (thesis §3.3.5, §3.6.1).
#[derive(Debug, Clone, PartialEq)]
pub struct Ptfo {
    /// Index of the obstacle in the map's obstacle list.
    pub obstacle: usize,
    /// The surface.
    pub surface: PtfoSurface,
    /// Tether-terrain friction, possibly an interval.
    pub friction: FrictionInterval,
}

/// Everything the frictional checks need besides the map: the PTFOs and the tension model.
#[derive(Debug, Clone, PartialEq)]
pub struct FrictionModel {
    /// The PTFOs; every other obstacle is geometric.
    pub ptfos: Vec<Ptfo>,
    /// `T_min, T_max, T_d, ε` (thesis §3.4.1).
    pub tensions: TensionAssumptions,
    /// Friction credited to geometric anchors in the capstan along the tether ([`holding`]);
    /// 0 credits none (conservative).
    pub geometric_friction: f64,
}

impl FrictionModel {
    /// The PTFO standing for map obstacle `index`, if any.
    pub fn ptfo_of(&self, index: usize) -> Option<&Ptfo> {
        self.ptfos.iter().find(|p| p.obstacle == index)
    }
}

/// Why frictional planning failed (as opposed to finding no feasible class).
#[derive(Debug, Error)]
pub enum FrictionalError {
    /// Two PTFOs name the same obstacle, or one names an obstacle the map does not have.
    #[error("PTFO {ptfo}: {problem}")]
    Spec {
        /// Index of the PTFO in the model.
        ptfo: usize,
        /// What is wrong.
        problem: String,
    },
    /// The friction credited to geometric anchors is negative or not finite.
    #[error("geometric_friction {} must be finite and >= 0", rappel_geometry::compact::Compact(*.0))]
    GeometricFriction(f64),
    /// A surface is unusable.
    #[error("PTFO on obstacle {obstacle}: {source}")]
    Surface {
        /// Map obstacle index.
        obstacle: usize,
        /// The defect.
        source: WrapError,
    },
    /// Classification failed.
    #[error(transparent)]
    Ptfo(#[from] PtfoError),
    /// A local BTM update failed.
    #[error("BTM update after a slip: {0}")]
    Btm(#[from] BtmError),
    /// Tracing the old SHP through the updated BTM failed.
    #[error("tracing the SHP after a slip: {0}")]
    Trace(#[from] HomotopyError),
    /// An internal inconsistency (a bug): what was expected.
    #[error("internal: {0}")]
    Internal(String),
}

/// Checks a model against a map with `obstacle_count` obstacles: one PTFO per obstacle at most,
/// every index in range, every surface valid.
pub fn validate_model(model: &FrictionModel, obstacle_count: usize) -> Result<(), FrictionalError> {
    for (i, p) in model.ptfos.iter().enumerate() {
        if p.obstacle >= obstacle_count {
            return Err(FrictionalError::Spec {
                ptfo: i,
                problem: format!(
                    "obstacle {} does not exist (the map has {obstacle_count})",
                    p.obstacle
                ),
            });
        }
        if model.ptfos[..i].iter().any(|q| q.obstacle == p.obstacle) {
            return Err(FrictionalError::Spec {
                ptfo: i,
                problem: format!("obstacle {} already has a PTFO", p.obstacle),
            });
        }
        p.surface
            .validate()
            .map_err(|source| FrictionalError::Surface {
                obstacle: p.obstacle,
                source,
            })?;
    }
    if !(model.geometric_friction.is_finite() && model.geometric_friction >= 0.0) {
        return Err(FrictionalError::GeometricFriction(model.geometric_friction));
    }
    Ok(())
}

/// The map obstacle index of a BTM obstacle id under the slip state's renaming.
pub(crate) fn original_index(renamed: &[(ObstacleId, usize)], id: ObstacleId) -> usize {
    renamed
        .iter()
        .rev()
        .find(|(o, _)| *o == id)
        .map_or(id.index(), |(_, i)| *i)
}
