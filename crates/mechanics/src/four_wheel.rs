//! A generic four-wheel rover as a [`RobotModel`] (a TReX-class robot as in Kumar §II: one rigid
//! body, four wheel contacts, the tether fixed to the body at height `h_t`).
//!
//! Robot frame as in [`crate::robot`], origin on the ground under the wheelbase centre. Wheels touch
//! the ground at `(±wheelbase/2, ±track/2, 0)`; the mass sits at `(0, 0, com_height)`; the tether
//! leaves at `tether_exit`. Defaults follow Kumar §IV where given (35 kg) and are otherwise
//! representative of a TReX-size robot: wheelbase 0.6 m, track 0.55 m, centre of mass 0.25 m
//! above ground, tether exit at the rear, 0.3 m behind centre and `h_t = 0.35` m high.

use crate::robot::{PointMass, RobotConfiguration, RobotError, RobotModel, non_negative, positive};
use nalgebra::Point3;
use serde::{Deserialize, Serialize};

/// Parameters of [`FourWheelRover`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct FourWheelParams {
    /// Mass (kg). Default 35 (Kumar §IV).
    pub mass: f64,
    /// Distance between front and rear axles (m). Default 0.6.
    pub wheelbase: f64,
    /// Distance between left and right wheels (m). Default 0.55.
    pub track: f64,
    /// Height of the centre of mass above the ground (m). Default 0.25.
    pub com_height: f64,
    /// Tether exit in the robot frame (m). Default `(-0.3, 0, 0.35)`.
    pub tether_exit: Point3<f64>,
    /// Moment bound coefficient `μ_m` of the wheel contacts (m). Default 0 (point contacts).
    pub moment_coefficient: f64,
}

impl Default for FourWheelParams {
    fn default() -> Self {
        FourWheelParams {
            mass: 35.0,
            wheelbase: 0.6,
            track: 0.55,
            com_height: 0.25,
            tether_exit: Point3::new(-0.3, 0.0, 0.35),
            moment_coefficient: 0.0,
        }
    }
}

/// A rigid four-wheel rover.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FourWheelRover {
    params: FourWheelParams,
}

impl FourWheelRover {
    /// A rover with validated parameters (positive mass and dimensions, finite tether exit at or
    /// above the ground, non-negative moment coefficient).
    ///
    /// # Example
    /// ```
    /// use rappel_mechanics::four_wheel::{FourWheelParams, FourWheelRover};
    /// use rappel_mechanics::robot::RobotModel;
    /// let r = FourWheelRover::new(FourWheelParams { mass: 50.0, ..Default::default() }).unwrap();
    /// assert_eq!(r.total_mass(), 50.0);
    /// ```
    pub fn new(params: FourWheelParams) -> Result<Self, RobotError> {
        positive(params.mass, "mass must be finite and > 0")?;
        positive(params.wheelbase, "wheelbase must be finite and > 0")?;
        positive(params.track, "track must be finite and > 0")?;
        non_negative(params.com_height, "com_height must be finite and >= 0")?;
        non_negative(
            params.moment_coefficient,
            "moment_coefficient must be finite and >= 0",
        )?;
        if !(params.tether_exit.iter().all(|c| c.is_finite()) && params.tether_exit.z >= 0.0) {
            return Err(RobotError::Parameter(
                "tether_exit must be finite and not below the ground",
            ));
        }
        Ok(FourWheelRover { params })
    }

    /// The parameters.
    pub fn params(&self) -> &FourWheelParams {
        &self.params
    }
}

impl RobotModel for FourWheelRover {
    fn name(&self) -> &str {
        "four-wheel"
    }

    fn contact_moment_coefficient(&self) -> f64 {
        self.params.moment_coefficient
    }

    fn configuration(
        &self,
        _anchor: Option<&Point3<f64>>,
    ) -> Result<RobotConfiguration, RobotError> {
        let p = &self.params;
        let (a, b) = (p.wheelbase / 2.0, p.track / 2.0);
        Ok(RobotConfiguration {
            masses: vec![PointMass {
                mass: p.mass,
                position: Point3::new(0.0, 0.0, p.com_height),
            }],
            contacts: vec![
                Point3::new(a, b, 0.0),
                Point3::new(a, -b, 0.0),
                Point3::new(-a, b, 0.0),
                Point3::new(-a, -b, 0.0),
            ],
            tether_exit: p.tether_exit,
        })
    }
}
