//! Pictures rendered to pixels (resvg) and checked for what must be visible: the obstacle grey
//! inside obstacles, the tether's colour on the chosen taut tether, the blocking anchor of an
//! infeasible class marked, a window that crops and magnifies, and stability dots coloured by
//! margin on the colour scale (the largest margin at the scale's bright end, the smallest at its
//! dark end, unstable poses hollow). Pixel positions come from the SVG's own map viewport
//! (`<svg id="rappel-map" ... viewBox=...>`), colours from the documented legend; set
//! `RAPPEL_RENDER_DIR` to keep the PNGs for looking at.

use nalgebra::Point2;
use rappel::geometry::polygon::Aabb;
use rappel::plan::{PlanOptions, plan_detailed};
use rappel::scenario::Scenario;
use rappel::stability::{StabilityOptions, stability_over_scenario};

/// The obstacle grey, the tether blue and the blocking red of the legend (`rappel_render::style`).
const OBSTACLE: [u8; 3] = [0x8c, 0x8c, 0x8c];
const TETHER: [u8; 3] = [0x08, 0x30, 0x6b];
const BLOCKING: [u8; 3] = [0xcb, 0x18, 0x1d];
/// Viridis at its ends (matplotlib's definition), the colour scale of margins.
const VIRIDIS_LOW: [u8; 3] = [68, 1, 84];
const VIRIDIS_HIGH: [u8; 3] = [253, 231, 37];

fn fixture(name: &str) -> Scenario {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures")
        .join(name);
    Scenario::load(&path).expect("fixture loads")
}

/// A rendered picture and the map-frame-to-pixel transform read from its SVG.
struct Rendered {
    pixmap: resvg::tiny_skia::Pixmap,
    /// (x, y, width, height) of the map viewport in px, and its viewBox (min x, min y, w, h).
    viewport: [f64; 4],
    view_box: [f64; 4],
}

fn attr(tag: &str, name: &str) -> String {
    let key = format!(" {name}=\"");
    let i = tag
        .find(&key)
        .unwrap_or_else(|| panic!("no {name} in {tag}"))
        + key.len();
    tag[i..i + tag[i..].find('"').expect("closing quote")].to_string()
}

fn render(svg: &str, name: &str) -> Rendered {
    let tree = resvg::usvg::Tree::from_str(svg, &resvg::usvg::Options::default()).expect("SVG");
    let size = tree.size().to_int_size();
    let mut pixmap = resvg::tiny_skia::Pixmap::new(size.width(), size.height()).expect("size");
    resvg::render(
        &tree,
        resvg::tiny_skia::Transform::default(),
        &mut pixmap.as_mut(),
    );
    if let Ok(dir) = std::env::var("RAPPEL_RENDER_DIR") {
        pixmap
            .save_png(std::path::Path::new(&dir).join(format!("{name}.png")))
            .expect("PNG written");
    }
    let start = svg.find("<svg id=\"rappel-map\"").expect("map viewport");
    let tag = &svg[start..start + svg[start..].find('>').expect("tag end")];
    let num = |s: &str| s.parse::<f64>().expect("number");
    let viewport = ["x", "y", "width", "height"].map(|a| num(&attr(tag, a)));
    let vb: Vec<f64> = attr(tag, "viewBox").split(' ').map(num).collect();
    Rendered {
        pixmap,
        viewport,
        view_box: [vb[0], vb[1], vb[2], vb[3]],
    }
}

impl Rendered {
    /// The pixel of a map-frame point (the map is drawn with y flipped: uphill at the top).
    fn pixel_of(&self, p: Point2<f64>) -> (i64, i64) {
        let [x0, y0, w, h] = self.viewport;
        let [bx, by, bw, bh] = self.view_box;
        let px = x0 + (p.x - bx) * w / bw;
        let py = y0 + (-p.y - by) * h / bh;
        (px.floor() as i64, py.floor() as i64)
    }

