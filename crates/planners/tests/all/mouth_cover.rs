//! The mouth-cover test against dense sampling of the mouth: whenever it drops a funnel, every
//! sampled mouth point is reached more cheaply by an endpoint or the arrival than the funnel's
//! lower bound (soundness, the property every pruning decision rests on), and it drops nearly all
//! the funnels the sampling shows clearly covered (it is conservative only near ties).

use nalgebra::Point2;
use proptest::prelude::*;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rappel_planners::mouth_cover::{Arrival, MouthEnd, is_covered, is_covered_with};

/// Samples of the mouth for the dense check.
const SAMPLES: usize = 2_001;

/// Smallest excess of the funnel's bound over the cheapest cover, over the sampled mouth points.
fn sampled_excess(apex: Point2<f64>, g: f64, a: MouthEnd, b: MouthEnd, s: Option<Arrival>) -> f64 {
    (0..SAMPLES)
        .map(|i| {
            let t = i as f64 / (SAMPLES - 1) as f64;
            let x = a.point + (b.point - a.point) * t;
            let lb = g + (x - apex).norm();
            let mut cover = (a.best + (x - a.point).norm()).min(b.best + (b.point - x).norm());
            if let Some(s) = s {
                cover = cover.min(s.length + (x - s.point).norm());
            }
            lb - cover
        })
        .fold(f64::INFINITY, f64::min)
}

fn point() -> impl Strategy<Value = Point2<f64>> {
    (-10.0..10.0f64, -10.0..10.0f64).prop_map(|(x, y)| Point2::new(x, y))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 4_000, rng_seed: proptest::test_runner::RngSeed::Fixed(35), ..ProptestConfig::default() })]

    #[test]
    fn a_dropped_funnel_is_beaten_at_every_mouth_point(
        a in point(), b in point(), apex in point(), s in point(),
        start in point(),
        extra in (0.0..3.0f64, 0.0..3.0f64, 0.0..3.0f64, -2.0..6.0f64),
        with_arrival in any::<bool>(),
    ) {
        // Lengths as from one start (so the covers are plausible), plus detours; the funnel's
        // own apex length varies around them so that both verdicts occur.
        let (ea, eb, es, ep) = extra;
        let ma = MouthEnd { point: a, best: (a - start).norm() + ea };
        let mb = MouthEnd { point: b, best: (b - start).norm() + eb };
        let arrival = with_arrival.then_some(Arrival { point: s, length: (s - start).norm() + es });
        let g = ((apex - start).norm() + ep).max(0.0);
        let covered = is_covered_with(&apex, g, ma, mb, arrival);
        let excess = sampled_excess(apex, g, ma, mb, arrival);
        if covered {
            // Sampling sees a point only approximately; the margin is 1e-9 of the scale.
            prop_assert!(excess > -1e-12, "dropped, but a mouth point is not beaten: {excess}");
        }
        if !with_arrival {
            prop_assert_eq!(covered, is_covered(&apex, g, ma, mb));
        }
    }
}

#[test]
fn the_test_drops_the_funnels_clearly_covered() {
    // Deterministic sweep: count the clearly covered cases (excess above 1e-6 at every sample) and
    // how many of them the test drops.
    let (mut clear, mut dropped, mut any_with_arrival) = (0usize, 0usize, 0usize);
    let mut rng = ChaCha8Rng::seed_from_u64(35);
    let mut next = || rng.random::<f64>();
    for _ in 0..20_000 {
        let mut p = || Point2::new(20.0 * next() - 10.0, 20.0 * next() - 10.0);
        let (a, b, apex, s, start) = (p(), p(), p(), p(), p());
        let ma = MouthEnd {
            point: a,
            best: (a - start).norm() + 3.0 * next(),
        };
        let mb = MouthEnd {
            point: b,
            best: (b - start).norm() + 3.0 * next(),
        };
        let arrival = Arrival {
            point: s,
            length: (s - start).norm() + 3.0 * next(),
        };
        let g = (apex - start).norm() + 8.0 * next() - 2.0;
        let g = g.max(0.0);
        if sampled_excess(apex, g, ma, mb, Some(arrival)) > 1e-6 {
            clear += 1;
            if is_covered_with(&apex, g, ma, mb, Some(arrival)) {
                dropped += 1;
                if !is_covered(&apex, g, ma, mb) {
                    any_with_arrival += 1;
                }
            }
        }
    }
    assert!(clear > 1_000, "too few covered cases to judge: {clear}");
    assert!(
        dropped as f64 >= 0.99 * clear as f64,
        "the test keeps too many covered funnels: {dropped} of {clear}"
    );
    assert!(
        any_with_arrival > 100,
        "the arrival covered only {any_with_arrival}"
    );
}
