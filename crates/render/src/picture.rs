//! The SVG canvas: pictures with one legend across every subcommand (GUIDE §5): obstacles filled grey, BTM
//! edges thin, the sleeve shaded, the taut tether (SHP) bold, anchors as squares, friction cones as
//! translucent wedges, ascent and descent paths in two colours, waypoints as stars, start and goal
//! marked; a side panel carries the legend, a scale bar and the fall-line arrow.
//!
//! A [`Picture`] collects layers in the map frame (y up the slope; the picture puts uphill at the
//! top) and renders them with [`Picture::finish`]. Later planners add their layers with the same
//! primitives.

use nalgebra::Point2;
use rappel_geometry::btm::Btm;
use rappel_geometry::dcel::HalfEdgeId;
use rappel_geometry::map::Map;
use rappel_geometry::polygon::Aabb;
use rappel_homotopy::funnel::TautPath;
use rappel_homotopy::sleeve::Sleeve;
use rappel_planners::feasibility;
use std::fmt::Write;

use crate::style::{Glyph, Layer, Marker, scale_colour};

/// A picture being drawn.
///
/// ```
/// use nalgebra::Point2;
/// use rappel_render::{Layer, Marker, Picture};
/// use rappel_geometry::polygon::Aabb;
/// let mut pic = Picture::new(Aabb { min: Point2::new(0.0, 0.0), max: Point2::new(10.0, 20.0) });
/// pic.marker(Layer::Start, Point2::new(5.0, 19.0));
/// let svg = pic.finish("example");
/// assert!(svg.starts_with("<svg") && svg.contains("start"));
/// ```
#[derive(Debug, Clone)]
pub struct Picture {
    bounds: Aabb,
    /// World units per pixel.
    unit: f64,
    body: Vec<(Layer, String)>,
    /// The tag of elements drawn now (`data-tag`, e.g. a class), for the viewer's picker.
    tag: Option<String>,
    /// Where north points in the map frame, when the picture has a georeference.
    north: Option<nalgebra::Vector2<f64>>,
    /// The downhill direction in the map frame (`-y` in the planning frame), if known.
    fall_line: Option<nalgebra::Vector2<f64>>,
    /// A colour scale drawn in the panel: its title and the values at its ends.
    scale: Option<(String, f64, f64)>,
    used: Vec<Layer>,
}

/// Width of the side panel, px.
const PANEL: f64 = 200.0;
/// Largest drawing area of an ordinary map, px.
const MAX_W: f64 = 900.0;
const MAX_H: f64 = 1400.0;
/// The narrow side of a long map (a crater strip) gets at least this many pixels...
const MIN_NARROW: f64 = 360.0;
/// ...unless its long side would then exceed this many (the picture stays openable).
const MAX_LONG: f64 = 16_000.0;
/// About how far apart coordinate ticks are, px.
const TICK_SPACING_PX: f64 = 120.0;
/// Most coordinate ticks along one edge (a bound on the picture's size).
const MAX_TICKS: i64 = 200;

/// A round length (1, 2 or 5 times a power of ten): the smallest at least `target` when
/// `at_least`, else the largest at most `target` (scale bars, tick steps).
pub(crate) fn round_length(target: f64, at_least: bool) -> f64 {
    let target = if target.is_finite() && target > 0.0 {
        target
    } else {
        1.0
    };
    let p = 10f64.powf(target.log10().floor());
    let candidates = [1.0, 2.0, 5.0, 10.0].map(|k| k * p);
    if at_least {
        candidates
            .into_iter()
            .find(|s| *s >= target)
            .unwrap_or(10.0 * p)
    } else {
        candidates.into_iter().rfind(|s| *s <= target).unwrap_or(p)
    }
}

/// Height of the title line above the map, px.
const TITLE_H: f64 = 26.0;

fn fmt(v: f64) -> String {
    let s = format!("{v:.4}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".to_string()
    } else {
        s.to_string()
    }
}

