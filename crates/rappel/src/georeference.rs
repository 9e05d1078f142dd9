//! Where a scenario made from a DEM lies in the DEM's own coordinates (issue 16): the DEM file,
//! its coordinate reference system when the file declares one, and the planning frame (origin,
//! the uphill and across unit vectors in the DEM's `(east, north)` coordinates, and the unfolding
//! of the plane series along the fall line, `rappel_terrain::frame`). With it, any point of a plan
//! (tether, anchors, waypoints, paths) maps back onto the DEM, so results can be laid over it in
//! a GIS (`rappel_render::export`).

use nalgebra::Point2;
use rappel_terrain::frame::PlanningFrame;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// How far from unit length, or from orthogonal, the frame's axes may be (relative; they are
/// written by rappel as unit vectors, so only rounding separates them).
pub const AXIS_TOLERANCE: f64 = 1e-9;

/// A scenario's georeference (module docs).
///
/// ```
/// use rappel::dem::dem_scenario;
/// use rappel::terrain::ingest::IngestOptions;
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/terrain/mars_hirise_dteec_010228_1490_crop.asc");
/// let d = dem_scenario(path.as_ref(), &IngestOptions::default()).unwrap();
/// let g = d.scenario.georeference.as_ref().unwrap();
/// g.validate().unwrap();
/// // The start maps back inside the DEM's extent.
/// let w = g.to_world(&d.scenario.start);
/// let grid = d.grid.geometry();
/// assert!(w.x > grid.west && w.x < grid.east() && w.y > grid.south() && w.y < grid.north);
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Georeference {
    /// The DEM file the scenario was made from: relative to the scenario file's directory
    /// (what `rappel dem` writes, [`dem_relative_to`]) or absolute; [`Georeference::dem_path`]
    /// resolves it.
    pub dem: String,
    /// The DEM's coordinate reference system (`EPSG:n`, a WKT definition, or a user-defined
    /// system's citation); `None` when the file declares none.
    #[serde(default)]
    pub crs: Option<String>,
    /// The planning frame in the DEM's coordinates.
    pub frame: PlanningFrame,
}

impl Georeference {
    /// Checks the frame: finite origin, unit orthogonal axes (within [`AXIS_TOLERANCE`]), and
    /// unfolding pieces in increasing order with finite positive stretches.
    pub fn validate(&self) -> Result<(), String> {
        let f = &self.frame;
        let finite = |v: f64| v.is_finite();
        if !(finite(f.origin.x) && finite(f.origin.y)) {
            return Err("frame origin must be finite".into());
        }
        for (name, v) in [("uphill", f.uphill), ("across", f.across)] {
            if !(finite(v.x) && finite(v.y)) || (v.norm() - 1.0).abs() > AXIS_TOLERANCE {
                return Err(format!("frame {name} axis must be a unit vector"));
            }
        }
        if f.uphill.dot(&f.across).abs() > AXIS_TOLERANCE {
            return Err("frame axes must be orthogonal".into());
        }
        if f.pieces.is_empty() {
            return Err("frame needs at least one unfolding piece".into());
        }
        for (i, p) in f.pieces.iter().enumerate() {
            if !(finite(p.s_start) && finite(p.y_start) && finite(p.stretch) && p.stretch > 0.0) {
                return Err(format!(
                    "frame piece {i} must have finite values and stretch > 0"
                ));
            }
            if i > 0
                && !(p.s_start > f.pieces[i - 1].s_start && p.y_start > f.pieces[i - 1].y_start)
            {
                return Err(format!("frame piece {i} does not follow piece {}", i - 1));
            }
        }
        Ok(())
    }

    /// The DEM file of the scenario read from `scenario`: [`Georeference::dem`] when absolute,
    /// else joined to the scenario file's directory; a relative path that names no file there
    /// but does from the working directory (a scenario written before the DEM path was made
    /// relative to its file) is taken from the working directory.
    ///
    /// ```
    /// use std::path::Path;
    /// # let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/terrain/mars_hirise_dteec_010228_1490_crop.asc");
    /// # let d = rappel::dem::dem_scenario(path.as_ref(), &Default::default()).unwrap();
    /// let mut g = d.scenario.georeference.unwrap();
    /// g.dem = "dems/crater.asc".into();
    /// assert_eq!(g.dem_path(Path::new("/data/site/s.ron")), Path::new("/data/site/dems/crater.asc"));
    /// ```
    pub fn dem_path(&self, scenario: &Path) -> PathBuf {
        let dem = Path::new(&self.dem);
        if dem.is_absolute() {
            return dem.to_path_buf();
        }
        let beside = scenario.parent().unwrap_or(Path::new("")).join(dem);
        if !beside.exists() && dem.exists() {
            return dem.to_path_buf();
        }
        beside
    }

    /// The DEM coordinates `(east, north)` of planning-frame point `p`.
    pub fn to_world(&self, p: &Point2<f64>) -> Point2<f64> {
        self.frame.to_world(p)
    }
}

/// The path of `dem` as the scenario file `scenario` should record it: relative to the
/// scenario's directory (`../dems/crater.asc`), so the pair can be moved or read from any
/// working directory; absolute when either path cannot be resolved (a missing directory) or the
/// two share no root.
///
/// ```
/// use rappel::georeference::dem_relative_to;
/// let fixtures = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures");
/// let dem = format!("{fixtures}/terrain/mars_hirise_dteec_010228_1490_crop.asc");
/// let scenario = format!("{fixtures}/plan/out.ron");
/// assert_eq!(dem_relative_to(dem.as_ref(), scenario.as_ref()), "../terrain/mars_hirise_dteec_010228_1490_crop.asc");
/// ```
pub fn dem_relative_to(dem: &Path, scenario: &Path) -> String {
    let dir = match scenario.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let (Ok(dem), Ok(dir)) = (dem.canonicalize(), dir.canonicalize()) else {
        return std::path::absolute(dem)
            .unwrap_or_else(|_| dem.to_path_buf())
            .display()
            .to_string();
    };
    let (a, b): (Vec<_>, Vec<_>) = (dem.components().collect(), dir.components().collect());
    let common = a.iter().zip(&b).take_while(|(x, y)| x == y).count();
    if common == 0 {
        return dem.display().to_string();
    }
    let mut rel = PathBuf::new();
    for _ in common..b.len() {
        rel.push("..");
    }
    rel.extend(&a[common..]);
    rel.display().to_string()
}
