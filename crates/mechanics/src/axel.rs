//! JPL's Axel rover as a [`RobotModel`] (thesis §1.5; Paton §IV-A and Fig. 6): two wheels on one
//! axle, a body between them, and a boom (caster arm) pivoting about the axle with the tether
//! leaving at its tip; and Axel's tether-tension estimate (thesis eq. 3.32, re-derived).
//!
//! # Model
//! Robot frame as in [`crate::robot`], origin on the ground under the axle centre. The wheels
//! (radius `r_w`) touch the ground at `(0, ±track/2, 0)`; the body's mass `m_1` sits on the axle
//! at `(0, 0, r_w)`; the boom of length `L_c` pivots about the axle and its mass `m_2` sits at its
//! midpoint; the tether leaves at the boom tip. The boom's azimuth points at the anchor; its
//! elevation follows [`BoomMode`] (Paton's *inline* and *in-contact* configurations). With the boom
//! in contact its tip is a third contact (Paton's `P3`).
//!
//! # Tension estimate (eq. 3.32)
//! In the vertical plane of the fall line (slope `η`), take moments about the wheel-ground contact
//! line, which eliminates the unknown contact forces (Fig. 2.19 with the arm added). With the
//! rover's weight `m g` acting at the axle (height `r_w` above the contact), its moment is
//! `m g r_w sin η`. The tether pulls with tension `T` at the boom tip along the angle `θ_t`
//! measured from the slope surface (up-slope positive, away from the ground positive), the boom
//! making angle `θ_c` with the slope. The tip is at `(L_c cos θ_c, r_w + L_c sin θ_c)` in
//! (up-slope, normal) coordinates, so the tether's moment arm is
//! `L_c sin(θ_c - θ_t) + r_w cos θ_t` and
//!
//! ```text
//! T_A = m g r_w sin η / (L_c sin(θ_c - θ_t) + r_w cos θ_t).
//! ```
//!
//! The printed eq. 3.32 has the same structure (`m g r_w sin η` over an `L_c sin(...)` term plus
//! an `r_w cos(η - θ_t)` term), with its angles measured from the horizontal instead of the slope.
//! Checks: with the arm along the tether (`θ_c = θ_t`) the tether line passes through the axle
//! and `T_A = m g sin η / cos θ_t`, the frictionless along-slope load; raising the arm lengthens
//! the moment arm and lowers the tension, the rest being carried by wheel friction.

use crate::robot::{PointMass, RobotConfiguration, RobotError, RobotModel, non_negative, positive};
use nalgebra::{Point3, Vector3};
use serde::{Deserialize, Serialize};

/// How the boom is posed (Paton §IV-A, "inline" and "in contact").
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum BoomMode {
    /// Inline with the tether when tethered; resting on the ground (trailing backward) otherwise.
    Auto,
    /// Along the line from the axle to the anchor; without a tether, straight up.
    Inline,
    /// Resting on the ground toward the anchor (backward without a tether); its tip is a contact.
    InContact,
    /// At a fixed elevation (radians above the ground plane) toward the anchor (backward without a
    /// tether).
    Fixed(f64),
    /// Resting on real ground at the elevation (radians above the ground plane, toward the anchor;
    /// backward without a tether) that a contact search found
    /// ([`crate::boom_contact::sweep_boom`]): it may lie below the pose's plane where the ground
    /// falls away (past a ledge's lip). The model adds no contact for it: the search supplies the
    /// boom's ground contact, which may be on the boom's shaft rather than its tip.
    Resting(f64),
}

/// Axel's parameters. The defaults are representative of the Axel rover as described in the
/// thesis (55 kg, the load of §3.3.4), not a specification: replace them with measured values.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct AxelParams {
    /// Wheel radius `r_w` (m). Default 0.35.
    pub wheel_radius: f64,
    /// Distance between the two wheel contacts (m). Default 0.9.
    pub track: f64,
    /// Body and wheel mass `m_1` (kg), on the axle. Default 48.
    pub body_mass: f64,
    /// Boom mass `m_2` (kg), at the boom midpoint. Default 7.
    pub boom_mass: f64,
    /// Boom length `L_c` from the axle to the tether exit (m). Default 1.0.
    pub boom_length: f64,
    /// Moment bound coefficient `μ_m` of a grousered wheel contact patch (m). Default 0.05.
    pub moment_coefficient: f64,
    /// Boom pose. Default [`BoomMode::Auto`].
    pub boom: BoomMode,
    /// Coulomb coefficient between the boom and the ground where the boom rests on it (its tip
    /// in [`BoomMode::InContact`], the swept boom's contact of
    /// [`crate::boom_contact::place_boom_in_contact`]); the wheels' coefficient is the ground's,
    /// given at placement. Default 0.6. **Assumed**: Paton gives no friction values at all (one
    /// `μ` for every contact in eqs. 2-3); 0.6 is the wheel-ground value assumed for his
    /// scenes, so the default changes no verdict; replace it with a measured boom-tip value.
    #[serde(default = "default_boom_friction")]
    pub boom_friction: f64,
}

