//! Frictional online planning (issue 12's online form; thesis §3.5.5 and §4.2.2): PTFOs in an
//! online session, with one mechanism for Alg. 14 and the online update.
//!
//! Whenever the session's SHP may have changed (PTFOs given, any map change applied, a PTFO
//! reclassified during the descent, e.g. with a new estimate of its friction), every anchor of
//! the SHP is decided again by Alg. 8-9 ([`decide_anchor_with`]):
//! - **slides**: the vertex is clipped from its PTFO ([`clip_vertex`], the frictional planner's
//!   own clip) and the clipped outline enters the session as an ordinary map change
//!   (`MapChange::Reshape`, or `Remove` when nothing is left): the same local retriangulation,
//!   classification against the sleeve, retrace and replanning as any other change (Alg. 13).
//!   So Alg. 14 *is* an online map change here;
//! - **volatile**: the class is unsafe (Alg. 8 line 12): its H-signature joins the constraints and
//!   the session replans (Alg. 13), reported as a blocked class;
//! - until every anchor is solid or geometric.
//!
//! Bound: each round clips one PTFO vertex or rejects one class; rounds beyond the PTFO vertices
//! present plus [`MAX_FRICTION_REJECTIONS`] are an internal error, never a hang.

use super::session_friction::SessionFriction;
use super::{ChangeOutcome, OnlineSession};
use crate::frictional::anchor_check::{AnchorVerdict, decide_anchors_with};
use crate::frictional::slip::{Clipped, clip_vertex};
use crate::frictional::{FrictionModel, validate_model};
use crate::online::OnlineError;
use crate::online::change::MapChange;
use crate::online::classify::ChangeCase;
use rappel_geometry::btm::UpdateReport;
use rappel_geometry::dcel::ObstacleId;
use rappel_mechanics::friction::FrictionInterval;
use rappel_mechanics::ptfo::PtfoClass;

/// Most classes one settling may reject as volatile (the CLI's class cap): with the search's
/// own class budget the replanning ends long before.
pub const MAX_FRICTION_REJECTIONS: usize = 1000;

impl OnlineSession {
    /// Plans with tether friction from now on: `model`'s PTFOs name obstacles by their index in
    /// the map the session was created with (their initial ids), and must all still exist. The
    /// current SHP's anchors are decided at once; the outcomes of any slips or rejections are
    /// returned.
    pub fn set_friction(
        &mut self,
        model: FrictionModel,
    ) -> Result<Vec<ChangeOutcome>, OnlineError> {
        validate_model(&model, self.poles.len())?;
        if let Some(p) = model
            .ptfos
            .iter()
            .find(|p| !self.alive(ObstacleId(p.obstacle as u32)))
        {
            return Err(OnlineError::Option(format!(
                "PTFO obstacle {} is no longer in the session's map",
                p.obstacle
            )));
        }
        self.friction = Some(SessionFriction {
            model,
            renamed: Vec::new(),
        });
        self.settle_friction()
    }

    /// The index in the session's initial map of the obstacle that BTM obstacle `id` stands for:
    /// a reshape's new outline (a slip's clipped PTFO among them) stands for the obstacle it
    /// replaced; other ids stand for themselves.
    pub fn initial_obstacle(&self, id: ObstacleId) -> usize {
        self.friction
            .as_ref()
            .map_or(id.index(), |f| f.original(id))
    }

    /// The PTFOs and tension model, when the session plans with friction.
    pub fn friction_model(&self) -> Option<&FrictionModel> {
        self.friction.as_ref().map(|f| &f.model)
    }

