//! Plane fitting (thesis §2.1.2, Fig. 2.2-2.3): approximating a crater-wall strip by a convex
//! series of planes down the fall line, "sections of relatively constant slope ... at angles
//! eta_1, ..., eta_np", progressively steeper going down.
//!
//! Method (bottom-up segmentation of the fall-line profile):
//! 1. In the horizontal frame `(t, s)` of [`crate::frame`] (`s` up the fall line), the
//!    known cells are cut into bands of equal width along `s`.
//! 2. Each band gets the least-squares plane `z = a + b s + c t`; `b` is the gradient along the fall
//!    line, `c` across it. Fits are kept as sufficient statistics (sums of products), so the fit of
//!    the union of two bands, and its residual, cost O(1).
//! 3. Bands with fewer than [`MIN_CELLS_PER_PLANE`] cells, or whose cells are collinear, are merged
//!    into a neighbour first.
//! 4. The *merge residual* of two neighbouring segments is the RMS, over their cells, of the height
//!    difference between their two planes and the single plane fitted to both. Least squares make
//!    it exact and cheap: since one plane is a special case of two, Pythagoras gives
//!    `SSE(merged) = SSE(lower) + SSE(upper) + n * merge_residual^2`. Unlike the merged plane's own
//!    residual, it does not count the terrain's roughness (which no plane removes), only the
//!    change of slope that merging hides: a hinge of gradient change `dg` at the middle of a run of
//!    length `L` has a merge residual of `dg L / (8 sqrt 3)`. Repeatedly, the neighbours with the
//!    smallest merge residual are merged, while it is at most the tolerance
//!    ([`DEFAULT_PLANE_MERGE_TOLERANCE_M`] by default).
//! 5. Convexity (thesis §2.1.2: the algorithms hold for "a series of progressively-steeper
//!    tether-demand planes which form a convex surface"; a shallower plane below a steeper one lets
//!    the taut tether lift off): while some plane is shallower than the plane above it, the
//!    violating pair with the smallest merge residual is merged, whatever the residual (the
//!    pool-adjacent-violators step of isotonic regression). The number of such merges is reported.
//!
//! Each plane's slope is its inclination along the fall line, `eta = atan |b|`; the cross gradient
//! `c` and the full inclination are reported beside it.

use serde::{Deserialize, Serialize};

use crate::frame::PlanningFrame;
use crate::grid::HeightGrid;
use crate::least_squares::{LsqPlane, PlaneStats};

/// Default width of the bands, in cells (of the larger cell size).
pub const DEFAULT_BAND_CELLS: f64 = 10.0;

/// Default tolerance on the merge residual (see the module docs), metres: neighbouring planes are
/// merged while one plane stays within this RMS of the two. Half a metre is a quarter of the
/// thesis' `H_max`: merging moves the modelled ground by much less than an obstacle's height.
pub const DEFAULT_PLANE_MERGE_TOLERANCE_M: f64 = 0.5;

/// Fewest known cells a plane is fitted to; smaller bands are merged into a neighbour first.
pub const MIN_CELLS_PER_PLANE: usize = 6;

/// How to segment the strip.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PlaneFitOptions {
    /// Band width along the fall line, horizontal metres; `None`: [`DEFAULT_BAND_CELLS`] cells.
    pub band_width_m: Option<f64>,
    /// Largest merge residual (metres, see the module docs) of two planes merged into one.
    /// Default [`DEFAULT_PLANE_MERGE_TOLERANCE_M`].
    pub merge_tolerance_m: f64,
    /// Merge planes until the series is convex (each plane at least as steep as the one above).
    /// Default `true`.
    pub enforce_convexity: bool,
}

impl Default for PlaneFitOptions {
    fn default() -> Self {
        PlaneFitOptions {
            band_width_m: None,
            merge_tolerance_m: DEFAULT_PLANE_MERGE_TOLERANCE_M,
            enforce_convexity: true,
        }
    }
}

/// Why no plane series could be fitted.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PlaneFitError {
    /// A band width that is not a positive finite number.
    #[error("band width {} m must be positive and finite", rappel_geometry::compact::Compact(*.0))]
    BadBandWidth(f64),
    /// A merge tolerance that is negative or not finite.
    #[error("merge tolerance {} m must be finite and >= 0", rappel_geometry::compact::Compact(*.0))]
    BadTolerance(f64),
    /// Too few known cells, or all on one line, to fit any plane.
    #[error(
        "cannot fit a plane: {known} known cells, not spread over two directions (at least {MIN_CELLS_PER_PLANE} are needed)"
    )]
    TooFewCells {
        /// Known cells.
        known: usize,
    },
}

impl PlaneFitOptions {
    /// Checks the options.
    pub fn validate(&self) -> Result<(), PlaneFitError> {
        if let Some(w) = self.band_width_m
            && !(w.is_finite() && w > 0.0)
        {
            return Err(PlaneFitError::BadBandWidth(w));
        }
        if !(self.merge_tolerance_m.is_finite() && self.merge_tolerance_m >= 0.0) {
            return Err(PlaneFitError::BadTolerance(self.merge_tolerance_m));
        }
        Ok(())
    }
}