/// [`AxelParams::boom_friction`]'s default.
pub const DEFAULT_BOOM_FRICTION: f64 = 0.6;

fn default_boom_friction() -> f64 {
    DEFAULT_BOOM_FRICTION
}

impl Default for AxelParams {
    fn default() -> Self {
        AxelParams {
            wheel_radius: 0.35,
            track: 0.9,
            body_mass: 48.0,
            boom_mass: 7.0,
            boom_length: 1.0,
            moment_coefficient: 0.05,
            boom: BoomMode::Auto,
            boom_friction: DEFAULT_BOOM_FRICTION,
        }
    }
}

/// The Axel rover model.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Axel {
    params: AxelParams,
}

impl Axel {
    /// An Axel with validated parameters: positive lengths and body mass, non-negative boom mass
    /// and moment coefficient, and a boom longer than the wheel radius (so it can reach the ground).
    pub fn new(params: AxelParams) -> Result<Self, RobotError> {
        positive(params.wheel_radius, "wheel_radius must be finite and > 0")?;
        positive(params.track, "track must be finite and > 0")?;
        positive(params.body_mass, "body_mass must be finite and > 0")?;
        non_negative(params.boom_mass, "boom_mass must be finite and >= 0")?;
        positive(params.boom_length, "boom_length must be finite and > 0")?;
        non_negative(
            params.moment_coefficient,
            "moment_coefficient must be finite and >= 0",
        )?;
        non_negative(
            params.boom_friction,
            "boom_friction must be finite and >= 0",
        )?;
        if params.boom_length <= params.wheel_radius {
            return Err(RobotError::Parameter(
                "boom_length must exceed wheel_radius",
            ));
        }
        if let BoomMode::Fixed(e) | BoomMode::Resting(e) = params.boom
            && !(e.is_finite() && e.abs() <= std::f64::consts::FRAC_PI_2)
        {
            return Err(RobotError::Parameter(
                "fixed or resting boom elevation must be within ±90 degrees",
            ));
        }
        Ok(Axel { params })
    }

    /// The parameters.
    pub fn params(&self) -> &AxelParams {
        &self.params
    }

    fn pivot(&self) -> Point3<f64> {
        Point3::new(0.0, 0.0, self.params.wheel_radius)
    }
}

impl RobotModel for Axel {
    fn name(&self) -> &str {
        "axel"
    }

    /// The third contact (the boom's tip on the ground, [`BoomMode::InContact`]) carries
    /// [`AxelParams::boom_friction`]; the wheels (0, 1) the ground's.
    fn contact_friction(&self, index: usize) -> Option<f64> {
        (index == 2).then_some(self.params.boom_friction)
    }

    /// The boom's tip on the ground (contact 2) is a point contact: no grouser patch.
    fn contact_is_point(&self, index: usize) -> bool {
        index == 2
    }

    fn contact_moment_coefficient(&self) -> f64 {
        self.params.moment_coefficient
    }

