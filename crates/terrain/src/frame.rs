//! The unfolded planning frame of a DEM (thesis §2.1.2, Fig. 2.3): the transform from world
//! coordinates `(east, north)` of the grid to the planar map frame of
//! [`crate::plane_series`], where `x` runs across the slope and `y` up it, so that the fall
//! line is `-y`.
//!
//! Construction, in two steps:
//! 1. a rotation: `s = (p - origin) . uphill` is the horizontal distance up the fall line and
//!    `t = (p - origin) . across` the horizontal distance across it, with `across` the uphill
//!    direction turned 90 degrees clockwise (so `(t, s)` is right-handed, like east/north);
//! 2. the isometric unfolding of the plane series: along the fall line each plane `i`, inclined at
//!    `eta_i`, stretches horizontal distance by `1 / cos eta_i`, so `y(s)` is the piecewise-linear
//!    distance *along the ground* from the bottom of the strip, and `x = t`. On each plane, whose
//!    strike runs along `x`, this is exactly an isometry; across plane edges it is the standard
//!    unfolding of a developable strip.
//!
//! The map region of a grid is its *sampled footprint*: the rectangle through the centres of the
//! outer cells, where the heights are known (cells extend half a cell beyond it). The origin is
//! placed so that the sampled footprint has `t >= 0` and `s >= 0`, touching both. Keeping the
//! boundary half a cell inside the cells' outer edges also keeps it clear of the cell corners that
//! obstacle hulls are made of, so hulls at the edge cross it cleanly.

use nalgebra::{Point2, Vector2};
use serde::{Deserialize, Serialize};

use crate::grid::GridGeometry;
use crate::slope::FallLine;

/// One piece of the unfolding: from horizontal distance `s_start` up to the next piece's start,
/// `y = y_start + (s - s_start) * stretch`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct UnfoldPiece {
    /// Where the piece starts, horizontal metres up the fall line.
    pub s_start: f64,
    /// Unfolded `y` at `s_start`.
    pub y_start: f64,
    /// Ground distance per horizontal distance: `1 / cos(eta)` of the plane (`>= 1`).
    pub stretch: f64,
}

/// The transform between world coordinates and the unfolded planning frame (see the module docs).
///
/// ```
/// use nalgebra::Point2;
/// use rappel_terrain::frame::PlanningFrame;
/// use rappel_terrain::slope::FallLine;
/// // Downhill to the south: uphill is north, across is east.
/// let f = PlanningFrame::new(&FallLine::from_azimuth(180.0).unwrap(), Point2::new(100.0, 50.0));
/// let p = f.to_planning(&Point2::new(103.0, 54.0));
/// assert!((p - Point2::new(3.0, 4.0)).norm() < 1e-12);
/// assert!((f.to_world(&p) - Point2::new(103.0, 54.0)).norm() < 1e-12);
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct PlanningFrame {
    /// Unit horizontal vector up the fall line (world components).
    #[schemars(with = "[f64; 2]")]
    pub uphill: Vector2<f64>,
    /// Unit horizontal vector across the slope: `uphill` turned 90 degrees clockwise.
    #[schemars(with = "[f64; 2]")]
    pub across: Vector2<f64>,
    /// The world point at `t = 0`, `s = 0`.
    #[schemars(with = "[f64; 2]")]
    pub origin: Point2<f64>,
    /// The unfolding, by increasing `s_start`; the first piece also extends below its start and
    /// the last above. Never empty.
    pub pieces: Vec<UnfoldPiece>,
}

impl PlanningFrame {
    /// A frame for the given fall line and origin, without unfolding (`y = s`).
    pub fn new(fall_line: &FallLine, origin: Point2<f64>) -> Self {
        let uphill = -fall_line.downhill;
        PlanningFrame {
            uphill,
            across: Vector2::new(uphill.y, -uphill.x),
            origin,
            pieces: vec![UnfoldPiece {
                s_start: 0.0,
                y_start: 0.0,
                stretch: 1.0,
            }],
        }
    }

    /// A frame for the grid `g`: its origin puts the sampled footprint at `t >= 0`, `s >= 0`.
    pub fn for_grid(g: &GridGeometry, fall_line: &FallLine) -> Self {
        let mut f = PlanningFrame::new(fall_line, Point2::origin());
        let (mut t_min, mut s_min) = (f64::INFINITY, f64::INFINITY);
        for c in g.sample_corners() {
            let (t, s) = f.horizontal(&c);
            t_min = t_min.min(t);
            s_min = s_min.min(s);
        }
        f.origin = Point2::origin() + f.across * t_min + f.uphill * s_min;
        f
    }

