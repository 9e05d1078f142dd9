//! Frictional planning benchmark (issue 12): `rappel plan` on the generated 1,000-obstacle crater
//! strip (`CraterStripOptions::new(1_000, 1)`, one 45° plane) with 20 % of the obstacles labelled
//! PTFOs (every obstacle the frictionless shortest tether wraps, then ChaCha8, seed 12; each a pillar of the obstacle's mean radius about its
//! centroid, friction drawn from [0.05, 1.2] so that some hold, some slide, some are volatile),
//! side by side in one run with the frictionless plan of the same scenario, and the same PTFOs
//! with friction [0.01, 0.011] (every wrap slides: Alg. 14's clips, local BTM updates and retracing). Target: the frictional
//! plan within 3x the frictionless plan's median. Both list up to 5 classes.

use criterion::{Criterion, criterion_group, criterion_main};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rappel::generated::crater_strip_scenario;
use rappel::mechanics::ptfo_surface::PtfoSurface;
use rappel::plan::{PlanOptions, plan_detailed};
use rappel::ptfo_spec::{FrictionRange, FrictionSpec, PtfoSpec, TensionSpec};
use rappel_geometry::generate::CraterStripOptions;
use std::hint::black_box;

fn friction(c: &mut Criterion) {
    let width = CraterStripOptions::new(1_000, 1).width;
    let plain = crater_strip_scenario(1_000, 1, width).expect("valid options");
    // 20 % of the obstacles are PTFOs: every obstacle the frictionless shortest tether wraps (so
    // that Alg. 8 has friction anchors to decide), then seeded random ones up to 200.
    let first =
        plan_detailed(&plain.validate().expect("valid"), &PlanOptions::default()).expect("plans");
    let mut chosen: Vec<usize> = first.report.classes[0]
        .anchors
        .iter()
        .filter_map(|a| a.obstacle.map(|o| o as usize))
        .collect();
    chosen.sort_unstable();
    chosen.dedup();
    let mut rng = ChaCha8Rng::seed_from_u64(12);
    let target = plain.map.obstacles.len() / 5;
    while chosen.len() < target {
        let i = rng.random_range(0..plain.map.obstacles.len());
        if !chosen.contains(&i) {
            chosen.push(i);
        }
    }
    let mut ptfos = Vec::new();
    for &i in &chosen {
        let o = &plain.map.obstacles[i];
        let n = o.vertices.len() as f64;
        let center = o
            .vertices
            .iter()
            .fold(nalgebra::Point2::origin(), |a, v| a + v.coords / n);
        // The smallest circle about the centroid holding every vertex: each anchor lies on the
        // pillar's footprint.
        let radius = o
            .vertices
            .iter()
            .map(|v| (v - center).norm())
            .fold(0.0, f64::max);
        let lo = rng.random_range(0.05..1.2);
        ptfos.push(PtfoSpec {
            obstacle: i,
            surface: PtfoSurface::Cylinder { center, radius },
            friction: FrictionRange { lo, hi: lo * 1.1 },
        });
    }
    let count = ptfos.len();
    let mut frictional = plain.clone();
    frictional.friction = Some(FrictionSpec {
        ptfos,
        tensions: TensionSpec::default(),
        geometric_friction: 0.0,
        holding: None,
    });
    // The same PTFOs with almost no friction: every wrap slides, exercising Alg. 14.
    let mut sliding = frictional.clone();
    if let Some(spec) = sliding.friction.as_mut() {
        for p in &mut spec.ptfos {
            p.friction = FrictionRange {
                lo: 0.01,
                hi: 0.011,
            };
        }
    }
    let options = PlanOptions::default();
    let slid = plan_detailed(&sliding.validate().expect("valid"), &options).expect("plans");
    let fs = slid
        .report
        .outcome
        .friction
        .as_ref()
        .expect("friction report");
    eprintln!(
        "friction bench (sliding): {} anchors in class 1 ({} on PTFOs), {} slips; {}",
        fs.classes[0].anchors.len() + fs.classes[0].slips.len(),
        fs.classes[0].slips.len()
            + fs.classes[0]
                .anchors
                .iter()
                .filter(|a| a.verdict != rappel::verdict::AnchorHold::Geometric)
                .count(),
        fs.classes.iter().map(|c| c.slips.len()).sum::<usize>(),
        fs.verdict
    );
    let report = plan_detailed(&frictional.validate().expect("valid"), &options).expect("plans");
    let f = report
        .report
        .outcome
        .friction
        .as_ref()
        .expect("friction report");
    let slips: usize = f.classes.iter().map(|c| c.slips.len()).sum();
    eprintln!(
        "friction bench: {count} PTFOs of {}; {} classes examined, {slips} slips; {}",
        plain.map.obstacles.len(),
        f.classes.len(),
        f.verdict
    );
    let mut g = c.benchmark_group("plan_1000_obstacles_20pct_ptfos");
    g.sample_size(10);
    g.bench_function("frictionless", |b| {
        b.iter(|| {
            black_box(plan_detailed(&plain.validate().expect("valid"), &options).expect("plans"))
        })
    });
    g.bench_function("frictional", |b| {
        b.iter(|| {
            black_box(
                plan_detailed(&frictional.validate().expect("valid"), &options).expect("plans"),
            )
        })
    });
    g.bench_function("frictional_all_sliding", |b| {
        b.iter(|| {
            black_box(plan_detailed(&sliding.validate().expect("valid"), &options).expect("plans"))
        })
    });
    g.finish();
}

criterion_group!(benches, friction);
criterion_main!(benches);
