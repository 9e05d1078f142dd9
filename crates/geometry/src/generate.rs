//! Random crater-wall maps for tests, benchmarks and `rappel gen-map`: a long strip (the wall, `y`
//! up the slope) strewn with non-overlapping convex obstacles of varied size, reproducible from a
//! seed on every platform (ChaCha8).
//!
//! Obstacle radii are log-uniform between [`CraterStripOptions::min_radius`] and
//! [`CraterStripOptions::max_radius`], so small rocks outnumber boulders as on real slopes. The
//! strip's length grows with the obstacle count to keep the density fixed, and obstacle-free bands
//! at the top and bottom hold the start (top) and goal (bottom).

use crate::map::Map;
use crate::polygon::{Aabb, Polygon, convex_hull};
use crate::spatial_grid::SpatialGrid;
use nalgebra::Point2;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

/// Parameters of a generated crater strip.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CraterStripOptions {
    /// Number of obstacles.
    pub obstacles: usize,
    /// RNG seed.
    pub seed: u64,
    /// Strip width across the slope, metres.
    pub width: f64,
    /// Smallest obstacle radius, metres.
    pub min_radius: f64,
    /// Largest obstacle radius, metres.
    pub max_radius: f64,
    /// Free ground per obstacle, square metres (sets the strip's length).
    pub area_per_obstacle: f64,
    /// Minimum gap between two obstacles, metres.
    pub clearance: f64,
}

impl CraterStripOptions {
    /// Defaults for `n` obstacles from `seed`: a 200 m wide strip, radii 0.5-4 m, 150 m² per
    /// obstacle, 0.5 m clearance.
    ///
    /// ```
    /// use rappel_geometry::generate::{crater_strip, CraterStripOptions};
    /// let g = crater_strip(&CraterStripOptions::new(50, 7)).unwrap();
    /// assert_eq!(g.map.obstacles.len(), 50);
    /// g.map.validate().unwrap();
    /// assert_eq!(g, crater_strip(&CraterStripOptions::new(50, 7)).unwrap());
    /// let mut wide = CraterStripOptions::new(5, 1);
    /// wide.width = 1e308;
    /// assert!(crater_strip(&wide).is_err());
    /// ```
    pub fn new(obstacles: usize, seed: u64) -> Self {
        CraterStripOptions {
            obstacles,
            seed,
            width: 200.0,
            min_radius: 0.5,
            max_radius: 4.0,
            area_per_obstacle: 150.0,
            clearance: 0.5,
        }
    }
}

/// Why generation options were refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GenerateError {
    /// A parameter is out of range; the message names it and the accepted range.
    #[error("crater strip: {0}")]
    Option(String),
    /// A star obstacle's parameter is out of range (`rappel::generated::star_scenario`); the
    /// message names it and the accepted range.
    #[error("star: {0}")]
    Star(String),
}

/// Largest strip width accepted, metres (a crater wall, not a continent).
pub const MAX_WIDTH: f64 = 1.0e6;
/// Largest obstacle count accepted.
pub const MAX_OBSTACLES: usize = 2_000_000;

impl CraterStripOptions {
    /// Checks every parameter: finite; radii `0 < min_radius <= max_radius`; clearance `>= 0`;
    /// `area_per_obstacle` larger than the biggest obstacle's footprint with its clearance (so the
    /// requested count always fits); the width room for the biggest obstacle and at most
    /// [`MAX_WIDTH`]; at most [`MAX_OBSTACLES`] obstacles.
    pub fn validate(&self) -> Result<(), GenerateError> {
        let bad = |m: String| Err(GenerateError::Option(m));
        for (name, v) in [
            ("width", self.width),
            ("min_radius", self.min_radius),
            ("max_radius", self.max_radius),
            ("area_per_obstacle", self.area_per_obstacle),
            ("clearance", self.clearance),
        ] {
            if !v.is_finite() {
                return bad(format!("{name} = {v:?} must be finite"));
            }
        }
        if !(self.min_radius > 0.0 && self.min_radius <= self.max_radius) {
            return bad(format!(
                "radii must satisfy 0 < min_radius ({}) <= max_radius ({})",
                self.min_radius, self.max_radius
            ));
        }
        if self.clearance < 0.0 {
            return bad(format!("clearance = {} must be >= 0", self.clearance));
        }
        let reach = 2.0 * self.max_radius + self.clearance;
        if self.area_per_obstacle < reach * reach {
            return bad(format!(
                "area_per_obstacle = {} must be at least (2 max_radius + clearance)^2 = {}",
                self.area_per_obstacle,
                reach * reach
            ));
        }
        if !(self.width >= 2.0 * reach && self.width <= MAX_WIDTH) {
            return bad(format!(
                "width = {:?} must be between {} and {MAX_WIDTH} m",
                self.width,
                2.0 * reach
            ));
        }
        if self.obstacles > MAX_OBSTACLES {
            return bad(format!(
                "{} obstacles: at most {MAX_OBSTACLES}",
                self.obstacles
            ));
        }
        Ok(())
    }
}

