//! Where a given tether may stick along its length on a scenario's DEM (thesis §3.3.5, Figs.
//! 3.13-3.15): [`rappel_mechanics::sticking_profile`] over the DEM and planning frame a
//! [`DemScenario`] carries.

use crate::dem::DemScenario;
use nalgebra::Point2;
pub use rappel_mechanics::sticking_profile::{MAX_SAMPLES, StickingSample};

/// Samples `tether` (planning-frame polyline) every `step` metres of plan length over `d`'s DEM
/// with tether-terrain friction `mu` ([`rappel_mechanics::sticking_profile::sticking_profile`]).
///
/// ```
/// use rappel::dem::dem_scenario;
/// use rappel::sticking_profile::sticking_profile;
/// use rappel::terrain::ingest::IngestOptions;
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/terrain/mars_hirise_dteec_010228_1490_crop.asc");
/// let d = dem_scenario(path.as_ref(), &IngestOptions::default()).unwrap();
/// let samples = sticking_profile(&d, &[d.scenario.start, d.scenario.goal], 0.4, 0.5);
/// assert!(samples.len() > 50);
/// ```
pub fn sticking_profile(
    d: &DemScenario,
    tether: &[Point2<f64>],
    mu: f64,
    step: f64,
) -> Vec<StickingSample> {
    let frame = &d.ingested.frame;
    rappel_mechanics::sticking_profile::sticking_profile(&d.grid, frame, tether, mu, step)
}
