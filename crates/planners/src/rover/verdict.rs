//! Whether a settled rover stands (Paton §IV-B): Axel's two boom configurations placed against the
//! ground and each judged by the stability QP with the tether from the anchor, or the four-wheel
//! rover's supporting wheels; a pose is stable when one configuration holds and its tether is not
//! detached from the anchor.

use nalgebra::Point3;
use serde::{Deserialize, Serialize};

use rappel_mechanics::axel::AxelParams;
use rappel_mechanics::boom_contact::{place_boom_in_contact, place_boom_inline};
use rappel_mechanics::four_wheel::{FourWheelParams, FourWheelRover};
use rappel_mechanics::four_wheel_settle::FourWheelPose;
use rappel_mechanics::settle::SettledPose;
use rappel_mechanics::stability_qp::StabilityQp;

use crate::anchor_prediction::{AnchorHistory, is_detached};

/// Wheel-ground friction used for the stability verdict (the scenes carry none; Paton's
/// simulations do not state one). Assumed.
pub const SCENE_FRICTION: f64 = 0.6;

/// Which robot a settle request places (`rappel settle --robot`).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum SettleRobot {
    /// Axel (default `AxelParams`): two wheels of 12 contact points, the body along the axle,
    /// the boom.
    #[default]
    Axel,
    /// The rigid four-wheel rover (default `FourWheelParams`, `mechanics::four_wheel`): four
    /// point wheels, no body geometry, the tether fixed to the body.
    FourWheel,
}

/// The boom label of the one verdict of a robot without a boom ([`BoomVerdict::boom`]).
pub const NO_BOOM: &str = "none";

/// The stability verdict of one boom configuration.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct BoomVerdict {
    /// `inline` or `in-contact` (Axel), `none` (a robot without a boom).
    pub boom: String,
    /// A static equilibrium exists (`None`: not checked, `error` says why).
    pub stable: Option<bool>,
    /// The error that prevented the check, if one did.
    pub error: Option<String>,
    /// Paton's normalised eq. 9 margin (0 when not stable).
    pub margin: f64,
}

/// The stability QP's verdict for `pose` with the tether from the anchor history `history`, in
/// both boom configurations of Axel `params`, with [`SCENE_FRICTION`]:
/// * **inline**: the boom along the line from the pivot to the last anchor, refused where it
///   would pass through the mesh ([`place_boom_inline`]);
/// * **in contact**: the boom swept toward the last anchor until it touches the mesh
///   ([`place_boom_in_contact`]: on its tip or its shaft, e.g. resting on a ledge's lip). The
///   tether leaves from the boom's tip, which is not the pivot the history was predicted for:
///   while the tip lies above the last anchor's `F_d` plane (Paton's detach test,
///   [`crate::anchor_prediction::is_detached`]) that anchor is popped and the boom swept again toward the one before
///   (at most once per anchor). Attaching anchors between the pivot and the tip is not
///   searched (the boom is at most `L_c` long).
pub fn boom_verdicts<G: rappel_mechanics::boom_contact::BoomGround + ?Sized>(
    ground: &G,
    pose: &SettledPose,
    params: &AxelParams,
    history: &AnchorHistory,
) -> Vec<BoomVerdict> {
    BOOM_CONFIGURATIONS
        .into_iter()
        .map(|boom| boom_verdict(ground, pose, params, history, boom))
        .collect()
}

/// Axel's two boom configurations, in the order [`boom_verdicts`] reports them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BoomConfiguration {
    /// The boom along the line from the pivot to the last anchor.
    Inline,
    /// The boom swept toward the last anchor until it touches the mesh.
    InContact,
}

/// Both configurations, inline first.
pub const BOOM_CONFIGURATIONS: [BoomConfiguration; 2] =
    [BoomConfiguration::Inline, BoomConfiguration::InContact];

/// Whether `pose` is stable with the tether from `history` in some boom configuration: the
/// `stable` of [`boom_verdicts`] (any configuration stable), found without the second
/// configuration's placement and QP when the inline boom is already stable (the planner's motion
/// checks need the verdict, not the margins).
pub fn pose_is_stable<G: rappel_mechanics::boom_contact::BoomGround + ?Sized>(
    ground: &G,
    pose: &SettledPose,
    params: &AxelParams,
    history: &AnchorHistory,
) -> bool {
    BOOM_CONFIGURATIONS
        .into_iter()
        .any(|boom| boom_verdict(ground, pose, params, history, boom).stable == Some(true))
}

/// The stability verdict of the settled four-wheel rover `pose` (default `FourWheelParams`) with
/// the tether from `anchor` to its tether exit ([`NO_BOOM`]): the supporting wheels' contacts
/// with frames from `ground`'s distance gradient, [`SCENE_FRICTION`], the stability QP.
pub fn four_wheel_verdict<D: rappel_terrain::surface::SignedDistance + ?Sized>(
    pose: &FourWheelPose,
    ground: &D,
    anchor: &Point3<f64>,
) -> BoomVerdict {
    let placed = FourWheelRover::new(FourWheelParams::default())
        .and_then(|rover| pose.place(&rover, ground, SCENE_FRICTION, Some((anchor, None))))
        .map_err(|e| e.to_string());
    qp_verdict(NO_BOOM, placed)
}

/// The stability QP's verdict on a placed robot (or the placement's error), labelled `boom`.
fn qp_verdict(
    boom: &str,
    placed: Result<rappel_mechanics::robot::PlacedRobot, String>,
) -> BoomVerdict {
    match placed.and_then(|placed| {
        StabilityQp::default()
            .check(&placed)
            .map_err(|e| e.to_string())
    }) {
        Ok(r) => BoomVerdict {
            boom: boom.to_string(),
            stable: Some(r.stable),
            error: None,
            margin: r.margin,
        },
        Err(e) => BoomVerdict {
            boom: boom.to_string(),
            stable: None,
            error: Some(e),
            margin: 0.0,
        },
    }
}

/// The verdict of one boom configuration (see [`boom_verdicts`]).
pub fn boom_verdict<G: rappel_mechanics::boom_contact::BoomGround + ?Sized>(
    ground: &G,
    pose: &SettledPose,
    params: &AxelParams,
    history: &AnchorHistory,
    boom: BoomConfiguration,
) -> BoomVerdict {
    let anchors = history.anchors();
    let in_contact = || {
        let mut n = anchors.len() - 1;
        // Each pass pops one anchor (n decreases) or returns: at most one pass per anchor.
        loop {
            let placed = place_boom_in_contact(
                pose,
                params,
                ground,
                SCENE_FRICTION,
                (&anchors[n].point, None),
            )
            .map_err(|e| e.to_string())?;
            let popped = n > 0 && is_detached(&anchors[n - 1], &anchors[n], &placed.1.tip);
            if !popped {
                return Ok(placed.0);
            }
            n -= 1;
        }
    };
    let (name, placed) = match boom {
        BoomConfiguration::Inline => (
            "inline",
            place_boom_inline(
                pose,
                params,
                ground,
                SCENE_FRICTION,
                (&history.last().point, None),
            )
            .map_err(|e| e.to_string()),
        ),
        BoomConfiguration::InContact => ("in-contact", in_contact()),
    };
    qp_verdict(name, placed)
}
