//! Stability of settled poses with predicted anchor histories on Paton's ledge (Fig. 8): with the
//! test-1 root anchor (behind the start) the tether anchors on the lip and the slope is stable;
//! with the test-2 root (in front) nothing attaches and the slope is unstable. Bad map input is
//! a typed error.

use rappel::planners::anchor_prediction::AnchorHistory;
use rappel::planners::rover::ground::PREDICT_RESOLUTION;
use rappel::planners::rover::stability_map::{
    MapSpec, MeshStabilityError, drive_and_check, stability_map, stability_map_through_field,
};
use rappel::terrain::paton_scene::PatonScene;

fn on_lip(scene: &PatonScene, a: &[f64; 3]) -> bool {
    a[0].abs() < 2.0 * PREDICT_RESOLUTION && (a[2] - scene.height).abs() < 2.0 * PREDICT_RESOLUTION
}

#[test]
fn drives_down_the_slope_with_both_paper_anchors() {
    let scene = PatonScene::paper(false);
    let ground = scene.mesh().unwrap();
    let roots = scene.anchor_points();
    let s = scene.start();
    let x = 0.5 * scene.slope_foot_x();
    for y in [-1.0, 0.0, 1.5] {
        let one = drive_and_check(
            &ground,
            &AnchorHistory::new(roots[0]).unwrap(),
            [s.x, s.y],
            [x, y],
            0.0,
        )
        .unwrap();
        assert_eq!(one.anchors.len(), 2, "{one:?}");
        assert!(on_lip(&scene, &one.anchors[1]), "{:?}", one.anchors);
        assert!(one.stable && one.margin > 0.0, "{one:?}");
        let two = drive_and_check(
            &ground,
            &AnchorHistory::new(roots[1]).unwrap(),
            [s.x, s.y],
            [x, y],
            0.0,
        )
        .unwrap();
        assert_eq!(two.anchors.len(), 1, "{two:?}");
        assert!(!two.stable, "{two:?}");
    }
}

#[test]
fn ledge_map_shades_like_fig_8() {
    let scene = PatonScene::paper(false);
    let ground = scene.mesh().unwrap();
    let roots = scene.anchor_points();
    let spec = MapSpec::fig8(&scene);
    let foot = scene.slope_foot_x();
    // The slope past the lip (within the boom's reach of the lip the boom, swept against the
    // mesh, rests on the lip or clears the top behind it: docs/mesh.md).
    let slope = |x: f64| x > 0.0 && x < foot - 0.3;
    let one = stability_map(&ground, &AnchorHistory::new(roots[0]).unwrap(), &spec).unwrap();
    assert_eq!(one.nx * one.ny, one.cells.len());
    assert_eq!(one.stable + one.unstable + one.failed, one.cells.len());
    let mut n = 0;
    for c in one.cells.iter().filter(|c| slope(c.ground[0])) {
        let p = c.pose.as_ref().unwrap_or_else(|| panic!("{c:?}"));
        assert!(p.stable, "{c:?}");
        assert!(on_lip(&scene, p.anchors.last().unwrap()), "{c:?}");
        n += 1;
    }
    assert!(n >= 36, "{n} slope cells");
    let two = stability_map(&ground, &AnchorHistory::new(roots[1]).unwrap(), &spec).unwrap();
    for c in two.cells.iter().filter(|c| slope(c.ground[0])) {
        let p = c.pose.as_ref().unwrap_or_else(|| panic!("{c:?}"));
        assert!(!p.stable && p.anchors.len() == 1, "{c:?}");
    }
    let svg = rappel_render::settle_map::map_svg(&one, &ground);
    assert!(svg.starts_with("<svg") || svg.contains("<svg"));
    assert!(svg.contains("stability map"));
}

#[test]
fn bad_maps_are_typed_errors() {
    let scene = PatonScene::paper(false);
    let ground = scene.mesh().unwrap();
    let root = AnchorHistory::new(scene.anchor_points()[0]).unwrap();
    let spec = MapSpec {
        x: (-2.0, 2.0),
        y: (-1.0, 1.0),
        step: 0.5,
        yaw_deg: 0.0,
        start: [-1.0, 0.0],
    };
    for bad in [
        MapSpec { step: 0.0, ..spec },
        MapSpec {
            step: f64::NAN,
            ..spec
        },
        MapSpec {
            x: (2.0, -2.0),
            ..spec
        },
        MapSpec {
            start: [30.0, 0.0],
            ..spec
        },
        MapSpec { step: 1e-4, ..spec },
    ] {
        assert!(
            matches!(
                stability_map(&ground, &root, &bad),
                Err(MeshStabilityError::Parameter(_))
            ),
            "{bad:?}"
        );
    }
    // The drive's target in the air beyond the ground: it does not settle.
    assert!(matches!(
        drive_and_check(&ground, &root, [-1.0, 0.0], [500.0, 0.0], 0.0),
        Err(MeshStabilityError::Settle { .. })
    ));
}

