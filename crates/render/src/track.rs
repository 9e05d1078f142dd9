//! Pictures of `rappel track` (Kumar Figs. 6-8): the unfolded frame with both robots' paths and
//! the tether at every waypoint, and the 3D view of the multi-slope terrain.

use nalgebra::Point2;
use rappel::track::TrackReport;
use rappel_terrain::multi_slope::MultiSlopeTerrain;
use rappel_terrain::surface::Terrain;

/// An SVG of the unfolded frame: surfaces, obstacles, the paths and the final tether.
pub fn track_picture(
    terrain: &MultiSlopeTerrain,
    path1: &[Point2<f64>],
    path2: &[Point2<f64>],
    report: &TrackReport,
) -> String {
    let polys = terrain.frame_polygons();
    let Frame {
        x0,
        y1,
        w,
        h,
        scale,
    } = Frame::of(polys.iter().flat_map(|p| p.vertices.iter()));
    let tx = |p: &Point2<f64>| {
        format!(
            "{:.2},{:.2}",
            (p.x - x0) * scale + 20.0,
            (y1 - p.y) * scale + 20.0
        )
    };
    let poly = |pts: &[Point2<f64>], style: &str| {
        let s: Vec<String> = pts.iter().map(tx).collect();
        format!("<polygon points=\"{}\" {style}/>\n", s.join(" "))
    };
    let line = |pts: &[Point2<f64>], style: &str| {
        let s: Vec<String> = pts.iter().map(tx).collect();
        format!(
            "<polyline points=\"{}\" fill=\"none\" {style}/>\n",
            s.join(" ")
        )
    };
    let mut out = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{:.0}\" height=\"{:.0}\">\n<title>rappel track {}</title>\n",
        w * scale + 40.0,
        h * scale + 40.0,
        report.name
    );
    for (i, p) in polys.iter().enumerate() {
        let shade = 235 - (terrain.slope_rad(i).to_degrees() as i64).clamp(0, 90);
        out += &poly(
            &p.vertices,
            &format!("fill=\"rgb({shade},{shade},{shade})\" stroke=\"#888\""),
        );
    }
    for o in terrain.obstacles() {
        out += &poly(&o.base.vertices, "fill=\"#555\"");
    }
    out += &line(path1, "stroke=\"#1f77b4\" stroke-width=\"2\"");
    out += &line(path2, "stroke=\"#2ca02c\" stroke-width=\"2\"");
    if let Some(last) = report.waypoints.last() {
        let pts: Vec<Point2<f64>> = last.configuration.iter().map(|a| a.point).collect();
        out += &line(
            &pts,
            "stroke=\"#d62728\" stroke-width=\"1.5\" stroke-dasharray=\"4 2\"",
        );
    }
    for w in &report.waypoints {
        let color = if w.stable { "#2ca02c" } else { "#d62728" };
        out += &format!(
            "<circle cx=\"{}\" cy=\"{}\" r=\"3\" fill=\"{color}\"/>\n",
            (w.position.x - x0) * scale + 20.0,
            (y1 - w.position.y) * scale + 20.0
        );
    }
    out += "</svg>\n";
    out
}

/// An axonometric (isometric) SVG of the folded terrain: surfaces shaded by slope, obstacles as
/// prisms, both paths on the ground and the final tether in 3D.
pub fn track_picture_3d(
    terrain: &MultiSlopeTerrain,
    path1: &[Point2<f64>],
    path2: &[Point2<f64>],
    report: &TrackReport,
) -> String {
    use nalgebra::Point3;
    let (c30, s30) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
    let project = |q: &Point3<f64>| Point2::new((q.x - q.y) * c30, (q.x + q.y) * s30 + q.z);
    let fold_all = |pts: &[Point2<f64>]| -> Vec<Point3<f64>> {
        pts.iter().filter_map(|p| terrain.world(p)).collect()
    };
    let mut faces: Vec<(Vec<Point3<f64>>, String)> = Vec::new();
    for (i, poly) in terrain.frame_polygons().iter().enumerate() {
        let shade = 235 - (terrain.slope_rad(i).to_degrees() as i64).clamp(0, 90);
        let pts = poly.vertices.iter().map(|p| terrain.fold(i, p)).collect();
        faces.push((
            pts,
            format!("fill=\"rgb({shade},{shade},{shade})\" stroke=\"#888\""),
        ));
    }
    for o in terrain.obstacles() {
        let n = terrain.normal(o.surface) * o.height;
        let base: Vec<Point3<f64>> = o
            .base
            .vertices
            .iter()
            .map(|p| terrain.fold(o.surface, p))
            .collect();
        for k in 0..base.len() {
            let (a, b) = (base[k], base[(k + 1) % base.len()]);
            faces.push((
                vec![a, b, b + n, a + n],
                "fill=\"#777\" stroke=\"#333\"".into(),
            ));
        }
        faces.push((
            base.iter().map(|p| p + n).collect(),
            "fill=\"#555\" stroke=\"#333\"".into(),
        ));
    }
    let lines: Vec<(Vec<Point3<f64>>, &str)> = vec![
        (fold_all(path1), "stroke=\"#1f77b4\" stroke-width=\"2\""),
        (fold_all(path2), "stroke=\"#2ca02c\" stroke-width=\"2\""),
        (
            report
                .waypoints
                .last()
                .map(|w| w.configuration.iter().map(|a| a.world).collect())
                .unwrap_or_default(),
            "stroke=\"#d62728\" stroke-width=\"1.5\" stroke-dasharray=\"4 2\"",
        ),
    ];
    let all: Vec<Point2<f64>> = faces
        .iter()
        .flat_map(|f| f.0.iter())
        .chain(lines.iter().flat_map(|l| l.0.iter()))
        .map(project)
        .collect();
    let Frame {
        x0,
        y1,
        w,
        h,
        scale,
    } = Frame::of(all.iter());
    let tx = |q: &Point3<f64>| {
        let p = project(q);
        format!(
            "{:.2},{:.2}",
            (p.x - x0) * scale + 20.0,
            (y1 - p.y) * scale + 20.0
        )
    };
    let mut out = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{:.0}\" height=\"{:.0}\">\n<title>rappel track {} (3D)</title>\n",
        w * scale + 40.0,
        h * scale + 40.0,
        report.name
    );
    for (pts, style) in &faces {
        let s: Vec<String> = pts.iter().map(tx).collect();
        out += &format!("<polygon points=\"{}\" {style}/>\n", s.join(" "));
    }
    for (pts, style) in &lines {
        let s: Vec<String> = pts.iter().map(tx).collect();
        out += &format!(
            "<polyline points=\"{}\" fill=\"none\" {style}/>\n",
            s.join(" ")
        );
    }
    out += "</svg>\n";
    out
}

/// The drawing box of a picture: the points' bounds scaled to 800 px on the longer side.
struct Frame {
    x0: f64,
    y1: f64,
    w: f64,
    h: f64,
    scale: f64,
}

impl Frame {
    fn of<'p>(points: impl Iterator<Item = &'p Point2<f64>>) -> Frame {
        let (mut x0, mut y0, mut x1, mut y1) = (f64::MAX, f64::MAX, f64::MIN, f64::MIN);
        for p in points {
            x0 = x0.min(p.x);
            y0 = y0.min(p.y);
            x1 = x1.max(p.x);
            y1 = y1.max(p.y);
        }
        let (w, h) = ((x1 - x0).max(1e-9), (y1 - y0).max(1e-9));
        Frame {
            x0,
            y1,
            w,
            h,
            scale: 800.0 / w.max(h),
        }
    }
}
