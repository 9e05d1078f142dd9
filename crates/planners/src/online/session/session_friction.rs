//! The PTFOs of an online session that plans with tether friction ([`SessionFriction`]): the
//! model and the renaming of obstacles re-inserted by reshapes. Held by the session
//! ([`super`]), used by its frictional planning ([`super::friction`]).

use crate::frictional::{FrictionModel, original_index};
use rappel_geometry::dcel::ObstacleId;

/// The session's PTFOs: the model (obstacles by their index in the session's initial map) and
/// the renaming of obstacles re-inserted by reshapes.
#[derive(Debug, Clone)]
pub(in crate::online) struct SessionFriction {
    pub(in crate::online) model: FrictionModel,
    pub(in crate::online) renamed: Vec<(ObstacleId, usize)>,
}

impl SessionFriction {
    /// Obstacle `new` replaces `old` (a reshape): it stands for the same PTFO, if any.
    pub(in crate::online) fn renamed(&mut self, old: ObstacleId, new: ObstacleId) {
        let index = original_index(&self.renamed, old);
        self.renamed.push((new, index));
    }

    pub(in crate::online) fn original(&self, id: ObstacleId) -> usize {
        original_index(&self.renamed, id)
    }
}