    /// A PTFO reclassified during the descent: the PTFO of initial map obstacle `obstacle` now
    /// has tether-terrain friction `friction` (a new estimate). The SHP's anchors are decided
    /// again (module docs).
    pub fn reclassify_ptfo(
        &mut self,
        obstacle: usize,
        friction: FrictionInterval,
    ) -> Result<Vec<ChangeOutcome>, OnlineError> {
        let Some(f) = &mut self.friction else {
            return Err(OnlineError::Option(
                "the session has no PTFOs (set_friction first)".into(),
            ));
        };
        let Some(p) = f.model.ptfos.iter_mut().find(|p| p.obstacle == obstacle) else {
            return Err(OnlineError::Option(format!(
                "obstacle {obstacle} is not a PTFO"
            )));
        };
        p.friction = friction;
        self.settle_friction()
    }

    /// Decides the SHP's anchors until they all hold (module docs).
    pub(super) fn settle_friction(&mut self) -> Result<Vec<ChangeOutcome>, OnlineError> {
        let mut out = Vec::new();
        let Some(f) = &self.friction else {
            return Ok(out);
        };
        let vertices: usize = f
            .model
            .ptfos
            .iter()
            .filter_map(|p| self.btm.obstacle_polygon(ObstacleId(p.obstacle as u32)))
            .map(|poly| poly.len())
            .sum::<usize>();
        let bound = vertices
            .saturating_add(self.btm.obstacle_ids().count())
            .saturating_add(MAX_FRICTION_REJECTIONS);
        for _ in 0..bound {
            let Some(c) = &self.class else {
                return Ok(out);
            };
            let Some(f) = &self.friction else {
                return Ok(out);
            };
            let taut = c.shp.taut.clone();
            let mut action = None;
            for d in decide_anchors_with(&f.model, |id| f.original(id), &taut)? {
                match d.verdict {
                    AnchorVerdict::Friction(PtfoClass::Slides) => {
                        action = Some((d.anchor, false, d.obstacle));
                        break;
                    }
                    AnchorVerdict::Friction(PtfoClass::Volatile) => {
                        action = Some((d.anchor, true, d.obstacle));
                        break;
                    }
                    _ => {}
                }
            }
            let Some((anchor, volatile, ptfo)) = action else {
                return Ok(out);
            };
            let id = anchor.obstacle.ok_or_else(|| {
                OnlineError::Internal("a friction anchor on the map boundary".into())
            })?;
            let place = format!(
                "PTFO {} at ({:.3}, {:.3})",
                ptfo.map_or_else(|| "?".to_string(), |i| i.to_string()),
                anchor.point.x,
                anchor.point.y
            );
            if volatile {
                let (h, length) = (c.h_signature.clone(), taut.length);
                let why = format!(
                    "volatile friction anchor on {place}: the class is unsafe (Alg. 8), rejected"
                );
                self.reject(h, length, why.clone());
                let decision = self.replan()?;
                let report = UpdateReport::default();
                let mut o = self.outcome(
                    "ptfo",
                    Some(id),
                    ChangeCase::Blocked,
                    &report,
                    0,
                    Some(length),
                );
                o.reason = why;
                o.decision = decision;
                o.backtrackable = self.backtrackable();
                o.clearance_shortfall = self.clearance_shortfall();
                out.push(o);
                continue;
            }
            let ring = self.btm.obstacle_polygon(id).ok_or_else(|| {
                OnlineError::Internal(format!("PTFO obstacle {id} has no outline"))
            })?;
            let change = match clip_vertex(&ring, &anchor.point) {
                Some(Clipped::Outline(polygon)) => MapChange::Reshape {
                    obstacle: id,
                    polygon,
                },
                Some(Clipped::Removed) => MapChange::Remove(id),
                None => {
                    return Err(OnlineError::Internal(format!(
                        "anchor is not a vertex of obstacle {id}"
                    )));
                }
            };
            for mut o in self.apply_change(&change)? {
                o.reason = format!(
                    "the tether slips over {place} (Alg. 9): vertex clipped (Alg. 14); {}",
                    o.reason
                );
                out.push(o);
            }
        }
        Err(OnlineError::Internal(format!(
            "more than {bound} friction decisions in one settling"
        )))
    }
}
