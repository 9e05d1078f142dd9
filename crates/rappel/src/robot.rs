//! The scenario's robot as a mechanics model: one place that turns [`RobotParams`] into a
//! [`RobotModel`] (Axel or a four-wheel rover) for the stability maps and for the planner's
//! traversability, so both judge the same robot.

use crate::scenario::{RobotModel as ModelKind, RobotParams};
use rappel_mechanics::axel::{Axel, AxelParams};
use rappel_mechanics::four_wheel::{FourWheelParams, FourWheelRover};
use rappel_mechanics::robot::RobotModel;

/// The wheeled model of the scenario's robot: Axel (body mass = the scenario's mass minus the
/// default boom, at least 1 kg) or a four-wheel rover of the scenario's mass. A `Point` robot has
/// no wheels; `None`.
///
/// ```
/// use rappel::robot::wheeled_model;
/// use rappel::scenario::{RobotModel, RobotParams};
/// let axel = RobotParams { model: RobotModel::Axel, ..RobotParams::default() };
/// assert!(wheeled_model(&axel).unwrap().is_some());
/// assert!(wheeled_model(&RobotParams::default()).unwrap().is_none());
/// ```
pub fn wheeled_model(params: &RobotParams) -> Result<Option<Box<dyn RobotModel + Sync>>, String> {
    let mass = params.mass_kg;
    Ok(match params.model {
        ModelKind::Point => None,
        ModelKind::Axel => {
            let defaults = AxelParams::default();
            let body_mass = (mass - defaults.boom_mass).max(1.0);
            Some(Box::new(
                Axel::new(AxelParams {
                    body_mass,
                    ..defaults
                })
                .map_err(|e| e.to_string())?,
            ))
        }
        ModelKind::FourWheel => Some(Box::new(
            FourWheelRover::new(FourWheelParams {
                mass,
                ..Default::default()
            })
            .map_err(|e| e.to_string())?,
        )),
    })
}

/// The wheeled model used where a model with contacts is required: the scenario's own, or for a
/// point robot a four-wheel rover of the same mass.
pub fn contact_model(params: &RobotParams) -> Result<Box<dyn RobotModel + Sync>, String> {
    match wheeled_model(params)? {
        Some(m) => Ok(m),
        None => Ok(Box::new(
            FourWheelRover::new(FourWheelParams {
                mass: params.mass_kg,
                ..Default::default()
            })
            .map_err(|e| e.to_string())?,
        )),
    }
}
