//! Axonometric SVG pictures of 3D scenes: the thesis' Fig. 3.14 hill view
//! ([`crate::dem::hill_view`]) and settled rover poses
//! ([`crate::settle::settled_pose_picture`]). One view for all: from the south-west, 30° above
//! the horizon, at true vertical scale, fitted to a 900-pixel square. Shapes are drawn in the
//! order they are added, in named groups; callers draw surfaces back to front by sorting them on
//! [`Axonometric::depth`] (larger is farther).

use nalgebra::{Point2, Point3};
use std::fmt::Write;

/// Largest side of the drawing, pixels.
const SIZE_PX: f64 = 900.0;

/// One shape: its 3D points, closed (polygon) or open (polyline), and its SVG attributes.
#[derive(Debug, Clone)]
struct Shape {
    points: Vec<Point3<f64>>,
    closed: bool,
    attributes: String,
}

/// An axonometric picture being drawn.
///
/// ```
/// use nalgebra::Point3;
/// use rappel_render::axonometric::Axonometric;
/// let mut a = Axonometric::default();
/// a.group("ground");
/// a.polygon(
///     &[Point3::origin(), Point3::new(1.0, 0.0, 0.0), Point3::new(0.0, 1.0, 0.5)],
///     "fill=\"#ccc\"",
/// );
/// let svg = a.render("a triangle");
/// assert!(svg.contains("<g id=\"ground\">") && svg.contains("<polygon"));
/// ```
#[derive(Debug, Clone, Default)]
pub struct Axonometric {
    groups: Vec<(String, Vec<Shape>)>,
    /// Legend entries: a label and the SVG attributes its swatch is drawn with.
    legend: Vec<(String, String)>,
}

impl Axonometric {
    /// How far back a point lies in the view (larger is farther): sort surfaces on it, largest
    /// first, to draw them back to front.
    pub fn depth(q: &Point3<f64>) -> f64 {
        q.x + q.y
    }

    /// The view's projection of `q` (plane coordinates, `y` up).
    pub fn project(q: &Point3<f64>) -> Point2<f64> {
        let (c30, s30) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
        Point2::new((q.x - q.y) * c30, (q.x + q.y) * s30 * 0.5 + q.z)
    }

    /// Starts the group `id` (an SVG `<g id>`): the shapes added next belong to it.
    pub fn group(&mut self, id: &str) {
        self.groups.push((id.to_string(), Vec::new()));
    }

    fn push(&mut self, points: &[Point3<f64>], closed: bool, attributes: &str) {
        if self.groups.is_empty() {
            self.group("shapes");
        }
        if let Some((_, shapes)) = self.groups.last_mut() {
            shapes.push(Shape {
                points: points.to_vec(),
                closed,
                attributes: attributes.to_string(),
            });
        }
    }

    /// A filled polygon with the SVG `attributes` (e.g. `fill="…" stroke="…"`).
    pub fn polygon(&mut self, points: &[Point3<f64>], attributes: &str) {
        self.push(points, true, attributes);
    }

    /// A surface polygon shaded grey by its slope: `cos_slope` is the cosine of its tilt from
    /// level (1: level, drawn lightest; 0: vertical, darkest), filled and outlined in that grey.
    pub fn shaded_polygon(&mut self, points: &[Point3<f64>], cos_slope: f64) {
        let shade = (110.0 + 130.0 * cos_slope.clamp(0.0, 1.0)) as u8;
        self.polygon(
            points,
            &format!(
                "fill=\"rgb({shade},{shade},{shade})\" stroke=\"rgb({shade},{shade},{shade})\" stroke-width=\"0.5\""
            ),
        );
    }

    /// A legend entry: `label` beside a swatch drawn with the same SVG `attributes` as its shapes
    /// (a filled box when they fill, a line otherwise), so the legend shows what is drawn.
    pub fn legend(&mut self, label: &str, attributes: &str) {
        self.legend
            .push((label.to_string(), attributes.to_string()));
    }

    /// An open polyline (not filled) with the SVG `attributes` (e.g. `stroke="…"`).
    pub fn polyline(&mut self, points: &[Point3<f64>], attributes: &str) {
        self.push(points, false, attributes);
    }