impl Picture {
    /// An empty picture of the map-frame box `bounds` (padded a little).
    pub fn new(bounds: Aabb) -> Self {
        let (w, h) = bounds.size();
        let pad = 0.02 * w.max(h).max(1e-9);
        let bounds = Aabb {
            min: Point2::new(bounds.min.x - pad, bounds.min.y - pad),
            max: Point2::new(bounds.max.x + pad, bounds.max.y + pad),
        };
        let (w, h) = bounds.size();
        // Fit in MAX_W x MAX_H; a long, thin map would become a sliver, so its narrow side is
        // widened to MIN_NARROW pixels as far as MAX_LONG allows for the long side.
        let fit = (w / MAX_W).max(h / MAX_H);
        let (narrow, long) = (w.min(h), w.max(h));
        let widen = (narrow / MIN_NARROW).max(long / MAX_LONG);
        let unit = fit.min(widen).max(1e-12);
        Picture {
            bounds,
            unit,
            body: Vec::new(),
            tag: None,
            north: None,
            fall_line: Some(nalgebra::Vector2::new(0.0, -1.0)),
            scale: None,
            used: Vec::new(),
        }
    }

    /// A picture framing a map.
    pub fn of_map(map: &Map) -> Self {
        Picture::new(map.aabb())
    }

    /// A picture framing `window` (`--window`: a crop, in the map frame) or, without one, the
    /// map. Markers and strokes are sized to what is framed; whatever lies outside is clipped.
    pub fn of_map_in(map: &Map, window: Option<&Aabb>) -> Self {
        Picture::new(window.copied().unwrap_or_else(|| map.aabb()))
    }

    /// World units per pixel of this picture.
    pub fn unit(&self) -> f64 {
        self.unit
    }

    /// Draws a colour scale ([`crate::style::SCALE_STOPS`]) in the panel, titled `title`, from `lo` to `hi`.
    pub fn set_colour_scale(&mut self, title: &str, lo: f64, hi: f64) {
        self.scale = Some((title.to_string(), lo, hi));
    }

    /// A disc of radius `r` in map units (e.g. sized to a grid step) filled with `fill` (`None`:
    /// the layer's own look, e.g. a hollow ring), with a hover text.
    pub fn disc(&mut self, layer: Layer, p: Point2<f64>, r: f64, fill: Option<&str>, title: &str) {
        if !self.shows(&[p]) {
            return;
        }
        self.use_layer(layer);
        let mut style = self.style(layer);
        if let Some(f) = fill {
            style = style.replacen(
                &format!("fill=\"{}\"", layer.look().0),
                &format!("fill=\"{f}\""),
                1,
            );
        }
        let s = format!(
            "<circle cx=\"{}\" cy=\"{}\" r=\"{}\" {style}><title>{}</title></circle>",
            fmt(p.x),
            fmt(p.y),
            fmt(r),
            escape(title)
        );
        self.push(layer, s);
    }

    /// Tags the elements drawn from now on (`None` stops tagging): the HTML viewer
    /// ([`crate::viewer`]) offers a picker over the tags, e.g. one per homotopy class.
    pub fn set_tag(&mut self, tag: Option<String>) {
        self.tag = tag;
    }

    fn push(&mut self, layer: Layer, s: String) {
        let s = match &self.tag {
            Some(t) => format!("<g data-tag=\"{}\">{s}</g>", escape(t)),
            None => s,
        };
        self.body.push((layer, s));
    }

    /// Sets the fall-line arrow of the panel to `direction` (downhill, map frame), or removes it
    /// (`None`: ground with no one downhill direction). The default is `-y`, the planning frame's
    /// downhill.
    pub fn set_fall_line(&mut self, direction: Option<nalgebra::Vector2<f64>>) {
        self.fall_line = direction
            .filter(|d| d.norm().is_finite() && d.norm() > 0.0)
            .map(|d| d / d.norm());
    }

    /// Draws a north arrow in the panel pointing along `direction` (map frame; e.g. a DEM's north
    /// in the planning frame).
    pub fn set_north(&mut self, direction: nalgebra::Vector2<f64>) {
        let n = direction.norm();
        if n.is_finite() && n > 0.0 {
            self.north = Some(direction / n);
        }
    }

