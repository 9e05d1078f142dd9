//! Diagnostics of the tethered-rover problem (`rappel_planners::rover::problem`, `rappel navigate`) on Paton's Table I tests: runs ABIT* with a validator that
//! logs every motion check (endpoints, anchors before and after, the failure reason, time) and
//! prints the tally of outcomes (`docs/sampler.md`, "Diagnosing test 3").
//!
//! `cargo run --release -p rappel-planners --example rover_diag -- TEST SEED ITERATIONS`; environment:
//! `INFL`, `COPY`, `BATCH`, `KF`, `BIAS` (shadow-sample fraction) override the settings, `EXACT` compares histories exactly,
//! `DUMP` prints every motion, `CORE` the shadow's core fraction (`TetherShadow::with_core_fraction`).
use rappel_planners::anchor_prediction::AnchorHistory;
use rappel_planners::rover::problem::{RoverProblem, RoverSpace, RoverState};
use rappel_planners::sampler::{Abit, MotionValidator, Termination};
use rappel_terrain::paton_scene::PatonScene;
use std::cell::RefCell;

/// One logged motion: from, to, anchors before, anchors after or the reason, seconds.
type Entry = (RoverState, RoverState, usize, Result<usize, String>, f64);

/// The rover problem with every motion check logged.
struct Logged<'a> {
    p: &'a RoverProblem,
    log: RefCell<Vec<Entry>>,
}

impl MotionValidator<RoverSpace, 4> for Logged<'_> {
    type History = AnchorHistory;
    fn initial_history(&self, s: &RoverState) -> AnchorHistory {
        self.p.initial_history(s)
    }
    fn state_valid(&self, s: &RoverState) -> bool {
        self.p.state_valid(s)
    }
    fn compatible(&self, a: &AnchorHistory, b: &AnchorHistory) -> bool {
        if std::env::var("EXACT").is_ok() {
            a == b
        } else {
            self.p.compatible(a, b)
        }
    }
    fn history_valid(&self, s: &RoverState, h: &AnchorHistory) -> bool {
        self.p.history_valid(s, h)
    }
    fn motion(
        &self,
        a: &RoverState,
        h: &AnchorHistory,
        b: &RoverState,
    ) -> Option<(f64, AnchorHistory)> {
        let t = std::time::Instant::now();
        let r = self.p.check_motion(a, h, b);
        let dt = t.elapsed().as_secs_f64();
        self.log.borrow_mut().push((
            *a,
            *b,
            h.len(),
            r.as_ref().map(|w| w.history.len()).map_err(|e| e.clone()),
            dt,
        ));
        r.ok().map(|w| (w.cost, w.history))
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let test: usize = args.get(1).map_or(3, |s| s.parse().unwrap());
    let seed: u64 = args.get(2).map_or(0, |s| s.parse().unwrap());
    let iters: u64 = args.get(3).map_or(750, |s| s.parse().unwrap());
    let scene = PatonScene::paper(test == 3);
    let mut p = RoverProblem::paton(&scene, if test == 1 { 0 } else { 1 }).unwrap();
    if let Ok(c) = std::env::var("CORE") {
        p.space.shadow = p
            .space
            .shadow
            .take()
            .map(|sh| sh.with_core_fraction(c.parse().unwrap()));
    }
    let v = Logged {
        p: &p,
        log: RefCell::new(Vec::new()),
    };
    let t = std::time::Instant::now();
    let mut abit = Abit::new(&p.space, &v, p.start, p.goal, {
        let env = |k: &str, d: f64| std::env::var(k).ok().map_or(d, |v| v.parse().unwrap());
        rappel_planners::rover::problem::rover_settings(seed)
            .with_initial_inflation(env("INFL", 1e6))
            .unwrap()
            .with_history_copy_fraction(env("COPY", 0.5))
            .unwrap()
            .with_batch_size(env("BATCH", 100.0) as usize)
            .unwrap()
            .with_rgg_k_factor(env("KF", 1.1))
            .unwrap()
            .with_biased_sample_fraction(env("BIAS", 0.0))
            .unwrap()
    })
    .unwrap();
    let st = abit.solve(Termination::iterations(iters)).unwrap();
    println!(
        "elapsed {:.2}s iterations {} batches {} states {} motions {} shadow samples {} events {:?}",
        t.elapsed().as_secs_f64(),
        st.iterations,
        st.batches,
        st.states,
        st.motions_checked,
        st.biased_samples,
        st.events.first()
    );
    let log = v.log.borrow();
    let tot: f64 = log.iter().map(|l| l.4).sum();
    println!(
        "motion time {:.2}s mean {:.1} ms",
        tot,
        1e3 * tot / log.len().max(1) as f64
    );
    let mut reasons = std::collections::BTreeMap::new();
    for l in log.iter() {
        let key = match &l.3 {
            Ok(n) => format!("ok (anchors {} -> {})", l.2, n),
            Err(e) => {
                let e = e.split(": ").skip(1).collect::<Vec<_>>().join(": ");
                let e: String = e.chars().take(30).collect();
                format!("fail: {e}")
            }
        };
        *reasons.entry(key).or_insert(0) += 1;
    }
    for (k, n) in reasons {
        println!("{n:6} {k}");
    }
    if std::env::var("DUMP").is_ok() {
        for l in log.iter() {
            println!(
                "{:.2} {:.2} {:.0} -> {:.2} {:.2} {:.0} h{} {:?}",
                l.0.x,
                l.0.y,
                l.0.yaw.to_degrees(),
                l.1.x,
                l.1.y,
                l.1.yaw.to_degrees(),
                l.2,
                l.3.as_ref()
                    .map_err(|e| e.chars().take(60).collect::<String>())
            );
        }
    }
}