/// One fitted plane of the series, `z = height_at_origin + fall_line_gradient * s +
/// cross_gradient * t` over `s_bottom <= s <= s_top`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FittedPlane {
    /// Lower edge, horizontal metres up the fall line.
    pub s_bottom: f64,
    /// Upper edge.
    pub s_top: f64,
    /// The plane's height at `t = 0`, `s = 0`.
    pub height_at_origin: f64,
    /// `dz/ds`: positive when the ground rises uphill, as it should.
    pub fall_line_gradient: f64,
    /// `dz/dt`.
    pub cross_gradient: f64,
    /// RMS of the cells' heights about the plane, metres.
    pub rms_residual_m: f64,
    /// Known cells fitted.
    pub cell_count: usize,
}

impl FittedPlane {
    /// The plane's height at horizontal position `(t, s)`.
    pub fn height(&self, t: f64, s: f64) -> f64 {
        self.height_at_origin + self.fall_line_gradient * s + self.cross_gradient * t
    }

    /// Inclination along the fall line, degrees in `[0, 90)`: the thesis' `eta`.
    pub fn slope_deg(&self) -> f64 {
        self.fall_line_gradient.abs().atan().to_degrees()
    }

    /// Inclination of the fitted plane itself (fall-line and cross gradients together), degrees.
    pub fn inclination_deg(&self) -> f64 {
        self.fall_line_gradient
            .hypot(self.cross_gradient)
            .atan()
            .to_degrees()
    }
}

/// The fitted series, top first, and how it was obtained.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlaneSeriesFit {
    /// The planes, top of the wall first; consecutive planes share an edge (`s_bottom` of one is
    /// `s_top` of the next).
    pub planes: Vec<FittedPlane>,
    /// Number of bands the strip was cut into.
    pub band_count: usize,
    /// Merges made to restore convexity beyond the residual tolerance.
    pub convexity_merges: usize,
}

/// A run of consecutive bands being merged.
#[derive(Debug, Clone, Copy)]
struct Segment {
    s_bottom: f64,
    s_top: f64,
    stats: PlaneStats,
    fit: Option<LsqPlane>,
}

/// The fit of `stats` when it has enough cells (in `(t, s)` order: `u = s`, `v = t`).
fn fit_of(stats: &PlaneStats) -> Option<LsqPlane> {
    (stats.count() >= MIN_CELLS_PER_PLANE)
        .then(|| stats.fit())
        .flatten()
}

impl Segment {
    fn merged(&self, upper: &Segment) -> Segment {
        let stats = self.stats.merged(&upper.stats);
        Segment {
            s_bottom: self.s_bottom,
            s_top: upper.s_top,
            stats,
            fit: fit_of(&stats),
        }
    }
}

/// Merges segments `i` and `i + 1` (bottom-up order).
fn merge_at(segs: &mut Vec<Segment>, i: usize) {
    let m = segs[i].merged(&segs[i + 1]);
    segs[i] = m;
    segs.remove(i + 1);
}

/// Sum of squared residuals of a segment's fit (infinite without a fit).
fn sse(seg: &Segment) -> f64 {
    seg.fit
        .map_or(f64::INFINITY, |f| f.rms * f.rms * seg.stats.count() as f64)
}

/// The merge residual of segments `lower` and `upper` (see the module docs); infinite when either
/// or the merged segment has no fit.
fn merge_residual(lower: &Segment, upper: &Segment) -> f64 {
    let m = lower.merged(upper);
    let extra = sse(&m) - sse(lower) - sse(upper);
    if extra.is_nan() {
        f64::INFINITY
    } else {
        (extra.max(0.0) / m.stats.count() as f64).sqrt()
    }
}

/// The pair `(i, i + 1)` among those accepted by `eligible` with the smallest merge residual.
fn cheapest_pair(
    segs: &[Segment],
    eligible: impl Fn(&Segment, &Segment) -> bool,
) -> Option<(usize, f64)> {
    let mut best: Option<(usize, f64)> = None;
    for i in 0..segs.len().saturating_sub(1) {
        if !eligible(&segs[i], &segs[i + 1]) {
            continue;
        }
        let cost = merge_residual(&segs[i], &segs[i + 1]);
        if best.is_none_or(|(_, c)| cost < c) {
            best = Some((i, cost));
        }
    }
    best
}

