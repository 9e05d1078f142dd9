//! The picture of `rappel navigate`: the ledge scene from above, the sampled rover poses, the
//! path found and its anchors.

use rappel::navigate::{NavigateReport, RoverProblem};

use crate::{Layer, Picture};

/// A top-down picture of a run: the sampled region's outline, the path (settled origins), the
/// tether from the root through the anchors to the path's end, the anchors (squares), the
/// start and the goal.
pub fn navigate_svg(problem: &RoverProblem, report: &NavigateReport) -> String {
    use nalgebra::Point2;
    use rappel_geometry::polygon::Aabb;
    let (lo, hi) = (problem.space.lo, problem.space.hi);
    let r = problem.root;
    let bounds = Aabb {
        min: Point2::new(lo[0].min(r.x) - 0.5, lo[1].min(r.y) - 0.5),
        max: Point2::new(hi[0].max(r.x) + 0.5, hi[1].max(r.y) + 0.5),
    };
    let mut pic = Picture::new(bounds);
    crate::relief::draw_relief(&mut pic, &problem.ground, &bounds);
    pic.set_fall_line(crate::relief::fall_line(&problem.ground));
    let outline = [
        Point2::new(lo[0], lo[1]),
        Point2::new(hi[0], lo[1]),
        Point2::new(hi[0], hi[1]),
        Point2::new(lo[0], hi[1]),
        Point2::new(lo[0], lo[1]),
    ];
    pic.polyline(Layer::Boundary, &outline);
    let flat = |p: &[f64; 3]| Point2::new(p[0], p[1]);
    let path: Vec<_> = report.path.iter().map(flat).collect();
    pic.polyline(Layer::Path, &path);
    if let Some(end) = report.path.last() {
        let mut tether: Vec<_> = report.anchors.iter().map(flat).collect();
        tether.push(flat(end));
        pic.polyline(Layer::Shp, &tether);
    }
    for (k, a) in report.anchors.iter().enumerate() {
        pic.titled_marker(
            Layer::Anchor,
            flat(a),
            &format!("anchor {k} ({:.2}, {:.2}, {:.2})", a[0], a[1], a[2]),
        );
    }
    if report.anchors.is_empty() {
        pic.titled_marker(
            Layer::Anchor,
            Point2::new(r.x, r.y),
            &format!("root anchor ({:.2}, {:.2}, {:.2})", r.x, r.y, r.z),
        );
    }
    let (s, g) = (problem.start, problem.goal);
    pic.marker(Layer::Start, Point2::new(s.x, s.y));
    pic.marker(Layer::Goal, Point2::new(g.x, g.y));
    pic.finish(&if report.found {
        format!(
            "rover path, seed {}: cost {:.2}, {} anchors",
            report.seed,
            report.cost.unwrap_or(f64::NAN),
            report.anchors.len()
        )
    } else {
        format!(
            "no path, seed {} ({} iterations)",
            report.seed, report.iterations
        )
    })
}
