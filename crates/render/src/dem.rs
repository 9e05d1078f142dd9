//! Pictures of `rappel dem`: the ingested scenario over its hillshade (planes, obstacles, the
//! fall line and north), the convexity map of PTFO detection (thesis Figs. 3.11-3.12), and the
//! sticking profile of a tether (Figs. 3.13-3.15: the plan view, the axonometric hill view and
//! the phi chart).

use nalgebra::{Point2, Point3};
use rappel::dem::{DemScenario, block_footprint};
use rappel::mechanics::ptfo_detection::{convexity, tolerance};
use rappel::sticking_profile::StickingSample;
use rappel_mechanics::curvature::Convexity;
use rappel_terrain::frame::PlanningFrame;
use rappel_terrain::grid::Raster;
use rappel_terrain::slope::{HillshadeOptions, SlopeField};

use crate::axonometric::Axonometric;
use crate::{Layer, Picture};

/// Largest number of shaded cells drawn per picture side; bigger grids are drawn subsampled.
pub const MAX_DRAWN_CELLS_PER_SIDE: usize = 160;

/// Most cells drawn along a side of a convexity picture (larger grids are subsampled).
const CONVEXITY_CELLS_PER_SIDE: usize = 300;
/// A saddle's convex direction is drawn on every this many drawn cells along each side.
const DIRECTION_EVERY: usize = 3;

/// Draws `hillshade` (values in `[0, 1]`, a raster on the DEM's grid) in the planning `frame`
/// on [`Layer::Terrain`], light so that grey obstacles stand out on it; at most
/// [`MAX_DRAWN_CELLS_PER_SIDE`] blocks of cells along each side (larger grids are drawn in
/// blocks). Cells outside the picture's frame are not written.
pub fn draw_hillshade(pic: &mut Picture, hillshade: &Raster, frame: &PlanningFrame) {
    let g = &hillshade.geometry;
    let step = g
        .nrows
        .max(g.ncols)
        .div_ceil(MAX_DRAWN_CELLS_PER_SIDE)
        .max(1);
    for r in (0..g.nrows).step_by(step) {
        for c in (0..g.ncols).step_by(step) {
            let v = hillshade.values[g.index(r, c)];
            if !v.is_finite() {
                continue;
            }
            let (r1, c1) = (
                (r + step - 1).min(g.nrows - 1),
                (c + step - 1).min(g.ncols - 1),
            );
            let pts: Vec<Point2<f64>> = [
                g.cell_corners(r, c)[0],
                g.cell_corners(r, c1)[1],
                g.cell_corners(r1, c1)[2],
                g.cell_corners(r1, c)[3],
            ]
            .iter()
            .map(|w| frame.to_planning(w))
            .collect();
            let level = (v.clamp(0.0, 1.0) * 105.0 + 150.0) as u8;
            pic.shaded_polygon(
                Layer::Terrain,
                &pts,
                &format!("#{level:02x}{level:02x}{level:02x}"),
            );
        }
    }
}

/// The hillshade of the DEM a scenario was made from ([`rappel::georeference::Georeference`]:
/// the DEM file, resolved against the scenario file `path`, and the planning frame), for drawing
/// under a plan: `None` when the scenario has no georeference; an error naming the file when the
/// DEM cannot be read.
pub fn scenario_hillshade(
    scenario: &rappel::scenario::Scenario,
    path: &std::path::Path,
) -> Option<Result<(Raster, PlanningFrame), String>> {
    let geo = scenario.georeference.as_ref()?;
    Some(
        rappel_terrain::dem::read_dem(geo.dem_path(path))
            .map_err(|e| format!("the scenario's DEM for the hillshade: {e}"))
            .map(|grid| {
                let shade = SlopeField::horn(&grid).hillshade(&HillshadeOptions::default());
                (shade, geo.frame.clone())
            }),
    )
}