    fn configuration(
        &self,
        anchor: Option<&Point3<f64>>,
    ) -> Result<RobotConfiguration, RobotError> {
        let p = &self.params;
        let pivot = self.pivot();
        // Horizontal azimuth toward the anchor (backward without a tether).
        let azimuth = match anchor {
            Some(a) => {
                let h = Vector3::new(a.x, a.y, 0.0);
                if h.norm() < crate::robot::MIN_TETHER_LENGTH {
                    return Err(RobotError::Anchor("anchor straight above the axle"));
                }
                h.normalize()
            }
            None => -Vector3::x(),
        };
        let elevation_dir = |e: f64| azimuth * e.cos() + Vector3::z() * e.sin();
        let ground_elevation = -(p.wheel_radius / p.boom_length).asin();
        let mode = match (p.boom, anchor) {
            (BoomMode::Auto | BoomMode::Inline, Some(a)) => Boom::Inline(a),
            (BoomMode::Inline, None) => Boom::Up,
            (BoomMode::Auto | BoomMode::InContact, _) => Boom::OnGround,
            (BoomMode::Fixed(e), _) => Boom::Elevation(e),
            (BoomMode::Resting(e), _) => Boom::Resting(e),
        };
        let (dir, tip_contact) = match mode {
            Boom::Inline(a) => {
                let d = a - pivot;
                let n = d.norm();
                if n <= p.boom_length {
                    return Err(RobotError::Anchor("anchor within the boom's reach"));
                }
                let d = d / n;
                if pivot.z + p.boom_length * d.z < 0.0 {
                    return Err(RobotError::Anchor("inline boom would dig into the ground"));
                }
                (d, false)
            }
            Boom::Up => (Vector3::z(), false),
            Boom::OnGround => (elevation_dir(ground_elevation), true),
            Boom::Elevation(e) => {
                if e < ground_elevation {
                    return Err(RobotError::Parameter(
                        "fixed boom elevation puts the tip below the ground",
                    ));
                }
                (elevation_dir(e), false)
            }
            Boom::Resting(e) => (elevation_dir(e), false),
        };
        let tip = pivot + dir * p.boom_length;
        let mut contacts = vec![
            Point3::new(0.0, p.track / 2.0, 0.0),
            Point3::new(0.0, -p.track / 2.0, 0.0),
        ];
        if tip_contact {
            contacts.push(Point3::new(tip.x, tip.y, 0.0));
        }
        let mut masses = vec![PointMass {
            mass: p.body_mass,
            position: pivot,
        }];
        if p.boom_mass > 0.0 {
            masses.push(PointMass {
                mass: p.boom_mass,
                position: pivot + dir * (p.boom_length / 2.0),
            });
        }
        Ok(RobotConfiguration {
            masses,
            contacts,
            tether_exit: tip,
        })
    }
}

/// A [`BoomMode`] resolved for one tether situation.
enum Boom<'a> {
    Inline(&'a Point3<f64>),
    Up,
    OnGround,
    Elevation(f64),
    Resting(f64),
}

/// Axel's tether tension estimate (thesis eq. 3.32, re-derived in the module docs): mass `mass`
/// (kg) at the axle, gravity `g`, wheel radius `wheel_radius`, boom length `boom_length`, slope
/// `slope`, boom angle `boom_angle` and tether angle `tether_angle` both from the slope surface
/// (radians). Returns `None` when the tether has no positive moment arm (it cannot hold the rover).
///
/// # Example
/// ```
/// use rappel_mechanics::axel::tether_tension_estimate;
/// // Boom along the tether: the tether carries the whole along-slope weight.
/// let t = tether_tension_estimate(55.0, 9.81, 0.35, 1.0, 0.9, 0.0, 0.0).unwrap();
/// assert!((t - 55.0 * 9.81 * 0.9f64.sin()).abs() < 1e-9);
/// ```
pub fn tether_tension_estimate(
    mass: f64,
    g: f64,
    wheel_radius: f64,
    boom_length: f64,
    slope: f64,
    boom_angle: f64,
    tether_angle: f64,
) -> Option<f64> {
    let arm = boom_length * (boom_angle - tether_angle).sin() + wheel_radius * tether_angle.cos();
    let t = mass * g * wheel_radius * slope.sin() / arm;
    (arm > 0.0 && t.is_finite()).then_some(t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn configurations_follow_boom_mode() {
        let axel = Axel::default();
        let free = axel.configuration(None).unwrap();
        assert_eq!(free.contacts.len(), 3);
        assert!(free.tether_exit.z.abs() < 1e-12 && free.tether_exit.x < 0.0);
        let anchor = Point3::new(-20.0, 0.0, 0.0);
        let inline = axel.configuration(Some(&anchor)).unwrap();
        assert_eq!(inline.contacts.len(), 2);
        // The tether exit lies on the axle-anchor line.
        let d1 = (inline.tether_exit - axel.pivot()).normalize();
        let d2 = (anchor - axel.pivot()).normalize();
        assert!((d1 - d2).norm() < 1e-12);
        assert!(
            axel.configuration(Some(&Point3::new(-0.5, 0.0, 0.0)))
                .is_err()
        );
        let bad = AxelParams {
            boom_length: 0.2,
            ..AxelParams::default()
        };
        assert!(Axel::new(bad).is_err());
        assert!((axel.total_mass() - 55.0).abs() < 1e-12);
    }

    #[test]
    fn tension_estimate_decreases_as_boom_rises() {
        let t = |c: f64| tether_tension_estimate(55.0, 9.81, 0.35, 1.0, 1.0, c, 0.0).unwrap();
        assert!(t(0.3) < t(0.0) && t(0.6) < t(0.3));
        assert_eq!(
            tether_tension_estimate(55.0, 9.81, 0.35, 1.0, 1.0, -1.2, 0.0),
            None
        );
    }
}