/// A generated map with a start at the top and a goal at the bottom.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GeneratedMap {
    /// The map.
    pub map: Map,
    /// Start point (top of the strip).
    pub start: Point2<f64>,
    /// Goal point (bottom of the strip).
    pub goal: Point2<f64>,
}

/// Height of the obstacle-free bands at the top and bottom, metres.
const END_BAND: f64 = 10.0;

/// Generates a crater strip (options checked by [`CraterStripOptions::validate`]). The map is
/// always valid; obstacles are placed by rejection sampling, and the strip is long enough that the
/// requested count always fits.
pub fn crater_strip(o: &CraterStripOptions) -> Result<GeneratedMap, GenerateError> {
    o.validate()?;
    let mut rng = ChaCha8Rng::seed_from_u64(o.seed);
    let length = (o.obstacles as f64 * o.area_per_obstacle / o.width).max(o.width) + 2.0 * END_BAND;
    let boundary = Polygon::new(vec![
        Point2::new(0.0, 0.0),
        Point2::new(o.width, 0.0),
        Point2::new(o.width, length),
        Point2::new(0.0, length),
    ]);
    let reach = 2.0 * o.max_radius + o.clearance;
    let bounds = Aabb {
        min: Point2::new(0.0, 0.0),
        max: Point2::new(o.width, length),
    };
    let cells = ((o.width * length) / (reach * reach)).min(1e9) as usize;
    let mut grid = SpatialGrid::new(bounds, cells.saturating_add(1));
    let mut discs: Vec<(Point2<f64>, f64)> = Vec::with_capacity(o.obstacles);
    let mut obstacles = Vec::with_capacity(o.obstacles);
    let margin = o.max_radius + o.clearance;
    let (lo, hi) = (o.min_radius.ln(), o.max_radius.ln());
    while obstacles.len() < o.obstacles {
        let r = rng.random_range(lo..=hi).exp();
        let c = Point2::new(
            rng.random_range(margin..o.width - margin),
            rng.random_range(END_BAND + margin..length - END_BAND - margin),
        );
        // Cells are about `reach` wide, so every disc that could be too close sits within two
        // rings of cells around the centre.
        let clear = (0..=2)
            .filter_map(|k| grid.ring_around(&c, k))
            .flatten()
            .all(|j| {
                let (cj, rj) = discs[j as usize];
                (cj - c).norm() >= r + rj + o.clearance
            });
        if !clear {
            continue;
        }
        let sides = rng.random_range(3..=8usize);
        let mut angles: Vec<f64> = (0..sides)
            .map(|_| rng.random_range(0.0..std::f64::consts::TAU))
            .collect();
        angles.sort_by(f64::total_cmp);
        let pts: Vec<Point2<f64>> = angles
            .iter()
            .map(|a| {
                let rr = r * rng.random_range(0.6..=1.0);
                Point2::new(c.x + rr * a.cos(), c.y + rr * a.sin())
            })
            .collect();
        let hull = convex_hull(&pts);
        if hull.len() < 3 || hull.is_degenerate() {
            continue;
        }
        grid.insert(&Aabb { min: c, max: c }, discs.len() as u32);
        discs.push((c, r));
        obstacles.push(hull);
    }
    Ok(GeneratedMap {
        map: Map::new(boundary, obstacles),
        start: Point2::new(o.width / 2.0, length - END_BAND / 2.0),
        goal: Point2::new(o.width / 2.0, END_BAND / 2.0),
    })
}