    /// A text label at `p` (map frame) on `layer`, 12 px high on screen.
    pub fn label(&mut self, layer: Layer, p: Point2<f64>, text: &str) {
        self.use_layer(layer);
        let size = 12.0 * self.unit;
        let s = format!(
            "<g transform=\"translate({} {}) scale(1,-1)\"><text font-size=\"{}\" fill=\"{}\">{}</text></g>",
            fmt(p.x),
            fmt(p.y),
            fmt(size),
            layer.look().1,
            escape(text)
        );
        self.push(layer, s);
    }

    /// A marker of its layer's shape ([`Layer::glyph`]) with a hover text (an SVG `<title>`:
    /// browsers and the viewer show it).
    pub fn titled_marker(&mut self, layer: Layer, p: Point2<f64>, title: &str) {
        if !self.shows(&[p]) {
            return;
        }
        self.use_layer(layer);
        let s = marker_svg(layer, p, 5.0 * self.unit, 1.0, self.unit);
        self.push(layer, format!("<g><title>{}</title>{s}</g>", escape(title)));
    }

    /// Whether anything of the shape with these points can be seen: its bounding box, grown by
    /// 20 pixels (markers and strokes), meets the framed box. What cannot be seen (outside a
    /// `--window`) is not written at all, so a crop of a large map stays small.
    fn shows(&self, pts: &[Point2<f64>]) -> bool {
        let b = Aabb::of_points(pts);
        let m = 20.0 * self.unit;
        b.min.x <= self.bounds.max.x + m
            && b.max.x >= self.bounds.min.x - m
            && b.min.y <= self.bounds.max.y + m
            && b.max.y >= self.bounds.min.y - m
    }

    fn use_layer(&mut self, layer: Layer) {
        if !self.used.contains(&layer) {
            self.used.push(layer);
        }
    }

    fn style(&self, layer: Layer) -> String {
        style_at(layer, self.unit)
    }

    fn points(pts: &[Point2<f64>]) -> String {
        pts.iter()
            .map(|p| format!("{},{}", fmt(p.x), fmt(p.y)))
            .collect::<Vec<_>>()
            .join(" ")
    }

    /// A closed filled polygon on `layer`.
    pub fn polygon(&mut self, layer: Layer, pts: &[Point2<f64>]) {
        if !self.shows(pts) {
            return;
        }
        self.use_layer(layer);
        let s = format!(
            "<polygon points=\"{}\" {}/>",
            Self::points(pts),
            self.style(layer)
        );
        self.push(layer, s);
    }

    /// A filled polygon on `layer` with its own fill colour (`#rrggbb`), for shaded terrain.
    pub fn shaded_polygon(&mut self, layer: Layer, pts: &[Point2<f64>], fill: &str) {
        if !self.shows(pts) {
            return;
        }
        self.use_layer(layer);
        let s = format!(
            "<polygon points=\"{}\" fill=\"{fill}\" stroke=\"{fill}\" stroke-width=\"{}\"/>",
            Self::points(pts),
            fmt(0.3 * self.unit)
        );
        self.push(layer, s);
    }

    /// An open polyline on `layer`.
    pub fn polyline(&mut self, layer: Layer, pts: &[Point2<f64>]) {
        if !self.shows(pts) {
            return;
        }
        self.use_layer(layer);
        let mut style = self.style(layer);
        style = style.replacen(&format!("fill=\"{}\"", layer.look().0), "fill=\"none\"", 1);
        let s = format!("<polyline points=\"{}\" {style}/>", Self::points(pts));
        self.push(layer, s);
    }

    /// Many segments on `layer` as one path element (for meshes).
    pub fn segments(
        &mut self,
        layer: Layer,
        segs: impl IntoIterator<Item = (Point2<f64>, Point2<f64>)>,
    ) {
        self.use_layer(layer);
        let mut d = String::new();
        for (a, b) in segs.into_iter().filter(|(a, b)| self.shows(&[*a, *b])) {
            let _ = write!(d, "M{} {}L{} {}", fmt(a.x), fmt(a.y), fmt(b.x), fmt(b.y));
        }
        let s = format!("<path d=\"{d}\" {}/>", self.style(layer));
        self.push(layer, s);
    }

    /// A marker of fixed on-screen size at `p`, of its layer's shape ([`Layer::glyph`]).
    pub fn marker(&mut self, layer: Layer, p: Point2<f64>) {
        if !self.shows(&[p]) {
            return;
        }
        self.use_layer(layer);
        let s = marker_svg(layer, p, 5.0 * self.unit, 1.0, self.unit);
        self.push(layer, s);
    }