/// The picture of a DEM scenario in the planning frame: hillshade, plane edges, tether obstacles
/// (grey), robot obstacles (orange outlines), start and goal.
pub fn dem_picture(d: &DemScenario, title: &str) -> String {
    let ing = &d.ingested;
    let mut pic = Picture::of_map(&d.scenario.map);
    draw_hillshade(&mut pic, &ing.hillshade, &ing.frame);
    for o in &ing.robot_obstacles {
        pic.polygon(Layer::RobotObstacle, &o.vertices);
    }
    let b = d.scenario.map.aabb();
    for p in &d.scenario.terrain.planes {
        for y in [p.y_top, p.y_bottom] {
            pic.polyline(
                Layer::PlaneEdge,
                &[
                    nalgebra::Point2::new(b.min.x, y),
                    nalgebra::Point2::new(b.max.x, y),
                ],
            );
        }
    }
    // Each plane labelled at its band's middle, by the map's left edge.
    for (i, (p, class)) in d.classified_planes().enumerate() {
        let kind = class.label();
        pic.label(
            Layer::PlaneEdge,
            nalgebra::Point2::new(b.min.x, 0.5 * (p.y_top + p.y_bottom)),
            &format!("plane {i}: {:.1}°, {kind}", p.slope_deg),
        );
    }
    // North: the DEM's north direction in the planning frame.
    let f = &d.ingested.frame;
    let o = f.to_world(&d.scenario.start);
    let north = f.to_planning(&(o + nalgebra::Vector2::new(0.0, 1.0))) - d.scenario.start;
    pic.set_north(north);
    pic.map(&d.scenario.map);
    pic.marker(Layer::Start, d.scenario.start);
    pic.marker(Layer::Goal, d.scenario.goal);
    pic.finish(title)
}

/// Thesis Figs. 3.11-3.12 on a DEM, in the planning frame: every cell coloured convex (green),
/// concave (red) or saddle (blue) under the convexity tolerance in force (flat cells are left
/// out), cyan segments along the convex directions of saddle cells (their axis; the directions
/// within the half-width around it are convex too), and the scenario's obstacles over it.
///
/// ```
/// use rappel::dem::dem_scenario;
/// use rappel_render::dem::convexity_picture;
/// use rappel::terrain::ingest::IngestOptions;
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/terrain/mars_hirise_dteec_010228_1490_crop.asc");
/// let d = dem_scenario(path.as_ref(), &IngestOptions::default()).unwrap();
/// let svg = convexity_picture(&d, None, "Mars convexity");
/// assert!(svg.contains("convex") && svg.contains("saddle"));
/// ```
pub fn convexity_picture(d: &DemScenario, min_curvature: Option<f64>, title: &str) -> String {
    let g = d.grid.geometry();
    let frame = &d.ingested.frame;
    let mut pic = Picture::of_map(&d.scenario.map);
    let Some((map, classes)) = convexity(&d.grid, min_curvature) else {
        return pic.finish(title);
    };
    let tol = tolerance(&d.grid, min_curvature);
    let step = g
        .nrows
        .max(g.ncols)
        .div_ceil(CONVEXITY_CELLS_PER_SIDE)
        .max(1);
    let mut directions = Vec::new();
    for (i, r) in (0..g.nrows).step_by(step).enumerate() {
        for (j, c) in (0..g.ncols).step_by(step).enumerate() {
            let layer = match classes[(r, c)] {
                Some(Convexity::Convex) => Layer::Convex,
                Some(Convexity::Concave) => Layer::Concave,
                Some(Convexity::Saddle) => Layer::Saddle,
                _ => continue,
            };
            let pts = block_footprint(d, r, c, step);
            pic.shaded_polygon(layer, &pts, layer.fill());
            if layer == Layer::Saddle
                && i % DIRECTION_EVERY == 0
                && j % DIRECTION_EVERY == 0
                && let Some(k) = map.get(r, c)
                && let Ok(Some(dirs)) = k.convex_directions(tol)
            {
                // The axis in the grid's (column, row) frame: rows run south, so north is -y.
                let half = 0.45 * step as f64 * g.cell_x.min(g.cell_y) * DIRECTION_EVERY as f64;
                let axis = nalgebra::Vector2::new(dirs.axis.x, -dirs.axis.y);
                let n = axis.norm();
                if n > 0.0 {
                    let centre = g.cell_center(r, c);
                    let off = axis * (half / n);
                    directions.push((
                        frame.to_planning(&(centre - off)),
                        frame.to_planning(&(centre + off)),
                    ));
                }
            }
        }
    }
    if !directions.is_empty() {
        pic.segments(Layer::ConvexDirection, directions);
    }
    for o in &d.scenario.map.obstacles {
        pic.polygon(Layer::Obstacle, &o.vertices);
    }
    pic.finish(title)
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
        pic.marker(layer, s.at);
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