/// Paton's use of the distance field: the Fig. 8 maps (test-1 and test-2 roots) with settling and
/// anchor prediction through the sparse 10 cm field against the same maps through parry's exact
/// distances. Every cell must settle in both or neither with the same verdict, and the last
/// anchors must agree within the field's error bound plus two prediction resolutions (a contact
/// is noticed up to `h` late, docs/mesh.md).
#[test]
fn field_map_agrees_with_the_exact_map() {
    let scene = PatonScene::paper(false);
    let ground = scene.mesh().unwrap();
    let spec = MapSpec::fig8(&scene);
    let h = 0.1;
    let bound = rappel::terrain::sparse_sdf::SparseSdf::from_mesh(
        &ground,
        &rappel::terrain::sparse_sdf::SparseSdfParams::new(h),
    )
    .unwrap()
    .error_bound();
    for root in scene.anchor_points().into_iter().take(2) {
        let root = AnchorHistory::new(root).unwrap();
        let exact = stability_map(&ground, &root, &spec).unwrap();
        let field = stability_map_through_field(&ground, &root, &spec, h).unwrap();
        assert_eq!(exact.cells.len(), field.cells.len());
        let mut compared = 0;
        for (e, f) in exact.cells.iter().zip(&field.cells) {
            assert_eq!(e.pose.is_some(), f.pose.is_some(), "{e:?} vs {f:?}");
            if let (Some(pe), Some(pf)) = (&e.pose, &f.pose) {
                assert_eq!(pe.stable, pf.stable, "{e:?} vs {f:?}");
                let (ae, af) = (pe.anchors.last().unwrap(), pf.anchors.last().unwrap());
                let gap = (0..3).map(|k| (ae[k] - af[k]).powi(2)).sum::<f64>().sqrt();
                assert!(
                    gap <= bound + 2.0 * h.max(PREDICT_RESOLUTION),
                    "{gap}: {e:?} vs {f:?}"
                );
                compared += 1;
            }
        }
        assert!(compared >= 60, "{compared} cells compared");
    }
    assert!(matches!(
        stability_map_through_field(
            &ground,
            &AnchorHistory::new(scene.anchor_points()[0]).unwrap(),
            &spec,
            -1.0
        ),
        Err(MeshStabilityError::Parameter(_))
    ));
}

/// `drive_and_check_with` through the sparse 10 cm field against the exact path on the ledge
/// (the drives of `drives_down_the_slope_with_both_paper_anchors`): the same verdict, the same
/// number of anchors, the last anchor within the field's error bound plus two prediction
/// resolutions, the target's origin within the bound; each answer names its distance source.
#[test]
fn a_drive_through_the_field_agrees_with_the_exact_drive() {
    use rappel::planners::rover::ground::{DistanceSource, GroundDistances};
    use rappel::planners::rover::stability_map::drive_and_check_with;
    let scene = PatonScene::paper(false);
    let ground = scene.mesh().unwrap();
    let h = 0.1;
    let exact = GroundDistances::new(&ground, DistanceSource::Exact).unwrap();
    let field = GroundDistances::new(&ground, DistanceSource::Field { resolution_m: h }).unwrap();
    let bound = field.report().error_bound_m.unwrap();
    let s = scene.start();
    let x = 0.5 * scene.slope_foot_x();
    for root in scene.anchor_points().into_iter().take(2) {
        let root = AnchorHistory::new(root).unwrap();
        for y in [-1.0, 0.0, 1.5] {
            let e = drive_and_check_with(&ground, &exact, &root, [s.x, s.y], [x, y], 0.0).unwrap();
            let f = drive_and_check_with(&ground, &field, &root, [s.x, s.y], [x, y], 0.0).unwrap();
            assert_eq!(e.distance_source.source, "exact");
            assert_eq!(f.distance_source.source, "field");
            assert_eq!(f.distance_source.resolution_m, Some(h));
            let (pe, pf) = (&e.stability, &f.stability);
            assert_eq!(pe.stable, pf.stable, "{pe:?} vs {pf:?}");
            assert_eq!(pe.anchors.len(), pf.anchors.len(), "{pe:?} vs {pf:?}");
            let dist = |a: &[f64; 3], b: &[f64; 3]| {
                (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt()
            };
            let (ae, af) = (pe.anchors.last().unwrap(), pf.anchors.last().unwrap());
            assert!(dist(ae, af) <= bound + 2.0 * h, "{ae:?} vs {af:?}");
            assert!(dist(&pe.origin, &pf.origin) <= bound, "{pe:?} vs {pf:?}");
        }
    }
}