    /// The map: boundary outline and grey obstacles.
    pub fn map(&mut self, map: &Map) {
        self.polygon(Layer::Boundary, &map.boundary.vertices);
        for o in &map.obstacles {
            self.polygon(Layer::Obstacle, &o.vertices);
        }
    }

    /// Every edge of a BTM, thin.
    pub fn btm(&mut self, btm: &Btm) {
        let d = btm.dcel();
        let segs: Vec<_> = btm
            .triangles()
            .flat_map(|t| t.half_edges())
            .filter(|&h: &HalfEdgeId| d.twin(h).is_none_or(|g| h < g))
            .map(|h| (d.point(d.origin(h)), d.point(d.destination(h))))
            .collect();
        self.segments(Layer::BtmEdge, segs);
    }

    /// Start (cross) and goal (circle) markers.
    pub fn start_goal(&mut self, start: Point2<f64>, goal: Point2<f64>) {
        self.marker(Layer::Start, start);
        self.marker(Layer::Goal, goal);
    }

    /// The finished SVG document, titled `title`.
    pub fn finish(mut self, title: &str) -> String {
        let (w, h) = self.bounds.size();
        let (pw, ph) = (w / self.unit, h / self.unit);
        let total_w = pw + PANEL;
        let total_h = (ph + TITLE_H).max(330.0);
        let mut out = String::new();
        let _ = writeln!(
            out,
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" viewBox=\"0 0 {} {}\" font-family=\"sans-serif\">",
            fmt(total_w),
            fmt(total_h),
            fmt(total_w),
            fmt(total_h)
        );
        let _ = writeln!(out, "<title>{}</title>", escape(title));
        let _ = writeln!(
            out,
            "<defs><marker id=\"rappel-arrow\" viewBox=\"0 0 10 10\" refX=\"9\" refY=\"5\" markerWidth=\"6\" markerHeight=\"6\" orient=\"auto\"><path d=\"M0 0L10 5L0 10z\"/></marker></defs>"
        );
        let _ = writeln!(out, "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>");
        // The title (and verdict, when the caller puts it in the title), drawn.
        let _ = writeln!(
            out,
            "<text x=\"8\" y=\"18\" font-size=\"15\" font-weight=\"bold\">{}</text>",
            escape(title)
        );
        // The map, y flipped so uphill is at the top.
        let _ = writeln!(
            out,
            "<svg id=\"rappel-map\" x=\"0\" y=\"{}\" width=\"{}\" height=\"{}\" viewBox=\"{} {} {} {}\">",
            fmt(TITLE_H),
            fmt(pw),
            fmt(ph),
            fmt(self.bounds.min.x),
            fmt(-self.bounds.max.y),
            fmt(w),
            fmt(h)
        );
        let _ = writeln!(out, "<g transform=\"scale(1,-1)\">");
        self.body.sort_by_key(|(layer, _)| layer.draw_order());
        // One group per run of a layer, named for the viewer's layer toggles.
        let mut open: Option<Layer> = None;
        for (layer, s) in &self.body {
            if open != Some(*layer) {
                if open.is_some() {
                    out.push_str("</g>\n");
                }
                let _ = writeln!(out, "<g data-layer=\"{}\">", escape(layer.label()));
                open = Some(*layer);
            }
            out.push_str(s);
            out.push('\n');
        }
        if open.is_some() {
            out.push_str("</g>\n");
        }
        self.ticks(&mut out);
        let _ = writeln!(out, "</g></svg>");
        self.panel(&mut out, pw);
        out.push_str("</svg>\n");
        out
    }

