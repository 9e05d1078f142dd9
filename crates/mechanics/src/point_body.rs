//! Kumar's free body of Robot 2 (Kumar §III-B, Fig. 4, eqs. 3a-3e) as a [`RobotModel`]: one body
//! whose ground reaction is a single force `(F_X, F_Y, F_Z)` in one friction pyramid, with the
//! weight, the ground force and the tether all acting at one point.
//!
//! Kumar's LP constrains the total ground force of Robot 2, `-μ F_Z <= F_X, F_Y <= μ F_Z` in the
//! local frame whose `X_L` runs along the tether towards the anchor (eq. 3c), and balances moments
//! about the last anchor (3b). With the forces concurrent at the body's point, (3b) adds nothing
//! to (3a) (the tether passes through the anchor; the weight and the ground force act where the
//! tether leaves). This model is that body: one mass, one point contact and the tether exit at the
//! robot origin. Placed facing away from its anchor (the robot's `x` axis on the tether's line in
//! the plane), its contact pyramid is Kumar's eq. 3c exactly. A wheeled rover such as
//! [`crate::four_wheel::FourWheelRover`] instead has one pyramid per wheel and a rigid body whose
//! moments must balance, which refuses some total forces this body admits.

use crate::robot::{PointMass, RobotConfiguration, RobotError, RobotModel, positive};
use nalgebra::Point3;

/// Kumar's point body (Fig. 4) of mass `mass` kg.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointBody {
    mass: f64,
}

impl PointBody {
    /// A point body of `mass` kg (finite and positive).
    ///
    /// # Example
    /// ```
    /// use rappel_mechanics::point_body::PointBody;
    /// use rappel_mechanics::robot::RobotModel;
    /// let body = PointBody::new(35.0).unwrap();
    /// assert_eq!(body.total_mass(), 35.0);
    /// assert_eq!(body.configuration(None).unwrap().contacts.len(), 1);
    /// assert!(PointBody::new(0.0).is_err());
    /// ```
    pub fn new(mass: f64) -> Result<Self, RobotError> {
        positive(mass, "mass must be finite and > 0")?;
        Ok(PointBody { mass })
    }
}

impl RobotModel for PointBody {
    fn name(&self) -> &str {
        "point-body"
    }

    fn contact_moment_coefficient(&self) -> f64 {
        0.0
    }

    fn configuration(
        &self,
        _anchor: Option<&Point3<f64>>,
    ) -> Result<RobotConfiguration, RobotError> {
        Ok(RobotConfiguration {
            masses: vec![PointMass {
                mass: self.mass,
                position: Point3::origin(),
            }],
            contacts: vec![Point3::origin()],
            tether_exit: Point3::origin(),
        })
    }

    fn contact_is_point(&self, _index: usize) -> bool {
        true
    }
}
