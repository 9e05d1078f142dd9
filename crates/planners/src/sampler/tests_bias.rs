//! Tests of the sample-bias hook ([`StateSpace::sample_biased`] with `biased_sample_fraction`):
//! the planner draws the requested share of its samples from the space's bias distribution and
//! only then, never at fraction 0, falls back to uniform sampling when the bias misses, and
//! stays deterministic.

use std::cell::Cell;

use rand::RngExt;
use rand_chacha::ChaCha8Rng;

use super::abit::Abit;
use super::obstacle_world::ObstacleWorld;
use super::real_vector::RealVectorSpace;
use super::settings::AbitSettings;
use super::space::{Informed, StateSpace};
use super::termination::Termination;
use super::validator::MotionValidator;

/// The square the test bias draws from (free of the world's disc).
const REGION: [[f64; 2]; 2] = [[1.5, 1.5], [2.5, 2.5]];

/// A plane with a disc obstacle whose bias distribution is uniform in [`REGION`] (or absent),
/// counting the planner's calls of the hook.
struct BiasedPlane {
    world: ObstacleWorld<2>,
    bias: bool,
    calls: Cell<u64>,
}

fn plane(bias: bool) -> BiasedPlane {
    BiasedPlane {
        world: super::tests_geometric::circle_2d(),
        bias,
        calls: Cell::new(0),
    }
}

fn in_region(p: &[f64; 2]) -> bool {
    (0..2).all(|i| p[i] >= REGION[0][i] && p[i] <= REGION[1][i])
}

impl StateSpace<2> for BiasedPlane {
    type State = [f64; 2];
    fn sample_uniform(&self, rng: &mut ChaCha8Rng) -> [f64; 2] {
        self.world.space.sample_uniform(rng)
    }
    fn sample_biased(&self, rng: &mut ChaCha8Rng) -> Option<[f64; 2]> {
        self.calls.set(self.calls.get() + 1);
        self.bias.then(|| {
            [
                rng.random_range(REGION[0][0]..REGION[1][0]),
                rng.random_range(REGION[0][1]..REGION[1][1]),
            ]
        })
    }
    fn sample_informed(
        &self,
        rng: &mut ChaCha8Rng,
        s: &[f64; 2],
        g: &[f64; 2],
        c: f64,
    ) -> Informed<[f64; 2]> {
        self.world.space.sample_informed(rng, s, g, c)
    }
    fn distance(&self, a: &[f64; 2], b: &[f64; 2]) -> f64 {
        self.world.space.distance(a, b)
    }
    fn cost_heuristic(&self, a: &[f64; 2], b: &[f64; 2]) -> f64 {
        self.world.space.cost_heuristic(a, b)
    }
    fn interpolate(&self, a: &[f64; 2], b: &[f64; 2], t: f64) -> [f64; 2] {
        self.world.space.interpolate(a, b, t)
    }
    fn key(&self, s: &[f64; 2]) -> [f64; 2] {
        *s
    }
    fn dimension(&self) -> usize {
        2
    }
}

impl MotionValidator<BiasedPlane, 2> for BiasedPlane {
    type History = ();
    fn initial_history(&self, _: &[f64; 2]) {}
    fn state_valid(&self, s: &[f64; 2]) -> bool {
        MotionValidator::<RealVectorSpace<2>, 2>::state_valid(&self.world, s)
    }
    fn motion(&self, a: &[f64; 2], h: &(), b: &[f64; 2]) -> Option<(f64, ())> {
        MotionValidator::<RealVectorSpace<2>, 2>::motion(&self.world, a, h, b)
    }
}

fn settings(fraction: f64, seed: u64) -> AbitSettings {
    AbitSettings::default()
        .with_biased_sample_fraction(fraction)
        .unwrap()
        .with_seed(seed)
}

#[test]
fn the_biased_fraction_of_samples_comes_from_the_hook() {
    // Fraction 0: the hook is never asked (Paton's uniform sampling keeps its random stream).
    let p = plane(true);
    let a = Abit::new(&p, &p, p.world.start, p.world.goal, settings(0.0, 1)).unwrap();
    assert_eq!(p.calls.get(), 0);
    assert_eq!(a.status().biased_samples, 0);
    // Fraction 0.5 of the first batch of 100: Binomial(100, 0.5) biased samples, each in the
    // region; the uniform ones land there with probability 1/36 only.
    let p = plane(true);
    let a = Abit::new(&p, &p, p.world.start, p.world.goal, settings(0.5, 1)).unwrap();
    let biased = a.status().biased_samples as usize;
    assert!((30..=70).contains(&biased), "{biased}");
    let inside = a
        .graph()
        .nodes
        .iter()
        .filter(|n| in_region(&n.state))
        .count();
    assert!(
        inside >= biased && inside <= biased + 15,
        "{inside} vs {biased}"
    );
    assert_eq!(a.status().states, 102);
}

#[test]
fn a_bias_that_misses_falls_back_to_uniform_samples() {
    let p = plane(false);
    let a = Abit::new(&p, &p, p.world.start, p.world.goal, settings(1.0, 4)).unwrap();
    let s = a.status();
    assert_eq!(s.biased_samples, 0);
    // One call per sample: `None` means the space's own search missed, no retries.
    assert_eq!(p.calls.get(), 100);
    assert_eq!(s.states, 102);
}

#[test]
fn biased_runs_are_deterministic_and_find_valid_paths() {
    let run = |seed| {
        let p = plane(true);
        let mut a = Abit::new(&p, &p, p.world.start, p.world.goal, settings(0.3, seed)).unwrap();
        a.solve(Termination::iterations(3000)).unwrap()
    };
    let (x, y, z) = (run(7), run(7), run(8));
    // Equal solutions, improvements (iteration and cost; wall times differ) and sample counts.
    assert_eq!(x.solution, y.solution);
    let ev = |s: &super::abit::PlannerStatus<[f64; 2], ()>| {
        s.events
            .iter()
            .map(|e| (e.iteration, e.cost.to_bits()))
            .collect::<Vec<_>>()
    };
    assert_eq!(ev(&x), ev(&y));
    assert_eq!(x.biased_samples, y.biased_samples);
    assert_ne!(x.solution, z.solution);
    let sol = x.solution.expect("a path around the disc");
    // Every segment keeps off the unit disc by more than the half check step can clip.
    for w in sol.path.windows(2) {
        let (a, b) = (w[0], w[1]);
        let d = [b[0] - a[0], b[1] - a[1]];
        let t = (-(a[0] * d[0] + a[1] * d[1]) / (d[0] * d[0] + d[1] * d[1])).clamp(0.0, 1.0);
        let c = [a[0] + t * d[0], a[1] + t * d[1]];
        assert!(c[0].hypot(c[1]) > 1.0 - 0.01, "{w:?}");
    }
    assert!(x.biased_samples > 0);
}
