//! Slope analysis and the plane series (issue 6, deliverables 2-3; thesis §2.1.2): the fall line of
//! a tilted plane is exact in any direction, a convex series of planes is recovered with the
//! slopes it was built with, a concave profile is made convex, the merge tolerance means what its
//! documentation says, and the unfolded frame is an isometry on each plane.

use nalgebra::Point2;
use rappel_terrain::frame::PlanningFrame;
use rappel_terrain::grid::{GridGeometry, HeightGrid};
use rappel_terrain::plane_fit::{PlaneFitOptions, PlaneSeriesFit, fit_plane_series};
use rappel_terrain::slope::{FallLine, SlopeField};
use rappel_terrain::synthetic::{ProfilePlane, plane_series_dem};

/// A profile DEM on a `n x n` grid of 1 m cells falling towards `azimuth`, and its fit.
fn fit(
    n: usize,
    azimuth: f64,
    planes: &[ProfilePlane],
    options: &PlaneFitOptions,
) -> (HeightGrid, PlanningFrame, PlaneSeriesFit) {
    let g = GridGeometry::new(n, n, 1.0, 1.0, 500.0, 800.0).unwrap();
    let fall = FallLine::from_azimuth(azimuth).unwrap();
    let dem = plane_series_dem(g, &fall, 2000.0, planes).unwrap();
    let frame = PlanningFrame::for_grid(&g, &fall);
    let series = fit_plane_series(&dem, &frame, options).unwrap();
    (dem, frame, series)
}

fn slopes(series: &PlaneSeriesFit) -> Vec<f64> {
    series.planes.iter().map(|p| p.slope_deg()).collect()
}

#[test]
fn fall_line_and_slope_of_a_tilted_plane_are_exact_in_any_direction() {
    for azimuth in [0.0, 45.0, 137.0, 200.0, 271.5, 359.0] {
        for slope in [5.0, 30.0, 60.0] {
            let g = GridGeometry::new(25, 31, 2.0, 1.5, 0.0, 0.0).unwrap();
            let fall = FallLine::from_azimuth(azimuth).unwrap();
            let dem = plane_series_dem(g, &fall, 100.0, &[ProfilePlane::new(1e6, slope)]).unwrap();
            let field = SlopeField::horn(&dem);
            let measured = field.fall_line().unwrap();
            let d = (measured.azimuth_deg() - azimuth + 540.0).rem_euclid(360.0) - 180.0;
            assert!(
                d.abs() < 1e-7,
                "azimuth {azimuth}: {}",
                measured.azimuth_deg()
            );
            assert!((measured.mean_slope_deg - slope).abs() < 1e-9);
            let s = field.slope_deg();
            assert!(s.values.iter().all(|v| (v - slope).abs() < 1e-9));
            let a = field.aspect_deg();
            assert!(a.values.iter().all(|v| {
                let d = (v - azimuth + 540.0).rem_euclid(360.0) - 180.0;
                d.abs() < 1e-7
            }));
        }
    }
}

#[test]
fn convex_series_is_recovered_with_its_slopes() {
    // 40 m runs, 1 m cells, bands of 10 cells: every break lies on a band edge.
    let planes = [15.0, 25.0, 35.0].map(|d| ProfilePlane::new(40.0, d));
    let (_, frame, series) = fit(121, 180.0, &planes, &PlaneFitOptions::default());
    let got = slopes(&series);
    assert_eq!(got.len(), 3, "{got:?}");
    for (g, want) in got.iter().zip([15.0, 25.0, 35.0]) {
        assert!((g - want).abs() < 1e-6, "{got:?}");
    }
    assert_eq!(series.convexity_merges, 0);
    for p in &series.planes {
        assert!(p.rms_residual_m < 1e-6);
        assert!(p.cross_gradient.abs() < 1e-9);
    }
    // Planes meet edge to edge, top first, and the breaks are where the profile bends: 40 m and
    // 80 m of horizontal run below the top (cell centres span 120 m).
    let unfolded = frame.unfolded(
        &series
            .planes
            .iter()
            .rev()
            .map(|p| (p.s_bottom, p.slope_deg()))
            .collect::<Vec<_>>(),
    );
    let top = series.planes[0].s_top;
    assert!((top - series.planes[0].s_bottom - 40.0).abs() < 1e-9);
    assert!((series.planes[1].s_top - series.planes[1].s_bottom - 40.0).abs() < 1e-9);
    for w in series.planes.windows(2) {
        assert_eq!(w[0].s_bottom, w[1].s_top);
    }
    // The unfolded length of each plane is its horizontal run over cos(eta).
    let y = |s: f64| unfolded.unfold(s);
    let len = y(series.planes[1].s_top) - y(series.planes[1].s_bottom);
    assert!((len - 40.0 / 25f64.to_radians().cos()).abs() < 1e-9);
}