    /// Coordinate ticks along the framed box's bottom and left edges, in the map frame (so they
    /// pan and zoom with the map in the viewer): a round step about [`TICK_SPACING_PX`] apart,
    /// each labelled with its coordinate in metres.
    fn ticks(&self, out: &mut String) {
        let step = round_length(TICK_SPACING_PX * self.unit, true);
        let (b, u) = (&self.bounds, self.unit);
        let _ = writeln!(
            out,
            "<g id=\"rappel-ticks\" stroke=\"#333333\" stroke-width=\"{}\" font-size=\"{}\" fill=\"#333333\">",
            fmt(u),
            fmt(10.0 * u)
        );
        let label = |out: &mut String, x: f64, y: f64, text: &str| {
            let _ = writeln!(
                out,
                "<g transform=\"translate({} {}) scale(1,-1)\"><text stroke=\"white\" stroke-width=\"{}\" paint-order=\"stroke\">{text}</text></g>",
                fmt(x),
                fmt(y),
                fmt(2.0 * u)
            );
        };
        // At most MAX_TICKS per axis (the step makes it about the frame over the spacing).
        let first = |lo: f64| (lo / step).ceil() as i64;
        let last = |hi: f64| (hi / step).floor() as i64;
        let (x0, x1) = (
            first(b.min.x),
            last(b.max.x).min(first(b.min.x) + MAX_TICKS),
        );
        for k in x0..=x1 {
            let x = k as f64 * step;
            let _ = writeln!(
                out,
                "<path d=\"M{} {}v{}\"/>",
                fmt(x),
                fmt(b.min.y),
                fmt(6.0 * u)
            );
            label(out, x + 2.0 * u, b.min.y + 8.0 * u, &fmt(x));
        }
        let (y0, y1) = (
            first(b.min.y),
            last(b.max.y).min(first(b.min.y) + MAX_TICKS),
        );
        for k in y0..=y1 {
            let y = k as f64 * step;
            let _ = writeln!(
                out,
                "<path d=\"M{} {}h{}\"/>",
                fmt(b.min.x),
                fmt(y),
                fmt(6.0 * u)
            );
            label(out, b.min.x + 8.0 * u, y + 2.0 * u, &fmt(y));
        }
        let _ = writeln!(out, "</g>");
    }

