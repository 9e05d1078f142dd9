//! Tether-free and tether-demand planes (thesis §2.1.2, after Abad-Manterola \[58\]; eq. 2.7).
//!
//! On a plane inclined at `eta` with wheel-terrain friction `mu`, a point robot holds its position
//! without the tether when friction can balance the downhill pull of gravity, `mu cos eta >=
//! sin eta`, i.e. `mu cot eta >= 1`. Eq. 2.7, `|theta_max| = asin(mu cot eta)`, is the largest
//! heading from the fall line the robot can keep on a *tether-demand* plane; when `mu cot eta >= 1`
//! every heading is possible and the plane is *tether-free*. This is the geometry crate's
//! classification from `mu` and the slope alone; robot models with a richer traversability
//! (wheel and body geometry, stability) live in the mechanics crate.

use serde::{Deserialize, Serialize};

/// Whether a plane needs the tether.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum PlaneClass {
    /// The robot can travel freely without tether forces (`mu >= tan eta`).
    TetherFree,
    /// The robot depends on the tether (`mu < tan eta`).
    TetherDemand,
}

impl PlaneClass {
    /// The class's name in reports and pictures: `"tether-free"` or `"tether-demand"`.
    ///
    /// ```
    /// use rappel_terrain::plane_class::PlaneClass;
    /// assert_eq!(PlaneClass::TetherDemand.label(), "tether-demand");
    /// ```
    pub fn label(self) -> &'static str {
        match self {
            PlaneClass::TetherFree => "tether-free",
            PlaneClass::TetherDemand => "tether-demand",
        }
    }
}

/// Classifies a plane of slope `slope_deg` for wheel-terrain friction `friction` (`mu`).
///
/// ```
/// use rappel_terrain::plane_class::{classify_plane, PlaneClass};
/// // mu = 0.4 holds up to atan(0.4) = 21.8 degrees.
/// assert_eq!(classify_plane(20.0, 0.4), PlaneClass::TetherFree);
/// assert_eq!(classify_plane(45.0, 0.4), PlaneClass::TetherDemand);
/// ```
pub fn classify_plane(slope_deg: f64, friction: f64) -> PlaneClass {
    if friction >= slope_deg.to_radians().tan() {
        PlaneClass::TetherFree
    } else {
        PlaneClass::TetherDemand
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn boundary_is_the_friction_angle() {
        let mu: f64 = 0.7;
        let angle = mu.atan().to_degrees();
        assert_eq!(classify_plane(angle - 1e-9, mu), PlaneClass::TetherFree);
        assert_eq!(classify_plane(angle + 1e-9, mu), PlaneClass::TetherDemand);
        assert_eq!(classify_plane(0.0, 0.0), PlaneClass::TetherFree);
        // eq. 2.7 is defined (mu cot eta < 1) exactly on tether-demand planes.
        for eta in [5.0f64, 30.0, 60.0, 85.0] {
            let defined = mu / eta.to_radians().tan() < 1.0;
            assert_eq!(defined, classify_plane(eta, mu) == PlaneClass::TetherDemand);
        }
    }
}