#[test]
fn off_axis_fall_line_finds_the_same_series() {
    let planes = [12.0, 24.0, 40.0].map(|d| ProfilePlane::new(45.0, d));
    let (_, frame, series) = fit(101, 200.0, &planes, &PlaneFitOptions::default());
    assert!((frame.fall_line_azimuth_deg() - 200.0).abs() < 1e-9);
    let got = slopes(&series);
    assert_eq!(got.len(), 3, "{got:?}");
    // Breaks need not fall on band edges: the band across a break joins one side.
    for (g, want) in got.iter().zip([12.0, 24.0, 40.0]) {
        assert!((g - want).abs() < 1.5, "{got:?}");
    }
    assert!(got.windows(2).all(|w| w[0] <= w[1]), "convex: {got:?}");
}

#[test]
fn concave_profile_is_merged_until_convex() {
    // Steeper above, shallower below: the taut tether would lift off (thesis §2.1.2).
    let planes = [ProfilePlane::new(60.0, 35.0), ProfilePlane::new(60.0, 15.0)];
    let (_, _, free) = fit(
        121,
        180.0,
        &planes,
        &PlaneFitOptions {
            enforce_convexity: false,
            ..Default::default()
        },
    );
    let got = slopes(&free);
    assert_eq!(got.len(), 2, "{got:?}");
    assert!((got[0] - 35.0).abs() < 1e-6 && (got[1] - 15.0).abs() < 1e-6);
    let (_, _, convex) = fit(121, 180.0, &planes, &PlaneFitOptions::default());
    assert_eq!(convex.planes.len(), 1);
    assert_eq!(convex.convexity_merges, 1);
    let s = convex.planes[0].slope_deg();
    assert!(s > 15.0 && s < 35.0, "{s}");
}

#[test]
fn merge_tolerance_is_the_hinge_residual() {
    // Two planes of 60 m each; merging them hides a hinge of gradient change dg over a run of
    // L = 120 m, whose merge residual is dg L / (8 sqrt 3) (module docs).
    let planes = [ProfilePlane::new(60.0, 20.0), ProfilePlane::new(60.0, 22.0)];
    let dg = 22f64.to_radians().tan() - 20f64.to_radians().tan();
    let hinge = dg * 120.0 / (8.0 * 3f64.sqrt());
    let with = |tol: f64| {
        fit(
            121,
            180.0,
            &planes,
            &PlaneFitOptions {
                merge_tolerance_m: tol,
                ..Default::default()
            },
        )
        .2
        .planes
        .len()
    };
    assert_eq!(with(hinge * 1.1), 1);
    assert_eq!(with(hinge * 0.9), 2);
}

#[test]
fn unfolding_is_an_isometry_on_each_plane() {
    let planes = [ProfilePlane::new(50.0, 20.0), ProfilePlane::new(50.0, 45.0)];
    let (dem, frame, series) = fit(101, 180.0, &planes, &PlaneFitOptions::default());
    let bottom_up: Vec<(f64, f64)> = series
        .planes
        .iter()
        .rev()
        .map(|p| (p.s_bottom, p.slope_deg()))
        .collect();
    let unfolded = frame.unfolded(&bottom_up);
    let g = dem.geometry();
    let point3 = |r: usize, c: usize| {
        let p = g.cell_center(r, c);
        (p, dem.height(r, c).unwrap())
    };
    // Pairs of cells on the same plane (upper: rows < 50, lower: rows > 51).
    for ((r1, c1), (r2, c2)) in [
        ((3, 4), (40, 90)),
        ((60, 10), (95, 77)),
        ((52, 50), (99, 0)),
    ] {
        let ((a, za), (b, zb)) = (point3(r1, c1), point3(r2, c2));
        let ground = ((a - b).norm_squared() + (za - zb).powi(2)).sqrt();
        let (pa, pb): (Point2<f64>, Point2<f64>) =
            (unfolded.to_planning(&a), unfolded.to_planning(&b));
        assert!(
            ((pa - pb).norm() - ground).abs() < 1e-9,
            "{ground} vs {}",
            (pa - pb).norm()
        );
    }
}
