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
//! ([`rappel_mechanics::curvature::height_derivatives`]); the surface normal is `(-∇h, 1)`.

use crate::axonometric::Axonometric;
use crate::dem::DemScenario;
use crate::svg::{Layer, Marker, Picture};
use nalgebra::{DMatrix, Point2, Point3, Vector2, Vector3};
use rappel_mechanics::curvature::height_derivatives;
use rappel_mechanics::darboux::DarbouxFrame;
use rappel_mechanics::sticking::omega_squared;
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

/// Samples `tether` (planning-frame polyline) every `step` metres of plan length over `d`'s DEM
/// with tether-terrain friction `mu` (module docs). Samples off the grid or next to unknown
/// heights are left out.
///
/// ```
/// use rappel::dem::dem_scenario;
/// use rappel::sticking_profile::sticking_profile;
/// use rappel::terrain::ingest::IngestOptions;
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/terrain/mars_hirise_dteec_010228_1490_crop.asc");
/// let d = dem_scenario(path.as_ref(), &IngestOptions::default()).unwrap();
/// let tether = [d.scenario.start, d.scenario.goal];
/// let samples = sticking_profile(&d, &tether, 0.4, 0.5);
/// assert!(samples.len() > 50);
/// ```
pub fn sticking_profile(
    d: &DemScenario,
    tether: &[Point2<f64>],
    mu: f64,
    step: f64,
) -> Vec<StickingSample> {
    let g = d.grid.geometry();
    let frame = &d.ingested.frame;
    let heights = DMatrix::from_fn(g.nrows, g.ncols, |r, c| {
        d.grid.height(r, c).unwrap_or(f64::NAN)
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
            let Some(h0) = d.grid.height(r, c) else {
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

/// Thesis Fig. 3.13 on a DEM: the scenario's obstacles, the tether, and its samples where
/// sticking is possible (black) or not (red).
pub fn sticking_picture(
    d: &DemScenario,
    tether: &[Point2<f64>],
    samples: &[StickingSample],
    title: &str,
) -> String {
    let mut pic = Picture::of_map(&d.scenario.map);
    pic.map(&d.scenario.map);
    pic.polyline(Layer::Shp, tether);
    for s in samples {
        let layer = if s.may_stick {
            Layer::MayStick
        } else {
            Layer::WillSlip
        };
        pic.marker(layer, s.at, Marker::Circle);
    }
    pic.finish(title)
}

/// Most grid cells along one side of [`hill_view`]'s terrain (coarser cells are averaged by
/// taking every k-th height), which bounds the picture to `HILL_VIEW_CELLS²` quads.
pub const HILL_VIEW_CELLS: usize = 90;

/// Most normal pairs drawn by [`hill_view`] (every k-th sample carries one).
pub const HILL_VIEW_ARROWS: usize = 60;

/// Thesis Fig. 3.14: an axonometric 3D view of the DEM around the draped tether (true vertical
/// scale), the tether in red, and at evenly spaced samples its Frenet-Serret normal (red) and the
/// surface normal (green), each drawn one twentieth of the window's diagonal long. The terrain is
/// the window of the grid holding the samples plus a margin of a tenth of its size, shaded by
/// slope and drawn back to front. Returns `None` without samples.
pub fn hill_view(d: &DemScenario, samples: &[StickingSample], title: &str) -> Option<String> {
    let g = d.grid.geometry();
    let first = samples.first()?;
    let (mut lo, mut hi) = (first.world, first.world);
    for s in samples {
        lo = lo.inf(&s.world);
        hi = hi.sup(&s.world);
    }
    let margin = 0.1 * (hi.x - lo.x).max(hi.y - lo.y) + 2.0 * g.cell_size();
    // Grid rows grow southwards: the window in grid indices, clamped to the grid.
    let (r_a, c_a) = g.world_to_grid(&Point2::new(lo.x - margin, hi.y + margin));
    let (r_b, c_b) = g.world_to_grid(&Point2::new(hi.x + margin, lo.y - margin));
    let clamp = |v: f64, n: usize| (v.max(0.0) as usize).min(n.saturating_sub(1));
    let (r0, r1) = (clamp(r_a.min(r_b), g.nrows), clamp(r_a.max(r_b), g.nrows));
    let (c0, c1) = (clamp(c_a.min(c_b), g.ncols), clamp(c_a.max(c_b), g.ncols));
    let stride = ((r1 - r0).max(c1 - c0) / HILL_VIEW_CELLS).max(1);
    let rows: Vec<usize> = (r0..=r1).step_by(stride).collect();
    let cols: Vec<usize> = (c0..=c1).step_by(stride).collect();
    let point = |r: usize, c: usize| {
        d.grid.height(r, c).map(|z| {
            let p = g.cell_center(r, c);
            Point3::new(p.x, p.y, z)
        })
    };
    let mut quads: Vec<(f64, [Point3<f64>; 4], f64)> = Vec::new();
    for w in rows.windows(2) {
        for v in cols.windows(2) {
            let corners = [
                point(w[0], v[0]),
                point(w[0], v[1]),
                point(w[1], v[1]),
                point(w[1], v[0]),
            ];
            let [Some(a), Some(b), Some(c), Some(e)] = corners else {
                continue;
            };
            let n = (c - a).cross(&(b - e));
            let cos_slope = (n.z.abs() / n.norm()).clamp(0.0, 1.0);
            let centre = Point3::from((a.coords + b.coords + c.coords + e.coords) / 4.0);
            quads.push((Axonometric::depth(&centre), [a, b, c, e], cos_slope));
        }
    }
    // Back (north-east, large x + y) to front.
    quads.sort_by(|a, b| b.0.total_cmp(&a.0));
    let arrow = (hi - lo).norm().max(g.cell_size()) / 20.0;
    let every = samples.len().div_ceil(HILL_VIEW_ARROWS).max(1);
    let mut view = Axonometric::default();
    view.group("terrain");
    for (_, q, cos_slope) in &quads {
        view.shaded_polygon(q, *cos_slope);
    }
    view.group("tether");
    let tether: Vec<Point3<f64>> = samples.iter().map(|s| s.world).collect();
    view.polyline(&tether, "stroke=\"#d62728\" stroke-width=\"2.5\"");
    view.group("normals");
    for s in samples.iter().step_by(every) {
        view.polyline(
            &[s.world, s.world + s.surface_normal * arrow],
            "class=\"surface-normal\" stroke=\"#2ca02c\" stroke-width=\"1.5\"",
        );
        if let Some(n) = s.curve_normal {
            view.polyline(
                &[s.world, s.world + n * arrow],
                "class=\"curve-normal\" stroke=\"#d62728\" stroke-width=\"1.5\"",
            );
        }
    }
    Some(view.render(title))
}

/// Thesis Fig. 3.15: `|φ|` along the tether's plan length, with the friction bound
/// `π - atan μ` above which (with `κ_n < 0`) the curve normal lies in the friction cone. An SVG
/// chart of its own (not a map picture).
pub fn phi_chart(samples: &[StickingSample], mu: f64, title: &str) -> String {
    use std::fmt::Write;
    let (w, h, m) = (800.0, 360.0, 50.0);
    let length = samples.last().map_or(1.0, |s| s.s).max(1e-9);
    let pi = std::f64::consts::PI;
    let x = |s: f64| m + (w - 2.0 * m) * s / length;
    let y = |phi: f64| h - m - (h - 2.0 * m) * phi / pi;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\">"
    );
    let _ = writeln!(out, "<rect width=\"{w}\" height=\"{h}\" fill=\"white\"/>");
    let _ = writeln!(
        out,
        "<text x=\"{m}\" y=\"24\" font-family=\"sans-serif\" font-size=\"15\">{}</text>",
        title.replace('&', "&amp;").replace('<', "&lt;")
    );
    // Axes.
    let _ = writeln!(
        out,
        "<path d=\"M{m} {} L{} {} M{m} {} L{m} {m}\" stroke=\"black\" fill=\"none\"/>",
        h - m,
        w - m,
        h - m,
        h - m
    );
    let bound = pi - mu.atan();
    let _ = writeln!(
        out,
        "<line x1=\"{m}\" y1=\"{by}\" x2=\"{}\" y2=\"{by}\" stroke=\"#31a354\" stroke-dasharray=\"6 4\"/>",
        w - m,
        by = y(bound)
    );
    let _ = writeln!(
        out,
        "<text x=\"{}\" y=\"{}\" font-family=\"sans-serif\" font-size=\"12\" fill=\"#31a354\">π - atan μ (μ = {mu})</text>",
        w - m - 150.0,
        y(bound) - 6.0
    );
    for s in samples {
        if let Some(phi) = s.phi {
            let colour = if s.may_stick { "black" } else { "#de2d26" };
            let _ = writeln!(
                out,
                "<circle cx=\"{:.2}\" cy=\"{:.2}\" r=\"2\" fill=\"{colour}\"/>",
                x(s.s),
                y(phi.abs())
            );
        }
    }
    let _ = writeln!(
        out,
        "<text x=\"{}\" y=\"{}\" font-family=\"sans-serif\" font-size=\"12\">tether length, m (0 .. {length:.1})</text>",
        w / 2.0 - 80.0,
        h - 15.0
    );
    let _ = writeln!(
        out,
        "<text x=\"8\" y=\"{}\" font-family=\"sans-serif\" font-size=\"12\">|φ| (0 .. π)</text>",
        m - 8.0
    );
    out.push_str("</svg>\n");
    out
}
