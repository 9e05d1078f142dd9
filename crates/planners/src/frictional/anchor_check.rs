//! Alg. 8 `CheckPTFOs` with Alg. 9 `TetherSlips` (thesis §3.4.2): each friction anchor of an SHP
//! is decided on the tether's actual contact, the wrap of the PTFO's surface between its incoming
//! and outgoing directions ([`rappel_mechanics::ptfo_surface`]), as **solid** (holds from `T_min`
//! to `T_max` with the lowest friction), **slides** (slips between `T_d` and `T_d + ε` with the
//! highest friction) or **volatile** (the class is unsafe) ([`rappel_mechanics::ptfo::classify`]).
//! A sliding anchor goes through Alg. 14 ([`super::slip`]) and the whole SHP is checked again,
//! until no anchor slides.
//!
//! A PTFO wrapped at several consecutive anchors (the tether running from one of its vertices to
//! the next with no other contact between, e.g. round a pillar drawn as a polygon) is one contact:
//! Alg. 9 reads "the tether configuration at `f`" and eq. 3.20 integrates `ω` over the tether's
//! contact, so the run's samples are classified together, by the total wrap, and every anchor of
//! the run takes that class ([`decide_anchors_with`]). Judging each vertex alone against the
//! whole `T_min .. T_max` would ask every vertex to hold what the wrap holds jointly. When a
//! vertex of the run has no contact, the run is decided vertex by vertex (the thesis is silent on
//! a partial wrap; our choice, `docs/friction.md`).
//!
//! Bound: every slip removes one PTFO vertex from the map, so the loop runs at most once more than
//! the PTFOs have vertices ([`check_ptfos`] returns an internal error past that bound).

use super::slip::{SlipEvent, SlipState};
use super::{FrictionModel, FrictionalError};
use nalgebra::Point2;
use rappel_geometry::dcel::ObstacleId;
use rappel_homotopy::funnel::{Anchor, TautPath};
use rappel_mechanics::ptfo::{PtfoClass, classify};
use rappel_mechanics::ptfo_surface::WrapError;
use rappel_mechanics::sticking::{TetherSample, omega_integral};
use serde::{Deserialize, Serialize};

/// What an anchor of the final SHP is, and how it holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum AnchorVerdict {
    /// A geometric obstacle (or the map boundary): it always holds.
    Geometric,
    /// A PTFO anchor with its class.
    Friction(PtfoClass),
}

/// One anchor's decision.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AnchorDecision {
    /// The anchor.
    pub anchor: Anchor,
    /// Its map obstacle index (`None` on the boundary).
    pub obstacle: Option<usize>,
    /// Geometric, or the friction class.
    pub verdict: AnchorVerdict,
    /// `∫ω ds` over the wrap with the lowest friction (0 without contact or for geometric ones).
    pub omega_integral_hold: f64,
    /// `∫ω ds` over the wrap with the highest friction.
    pub omega_integral_slide: f64,
    /// Why there is no contact, when there is none.
    pub no_contact: Option<String>,
}

/// The outcome of Alg. 8 for one class.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PtfoCheck {
    /// The SHP after every slip.
    pub taut: TautPath,
    /// Its anchors, decided.
    pub anchors: Vec<AnchorDecision>,
    /// The slips, in order.
    pub slips: Vec<SlipEvent>,
    /// The first volatile anchor (index into `anchors`): the class is unsafe (Alg. 8 line 12).
    pub volatile: Option<usize>,
}

/// Decides one anchor of `taut` (Alg. 9 on its wrap, with the classes of §3.4.1).
pub fn decide_anchor(
    model: &FrictionModel,
    state: &SlipState<'_>,
    taut: &TautPath,
    anchor: &Anchor,
) -> Result<AnchorDecision, FrictionalError> {
    decide_anchor_with(model, |id| state.original(id), taut, anchor)
}

/// [`decide_anchor`] with the map obstacle index of a BTM obstacle given by `original` (the
/// online session keeps its own renaming of obstacles re-inserted after a clip).
pub fn decide_anchor_with(
    model: &FrictionModel,
    original: impl Fn(ObstacleId) -> usize,
    taut: &TautPath,
    anchor: &Anchor,
) -> Result<AnchorDecision, FrictionalError> {
    let obstacle = anchor.obstacle.map(original);
    let geometric = AnchorDecision {
        anchor: *anchor,
        obstacle,
        verdict: AnchorVerdict::Geometric,
        omega_integral_hold: 0.0,
        omega_integral_slide: 0.0,
        no_contact: None,
    };
    let Some(ptfo) = obstacle.and_then(|o| model.ptfo_of(o)) else {
        return Ok(geometric);
    };
    let (incoming, outgoing) = directions(taut, anchor)?;
    match ptfo.surface.wrap(&anchor.point, &incoming, &outgoing) {
        Ok(samples) => {
            let class = classify(&samples, ptfo.friction, &model.tensions)?;
            let hold = omega_integral(&samples, ptfo.friction.for_holding())
                .map_err(rappel_mechanics::ptfo::PtfoError::from)?;
            let slide = omega_integral(&samples, ptfo.friction.for_sliding())
                .map_err(rappel_mechanics::ptfo::PtfoError::from)?;
            Ok(AnchorDecision {
                verdict: AnchorVerdict::Friction(class),
                omega_integral_hold: hold,
                omega_integral_slide: slide,
                ..geometric
            })
        }
        // Condition 1 fails: the tether slides over (thesis §3.4.1 rule 2).
        Err(WrapError::NoContact(why)) => Ok(AnchorDecision {
            verdict: AnchorVerdict::Friction(PtfoClass::Slides),
            no_contact: Some(why.to_string()),
            ..geometric
        }),
        Err(source) => Err(FrictionalError::Surface {
            obstacle: ptfo.obstacle,
            source,
        }),
    }
}