    /// Legend, scale bar and fall-line arrow, in pixels right of the map.
    fn panel(&self, out: &mut String, x0: f64) {
        let x = x0 + 16.0;
        let _ = writeln!(out, "<g font-size=\"13\">");
        let mut y = 24.0 + TITLE_H;
        let _ = writeln!(
            out,
            "<text x=\"{}\" y=\"{}\" font-weight=\"bold\">legend</text>",
            fmt(x),
            fmt(y)
        );
        let mut used = self.used.clone();
        used.sort_by_key(|l| l.draw_order());
        for layer in used {
            y += 20.0;
            let (fill, stroke, width, opacity) = layer.look();
            let swatch = match layer.glyph() {
                Glyph::Mark(_) => marker_svg(layer, Point2::new(x + 10.0, y - 5.0), 5.0, -1.0, 1.0),
                Glyph::Disc => format!(
                    "<circle cx=\"{}\" cy=\"{}\" r=\"5\" fill=\"{fill}\" stroke=\"{stroke}\"/>",
                    fmt(x + 10.0),
                    fmt(y - 5.0)
                ),
                Glyph::Area => format!(
                    "<rect x=\"{}\" y=\"{}\" width=\"20\" height=\"10\" fill=\"{fill}\" fill-opacity=\"{}\" stroke=\"{stroke}\"/>",
                    fmt(x),
                    fmt(y - 10.0),
                    fmt(opacity.max(0.3))
                ),
                Glyph::Line => format!(
                    "<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"{stroke}\" stroke-width=\"{}\"/>",
                    fmt(x),
                    fmt(y - 5.0),
                    fmt(x + 20.0),
                    fmt(y - 5.0),
                    fmt(width.max(1.0))
                ),
            };
            let _ = writeln!(
                out,
                "{swatch}<text x=\"{}\" y=\"{}\">{}</text>",
                fmt(x + 28.0),
                fmt(y),
                layer.label()
            );
            if let Some(note) = layer.legend_note() {
                y += 13.0;
                let _ = writeln!(
                    out,
                    "<text x=\"{}\" y=\"{}\" font-size=\"10\">{}</text>",
                    fmt(x + 28.0),
                    fmt(y),
                    escape(&note)
                );
            }
        }
        if let Some((title, lo, hi)) = &self.scale {
            // The colour scale: a ramp over SCALE_STOPS, low at the left.
            y += 34.0;
            let _ = writeln!(
                out,
                "<text x=\"{}\" y=\"{}\">{}</text>",
                fmt(x),
                fmt(y),
                escape(title)
            );
            y += 8.0;
            for i in 0..20 {
                let _ = writeln!(
                    out,
                    "<rect x=\"{}\" y=\"{}\" width=\"7\" height=\"12\" fill=\"{}\"/>",
                    fmt(x + 7.0 * f64::from(i)),
                    fmt(y),
                    scale_colour(f64::from(i) / 19.0)
                );
            }
            y += 26.0;
            let _ = writeln!(
                out,
                "<text x=\"{}\" y=\"{}\">{}</text><text x=\"{}\" y=\"{}\" text-anchor=\"end\">{}</text>",
                fmt(x),
                fmt(y),
                fmt(*lo),
                fmt(x + 140.0),
                fmt(y),
                fmt(*hi)
            );
        }
        // Scale bar: a round length near 120 px.
        y += 40.0;
        let len = round_length(120.0 * self.unit, false);
        let px = len / self.unit;
        let _ = writeln!(
            out,
            "<path d=\"M{} {}v-6v6h{}v-6\" stroke=\"black\" stroke-width=\"2\" fill=\"none\"/><text x=\"{}\" y=\"{}\">{} m</text>",
            fmt(x),
            fmt(y),
            fmt(px),
            fmt(x),
            fmt(y + 16.0),
            fmt(len)
        );
        // Fall-line arrow: downhill in the map frame (y up in the picture).
        if let Some(f) = self.fall_line {
            y += 40.0;
            let (cx, cy) = (x + 30.0, y + 30.0);
            let (dx, dy) = (f.x * 28.0, -f.y * 28.0);
            let _ = writeln!(
                out,
                "<path d=\"M{} {}L{} {}\" stroke=\"black\" stroke-width=\"2\" marker-end=\"url(#rappel-arrow)\"/><text x=\"{}\" y=\"{}\">fall line</text>",
                fmt(cx - dx),
                fmt(cy - dy),
                fmt(cx + dx),
                fmt(cy + dy),
                fmt(x + 66.0),
                fmt(cy + 4.0)
            );
            y += 30.0;
        }
        if let Some(n) = self.north {
            // North arrow: the map's y axis points up in the picture.
            y += 80.0;
            let (cx, cy) = (x + 10.0, y + 30.0);
            let (dx, dy) = (n.x * 28.0, -n.y * 28.0);
            let _ = writeln!(
                out,
                "<path d=\"M{} {}L{} {}\" stroke=\"black\" stroke-width=\"2\" marker-end=\"url(#rappel-arrow)\"/><circle cx=\"{}\" cy=\"{}\" r=\"2\"/><text x=\"{}\" y=\"{}\" font-weight=\"bold\">N</text>",
                fmt(cx - dx),
                fmt(cy - dy),
                fmt(cx + dx),
                fmt(cy + dy),
                fmt(cx),
                fmt(cy),
                fmt(cx + dx * 1.35 - 4.0),
                fmt(cy + dy * 1.35 + 4.0)
            );
        }
        let _ = writeln!(out, "</g>");
    }
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// Drawing the homotopy layer's objects: sleeves, taut tethers, input paths, friction cones.
impl Picture {
    /// A friction-cone wedge of half-angle `max_angle` below `apex`, `reach` long, clipped to the
    /// convex reachable-set piece `piece` (translucent).
    pub fn friction_cone(
        &mut self,
        apex: &Point2<f64>,
        max_angle: f64,
        reach: f64,
        piece: &[Point2<f64>],
    ) {
        let fan: Vec<Point2<f64>> = (0..=8)
            .map(|i| {
                let t = -1.0 + 2.0 * i as f64 / 8.0;
                let a = t * max_angle;
                Point2::new(apex.x + reach * a.sin(), apex.y - reach * a.cos())
            })
            .collect();
        let mut wedge = vec![*apex];
        wedge.extend(fan);
        let clipped = clip_convex(&wedge, piece);
        if clipped.len() >= 3 {
            self.polygon(Layer::FrictionCone, &clipped);
        }
    }
    /// A sleeve's triangles, shaded.
    pub fn sleeve(&mut self, btm: &Btm, sleeve: &Sleeve) {
        let d = btm.dcel();
        for &t in sleeve.triangles() {
            self.polygon(Layer::Sleeve, &d.triangle_points(t));
        }
    }

