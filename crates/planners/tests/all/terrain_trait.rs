//! The Chapter-2 planner's plane series taken through the `Terrain` trait
//! (`PlaneSeries::from_terrain`): equal to the series built from the planes directly on random
//! plane-series terrains, right on a developed multi-slope chain, and refused, naming the surface,
//! where a surface's fall line is not the frame's.

use nalgebra::Point3;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rappel_mechanics::friction_cone::TetherFrictionCone;
use rappel_planners::terrain::{PlaneSeries, TerrainError};
use rappel_terrain::kumar::kumar_scene;
use rappel_terrain::multi_slope::{MultiSlopeTerrain, SurfaceSpec};
use rappel_terrain::plane_series::TerrainPlane;
use rappel_terrain::plane_series_terrain::PlaneSeriesTerrain;

#[test]
fn the_trait_gives_the_same_series_as_the_planes() {
    let mut rng = ChaCha8Rng::seed_from_u64(13);
    for case in 0..60 {
        let n = rng.random_range(1..6usize);
        let mut y = 100.0;
        let mut planes = Vec::new();
        for _ in 0..n {
            let h = rng.random_range(1.0..40.0);
            planes.push(TerrainPlane::new(
                y,
                y - h,
                rng.random_range(0.0..80.0),
                rng.random_range(0.0..1.2),
            ));
            y -= h;
        }
        let t = PlaneSeriesTerrain::new(&planes, (-20.0, 20.0), vec![]).expect("terrain");
        let direct = PlaneSeries::new(&planes, &TetherFrictionCone).expect("direct");
        let through = PlaneSeries::from_terrain(&t, (y, 100.0), &TetherFrictionCone)
            .unwrap_or_else(|e| panic!("case {case}: {e}"));
        assert_eq!(through.planes().len(), n);
        for (a, b) in through.planes().iter().zip(direct.planes()) {
            assert_eq!(
                (a.y_top, a.y_bottom, a.friction),
                (b.y_top, b.y_bottom, b.friction)
            );
            assert!((a.slope_deg - b.slope_deg).abs() < 1e-9, "case {case}");
        }
        for (a, b) in through.limits().iter().zip(direct.limits()) {
            assert_eq!(a.is_tether_demand(), b.is_tether_demand(), "case {case}");
            if let (Some(x), Some(y)) = (a.max_angle(), b.max_angle()) {
                assert!((x - y).abs() < 1e-9, "case {case}");
            }
        }
    }
}

#[test]
fn kumar_environment_is_a_band_series() {
    let t = kumar_scene().expect("scene");
    let s = PlaneSeries::from_terrain(&t, (-4.0, 30.0), &TetherFrictionCone).expect("bands");
    let slopes: Vec<f64> = s.planes().iter().map(|p| p.slope_deg.round()).collect();
    assert_eq!(slopes, vec![0.0, 55.0, 65.0, 0.0]);
    let tops: Vec<f64> = s.planes().iter().map(|p| p.y_top).collect();
    assert_eq!(tops, vec![30.0, 16.0, 8.0, 0.0]);
}

fn p(x: f64, y: f64, z: f64) -> Point3<f64> {
    Point3::new(x, y, z)
}

#[test]
fn a_developed_chain_down_the_fall_line_is_accepted_and_a_sideways_one_refused() {
    // A flat top and a 45° slope falling away from its edge y = 0 (down the frame's -y).
    let top = SurfaceSpec {
        vertices: vec![
            p(0., 0., 0.),
            p(10., 0., 0.),
            p(10., 10., 0.),
            p(0., 10., 0.),
        ],
        friction: 0.4,
    };
    let s = 10.0 / 2f64.sqrt();
    let down = SurfaceSpec {
        vertices: vec![p(0., 0., 0.), p(0., -s, -s), p(10., -s, -s), p(10., 0., 0.)],
        friction: 0.4,
    };
    let t = MultiSlopeTerrain::new(vec![top.clone(), down], vec![]).expect("terrain");
    let series = PlaneSeries::from_terrain(&t, (-10.0, 10.0), &TetherFrictionCone).expect("bands");
    assert_eq!(series.planes().len(), 2);
    assert!((series.planes()[1].slope_deg - 45.0).abs() < 1e-9);
    assert_eq!(series.planes()[1].y_top, 0.0);
    // The same slope, but tilted so that it also falls sideways: its fall line is not -y.
    let skew = SurfaceSpec {
        vertices: vec![
            p(0., 0., 0.),
            p(0., -s, -s),
            p(10., -s, -s - 3.0),
            p(10., 0., -3.0),
        ],
        friction: 0.4,
    };
    let top_skew = SurfaceSpec {
        vertices: vec![
            p(0., 0., 0.),
            p(10., 0., -3.0),
            p(10., 10., -3.0),
            p(0., 10., 0.),
        ],
        friction: 0.4,
    };
    let t = MultiSlopeTerrain::new(vec![top_skew, skew], vec![]).expect("terrain");
    match PlaneSeries::from_terrain(&t, (-10.0, 10.0), &TetherFrictionCone) {
        Err(TerrainError::NotABandSeries { surface, problem }) => {
            assert_eq!(surface, 0, "{problem}");
            assert!(problem.contains("fall line"), "{problem}");
        }
        other => panic!("expected a refusal, got {other:?}"),
    }
}
