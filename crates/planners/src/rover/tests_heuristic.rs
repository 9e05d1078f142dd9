//! Property tests of the rover's cost estimates (`docs/sampler.md`, "A yaw-aware heuristic"):
//! on Paton's test 3 scene, seeded chains of motions the validator accepts, each motion's cost
//! at least its edge estimate ([`StateSpace::motion_cost_heuristic`]) and that at least the
//! path estimate ([`StateSpace::cost_heuristic`]), and every stretch of a chain at least the
//! path estimate between its ends. The chains include motions along the current heading, where
//! the estimates are nearly exact, so an inflated estimate fails these tests. Also: the edge
//! estimate is at least the path estimate for any pair, and a drive ending at a slope break is
//! at most [`DRIVE_MARGIN`] shorter than its planar length.

use std::sync::OnceLock;

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::problem::{DRIVE_MARGIN, RoverProblem, RoverState, commanded_turning, motion_poses};
use crate::sampler::{MotionValidator, StateSpace};
use rappel_terrain::paton_scene::PatonScene;

/// A chain of accepted motions: its states and each motion's cost as the validator charged it.
struct Chain {
    states: Vec<RoverState>,
    costs: Vec<f64>,
}

/// Motion checks the chains are built from (accepted or not).
const CHECKS: usize = 300;
/// Most motions per chain.
const CHAIN_MOTIONS: usize = 4;

fn scene() -> &'static RoverProblem {
    static P: OnceLock<RoverProblem> = OnceLock::new();
    P.get_or_init(|| RoverProblem::paton(&PatonScene::paper(true), 1).unwrap())
}

/// The next state of a chain from `cur`: one in eight at the same point with a new heading (the
/// degenerate motion, a turn in place), half of the rest roughly ahead along the heading with
/// a similar heading (the motions paths are made of, where the estimates are tight), the
/// others anywhere within 2 m with any heading.
fn next_state(rng: &mut ChaCha8Rng, cur: &RoverState) -> RoverState {
    use std::f64::consts::PI;
    let r = rng.random::<f64>();
    if r < 0.125 {
        RoverState {
            yaw: rng.random_range(-PI..PI),
            ..*cur
        }
    } else if r < 0.56 {
        let d = rng.random_range(0.2..1.5);
        let dir = cur.yaw + rng.random_range(-0.3..0.3);
        RoverState {
            x: cur.x + d * dir.cos(),
            y: cur.y + d * dir.sin(),
            yaw: cur.yaw + rng.random_range(-0.5..0.5),
        }
    } else {
        RoverState {
            x: cur.x + rng.random_range(-2.0..2.0),
            y: cur.y + rng.random_range(-2.0..2.0),
            yaw: rng.random_range(-PI..PI),
        }
    }
}

/// The seeded chains, built once for both tests: chains start at valid uniform states with the
/// root anchor's history and continue with each accepted motion's history.
fn chains() -> &'static [Chain] {
    static C: OnceLock<Vec<Chain>> = OnceLock::new();
    C.get_or_init(|| {
        let p = scene();
        let mut rng = ChaCha8Rng::seed_from_u64(33);
        let mut out = Vec::new();
        let mut checks = 0;
        while checks < CHECKS {
            let s0 = p.space.sample_uniform(&mut rng);
            if !p.state_valid(&s0) {
                continue;
            }
            let mut h = p.initial_history(&s0);
            let mut chain = Chain {
                states: vec![s0],
                costs: Vec::new(),
            };
            while chain.costs.len() < CHAIN_MOTIONS && checks < CHECKS {
                let cur = *chain.states.last().unwrap();
                let next = next_state(&mut rng, &cur);
                if !p.state_valid(&next) {
                    break;
                }
                checks += 1;
                let Some((cost, h2)) = p.motion(&cur, &h, &next) else {
                    break;
                };
                chain.states.push(next);
                chain.costs.push(cost);
                h = h2;
            }
            if !chain.costs.is_empty() {
                out.push(chain);
            }
        }
        out
    })
}