    /// This frame with the unfolding of planes given bottom first as `(s_bottom, slope_deg)`:
    /// plane `i` covers `s` from its `s_bottom` to the next plane's; the lowest plane's `s_bottom`
    /// is unfolded to `y = 0`.
    ///
    /// ```
    /// use nalgebra::Point2;
    /// use rappel_terrain::frame::PlanningFrame;
    /// use rappel_terrain::slope::FallLine;
    /// let f = PlanningFrame::new(&FallLine::from_azimuth(180.0).unwrap(), Point2::origin())
    ///     .unfolded(&[(0.0, 60.0), (10.0, 0.0)]);
    /// // 10 m of horizontal run at 60 degrees is 20 m of ground.
    /// assert!((f.unfold(10.0) - 20.0).abs() < 1e-12);
    /// assert!((f.unfold(15.0) - 25.0).abs() < 1e-12);
    /// assert!((f.fold(25.0) - 15.0).abs() < 1e-12);
    /// ```
    pub fn unfolded(&self, planes_bottom_up: &[(f64, f64)]) -> Self {
        let mut pieces = Vec::with_capacity(planes_bottom_up.len());
        let mut y = 0.0;
        for (i, &(s_start, slope_deg)) in planes_bottom_up.iter().enumerate() {
            if i > 0 {
                let prev: &UnfoldPiece = &pieces[i - 1];
                y = prev.y_start + (s_start - prev.s_start) * prev.stretch;
            }
            pieces.push(UnfoldPiece {
                s_start,
                y_start: y,
                stretch: 1.0 / slope_deg.to_radians().cos(),
            });
        }
        if pieces.is_empty() {
            pieces = self.pieces.clone();
        }
        PlanningFrame {
            pieces,
            ..self.clone()
        }
    }

    /// `(t, s)`: horizontal distances across and up the fall line from the origin.
    pub fn horizontal(&self, world: &Point2<f64>) -> (f64, f64) {
        let d = world - self.origin;
        (d.dot(&self.across), d.dot(&self.uphill))
    }

    /// Index of the piece that holds horizontal distance `s`.
    pub fn piece_index(&self, s: f64) -> usize {
        self.pieces
            .partition_point(|p| p.s_start <= s)
            .saturating_sub(1)
    }

    /// Unfolded `y` of horizontal distance `s`.
    pub fn unfold(&self, s: f64) -> f64 {
        let p = &self.pieces[self.piece_index(s)];
        p.y_start + (s - p.s_start) * p.stretch
    }

    /// Horizontal distance `s` of unfolded `y` (the inverse of [`PlanningFrame::unfold`]).
    pub fn fold(&self, y: f64) -> f64 {
        let i = self
            .pieces
            .partition_point(|p| p.y_start <= y)
            .saturating_sub(1);
        let p = &self.pieces[i];
        p.s_start + (y - p.y_start) / p.stretch
    }

    /// The planning-frame point of a world point.
    pub fn to_planning(&self, world: &Point2<f64>) -> Point2<f64> {
        let (t, s) = self.horizontal(world);
        Point2::new(t, self.unfold(s))
    }

    /// The world point of a planning-frame point (the inverse of [`PlanningFrame::to_planning`]).
    pub fn to_world(&self, p: &Point2<f64>) -> Point2<f64> {
        self.origin + self.across * p.x + self.uphill * self.fold(p.y)
    }

    /// Compass azimuth of the fall line (downhill), degrees clockwise from north.
    pub fn fall_line_azimuth_deg(&self) -> f64 {
        FallLine {
            downhill: -self.uphill,
            mean_slope_deg: f64::NAN,
        }
        .azimuth_deg()
    }

