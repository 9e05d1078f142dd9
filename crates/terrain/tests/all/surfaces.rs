//! The `Terrain` trait's two implementations agree: a multi-slope terrain built from the 3D
//! rectangles of a plane series folds, unfolds, tilts and classifies its edges as the plane series'
//! closed form does; fold and unfold are inverse isometries; bad surfaces are typed errors naming
//! the surface.

use nalgebra::{Point2, Point3};
use proptest::prelude::*;
use rappel_terrain::multi_slope::{MultiSlopeError, MultiSlopeTerrain, ObstacleSpec, SurfaceSpec};
use rappel_terrain::plane_series::TerrainPlane;
use rappel_terrain::plane_series_terrain::PlaneSeriesTerrain;
use rappel_terrain::surface::{EdgeKind, Terrain};

/// The 3D rectangles of a plane series across `x` in `[0, w]`, each surface listed so that its
/// first vertex is on its upper edge.
fn rectangles(planes: &[TerrainPlane], w: f64) -> Vec<SurfaceSpec> {
    let (mut y, mut z) = (planes[0].y_top, 0.0);
    let mut out = Vec::new();
    for p in planes {
        let d = p.y_top - p.y_bottom;
        let (s, c) = p.slope_rad().sin_cos();
        let (y2, z2) = (y - d * c, z - d * s);
        let v = if out.is_empty() {
            // Surface 0: first edge along +x at its lower edge, so the frame matches the series'
            // frame shifted by y_bottom.
            vec![
                Point3::new(0.0, y2, z2),
                Point3::new(w, y2, z2),
                Point3::new(w, y, z),
                Point3::new(0.0, y, z),
            ]
        } else {
            vec![
                Point3::new(0.0, y, z),
                Point3::new(0.0, y2, z2),
                Point3::new(w, y2, z2),
                Point3::new(w, y, z),
            ]
        };
        out.push(SurfaceSpec {
            vertices: v,
            friction: p.friction,
        });
        (y, z) = (y2, z2);
    }
    out
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn multi_slope_agrees_with_the_plane_series(
        slopes in proptest::collection::vec(0.0f64..85.0, 1..5),
        lengths in proptest::collection::vec(1.0f64..20.0, 5),
        x in 0.0f64..10.0,
        t in 0.0f64..1.0,
    ) {
        let mut top = 0.0;
        let planes: Vec<TerrainPlane> = slopes.iter().enumerate().map(|(i, s)| {
            let p = TerrainPlane::new(top, top - lengths[i], *s, 0.4);
            top -= lengths[i];
            p
        }).collect();
        let series = PlaneSeriesTerrain::new(&planes, (0.0, 10.0), vec![]).unwrap();
        let multi = MultiSlopeTerrain::new(rectangles(&planes, 10.0), vec![]).unwrap();
        // The multi-slope frame is the series' frame shifted by the top plane's lower edge.
        let shift = planes[0].y_bottom;
        let y = planes[0].y_top + t * (top - planes[0].y_top);
        let ps = Point2::new(x, y);
        let pm = Point2::new(x, y - shift);
        let (s1, s2) = (series.surface_at(&ps).unwrap(), multi.surface_at(&pm).unwrap());
        prop_assert_eq!(s1, s2);
        let (w1, w2) = (series.fold(s1, &ps), multi.fold(s2, &pm));
        // World frames differ by the series' convention (Y = y on the top plane's upper edge).
        let off = series.fold(0, &Point2::new(0.0, planes[0].y_top))
            - multi.fold(0, &Point2::new(0.0, planes[0].y_top - shift));
        prop_assert!((w1 - (w2 + off)).norm() < 1e-9 * (1.0 + w1.coords.norm()));
        prop_assert!((multi.unfold(s2, &w2) - pm).norm() < 1e-9 * (1.0 + pm.coords.norm()));
        prop_assert!((series.slope_rad(s1) - multi.slope_rad(s2)).abs() < 1e-9);
        for (a, b) in series.edges().iter().zip(multi.edges()) {
            prop_assert_eq!(a.kind, b.kind);
            prop_assert!((a.bend - b.bend).abs() < 1e-9);
        }
    }
}

#[test]
fn crest_and_valley_edges() {
    let planes = [
        TerrainPlane::new(20.0, 10.0, 0.0, 0.4),
        TerrainPlane::new(10.0, 5.0, 40.0, 0.4),
        TerrainPlane::new(5.0, 0.0, 10.0, 0.4),
    ];
    let multi = MultiSlopeTerrain::new(rectangles(&planes, 10.0), vec![]).unwrap();
    let kinds: Vec<EdgeKind> = multi.edges().iter().map(|e| e.kind).collect();
    assert_eq!(kinds, vec![EdgeKind::Crest, EdgeKind::Valley]);
}

#[test]
fn bad_surfaces_and_obstacles_are_typed_errors_naming_them() {
    let planes = [
        TerrainPlane::new(20.0, 10.0, 0.0, 0.4),
        TerrainPlane::new(10.0, 0.0, 40.0, 0.4),
    ];
    let good = rectangles(&planes, 10.0);
    // A surface sharing no edge with the one before.
    let mut s = good.clone();
    for v in &mut s[1].vertices {
        v.x += 50.0;
    }
    assert_eq!(
        MultiSlopeTerrain::new(s, vec![]),
        Err(MultiSlopeError::NoSharedEdge { surface: 1 })
    );
    // A vertex off the plane.
    let mut s = good.clone();
    s[1].vertices[2].z += 1.0;
    assert!(matches!(
        MultiSlopeTerrain::new(s, vec![]),
        Err(MultiSlopeError::NotPlanar { surface: 1, .. })
    ));
    // Degenerate: collinear vertices.
    let mut s = good.clone();
    s[0].vertices = vec![
        Point3::origin(),
        Point3::new(1.0, 0.0, 0.0),
        Point3::new(2.0, 0.0, 0.0),
    ];
    assert!(matches!(
        MultiSlopeTerrain::new(s, vec![]),
        Err(MultiSlopeError::Degenerate { surface: 0 })
    ));
    // Not finite.
    let mut s = good.clone();
    s[1].vertices[0].y = f64::NAN;
    assert_eq!(
        MultiSlopeTerrain::new(s, vec![]),
        Err(MultiSlopeError::NonFinite { surface: 1 })
    );
    // An obstacle off its surface, and one with no height.
    let ob = |base: Vec<Point3<f64>>, height| ObstacleSpec {
        surface: 0,
        base,
        height,
        friction: 0.4,
    };
    let sq = |x: f64, y: f64| {
        vec![
            Point3::new(x, y, 0.0),
            Point3::new(x + 1.0, y, 0.0),
            Point3::new(x + 1.0, y + 1.0, 0.0),
            Point3::new(x, y + 1.0, 0.0),
        ]
    };
    assert!(matches!(
        MultiSlopeTerrain::new(
            good.clone(),
            vec![ob(sq(2.0, 12.0), 1.0), ob(sq(20.0, 12.0), 1.0)]
        ),
        Err(MultiSlopeError::Obstacle { obstacle: 1, .. })
    ));
    assert!(matches!(
        MultiSlopeTerrain::new(good.clone(), vec![ob(sq(2.0, 12.0), 0.0)]),
        Err(MultiSlopeError::Obstacle { obstacle: 0, .. })
    ));
    assert!(MultiSlopeTerrain::new(good, vec![ob(sq(2.0, 12.0), 1.0)]).is_ok());
    assert_eq!(
        MultiSlopeTerrain::new(vec![], vec![]),
        Err(MultiSlopeError::SurfaceCount(0))
    );
}
