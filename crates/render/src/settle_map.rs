//! The picture of `rappel settle-map` (Paton Fig. 8): every assessed cell of the stability map
//! coloured by its margin over the mesh's outline, the root anchor, the start and the drive.

use nalgebra::Point2;
use rappel::planners::rover::stability_map::StabilityMap;
use rappel_geometry::polygon::Aabb;
use rappel_terrain::mesh::TriMesh;

use crate::style::scale_colour;
use crate::{Layer, Picture};

/// A top-down picture of a map like Paton's Fig. 8: stable cells coloured by their margin on the
/// colour scale of every stability picture ([`crate::style::SCALE_STOPS`], drawn in the panel),
/// unstable ones grey, cells that did not settle left blank, the ground mesh's creases
/// (edges between triangles more than 1° apart) as plane edges, the start, the root anchor and
/// the distinct last anchors (squares).
pub fn map_svg(map: &StabilityMap, ground: &TriMesh) -> String {
    let h = 0.5 * map.spec.step;
    let bounds = Aabb {
        min: Point2::new(map.spec.x.0 - h, map.spec.y.0 - h),
        max: Point2::new(map.spec.x.1 + h, map.spec.y.1 + h),
    };
    let mut pic = Picture::new(bounds);
    crate::relief::draw_relief(&mut pic, ground, &bounds);
    pic.set_fall_line(crate::relief::fall_line(ground));
    let margins = map
        .cells
        .iter()
        .filter_map(|c| c.pose.as_ref())
        .filter(|p| p.stable)
        .map(|p| p.margin);
    let lo = margins.clone().fold(f64::INFINITY, f64::min);
    let hi = margins.fold(f64::NEG_INFINITY, f64::max);
    for c in &map.cells {
        let Some(p) = &c.pose else { continue };
        let sq = [
            Point2::new(c.ground[0] - h, c.ground[1] - h),
            Point2::new(c.ground[0] + h, c.ground[1] - h),
            Point2::new(c.ground[0] + h, c.ground[1] + h),
            Point2::new(c.ground[0] - h, c.ground[1] + h),
        ];
        if p.stable {
            let t = if hi > lo {
                (p.margin - lo) / (hi - lo)
            } else {
                1.0
            };
            pic.shaded_polygon(Layer::StableCell, &sq, &scale_colour(t));
        } else {
            pic.polygon(Layer::UnstableCell, &sq);
        }
    }
    if lo.is_finite() && hi.is_finite() {
        pic.set_colour_scale("stability margin, N", lo, hi);
    }
    // Creases of the ground within the picture.
    let (v, t) = (ground.vertices(), ground.triangles());
    if t.len() <= 20_000 {
        let mut edges: std::collections::HashMap<(usize, usize), Vec<usize>> = Default::default();
        for (k, tri) in t.iter().enumerate() {
            for e in 0..3 {
                let (a, b) = (tri[e], tri[(e + 1) % 3]);
                edges.entry((a.min(b), a.max(b))).or_default().push(k);
            }
        }
        let mut segs = Vec::new();
        let mut keys: Vec<_> = edges.keys().copied().collect();
        keys.sort_unstable();
        for key in keys {
            let f = &edges[&key];
            let crease = f.len() != 2
                || ground.face_normal(f[0]).dot(&ground.face_normal(f[1]))
                    < 1f64.to_radians().cos();
            if crease {
                segs.push((
                    Point2::new(v[key.0].x, v[key.0].y),
                    Point2::new(v[key.1].x, v[key.1].y),
                ));
            }
        }
        for (a, b) in segs {
            pic.polyline(Layer::PlaneEdge, &[a, b]);
        }
    }
    let mut seen: Vec<[f64; 3]> = Vec::new();
    for c in &map.cells {
        if let Some(p) = &c.pose
            && p.anchors.len() > 1
        {
            let a = *p.anchors.last().expect("non-empty");
            if !seen
                .iter()
                .any(|s| (s[0] - a[0]).abs() + (s[1] - a[1]).abs() < map.spec.step)
            {
                seen.push(a);
            }
        }
    }
    for a in seen {
        pic.titled_marker(
            Layer::Anchor,
            Point2::new(a[0], a[1]),
            &format!("last anchor ({:.2}, {:.2}, {:.2})", a[0], a[1], a[2]),
        );
    }
    pic.titled_marker(
        Layer::Anchor,
        Point2::new(map.root[0], map.root[1]),
        &format!(
            "root anchor ({:.2}, {:.2}, {:.2})",
            map.root[0], map.root[1], map.root[2]
        ),
    );
    pic.marker(
        Layer::Start,
        Point2::new(map.spec.start[0], map.spec.start[1]),
    );
    pic.finish(&format!(
        "stability map: {} stable, {} unstable, {} not settled or unreached",
        map.stable, map.unstable, map.failed
    ))
}