    /// The SVG document: every shape fitted into the drawing, under `title`.
    pub fn render(&self, title: &str) -> String {
        let (mut x0, mut x1, mut y0, mut y1) = (
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        );
        for s in self.groups.iter().flat_map(|g| &g.1) {
            for p in s.points.iter().map(Self::project) {
                (x0, x1, y0, y1) = (x0.min(p.x), x1.max(p.x), y0.min(p.y), y1.max(p.y));
            }
        }
        if !x0.is_finite() {
            (x0, x1, y0, y1) = (0.0, 1.0, 0.0, 1.0);
        }
        let scale = SIZE_PX / (x1 - x0).max(y1 - y0).max(1e-9);
        let legend_h = 20.0 * self.legend.len() as f64;
        let (w, h) = (
            (x1 - x0) * scale + 40.0,
            (y1 - y0) * scale + 110.0 + legend_h,
        );
        let tx = |q: &Point3<f64>| {
            let p = Self::project(q);
            format!(
                "{:.2},{:.2}",
                (p.x - x0) * scale + 20.0,
                (y1 - p.y) * scale + 50.0
            )
        };
        let mut out = String::new();
        let _ = writeln!(
            out,
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w:.0}\" height=\"{h:.0}\" viewBox=\"0 0 {w:.0} {h:.0}\">"
        );
        let _ = writeln!(
            out,
            "<rect width=\"{w:.0}\" height=\"{h:.0}\" fill=\"white\"/>"
        );
        let _ = writeln!(
            out,
            "<text x=\"20\" y=\"28\" font-family=\"sans-serif\" font-size=\"15\">{}</text>",
            title.replace('&', "&amp;").replace('<', "&lt;")
        );
        for (id, shapes) in &self.groups {
            let _ = writeln!(out, "<g id=\"{id}\">");
            for s in shapes {
                let pts: Vec<String> = s.points.iter().map(tx).collect();
                let (tag, fill) = if s.closed {
                    ("polygon", "")
                } else {
                    ("polyline", " fill=\"none\"")
                };
                let _ = writeln!(
                    out,
                    "<{tag} points=\"{}\"{fill} {}/>",
                    pts.join(" "),
                    s.attributes
                );
            }
            let _ = writeln!(out, "</g>");
        }
        // The legend and a scale bar along the x axis, below the drawing.
        let mut y = (y1 - y0) * scale + 80.0;
        let _ = writeln!(
            out,
            "<g id=\"legend\" font-family=\"sans-serif\" font-size=\"13\">"
        );
        for (label, attributes) in &self.legend {
            let swatch = if attributes.contains("fill=") && !attributes.contains("fill=\"none\"") {
                format!(
                    "<rect x=\"20\" y=\"{:.0}\" width=\"20\" height=\"10\" {attributes}/>",
                    y - 10.0
                )
            } else {
                format!(
                    "<line x1=\"20\" y1=\"{0:.0}\" x2=\"40\" y2=\"{0:.0}\" {attributes}/>",
                    y - 5.0
                )
            };
            let _ = writeln!(
                out,
                "{swatch}<text x=\"48\" y=\"{y:.0}\">{}</text>",
                label.replace('&', "&amp;").replace('<', "&lt;")
            );
            y += 20.0;
        }
        let (len, px) = scale_bar(scale * Self::project(&Point3::new(1.0, 0.0, 0.0)).coords.norm());
        let _ = writeln!(
            out,
            "<path d=\"M20 {y:.0}v-6v6h{px:.1}v-6\" stroke=\"black\" stroke-width=\"2\" fill=\"none\"/><text x=\"{:.0}\" y=\"{y:.0}\">{len} m along x (true vertical scale)</text>",
            28.0 + px
        );
        let _ = writeln!(out, "</g>");
        let _ = writeln!(out, "</svg>");
        out
    }
}

/// A round scale-bar length for a drawing of `px_per_m` pixels per metre, at most 150 px long,
/// with its length in pixels.
fn scale_bar(px_per_m: f64) -> (f64, f64) {
    let len = crate::picture::round_length(150.0 / px_per_m.max(1e-12), false);
    (len, len * px_per_m)
}
