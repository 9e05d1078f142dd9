//! `--field RES`, shared by `rappel settle`, `settle-map` and `navigate`: settle and predict
//! anchors through the sparse distance field of the ground at `RES` metres instead of parry's
//! exact mesh distances ([`rappel::planners::rover::ground`]). Every refusal names the flag and the value.

use crate::output::CliError;
use rappel::geometry::compact::Compact;
use rappel::planners::rover::ground::{DistanceSource, DistanceSourceError, GroundDistances};
use rappel::terrain::mesh::TriMesh;

/// `--field RES`.
#[derive(clap::Args, Debug, Default)]
pub struct FieldArg {
    /// Settle (footprint, drop, body points along the axle) and predict anchors (the tether's
    /// swept triangle) through the sparse signed distance field of the ground at this
    /// resolution, metres, propagated to 1 m (Paton §IV's use of the field; default: parry's
    /// exact mesh distances). The boom sweep and the stability QP stay on the mesh. The JSON
    /// report's `distance_source` says which was used and the field's error bound.
    #[arg(long, value_parser = crate::numbers::finite, value_name = "RES", allow_negative_numbers = true)]
    pub field: Option<f64>,
}

impl FieldArg {
    /// The distance source asked for.
    pub fn source(&self) -> DistanceSource {
        match self.field {
            Some(resolution_m) => DistanceSource::Field { resolution_m },
            None => DistanceSource::Exact,
        }
    }

    /// The ground's distances from the source asked for; a refusal names `--field` and its
    /// value.
    pub fn distances(&self, ground: &TriMesh) -> Result<GroundDistances, CliError> {
        GroundDistances::new(ground, self.source()).map_err(|e| self.error(e))
    }

    /// `e` as a CLI error naming the flag and its value (`--field RES: why`; without `--field`,
    /// the library's message alone).
    pub fn error(&self, e: DistanceSourceError) -> CliError {
        match (self.field, e) {
            (Some(res), DistanceSourceError::Field(why)) => CliError(format!(
                "--field {}: cannot build the distance field at this resolution: {why}",
                Compact(res)
            )),
            (Some(res), e) => CliError(format!("--field {}: {e}", Compact(res))),
            (None, e) => CliError(e.to_string()),
        }
    }
}
