//! Benchmarks of tether tracking (issue 13): one tracking step on Kumar's scene (S0 flat with two
//! square obstacles, S1 55 deg, S2 65 deg, S3 flat), and a 10,000-step path winding around the
//! obstacles and descending over the crests (ground anchors recomputed at the end). Targets: one
//! step < 5 us, 10,000 steps < 50 ms.

use criterion::{Criterion, criterion_group, criterion_main};
use nalgebra::Point2;
use rappel_planners::tether_tracking::TetherTracker;
use rappel_terrain::kumar::kumar_scene;
use std::hint::black_box;

/// A closed loop around O2 (through its corners' neighbourhood), then down the slopes and back.
fn loop_path(steps: usize) -> Vec<Point2<f64>> {
    let ring = [
        Point2::new(5.0, 18.0),
        Point2::new(5.0, 23.0),
        Point2::new(1.0, 23.0),
        Point2::new(1.0, 18.0),
        Point2::new(3.0, 10.0),
        Point2::new(5.0, 2.0),
        Point2::new(6.0, 12.0),
    ];
    let per_leg = (steps / ring.len()).max(1);
    let mut out = Vec::with_capacity(steps);
    let mut k = 0;
    while out.len() < steps {
        let (a, b) = (ring[k % ring.len()], ring[(k + 1) % ring.len()]);
        for i in 1..=per_leg {
            if out.len() == steps {
                break;
            }
            out.push(a + (b - a) * (i as f64 / per_leg as f64));
        }
        k += 1;
    }
    out
}

fn tracking(c: &mut Criterion) {
    let scene = kumar_scene().expect("valid scene");
    let base = Point2::new(3.0, 17.0);
    let path = loop_path(10_000);
    c.bench_function("tracking/kumar scene: one step", |b| {
        let mut tracker = TetherTracker::new(&scene, base, path[path.len() - 1]).expect("start");
        let mut i = 0;
        b.iter(|| {
            tracker.step(black_box(path[i])).expect("valid step");
            i = (i + 1) % path.len();
        })
    });
    c.bench_function("tracking/kumar scene: 10,000-step path", |b| {
        b.iter(|| {
            let mut tracker =
                TetherTracker::new(&scene, base, path[path.len() - 1]).expect("start");
            tracker.follow(black_box(&path)).expect("valid path");
            black_box(tracker.configuration().len())
        })
    });
}

criterion_group!(benches, tracking);
criterion_main!(benches);
