//! Pictures of `rappel track` (Kumar Figs. 6-8): the unfolded frame with both robots' paths and
//! the tether at every waypoint, and the 3D view of the multi-slope terrain.

use nalgebra::Point2;
use rappel::track::TrackReport;
use rappel_geometry::polygon::Aabb;
use rappel_terrain::multi_slope::MultiSlopeTerrain;
use rappel_terrain::surface::Terrain;

use crate::axonometric::Axonometric;
use crate::{Layer, Picture};

/// The picture of the unfolded frame (Kumar Figs. 6-7) on the shared canvas: the surfaces shaded
/// by slope, the prism obstacles, both robots' paths, the tether at the last waypoint, and every
/// waypoint of Robot 2 stable or not (hover: its tensions).
pub fn track_picture(
    terrain: &MultiSlopeTerrain,
    path1: &[Point2<f64>],
    path2: &[Point2<f64>],
    report: &TrackReport,
) -> String {
    let polys = terrain.frame_polygons();
    let bounds = Aabb::of_points(
        polys
            .iter()
            .flat_map(|p| p.vertices.iter())
            .chain(path1)
            .chain(path2),
    );
    let mut pic = Picture::new(bounds);
    for (i, p) in polys.iter().enumerate() {
        let shade = 235 - (terrain.slope_rad(i).to_degrees() as i64).clamp(0, 90);
        let grey = format!("#{shade:02x}{shade:02x}{shade:02x}");
        pic.shaded_polygon(Layer::Surface, &p.vertices, &grey);
    }
    for o in terrain.obstacles() {
        pic.polygon(Layer::Obstacle, &o.base.vertices);
    }
    pic.polyline(Layer::HoldingPath, path1);
    pic.polyline(Layer::DescendingPath, path2);
    if let Some(last) = report.waypoints.last() {
        let pts: Vec<Point2<f64>> = last.configuration.iter().map(|a| a.point).collect();
        pic.polyline(Layer::Shp, &pts);
    }
    let r = 4.0 * pic.unit();
    for w in &report.waypoints {
        let title = format!(
            "waypoint {}: {}; T2max {:.1} N, T1 limit {:.1} N",
            w.waypoint,
            if w.stable { "stable" } else { "not stable" },
            w.t2max_n,
            w.t1_limit_n
        );
        let layer = if w.stable {
            Layer::Stable
        } else {
            Layer::Unstable
        };
        pic.disc(layer, w.position, r, None, &title);
    }
    pic.finish(&format!("rappel track {}: {}", report.name, report.verdict))
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
    let mut view = Axonometric::default();
    view.group("terrain");
    for (pts, style) in &faces {
        view.polygon(pts, style);
    }
    view.group("paths");
    for (pts, style) in &lines {
        view.polyline(pts, style);
    }
    view.legend(
        "surface (darker: steeper)",
        "fill=\"rgb(200,200,200)\" stroke=\"#888\"",
    );
    view.legend("obstacle (prism)", "fill=\"#555\" stroke=\"#333\"");
    view.legend("robot 1 path (holding)", lines[0].1);
    view.legend("robot 2 path", lines[1].1);
    view.legend("tether at the last waypoint", lines[2].1);
    view.render(&format!(
        "rappel track {} (3D): {}",
        report.name, report.verdict
    ))
}