/// Fits the convex plane series of `dem` along the fall line of `frame` (see the module docs).
///
/// ```
/// use rappel_terrain::grid::GridGeometry;
/// use rappel_terrain::frame::PlanningFrame;
/// use rappel_terrain::plane_fit::{fit_plane_series, PlaneFitOptions};
/// use rappel_terrain::slope::FallLine;
/// use rappel_terrain::synthetic::{plane_series_dem, ProfilePlane};
/// // 40 m (horizontal) at 20 degrees above 40 m at 35 degrees, falling to the south.
/// let g = GridGeometry::new(80, 30, 1.0, 1.0, 0.0, 80.0).unwrap();
/// let planes = [ProfilePlane::new(40.0, 20.0), ProfilePlane::new(40.0, 35.0)];
/// let south = FallLine::from_azimuth(180.0).unwrap();
/// let dem = plane_series_dem(g, &south, 500.0, &planes).unwrap();
/// let frame = PlanningFrame::for_grid(&g, &south);
/// let fit = fit_plane_series(&dem, &frame, &PlaneFitOptions::default()).unwrap();
/// assert_eq!(fit.planes.len(), 2);
/// assert!((fit.planes[0].slope_deg() - 20.0).abs() < 1e-6);
/// assert!((fit.planes[1].slope_deg() - 35.0).abs() < 1e-6);
/// ```
pub fn fit_plane_series(
    dem: &HeightGrid,
    frame: &PlanningFrame,
    options: &PlaneFitOptions,
) -> Result<PlaneSeriesFit, PlaneFitError> {
    options.validate()?;
    let g = dem.geometry();
    let width = options
        .band_width_m
        .unwrap_or(DEFAULT_BAND_CELLS * g.cell_size());
    // The bands span the sampled footprint (cell centres), which the map covers.
    let (mut s_lo, mut s_hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for c in g.sample_corners() {
        let s = frame.horizontal(&c).1;
        s_lo = s_lo.min(s);
        s_hi = s_hi.max(s);
    }
    let band_count = (((s_hi - s_lo) / width).ceil() as usize).clamp(1, g.len());
    // The reference point: the grid's centre, at the mean height.
    let centre = g.cell_center(g.nrows / 2, g.ncols / 2);
    let (t0, s0) = frame.horizontal(&centre);
    let z0 = dem.height_range().map_or(0.0, |(lo, hi)| 0.5 * (lo + hi));

    let mut segs: Vec<Segment> = (0..band_count)
        .map(|k| Segment {
            s_bottom: if k == 0 {
                s_lo
            } else {
                s_lo + k as f64 * width
            },
            s_top: if k + 1 == band_count {
                s_hi
            } else {
                s_lo + (k + 1) as f64 * width
            },
            stats: PlaneStats::default(),
            fit: None,
        })
        .collect();
    let mut known = 0usize;
    for row in 0..g.nrows {
        for col in 0..g.ncols {
            let Some(z) = dem.height(row, col) else {
                continue;
            };
            known += 1;
            let (t, s) = frame.horizontal(&g.cell_center(row, col));
            let k = (((s - s_lo) / width).floor().max(0.0) as usize).min(band_count - 1);
            segs[k].stats.add(s - s0, t - t0, z - z0);
        }
    }
    for seg in &mut segs {
        seg.fit = fit_of(&seg.stats);
    }

    // Step 3: bands that cannot be fitted join a neighbour (the one giving the better fit).
    while let Some(i) = segs.iter().position(|s| s.fit.is_none()) {
        if segs.len() == 1 {
            return Err(PlaneFitError::TooFewCells { known });
        }
        let cost = |j: usize| {
            segs[j]
                .merged(&segs[j + 1])
                .fit
                .map_or(f64::INFINITY, |f| f.rms)
        };
        let j = match (i.checked_sub(1), (i + 1 < segs.len()).then_some(i)) {
            (Some(below), Some(above)) => {
                if cost(below) <= cost(above) {
                    below
                } else {
                    above
                }
            }
            (Some(below), None) => below,
            (None, Some(above)) => above,
            (None, None) => unreachable!("more than one segment"),
        };
        merge_at(&mut segs, j);
    }

    // Step 4: merge while the merge residual stays within the tolerance.
    while let Some((i, cost)) = cheapest_pair(&segs, |_, _| true) {
        if cost > options.merge_tolerance_m {
            break;
        }
        merge_at(&mut segs, i);
    }

    // Step 5: restore convexity: going down, planes must not get shallower.
    let mut convexity_merges = 0;
    if options.enforce_convexity {
        let gradient = |s: &Segment| s.fit.map_or(0.0, |f| f.grad_u);
        while let Some((i, _)) =
            cheapest_pair(&segs, |lower, upper| gradient(lower) < gradient(upper))
        {
            merge_at(&mut segs, i);
            convexity_merges += 1;
        }
    }

    let planes = segs
        .iter()
        .rev()
        .map(|seg| {
            let f = seg.fit.expect("every segment was fitted in step 3");
            let height_at_origin = z0 + f.height(-s0, -t0);
            FittedPlane {
                s_bottom: seg.s_bottom,
                s_top: seg.s_top,
                height_at_origin,
                fall_line_gradient: f.grad_u,
                cross_gradient: f.grad_v,
                rms_residual_m: f.rms,
                cell_count: seg.stats.count(),
            }
        })
        .collect();
    Ok(PlaneSeriesFit {
        planes,
        band_count,
        convexity_merges,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn options_are_checked() {
        let bad = PlaneFitOptions {
            band_width_m: Some(0.0),
            ..Default::default()
        };
        assert_eq!(bad.validate(), Err(PlaneFitError::BadBandWidth(0.0)));
        let bad = PlaneFitOptions {
            merge_tolerance_m: f64::NAN,
            ..Default::default()
        };
        assert!(matches!(
            bad.validate(),
            Err(PlaneFitError::BadTolerance(_))
        ));
    }
}
