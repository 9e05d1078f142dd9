//! Potential tether friction obstacles from a DEM (thesis §3.1.1 and §3.4): [`label_ptfos`] adds
//! the convex patches [`rappel_mechanics::ptfo_detection`] finds on a scenario's DEM to its map
//! and a `friction` section to it, with the tether-terrain friction the caller supplies
//! (`rappel dem --ptfo-friction LO[,HI]`; the DEM cannot give it). The detection (curvature
//! classes, patches, hulls, height patches) is the mechanics crate's; this module only writes
//! its result into the scenario.

use crate::dem::DemScenario;
pub use crate::dem::PtfoLabels;
use crate::ptfo_spec::{FrictionRange, FrictionSpec, PtfoSpec};
use rappel_mechanics::ptfo_detection::{DetectionError, DetectionOptions, detect_ptfos};
use rappel_mechanics::ptfo_surface::PtfoSurface;

pub use rappel_mechanics::ptfo_detection::MAX_PTFOS;

/// How to label PTFOs: the friction the DEM cannot give, and the detection's thresholds (see
/// [`DetectionOptions`] for each).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PtfoLabelOptions {
    /// Tether-terrain friction of every PTFO.
    pub friction: FrictionRange,
    /// Flatness tolerance of the convexity test, 1/m; `None`: the default per cell size.
    pub min_curvature: Option<f64>,
    /// Fewest cells of a patch (>= 1).
    pub min_cells: usize,
    /// Also label saddle cells that are convex along the fall line.
    pub saddles: bool,
}

impl PtfoLabelOptions {
    /// Options with the given friction and default thresholds.
    pub fn with_friction(friction: FrictionRange) -> Self {
        let DetectionOptions {
            min_curvature,
            min_cells,
            saddles,
        } = DetectionOptions::default();
        PtfoLabelOptions {
            friction,
            min_curvature,
            min_cells,
            saddles,
        }
    }
}

/// Why labelling failed as a whole.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PtfoLabelError {
    /// An option out of range.
    #[error("PTFO labelling: {0}")]
    Options(String),
    /// The scenario already has a friction section.
    #[error("the scenario already has a friction section")]
    HasFriction,
}

/// Labels the convex patches of `d`'s DEM as PTFOs, adding them to its map and a `friction`
/// section to its scenario (tensions derived from the robot, thesis §3.4.1).
///
/// ```
/// use rappel::dem::dem_scenario;
/// use rappel::dem_ptfo::{label_ptfos, PtfoLabelOptions};
/// use rappel::ptfo_spec::FrictionRange;
/// use rappel::terrain::ingest::IngestOptions;
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/terrain/mars_hirise_dteec_010228_1490_crop.asc");
/// let mut d = dem_scenario(path.as_ref(), &IngestOptions::default()).unwrap();
/// let geometric = d.scenario.map.obstacles.len();
/// let opts = PtfoLabelOptions::with_friction(FrictionRange { lo: 0.4, hi: 0.6 });
/// let labels = label_ptfos(&mut d, &opts).unwrap();
/// assert_eq!(d.scenario.map.obstacles.len(), geometric + labels.ptfos);
/// d.scenario.validate().unwrap();
/// ```
pub fn label_ptfos(
    d: &mut DemScenario,
    o: &PtfoLabelOptions,
) -> Result<PtfoLabels, PtfoLabelError> {
    let options = |e: DetectionError| PtfoLabelError::Options(e.0);
    let (min_curvature, min_cells, saddles) = (o.min_curvature, o.min_cells, o.saddles);
    let detection = DetectionOptions {
        min_curvature,
        min_cells,
        saddles,
    };
    detection.validate().map_err(options)?;
    let FrictionRange { lo, hi } = o.friction;
    if !(lo.is_finite() && hi.is_finite() && 0.0 < lo && lo <= hi) {
        return Err(PtfoLabelError::Options(format!(
            "tether-terrain friction {lo}..{hi} must satisfy 0 < lo <= hi"
        )));
    }
    if d.scenario.friction.is_some() {
        return Err(PtfoLabelError::HasFriction);
    }
    let (i, map) = (&d.ingested, &mut d.scenario.map);
    let found = detect_ptfos(&d.grid, &i.frame, &i.plane_fits, map, &detection);
    let found = found.map_err(options)?;
    d.ptfo_cells = found.ptfos.iter().map(|p| p.patch.clone()).collect();
    let ptfos: Vec<PtfoSpec> = found
        .ptfos
        .into_iter()
        .map(|p| {
            map.obstacles.push(p.hull);
            PtfoSpec {
                obstacle: map.obstacles.len() - 1,
                surface: PtfoSurface::HeightField(p.surface),
                friction: o.friction,
            }
        })
        .collect();
    let labels = PtfoLabels {
        convex_cells: found.convex_cells,
        saddle_cells: found.saddle_cells,
        patches: found.patches,
        ptfos: ptfos.len(),
        cells: d.ptfo_cells.iter().map(Vec::len).collect(),
        dropped: found.dropped,
    };
    if !ptfos.is_empty() {
        let (tensions, geometric_friction, holding) = (Default::default(), 0.0, None);
        d.scenario.friction = Some(FrictionSpec {
            ptfos,
            tensions,
            geometric_friction,
            holding,
        });
    }
    Ok(labels)
}