    /// A taut tether, bold, with its anchors as squares.
    pub fn taut_path(&mut self, taut: &TautPath) {
        self.polyline(Layer::Shp, &taut.points);
        for a in &taut.anchors {
            self.marker(Layer::Anchor, a.point);
        }
    }

    /// An input path, thin.
    pub fn path(&mut self, points: &[Point2<f64>]) {
        self.polyline(Layer::Path, points);
    }
}

/// The part of the convex polygon `subject` inside the convex polygon `clip` (either orientation),
/// for drawing only.
fn clip_convex(subject: &[Point2<f64>], clip: &[Point2<f64>]) -> Vec<Point2<f64>> {
    let n = clip.len();
    let twice_area: f64 = (0..n)
        .map(|i| {
            let (a, b) = (clip[i], clip[(i + 1) % n]);
            a.x * b.y - a.y * b.x
        })
        .sum();
    let mut out = subject.to_vec();
    for i in 0..n {
        let (a, b) = (clip[i], clip[(i + 1) % n]);
        let dir = if twice_area >= 0.0 { b - a } else { a - b };
        out = feasibility::clip(&out, &a, &dir);
        if out.is_empty() {
            break;
        }
    }
    out
}

/// The SVG attributes of `layer`'s look with stroke widths in units of `unit` per pixel.
fn style_at(layer: Layer, unit: f64) -> String {
    let (fill, stroke, width, opacity) = layer.look();
    format!(
        "fill=\"{fill}\" fill-opacity=\"{}\" stroke=\"{stroke}\" stroke-width=\"{}\" stroke-linejoin=\"round\" stroke-linecap=\"round\"",
        fmt(opacity),
        fmt(width * unit)
    )
}

/// The marker of `layer` ([`Layer::glyph`]; a layer drawn as a marker always has a marker glyph,
/// others fall back to a circle) centred at `p` with radius `r`, strokes in units of `unit` per
/// pixel; `y_up` is 1 in the map frame (y up) and -1 in the legend (pixels, y down).
fn marker_svg(layer: Layer, p: Point2<f64>, r: f64, y_up: f64, unit: f64) -> String {
    let shape = match layer.glyph() {
        Glyph::Mark(m) => m,
        _ => Marker::Circle,
    };
    let style = style_at(layer, unit);
    match shape {
        Marker::Circle => format!(
            "<circle cx=\"{}\" cy=\"{}\" r=\"{}\" {style}/>",
            fmt(p.x),
            fmt(p.y),
            fmt(r)
        ),
        Marker::Square => format!(
            "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" {style}/>",
            fmt(p.x - r * 0.8),
            fmt(p.y - r * 0.8),
            fmt(1.6 * r),
            fmt(1.6 * r)
        ),
        Marker::Star => {
            let pts: Vec<Point2<f64>> = (0..10)
                .map(|i| {
                    let a = std::f64::consts::FRAC_PI_2 + i as f64 * std::f64::consts::PI / 5.0;
                    let rr = if i % 2 == 0 { 1.3 * r } else { 0.55 * r };
                    Point2::new(p.x + rr * a.cos(), p.y + y_up * rr * a.sin())
                })
                .collect();
            format!("<polygon points=\"{}\" {style}/>", Picture::points(&pts))
        }
        Marker::Cross => {
            let w = 1.6 * r;
            let (_, stroke, _, _) = layer.look();
            format!(
                "<path d=\"M{} {}L{} {}M{} {}L{} {}\" stroke=\"{stroke}\" stroke-width=\"{}\" fill=\"none\"/>",
                fmt(p.x - w / 2.0),
                fmt(p.y - w / 2.0),
                fmt(p.x + w / 2.0),
                fmt(p.y + w / 2.0),
                fmt(p.x - w / 2.0),
                fmt(p.y + w / 2.0),
                fmt(p.x + w / 2.0),
                fmt(p.y - w / 2.0),
                fmt(2.5 * unit)
            )
        }
    }
}