    /// The world segment where the line `s = const` crosses the grid's footprint, if it does
    /// (to draw plane edges over a map of the grid).
    pub fn level_line_in_grid(&self, g: &GridGeometry, s: f64) -> Option<[Point2<f64>; 2]> {
        // Parametrise the line as origin + uphill * s + across * t and clip t to the rectangle
        // (Liang-Barsky).
        let base = self.origin + self.uphill * s;
        let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
        for (p, d, min, max) in [
            (base.x, self.across.x, g.west, g.east()),
            (base.y, self.across.y, g.south(), g.north),
        ] {
            if d.abs() < 1e-15 {
                if p < min || p > max {
                    return None;
                }
            } else {
                let (a, b) = ((min - p) / d, (max - p) / d);
                lo = lo.max(a.min(b));
                hi = hi.min(a.max(b));
            }
        }
        (lo < hi).then(|| [base + self.across * lo, base + self.across * hi])
    }

    /// The grid's sampled footprint (see the module docs) in the planning frame,
    /// counter-clockwise, with a vertex wherever an edge of it crosses a plane edge (so that the
    /// unfolded outline is exact).
    pub fn footprint(&self, g: &GridGeometry) -> Vec<Point2<f64>> {
        let corners = g.sample_corners();
        let mut out = Vec::new();
        for i in 0..4 {
            let (a, b) = (corners[i], corners[(i + 1) % 4]);
            out.push(self.to_planning(&a));
            let (sa, sb) = (self.horizontal(&a).1, self.horizontal(&b).1);
            let mut breaks: Vec<f64> = self
                .pieces
                .iter()
                .skip(1)
                .map(|p| p.s_start)
                .filter(|&s| (s > sa.min(sb)) && (s < sa.max(sb)))
                .collect();
            if sb < sa {
                breaks.reverse();
            }
            for s in breaks {
                let lambda = (s - sa) / (sb - sa);
                let w = a + (b - a) * lambda;
                let (t, _) = self.horizontal(&w);
                out.push(Point2::new(t, self.unfold(s)));
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_is_right_handed_and_round_trips() {
        for az in [0.0, 37.0, 90.0, 200.0, 311.0] {
            let fl = FallLine::from_azimuth(az).unwrap();
            let f = PlanningFrame::new(&fl, Point2::new(5.0, -3.0)).unfolded(&[
                (-10.0, 20.0),
                (0.0, 35.0),
                (12.5, 50.0),
            ]);
            // Cross product across x uphill = +1 (counter-clockwise from x to y).
            assert!((f.across.x * f.uphill.y - f.across.y * f.uphill.x - 1.0).abs() < 1e-12);
            for w in [
                Point2::new(0.0, 0.0),
                Point2::new(40.0, -7.0),
                Point2::new(-3.0, 22.0),
            ] {
                let back = f.to_world(&f.to_planning(&w));
                assert!((back - w).norm() < 1e-9, "{az} {w} {back}");
            }
            assert!((f.fall_line_azimuth_deg() - az).abs() < 1e-9);
        }
    }

    #[test]
    fn unfolding_measures_ground_distance() {
        let f = PlanningFrame::new(&FallLine::from_azimuth(180.0).unwrap(), Point2::origin())
            .unfolded(&[(0.0, 45.0), (10.0, 30.0)]);
        // Ground distance of 10 m horizontal at 45 degrees, then 5 m at 30 degrees.
        let expect = 10.0 * 2f64.sqrt() + 5.0 / 30f64.to_radians().cos();
        assert!((f.unfold(15.0) - expect).abs() < 1e-12);
        assert_eq!(f.unfold(0.0), 0.0);
    }

    #[test]
    fn footprint_is_counter_clockwise_with_breaks() {
        let g = GridGeometry::new(10, 20, 1.0, 1.0, 0.0, 10.0).unwrap();
        let fl = FallLine::from_azimuth(200.0).unwrap();
        let f = PlanningFrame::for_grid(&g, &fl).unfolded(&[(0.0, 10.0), (4.0, 40.0)]);
        let fp = f.footprint(&g);
        let poly = rappel_geometry::polygon::Polygon::new(fp.clone());
        assert!(poly.is_counter_clockwise());
        // 4 corners plus two crossings of the break line s = 4.
        assert_eq!(fp.len(), 6);
        let (xmin, ymin) = fp.iter().fold((f64::INFINITY, f64::INFINITY), |(a, b), p| {
            (a.min(p.x), b.min(p.y))
        });
        assert!(xmin.abs() < 1e-9 && ymin.abs() < 1e-9);
        let seg = f.level_line_in_grid(&g, 4.0).unwrap();
        for p in seg {
            assert!((f.horizontal(&p).1 - 4.0).abs() < 1e-9);
        }
        assert!(f.level_line_in_grid(&g, -1.0).is_none());
    }
}