/// Decides every anchor of `taut` in tether order (Alg. 8-9), a run of consecutive anchors on the
/// same PTFO by its total wrap (module docs); `original` as in [`decide_anchor_with`].
pub fn decide_anchors_with(
    model: &FrictionModel,
    original: impl Fn(ObstacleId) -> usize,
    taut: &TautPath,
) -> Result<Vec<AnchorDecision>, FrictionalError> {
    let anchors = &taut.anchors;
    let mut out = Vec::with_capacity(anchors.len());
    let mut i = 0;
    while i < anchors.len() {
        let obstacle = anchors[i].obstacle.map(&original);
        let mut j = i + 1;
        while j < anchors.len()
            && obstacle.is_some()
            && anchors[j].obstacle.map(&original) == obstacle
        {
            j += 1;
        }
        let ptfo = obstacle.and_then(|o| model.ptfo_of(o));
        let run = &anchors[i..j];
        match ptfo {
            Some(ptfo) if run.len() > 1 => {
                let mut wraps = Vec::with_capacity(run.len());
                for a in run {
                    let (incoming, outgoing) = directions(taut, a)?;
                    match ptfo.surface.wrap(&a.point, &incoming, &outgoing) {
                        Ok(samples) => wraps.push(samples),
                        Err(WrapError::NoContact(_)) => break,
                        Err(source) => {
                            return Err(FrictionalError::Surface {
                                obstacle: ptfo.obstacle,
                                source,
                            });
                        }
                    }
                }
                if wraps.len() < run.len() {
                    for a in run {
                        out.push(decide_anchor_with(model, &original, taut, a)?);
                    }
                } else {
                    let all: Vec<TetherSample> = wraps.concat();
                    let class = classify(&all, ptfo.friction, &model.tensions)?;
                    for (a, samples) in run.iter().zip(&wraps) {
                        let hold = omega_integral(samples, ptfo.friction.for_holding())
                            .map_err(rappel_mechanics::ptfo::PtfoError::from)?;
                        let slide = omega_integral(samples, ptfo.friction.for_sliding())
                            .map_err(rappel_mechanics::ptfo::PtfoError::from)?;
                        out.push(AnchorDecision {
                            anchor: *a,
                            obstacle,
                            verdict: AnchorVerdict::Friction(class),
                            omega_integral_hold: hold,
                            omega_integral_slide: slide,
                            no_contact: None,
                        });
                    }
                }
            }
            _ => {
                for a in run {
                    out.push(decide_anchor_with(model, &original, taut, a)?);
                }
            }
        }
        i = j;
    }
    Ok(out)
}

/// The incoming and outgoing tether directions at an anchor of `taut`.
pub(crate) fn directions(
    taut: &TautPath,
    anchor: &Anchor,
) -> Result<(nalgebra::Vector2<f64>, nalgebra::Vector2<f64>), FrictionalError> {
    let i = taut
        .vertices
        .iter()
        .position(|v| *v == Some(anchor.vertex))
        .filter(|&i| i > 0 && i + 1 < taut.points.len())
        .ok_or_else(|| FrictionalError::Internal("anchor not interior to its path".into()))?;
    Ok((
        taut.points[i] - taut.points[i - 1],
        taut.points[i + 1] - taut.points[i],
    ))
}

/// Alg. 8 on the SHP `taut` of the map in `state` (module docs).
pub fn check_ptfos(
    model: &FrictionModel,
    state: &mut SlipState<'_>,
    taut: TautPath,
    ptfo_vertex_count: usize,
) -> Result<PtfoCheck, FrictionalError> {
    let mut taut = taut;
    let mut slips = Vec::new();
    for _ in 0..=ptfo_vertex_count {
        let mut decisions = decide_anchors_with(model, |id| state.original(id), &taut)?;
        let mut slipping = None;
        for at in 0..decisions.len() {
            match decisions[at].verdict {
                AnchorVerdict::Friction(PtfoClass::Slides) => {
                    slipping = Some(decisions[at].anchor);
                    decisions.truncate(at + 1);
                    break;
                }
                AnchorVerdict::Friction(PtfoClass::Volatile) => {
                    decisions.truncate(at + 1);
                    return Ok(PtfoCheck {
                        taut,
                        anchors: decisions,
                        slips,
                        volatile: Some(at),
                    });
                }
                _ => {}
            }
        }
        let Some(a) = slipping else {
            return Ok(PtfoCheck {
                taut,
                anchors: decisions,
                slips,
                volatile: None,
            });
        };
        let (next, event) = state.update_with_slipped(&taut, &a)?;
        slips.push(event);
        taut = next;
    }
    Err(FrictionalError::Internal(format!(
        "more slips than PTFO vertices ({ptfo_vertex_count})"
    )))
}

/// The anchor points of a check, for reports.
pub fn anchor_points(check: &PtfoCheck) -> Vec<Point2<f64>> {
    check.anchors.iter().map(|d| d.anchor.point).collect()
}