#[test]
fn an_accepted_motion_costs_at_least_its_edge_estimate_and_that_at_least_the_path_estimate() {
    let (p, chains) = (scene(), chains());
    let motions: usize = chains.iter().map(|c| c.costs.len()).sum();
    let (mut in_place, mut tightest) = (0, f64::INFINITY);
    for c in chains {
        for (w, &cost) in c.states.windows(2).zip(&c.costs) {
            let (a, b) = (&w[0], &w[1]);
            let (motion, path) = (
                p.space.motion_cost_heuristic(a, b),
                p.space.cost_heuristic(a, b),
            );
            assert!(
                cost >= motion && motion >= path,
                "{a:?} -> {b:?}: cost {cost}, motion estimate {motion}, path estimate {path}"
            );
            in_place += usize::from(a.x == b.x && a.y == b.y);
            tightest = tightest.min(cost / motion);
        }
    }
    eprintln!(
        "{motions} accepted motions, {in_place} in place, cost / edge estimate >= {tightest}"
    );
    // Enough accepted motions, turns in place among them, and the estimate within 2 % of the
    // cost somewhere: an estimate inflated by a few per cent fails the bound above.
    assert!(
        motions >= 30 && in_place >= 2,
        "{motions} motions, {in_place} in place"
    );
    assert!(tightest < 1.02, "cost / estimate at least {tightest}");
}

#[test]
fn a_chain_of_accepted_motions_costs_at_least_the_path_estimate_between_its_ends() {
    let (p, chains) = (scene(), chains());
    let mut stretches = 0;
    for c in chains {
        for i in 0..c.states.len() {
            let mut cost = 0.0;
            for j in i + 1..c.states.len() {
                cost += c.costs[j - 1];
                let path = p.space.cost_heuristic(&c.states[i], &c.states[j]);
                assert!(
                    cost >= path,
                    "{:?}: cost {cost} from state {i} to {j}, path estimate {path}",
                    c.states
                );
                stretches += usize::from(j > i + 1);
            }
        }
    }
    eprintln!(
        "{} chains, {stretches} stretches of several motions",
        chains.len()
    );
    assert!(stretches >= 10, "{stretches} stretches of several motions");
}

#[test]
fn the_edge_estimate_is_at_least_the_path_estimate_for_any_pair() {
    // Cheap, so many pairs: the bound the two estimates must keep between them, including
    // pairs at one point and headings the shorter way round either side of a half turn.
    let space = &scene().space;
    let mut rng = ChaCha8Rng::seed_from_u64(34);
    for k in 0..20_000 {
        let a = space.sample_uniform(&mut rng);
        let b = match k % 4 {
            0 => RoverState {
                yaw: rng.random_range(-4.0..4.0),
                ..a
            },
            _ => space.sample_uniform(&mut rng),
        };
        let (motion, path) = (
            space.motion_cost_heuristic(&a, &b),
            space.cost_heuristic(&a, &b),
        );
        assert!(motion >= path, "{a:?} -> {b:?}: {motion} < {path}");
        // The turning of a motion is at most two half turns.
        assert!(commanded_turning(&a, &b) <= 2.0 * std::f64::consts::PI + 1e-12);
    }
}

#[test]
fn a_drive_ending_at_a_slope_break_is_at_most_the_margin_shorter_than_its_planar_length() {
    // The drive between settled origins, as the validator charges it, for motions ending
    // within 0.4 m of the slope's foot (x = 2.80) or the lip (x = 0), where a footprint
    // straddles the break and its settled origin leaves its ground point: settling only (the
    // drive does not depend on the tether), so many motions.
    let p = scene();
    let mut rng = ChaCha8Rng::seed_from_u64(35);
    let (mut motions, mut worst) = (0, f64::NEG_INFINITY);
    while motions < 120 {
        let break_x = if motions % 3 == 0 { 0.0 } else { 2.8 };
        let b = RoverState {
            x: break_x + rng.random_range(-0.4..0.4),
            y: rng.random_range(-2.5..2.5),
            yaw: rng.random_range(-3.2..3.2),
        };
        let (d, dir) = (rng.random_range(0.1..1.5), rng.random_range(-3.2..3.2f64));
        let a = RoverState {
            x: b.x + d * dir.cos(),
            y: b.y + d * dir.sin(),
            yaw: rng.random_range(-3.2..3.2),
        };
        let Some(poses) = motion_poses(&a, &b) else {
            continue;
        };
        let Ok(origins) = poses
            .iter()
            .map(|(s, _)| p.settle(s).map(|pose| pose.origin))
            .collect::<Result<Vec<_>, _>>()
        else {
            continue;
        };
        let drive: f64 = origins
            .windows(2)
            .zip(&poses[1..])
            .filter(|(_, (_, step))| *step > 0.0)
            .map(|(o, _)| (o[1] - o[0]).norm())
            .sum();
        let planar = (b.x - a.x).hypot(b.y - a.y);
        assert!(
            drive >= planar - DRIVE_MARGIN,
            "{a:?} -> {b:?}: drive {drive}, planar {planar}"
        );
        worst = worst.max(planar - drive);
        motions += 1;
    }
    eprintln!("largest shortfall of the drive below the planar length: {worst} m");
}