    /// Pixels per metre.
    fn scale(&self) -> f64 {
        self.viewport[2] / self.view_box[2]
    }

    fn rgb(&self, x: i64, y: i64) -> Option<[u8; 3]> {
        let (x, y) = (u32::try_from(x).ok()?, u32::try_from(y).ok()?);
        let c = self.pixmap.pixel(x, y)?.demultiply();
        Some([c.red(), c.green(), c.blue()])
    }

    /// Whether a pixel within `r` px of `p` has `colour` (each channel within `tol`).
    fn shows_near(&self, p: Point2<f64>, r: i64, colour: [u8; 3], tol: u8) -> bool {
        let (cx, cy) = self.pixel_of(p);
        (-r..=r).any(|dx| {
            (-r..=r).any(|dy| {
                self.rgb(cx + dx, cy + dy)
                    .is_some_and(|c| c.iter().zip(colour).all(|(a, b)| a.abs_diff(b) <= tol))
            })
        })
    }
}

#[test]
fn plan_pictures_show_obstacles_the_tether_and_the_blocking_anchor() {
    let s = fixture("plan/shortest-infeasible.ron");
    let plan = plan_detailed(&s.validate().expect("valid"), &PlanOptions::default()).expect("plan");
    let svg = rappel_render::plan::picture(&plan, &s, None);
    let r = render(&svg, "plan-shortest-infeasible");
    // The obstacle's centroid is grey, whatever lies under it (sleeve, cones, BTM edges).
    let centroid = Point2::new((40.0 + 65.0 + 45.0) / 3.0, (85.0 + 40.0 + 40.0) / 3.0);
    assert!(
        r.shows_near(centroid, 0, OBSTACLE, 2),
        "obstacle grey at {centroid}"
    );
    // The chosen class (rank 2) passes east of the obstacle: its first tether segment, start to
    // the anchor (65, 40), is drawn in the tether's colour at its middle.
    let chosen = plan.report.outcome.chosen.as_ref().expect("a pair");
    assert_eq!(chosen.rank, 2);
    let c2 = &plan.report.classes[1];
    let mid = Point2::from((c2.points[0].coords + c2.points[1].coords) / 2.0);
    assert!(r.shows_near(mid, 1, TETHER, 24), "tether colour at {mid}");
    // Class 1 is blocked at its anchor 1, (40, 85): marked in the blocking red.
    assert!(!plan.report.classes[0].feasible);
    assert!(r.shows_near(Point2::new(40.0, 85.0), 2, BLOCKING, 24));
    // ...and not the obstacle grey everywhere: a free point away from everything is white.
    assert!(r.shows_near(Point2::new(5.0, 60.0), 0, [255, 255, 255], 2));

    // A window around the obstacle crops and magnifies: more pixels per metre, the same grey.
    let window = Aabb {
        min: Point2::new(30.0, 30.0),
        max: Point2::new(70.0, 95.0),
    };
    let cropped = render(
        &rappel_render::plan::picture(&plan, &s, Some(&window)),
        "plan-window",
    );
    assert!(
        cropped.scale() > 1.5 * r.scale(),
        "{} vs {}",
        cropped.scale(),
        r.scale()
    );
    assert!(cropped.shows_near(centroid, 0, OBSTACLE, 2));
    assert!(cropped.shows_near(mid, 1, TETHER, 24));
    // The start (50, 100) lies outside the window: its red cross is clipped away.
    let (_, y_start) = cropped.pixel_of(Point2::new(50.0, 100.0));
    assert!(y_start < cropped.viewport[1] as i64);
}

