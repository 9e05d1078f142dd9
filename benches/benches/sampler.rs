//! ABIT* (`rappel_planners::sampler`) on the obstacle worlds shared with the OMPL BIT* peer
//! (`benches/ompl_peer/`): time to the first solution, and a fixed number of iterations.

use criterion::{Criterion, criterion_group, criterion_main};
use rappel_planners::sampler::{Abit, AbitSettings, ObstacleWorld, Termination, WorldFile};

fn world<const D: usize>(json: &str) -> ObstacleWorld<D> {
    let file: WorldFile = serde_json::from_str(json).expect("the shared world file parses");
    file.to_world::<D>().expect("the shared world is valid")
}

/// Iteration cap of the first-solution runs (never reached on these worlds).
const FIRST_CAP: u64 = 1_000_000;

fn bench_world<const D: usize>(c: &mut Criterion, name: &str, w: &ObstacleWorld<D>) {
    let mut seed = 0u64;
    c.bench_function(&format!("sampler/first_solution/{name}"), |b| {
        b.iter(|| {
            seed += 1;
            let s = AbitSettings::default().with_seed(seed);
            let mut p = Abit::new(&w.space, w, w.start, w.goal, s).expect("planner");
            let st = p
                .solve(Termination::iterations(FIRST_CAP).or_cost_at_most(f64::MAX))
                .expect("solve");
            assert!(st.solution.is_some());
            st.iterations
        })
    });
    c.bench_function(&format!("sampler/5000_iterations/{name}"), |b| {
        b.iter(|| {
            let s = AbitSettings::default().with_seed(7);
            let mut p = Abit::new(&w.space, w, w.start, w.goal, s).expect("planner");
            p.solve(Termination::iterations(5000))
                .expect("solve")
                .solution
                .map(|s| s.cost)
        })
    });
}

fn sampler(c: &mut Criterion) {
    let w2 = world::<2>(include_str!("../ompl_peer/worlds/boxes_2d.json"));
    let w3 = world::<3>(include_str!("../ompl_peer/worlds/boxes_3d.json"));
    bench_world(c, "boxes_2d", &w2);
    bench_world(c, "boxes_3d", &w3);
}

criterion_group!(benches, sampler);
criterion_main!(benches);
