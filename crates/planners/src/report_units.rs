//! Units in reports (`docs/output-format.md`): angles are written in degrees, rounded to
//! [`ANGLE_DECIMALS`] decimals so that no float noise (`45.00000000000001`) reaches a reader,
//! while the planners keep radians inside. [`radians_as_degrees`] is the serde adapter for a
//! radian field whose report name ends in `_deg`.

/// Decimals kept in an angle in degrees: 1e-9° is far below any tolerance of the planners.
pub const ANGLE_DECIMALS: i32 = 9;

/// `v` rounded to `decimals` decimals (unchanged when not finite or too large to have them;
/// `-0` becomes `0`).
pub fn round_to(v: f64, decimals: i32) -> f64 {
    let scale = 10f64.powi(decimals);
    let r = (v * scale).round() / scale;
    if r.is_finite() { r + 0.0 } else { v }
}

/// An angle in radians as degrees rounded to [`ANGLE_DECIMALS`] decimals.
pub fn deg(radians: f64) -> f64 {
    round_to(radians.to_degrees(), ANGLE_DECIMALS)
}

/// `#[serde(rename = "NAME_deg", with = "radians_as_degrees")]` on an `f64` field in radians:
/// written as [`deg`], read back as radians. With `#[schemars(with = "f64")]`.
pub mod radians_as_degrees {
    use serde::{Deserialize, Serialize};

    /// Writes `radians` in degrees.
    pub fn serialize<S: serde::Serializer>(radians: &f64, s: S) -> Result<S::Ok, S::Error> {
        super::deg(*radians).serialize(s)
    }

    /// Reads degrees into radians.
    pub fn deserialize<'de, D: serde::Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
        f64::deserialize(d).map(f64::to_radians)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn degrees_are_rounded_and_read_back_to_the_same_text() {
        assert_eq!(deg(std::f64::consts::FRAC_PI_4), 45.0);
        assert_eq!(round_to(0.1 + 0.2, 9), 0.3);
        assert_eq!(round_to(-0.0, 3).to_string(), "0");
        // Written, read back, written again: the same degrees (the rounding absorbs the ulp).
        for r in [0.1, 1.234_567_891_23, 3.0, -2.5] {
            let d = deg(r);
            assert_eq!(deg(d.to_radians()), d);
        }
    }
}
