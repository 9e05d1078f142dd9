//! Benchmarks of the mechanics crate (issue 5): one wheel/tether QP check of an Axel pose, one
//! tension-limited LP check of a four-wheel rover (the dense simplex beside clarabel), a 10,000-pose stability grid in parallel with
//! rayon, and the split of a QP check into our assembly, clarabel's setup and clarabel's solve.

use criterion::{Criterion, criterion_group, criterion_main};
use nalgebra::Point3;
use rappel_mechanics::axel::Axel;
use rappel_mechanics::four_wheel::FourWheelRover;
use rappel_mechanics::robot::{PlacedRobot, PlanarPose, SlopePlane, TetherSpec, place};
use rappel_mechanics::stability_map::{FixedAnchors, GridSpec, Heading, MapPlane, stability_map};
use rappel_mechanics::stability_qp::StabilityQp;
use rappel_mechanics::tension_lp::TensionLimitedLp;
use std::f64::consts::PI;
use std::hint::black_box;

fn axel_pose() -> PlacedRobot {
    let plane = SlopePlane::new(40f64.to_radians(), 0.8).expect("valid plane");
    let tether = TetherSpec {
        anchor: Point3::new(3.0, 30.0, 0.0),
        max_tension: None,
    };
    place(
        &Axel::default(),
        &PlanarPose::new(0.0, 0.0, PI),
        &plane,
        Some(&tether),
    )
    .expect("placeable pose")
}

fn rover_pose() -> PlacedRobot {
    let plane = SlopePlane::new(55f64.to_radians(), 0.4).expect("valid plane");
    let tether = TetherSpec {
        anchor: Point3::new(2.0, 30.0, 0.35),
        max_tension: Some(300.0),
    };
    place(
        &FourWheelRover::default(),
        &PlanarPose::new(0.0, 0.0, PI),
        &plane,
        Some(&tether),
    )
    .expect("placeable pose")
}

fn checks(c: &mut Criterion) {
    let axel = axel_pose();
    let rover = rover_pose();
    let qp = StabilityQp::default();
    let lp = TensionLimitedLp::default();
    c.bench_function("mechanics/qp_axel_check", |b| {
        b.iter(|| qp.check(black_box(&axel)))
    });
    // The dense simplex beside clarabel on the same LP; their answers agree first.
    let (dense, oracle) = (
        lp.check(&rover).expect("dense"),
        lp.check_clarabel(&rover).expect("clarabel"),
    );
    assert_eq!(dense.stable, oracle.stable);
    let (a, b) = (
        dense.required_tension.unwrap(),
        oracle.required_tension.unwrap(),
    );
    assert!((a - b).abs() < 1e-6 * 35.0 * 9.81, "{a} vs {b}");
    c.bench_function("mechanics/lp_rover_check", |b| {
        b.iter(|| lp.check(black_box(&rover)))
    });
    c.bench_function("mechanics/lp_rover_check_clarabel", |b| {
        b.iter(|| lp.check_clarabel(black_box(&rover)))
    });
    // The QP time split: our assembly; assembly + clarabel setup; assembly + setup + solve.
    c.bench_function("mechanics/qp_split/assemble", |b| {
        b.iter(|| qp.assemble(black_box(&axel)))
    });
    c.bench_function("mechanics/qp_split/assemble_setup", |b| {
        b.iter(|| {
            qp.assemble(black_box(&axel))
                .and_then(|p| p.setup())
                .map(|_| ())
        })
    });
    c.bench_function("mechanics/qp_split/assemble_setup_solve", |b| {
        b.iter(|| {
            qp.assemble(black_box(&axel))
                .and_then(|p| p.setup())
                .and_then(|s| s.solve())
        })
    });
}

fn grid(c: &mut Criterion) {
    // 100 x 100 Axel poses on a 45° slope, tethered to an anchor above, in parallel.
    let plane = MapPlane {
        plane: SlopePlane::new(45f64.to_radians(), 0.8).expect("valid plane"),
        x_range: [-9.9, 9.9],
        y_range: [0.0, 19.8],
    };
    let anchors = FixedAnchors(vec![Some(TetherSpec {
        anchor: Point3::new(0.0, 40.0, 0.0),
        max_tension: None,
    })]);
    let spec = GridSpec::new(0.2, Heading::AwayFromAnchor).expect("valid grid");
    let qp = StabilityQp::default();
    let robot = Axel::default();
    assert_eq!(
        rappel_mechanics::stability_map::grid_positions(&[plane], &spec)
            .map(|p| p.len())
            .unwrap_or(0),
        10_000
    );
    let mut group = c.benchmark_group("mechanics");
    group.sample_size(10);
    group.bench_function("grid_10k_qp_rayon", |b| {
        b.iter(|| stability_map(&robot, &qp, &[plane], &anchors, &spec))
    });
    group.finish();
}

criterion_group!(benches, checks, grid);
criterion_main!(benches);
