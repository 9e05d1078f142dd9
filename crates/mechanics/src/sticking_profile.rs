//! Where a given tether may stick along its length on a DEM (thesis §3.3.5, Figs. 3.13-3.15): the
//! tether's plan path (in the planning frame) draped over the terrain, sampled along its length;
//! at each sample the Darboux frame of the draped curve gives the normal and geodesic curvatures
//! and the angle `φ` between the curve normal and the surface normal, and Konyukhov's first two
//! conditions decide whether sticking is possible there (thesis eqs. 3.25-3.26: the tether presses
//! on the ground, `κ_n < 0`, and its curve normal lies in the friction cone, `|κ_g| < μ |κ_n|`).
//! Condition 3 (the tensions) is the frictional planner's business (Alg. 9).
//!
//! The draped curve over a straight plan segment of horizontal direction `u` is
//! `r(t) = (p + t u, h(p + t u))`, so `r' = (u, ∇h·u)` and `r'' = (0, 0, uᵀ H u)`, with the
//! height's gradient and Hessian from the DEM by central differences at the nearest cell
//! ([`crate::curvature::height_derivatives`]); the surface normal is `(-∇h, 1)`.

use crate::curvature::height_derivatives;
use crate::darboux::DarbouxFrame;
use crate::sticking::omega_squared;
use nalgebra::{DMatrix, Point2, Point3, Vector2, Vector3};
use rappel_terrain::frame::PlanningFrame;
use rappel_terrain::grid::HeightGrid;
use serde::Serialize;

/// Most samples along one tether (a longer tether is sampled more coarsely).
pub const MAX_SAMPLES: usize = 20_000;

/// One sample of the draped tether.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct StickingSample {
    /// Plan arc length from the tether's start, m.
    pub s: f64,
    /// Where, in the planning frame.
    pub at: Point2<f64>,
    /// Where, in the world (easting, northing, height on the DEM's first-order surface through
    /// the nearest cell centre), m.
    pub world: Point3<f64>,
    /// The unit surface normal there (upwards).
    pub surface_normal: Vector3<f64>,
    /// The unit Frenet-Serret normal of the draped tether, `None` where it is straight.
    pub curve_normal: Option<Vector3<f64>>,
    /// Normal curvature `κ_n`, 1/m (negative where the tether presses into a hump).
    pub normal_curvature: f64,
    /// Geodesic curvature `κ_g`, 1/m.
    pub geodesic_curvature: f64,
    /// `φ` in `(-π, π]`, radians, `None` where the draped curve is straight.
    pub phi: Option<f64>,
    /// Conditions 1 and 2 hold: sticking is possible here with the right tensions.
    pub may_stick: bool,
}

/// Samples `tether` (a polyline in `frame`, the planning frame of `grid`) every `step` metres of
/// plan length over the DEM `grid` with tether-terrain friction `mu` (module docs). Samples off
/// the grid or next to unknown heights are left out.
///
/// ```
/// use rappel_mechanics::sticking_profile::sticking_profile;
/// use rappel_terrain::{dem::read_dem, ingest::{ingest, IngestOptions}};
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/terrain/mars_hirise_dteec_010228_1490_crop.asc");
/// let grid = read_dem(path).unwrap();
/// let i = ingest(&grid, &IngestOptions::default()).unwrap();
/// let samples = sticking_profile(&grid, &i.frame, &[i.start, i.goal], 0.4, 0.5);
/// assert!(samples.len() > 50);
/// ```
pub fn sticking_profile(
    grid: &HeightGrid,
    frame: &PlanningFrame,
    tether: &[Point2<f64>],
    mu: f64,
    step: f64,
) -> Vec<StickingSample> {
    let g = grid.geometry();
    let heights = DMatrix::from_fn(g.nrows, g.ncols, |r, c| {
        grid.height(r, c).unwrap_or(f64::NAN)
    });
    let total: f64 = tether.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
    if !(total.is_finite() && step.is_finite() && step > 0.0 && mu.is_finite() && mu > 0.0) {
        return Vec::new();
    }
    let step = step.max(total / MAX_SAMPLES as f64);
    let mut out = Vec::new();
    let mut s0 = 0.0;
    for w in tether.windows(2) {
        let len = (w[1] - w[0]).norm();
        if len == 0.0 {
            continue;
        }
        let n = (len / step).ceil() as usize;
        for k in 0..n {
            let t = (k as f64 + 0.5) / n as f64;
            let at = w[0] + (w[1] - w[0]) * t;
            // The horizontal direction of the segment in the world, here.
            let (a, b) = (
                frame.to_world(&at),
                frame.to_world(&(at + (w[1] - w[0]) * 1e-3)),
            );
            let u = b - a;
            if u.norm() == 0.0 {
                continue;
            }
            let u = u / u.norm();
            let (fr, fc) = g.world_to_grid(&a);
            if !(fr >= 0.0 && fc >= 0.0) {
                continue;
            }
            let (r, c) = (fr as usize, fc as usize);
            let Some(hd) = height_derivatives(&heights, r, c, g.cell_x, g.cell_y) else {
                continue;
            };
            // Grid frame (x east, y south) to world (east, north).
            let grad = Vector2::new(hd.hx, -hd.hy);
            let hess = nalgebra::Matrix2::new(hd.hxx, -hd.hxy, -hd.hxy, hd.hyy);
            let velocity = Vector3::new(u.x, u.y, grad.dot(&u));
            let acceleration = Vector3::new(0.0, 0.0, (u.transpose() * hess * u)[(0, 0)]);
            let normal = Vector3::new(-grad.x, -grad.y, 1.0);
            let Ok(f) = DarbouxFrame::new(&velocity, &acceleration, &normal) else {
                continue;
            };
            let Some(h0) = grid.height(r, c) else {
                continue;
            };
            let world = Point3::new(a.x, a.y, h0 + grad.dot(&(a - g.cell_center(r, c))));
            let phi = f.phi();
            let may_stick = phi.is_some()
                && f.normal_curvature < 0.0
                && omega_squared(f.normal_curvature, f.geodesic_curvature, mu) > 0.0;
            out.push(StickingSample {
                s: s0 + t * len,
                at,
                world,
                surface_normal: normal.normalize(),
                curve_normal: f.curve_normal().map(|n| n.into_inner()),
                normal_curvature: f.normal_curvature,
                geodesic_curvature: f.geodesic_curvature,
                phi,
                may_stick,
            });
        }
        s0 += len;
    }
    out
}