#[test]
fn stability_dots_are_coloured_by_margin_and_leave_obstacles_visible() {
    let s = fixture("online-example.ron");
    let options = StabilityOptions {
        grid_step: 4.0,
        tension_limit: Some(300.0),
        ..Default::default()
    };
    let report = stability_over_scenario(s.validate().expect("valid scenario"), &options)
        .expect("stability map");
    let r = render(
        &rappel_render::stability::picture(&report, &s, None, "stability"),
        "stability-online-example",
    );
    let stable: Vec<_> = report.dots.iter().filter(|d| d.margin.is_some()).collect();
    assert!(stable.len() >= 2, "need stable poses with margins");
    let by_margin = |a: &&&rappel::stability::StabilityDot,
                     b: &&&rappel::stability::StabilityDot| {
        a.margin.partial_cmp(&b.margin).expect("finite margins")
    };
    let best = stable.iter().max_by(by_margin).expect("one");
    let worst = stable.iter().min_by(by_margin).expect("one");
    assert!(
        r.shows_near(best.point, 0, VIRIDIS_HIGH, 6),
        "best margin bright"
    );
    assert!(
        r.shows_near(worst.point, 0, VIRIDIS_LOW, 6),
        "worst margin dark"
    );
    // An unstable pose is a ring: its centre shows the background, not a filled red disc.
    if let Some(u) = report.dots.iter().find(|d| !d.stable) {
        assert!(
            r.shows_near(u.point, 0, [255, 255, 255], 2),
            "hollow unstable dot"
        );
    }
    // The dots are sized to the grid step: a disc's edge is about 0.45 step from its centre, so
    // a point 0.3 step to the side of the best dot still has its colour, and no dot swallows an
    // obstacle: both obstacles' centroids stay grey.
    let side = Point2::new(best.point.x + 0.3 * options.grid_step, best.point.y);
    assert!(r.shows_near(side, 0, VIRIDIS_HIGH, 6));
    for c in [Point2::new(47.0 / 3.0, 37.0), Point2::new(77.0 / 3.0, 21.0)] {
        assert!(r.shows_near(c, 0, OBSTACLE, 2), "obstacle grey at {c}");
    }
}

/// A `--window` crop writes only what can be seen: on the 1,000-obstacle strip a 20 m window
/// round the 500th obstacle holds a few, not all of them, and every obstacle that does meet the window is
/// drawn (its vertices appear in the SVG).
#[test]
fn a_window_writes_only_the_obstacles_it_shows() {
    let s = fixture("generated/crater-strip-1000.ron");
    let btm = rappel::geometry::btm::Btm::from_map(&s.map).unwrap();
    let b = Aabb::of_points(&s.map.obstacles[500].vertices);
    let c = Point2::new(0.5 * (b.min.x + b.max.x), 0.5 * (b.min.y + b.max.y));
    let window = Aabb {
        min: Point2::new(c.x - 10.0, c.y - 10.0),
        max: Point2::new(c.x + 10.0, c.y + 10.0),
    };
    let draw = |w: Option<&Aabb>| {
        let mut pic = match w {
            Some(w) => rappel_render::Picture::new(*w),
            None => rappel_render::Picture::of_map(&s.map),
        };
        pic.btm(&btm);
        pic.map(&s.map);
        pic.finish("crop")
    };
    let (whole, crop) = (draw(None), draw(Some(&window)));
    let count = |svg: &str| svg.matches("<polygon").count();
    assert!(count(&whole) > s.map.obstacles.len(), "{}", count(&whole));
    assert!(
        count(&crop) < count(&whole) / 10,
        "{} of {}",
        count(&crop),
        count(&whole)
    );
    assert!(
        crop.len() * 10 < whole.len(),
        "{} bytes of {}",
        crop.len(),
        whole.len()
    );
    let meets = |o: &rappel::geometry::polygon::Polygon| {
        let b = Aabb::of_points(&o.vertices);
        b.min.x <= window.max.x
            && b.max.x >= window.min.x
            && b.min.y <= window.max.y
            && b.max.y >= window.min.y
    };
    let shown = s.map.obstacles.iter().filter(|o| meets(o)).count();
    assert!(shown > 0);
    assert!(
        count(&crop) > shown,
        "{} drawn, {shown} meet the window",
        count(&crop)
    );
}
