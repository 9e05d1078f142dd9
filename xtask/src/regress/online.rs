//! Regression suite `online`: the online paper's worked example (Fig. 11d-f), one fixture per case
//! of thesis §3.5.3 and for removals, each with the decision its geometry was drawn for, and the
//! completeness study (thesis §3.5.3: "it will eventually find a path to the bottom, if there is
//! one"): over seeded prior/true crater-strip pairs, whenever the offline planner (Alg. 6 on the
//! true map, the independent reference) finds a feasible class, the online run reaches the goal.
//! 20 pairs by default, 200 with `--full`.

use super::case::{Case, full, workspace_root};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rappel::geometry::map::Map;
use rappel::geometry::polygon::Polygon;
use rappel::geometry::predicates::{SegmentContact, segment_contact};
use rappel::nalgebra::Vector2;
use rappel::online::run;
use rappel::plan::{PlanOptions, plan};
use rappel::planners::online::simulate::Ending;
use rappel::planners::online::{ChangeCase, Decision, SimulationOptions, SimulationReport};
use rappel::planners::visibility_graph;
use rappel::scenario::Scenario;

const SUITE: &str = "online";

/// The online form of frictional planning: a PTFO believed to hold is sensed to be nearly
/// frictionless during the descent; the session reclassifies it, its corner slips and is clipped
/// as a map change. References: the frictional planner (Alg. 7 with 8, 9 and 14) on the true
/// scenario, from scratch (it shares the anchor decision and the clip with the session, so it
/// checks the online mechanism), and the closed form of the straight tether.
fn frictional(cases: &mut Vec<Case>) -> Result<(), String> {
    use rappel::planners::online::simulate::Difference;
    let name = "online/friction-weaker";
    let prior = load(&format!("{name}.prior.ron"))?;
    let truth = load(&format!("{name}.ron"))?;
    let report = simulate(&prior, &truth, 5.0)?;
    let sensed: Vec<_> = report
        .timeline
        .iter()
        .filter(|e| e.difference == Difference::Friction { prior: 0 })
        .collect();
    let slipped = !sensed.is_empty() && sensed.iter().all(|e| e.outcome.reason.contains("slips"));
    cases.push(Case::closed_form(
        SUITE,
        format!("{name}: the weaker PTFO sensed and reclassified"),
        format!("{} event(s), slips: {}", sensed.len(), yes(slipped)),
        "at least 1 event, every one a slip (truth's friction 0.01)",
        slipped,
    ));
    let offline = plan(&truth, &PlanOptions::default()).map_err(|e| format!("{name}: {e}"))?;
    let reference = offline.outcome.friction.as_ref().and_then(|f| {
        let rank = f.chosen?;
        f.classes
            .iter()
            .find(|c| c.rank == rank)
            .map(|c| c.length_m)
    });
    let measured = report.final_class_length_m;
    let same =
        matches!((measured, reference), (Some(a), Some(b)) if (a - b).abs() <= 1e-9 * b.max(1.0));
    cases.push(Case::oracle(
        SUITE,
        format!("{name}: final class SHP, m"),
        measured.map_or("none".into(), |l| format!("{l:.6}")),
        reference.map_or("none".into(), |l| {
            format!("{l:.6} (Alg. 7 on the true scenario, from scratch)")
        }),
        same,
    ));
    // Independent of the friction code both sides above share (Alg. 8-9 decisions, the clip): at
    // friction 0.01 no wrap of the pillar holds, and the start and goal lie on the line through
    // its diagonal corners, so the tether ends straight: |goal - start|.
    let straight = (truth.goal - truth.start).norm();
    cases.push(Case::closed_form(
        SUITE,
        format!("{name}: final class SHP against the closed form, m"),
        measured.map_or("none".into(), |l| format!("{l:.6}")),
        format!("{straight:.6} (|goal - start|: the nearly frictionless pillar holds nothing)"),
        measured.is_some_and(|l| (l - straight).abs() <= 1e-9 * straight),
    ));
    cases.push(Case::closed_form(
        SUITE,
        format!("{name}: ending"),
        format!("{:?}, homotopic: {}", report.ending, yes(report.homotopic)),
        "Goal, homotopic: yes",
        report.ending == Ending::Goal && report.homotopic,
    ));
    Ok(())
}

/// Pairs of the completeness study in CI and with `--full`.
const PAIRS_CI: u64 = 20;
const PAIRS_FULL: u64 = 200;

fn load(name: &str) -> Result<Scenario, String> {
    Scenario::load(workspace_root().join("fixtures").join(name)).map_err(|e| format!("{name}: {e}"))
}

fn simulate(prior: &Scenario, truth: &Scenario, range: f64) -> Result<SimulationReport, String> {
    let options = SimulationOptions {
        sensor_range: range,
        ..Default::default()
    };
    run(prior, truth, &options, &mut |_, _| {})
        .map(|r| r.report)
        .map_err(|e| e.to_string())
}

fn decision_word(d: &Decision) -> String {
    match d {
        Decision::Switched { backtrack_m, .. } => format!("switched, {backtrack_m:.2} m back"),
        other => format!("{other:?}").to_lowercase(),
    }
}

/// Runs the suite.
pub fn suite() -> Result<Vec<Case>, String> {
    let mut cases = Vec::new();
    worked_example(&mut cases)?;
    case_fixtures(&mut cases)?;
    frictional(&mut cases)?;
    completeness(&mut cases)?;
    Ok(cases)
}

/// Fig. 11d-f: the robot turns the corner of the first obstacle, discovers a third in its sleeve,
/// the SHP changes (a new anchor on it), the class is still feasible, and the robot goes on from
/// where it is.
fn worked_example(cases: &mut Vec<Case>) -> Result<(), String> {
    let name = "Fig. 11 online-example-discovered";
    let prior = load("online-example.ron")?;
    let truth = load("online-example-discovered.ron")?;
    let discovered = truth.map.obstacles[2].clone();
    // The redrawn obstacle meets the prior plan's taut tether (the complaint).
    let planned = plan(&prior, &PlanOptions::default()).map_err(|e| e.to_string())?;
    let shp = &planned.classes[0].points;
    let touches = shp.windows(2).any(|w| {
        discovered
            .edges()
            .any(|(p, q)| segment_contact(p, q, &w[0], &w[1]) != SegmentContact::Disjoint)
    });
    cases.push(Case::paper_verdict(
        SUITE,
        format!("{name}: new obstacle meets the prior SHP"),
        yes(touches),
        "yes (Fig. 11e: the SHP changes)",
        touches,
    ));
    let r = simulate(&prior, &truth, SimulationOptions::default().sensor_range)?;
    let event = r.timeline.first();
    let corner = prior.map.obstacles[0].vertices[1];
    let after_corner = event.is_some_and(|e| e.robot.y < corner.y);
    cases.push(Case::paper_verdict(
        SUITE,
        format!("{name}: discovered after turning the corner"),
        event.map_or("no event".into(), |e| {
            format!("at ({:.2}, {:.2})", e.robot.x, e.robot.y)
        }),
        format!("below the corner y = {}", corner.y),
        after_corner && r.timeline.len() == 1,
    ));
    let case = event.map(|e| e.outcome.case);
    cases.push(Case::closed_form(
        SUITE,
        format!("{name}: case"),
        format!("{case:?}"),
        "Split (drawn strictly inside the sleeve)",
        case == Some(ChangeCase::Split),
    ));
    let decision = event.map(|e| e.outcome.decision.clone());
    let from_robot =
        matches!(decision, Some(Decision::Switched { backtrack_m, .. }) if backtrack_m == 0.0);
    cases.push(Case::paper_verdict(
        SUITE,
        format!("{name}: decision"),
        decision.as_ref().map_or("none".into(), decision_word),
        "new descent from the robot's position, 0 m back (Fig. 11f)",
        from_robot,
    ));
    let anchors_on_new = r
        .final_class_length_m
        .zip(r.initial_class_length_m)
        .is_some_and(|(after, before)| after > before);
    cases.push(Case::paper_verdict(
        SUITE,
        format!("{name}: SHP longer after the discovery"),
        format!(
            "{:.3} -> {:.3} m",
            r.initial_class_length_m.unwrap_or(f64::NAN),
            r.final_class_length_m.unwrap_or(f64::NAN)
        ),
        "longer (it wraps the new obstacle)",
        anchors_on_new,
    ));
    cases.push(Case::paper_verdict(
        SUITE,
        format!("{name}: end"),
        format!("{:?}, homotopic {}", r.ending, yes(r.homotopic)),
        "Goal, homotopic yes (paper: the robot continues to the goal)",
        r.ending == Ending::Goal && r.homotopic,
    ));
    Ok(())
}

/// One fixture per case, with the case and decision its geometry was drawn for.
fn case_fixtures(cases: &mut Vec<Case>) -> Result<(), String> {
    struct Row {
        prior: &'static str,
        truth: &'static str,
        range: f64,
        case: ChangeCase,
        decision: &'static str,
        ending: &'static str,
        why: &'static str,
    }
    let rows = [
        Row {
            prior: "online-example.ron",
            truth: "online/case-1-blocked.ron",
            range: 5.0,
            case: ChangeCase::Blocked,
            decision: "nofeasibleclass",
            ending: "no feasible class",
            why: "ledge crosses both sides; detours exceed the 45° cone",
        },
        Row {
            prior: "online/case-1-blocked-flat.prior.ron",
            truth: "online/case-1-blocked-flat.ron",
            range: 5.0,
            case: ChangeCase::Blocked,
            decision: "switched, backtrack > 0",
            ending: "goal",
            why: "ledge crosses both sides; tether-free: backtrack, west class",
        },
        Row {
            prior: "online-example.ron",
            truth: "online/case-2-geometry.ron",
            range: 12.0,
            case: ChangeCase::GeometryChanged,
            decision: "continue",
            ending: "goal",
            why: "rock crosses the right side only, away from the tether",
        },
        Row {
            prior: "online-example.ron",
            truth: "online/case-3-shp.ron",
            range: 5.0,
            case: ChangeCase::ShpChanged,
            decision: "switched, 0 m back",
            ending: "goal",
            why: "ledge crosses the left side and the taut tether",
        },
        Row {
            prior: "online-example.ron",
            truth: "online/case-4-split.ron",
            range: 5.0,
            case: ChangeCase::Split,
            decision: "newpaths",
            ending: "goal",
            why: "rock inside the sleeve across the SHP, beside the descent",
        },
        Row {
            prior: "online-example.ron",
            truth: "online/removal-anchors.ron",
            range: 5.0,
            case: ChangeCase::AnchorsChanged,
            decision: "newpaths",
            ending: "goal",
            why: "the phantom carries the SHP's second anchor",
        },
        Row {
            prior: "online/removal-opened.prior.ron",
            truth: "online-example.ron",
            range: 5.0,
            case: ChangeCase::SleeveOpened,
            decision: "continue",
            ending: "goal",
            why: "the phantom lies in the sleeve beside the tether",
        },
    ];
    for row in rows {
        let r = simulate(&load(row.prior)?, &load(row.truth)?, row.range)?;
        let first = r.timeline.first();
        let case = first.map(|e| e.outcome.case);
        let decision = first.map(|e| &e.outcome.decision);
        let decision_ok = match row.decision {
            "switched, backtrack > 0" => {
                matches!(decision, Some(Decision::Switched { backtrack_m, .. }) if *backtrack_m > 0.0)
            }
            "switched, 0 m back" => {
                matches!(decision, Some(Decision::Switched { backtrack_m, .. }) if *backtrack_m == 0.0)
            }
            "continue" => decision == Some(&Decision::Continue),
            "newpaths" => decision == Some(&Decision::NewPaths),
            "nofeasibleclass" => decision == Some(&Decision::NoFeasibleClass),
            _ => false,
        };
        let ending_ok = match row.ending {
            "goal" => r.ending == Ending::Goal && r.homotopic,
            _ => matches!(r.ending, Ending::NoFeasibleClass { .. }),
        };
        cases.push(Case::closed_form(
            SUITE,
            format!("{}: case, decision, end", row.truth),
            format!(
                "{case:?}, {}, {:?}",
                decision.map_or("none".into(), decision_word),
                r.ending
            ),
            format!(
                "{:?}, {}, {} ({})",
                row.case, row.decision, row.ending, row.why
            ),
            case == Some(row.case) && decision_ok && ending_ok,
        ));
    }
    Ok(())
}

/// A seeded prior/true pair: a crater strip as the truth, and a prior with some of its
/// obstacles hidden, some phantoms added (taken from a denser strip of the same seed, so they
/// never overlap the truth) and some shifted.
fn pair(seed: u64) -> Result<(Scenario, Scenario), String> {
    let width = 30.0;
    let dense =
        rappel::generated::crater_strip_scenario(40, seed, width).map_err(|e| e.to_string())?;
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x0001_111e);
    let mut truth_obstacles = Vec::new();
    let mut prior_obstacles = Vec::new();
    for o in &dense.map.obstacles {
        match rng.random_range(0..100) {
            0..25 => truth_obstacles.push(o.clone()), // hidden from the prior
            25..45 => prior_obstacles.push(o.clone()), // a phantom
            45..60 => {
                let d = Vector2::new(rng.random_range(-1.5..1.5), rng.random_range(-1.5..1.5));
                let moved = Polygon::new(o.vertices.iter().map(|p| p + d).collect());
                truth_obstacles.push(o.clone());
                let mut trial = Map::new(dense.map.boundary.clone(), prior_obstacles.clone());
                trial.obstacles.push(moved.clone());
                let ok = trial.validate().is_ok()
                    && [dense.start, dense.goal]
                        .iter()
                        .all(|p| trial.validate_point("endpoint", p).is_ok())
                    && truth_obstacles.iter().chain(&dense.map.obstacles).all(|t| {
                        t == o
                            || !t.edges().any(|(a, b)| {
                                moved.edges().any(|(c, e)| {
                                    segment_contact(a, b, c, e) != SegmentContact::Disjoint
                                })
                            })
                    });
                prior_obstacles.push(if ok { moved } else { o.clone() });
            }
            _ => {
                truth_obstacles.push(o.clone());
                prior_obstacles.push(o.clone());
            }
        }
    }
    let mut prior = dense.clone();
    prior.map.obstacles = prior_obstacles;
    let mut truth = dense;
    truth.map.obstacles = truth_obstacles;
    prior
        .map
        .validate()
        .map_err(|e| format!("seed {seed} prior: {e}"))?;
    Ok((prior, truth))
}

fn percentile(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let i = ((sorted.len() - 1) as f64 * q).round() as usize;
    sorted[i]
}

fn completeness(cases: &mut Vec<Case>) -> Result<(), String> {
    let n = if full() { PAIRS_FULL } else { PAIRS_CI };
    let (mut offline_feasible, mut reached, mut homotopic) = (0, 0, 0);
    let mut ratios = Vec::new();
    let mut backs = Vec::new();
    // Per run: reported - retraced backtrack, (travelled - 2 back) - geodesic, retraced.
    let mut back_checks: Vec<(f64, f64, f64)> = Vec::new();
    let mut failures = Vec::new();
    for seed in 0..n {
        let (prior, truth) = pair(seed)?;
        let options = PlanOptions {
            classes: rappel::planners::online::DEFAULT_ONLINE_CLASSES,
            ..Default::default()
        };
        let offline = plan(&truth, &options).map_err(|e| e.to_string())?;
        // The offline optimum: the shortest class whose ascent is feasible on the true map.
        let Some(optimal) = offline
            .classes
            .iter()
            .find(|c| c.feasible)
            .map(|c| c.length_m)
        else {
            continue;
        };
        offline_feasible += 1;
        match simulate(&prior, &truth, SimulationOptions::default().sensor_range) {
            Ok(r) if r.ending == Ending::Goal => {
                reached += 1;
                homotopic += usize::from(r.homotopic);
                ratios.push(r.travelled_m / optimal);
                backs.push(r.backtracked_m);
                let geodesic = visibility_graph::shortest_path(&truth.map, truth.start, truth.goal)
                    .map_or(f64::NAN, |p| p.length);
                let retraced = retraced_length(&r.travelled);
                back_checks.push((
                    r.backtracked_m - retraced,
                    r.travelled_m - 2.0 * r.backtracked_m - geodesic,
                    retraced,
                ));
            }
            Ok(r) => failures.push(format!("seed {seed}: {:?}", r.ending)),
            Err(e) => failures.push(format!("seed {seed}: {e}")),
        }
    }
    ratios.sort_by(f64::total_cmp);
    backs.sort_by(f64::total_cmp);
    cases.push(Case::oracle(
        SUITE,
        format!("completeness, {n} seeded pairs: goal reached when offline feasible"),
        format!(
            "{reached} of {offline_feasible}{}",
            if failures.is_empty() {
                String::new()
            } else {
                format!(" ({})", failures.join("; "))
            }
        ),
        "all (thesis §3.5.3 completeness; offline Alg. 6 on the true map)",
        reached == offline_feasible && offline_feasible > 0,
    ));
    cases.push(Case::property(
        SUITE,
        "completeness: ascent and descent homotopic at the goal",
        format!("{homotopic} of {reached}"),
        "all",
        homotopic == reached,
    ));
    let lowest = ratios.first().copied().unwrap_or(f64::NAN);
    cases.push(Case::oracle(
        SUITE,
        "completeness: travelled / offline-optimal length (median, p95, min)",
        format!(
            "{:.3}, {:.3}, {:.3}",
            percentile(&ratios, 0.5),
            percentile(&ratios, 0.95),
            lowest
        ),
        "min >= 1 - 1e-9 (no run beats the offline optimum on the true map)",
        lowest >= 1.0 - 1e-9,
    ));
    let worst_back = back_checks
        .iter()
        .map(|c| c.0)
        .fold(f64::NEG_INFINITY, f64::max);
    let worst_walk = back_checks
        .iter()
        .map(|c| c.1)
        .fold(f64::INFINITY, f64::min);
    let retracing = back_checks.iter().filter(|c| c.2 > 0.0).count();
    let uncounted = back_checks.iter().filter(|c| c.0 < -1e-6).count();
    cases.push(Case::oracle(
        SUITE,
        "completeness: backtracked distance (median, p95), m",
        format!(
            "{:.2}, {:.2}; {retracing} run(s) retrace, {uncounted} retrace more than reported; \
             largest reported - retraced {worst_back:.1e} m; least (travelled - 2 back) - \
             geodesic {worst_walk:.3} m",
            percentile(&backs, 0.5),
            percentile(&backs, 0.95)
        ),
        "each run: every reported metre is the robot's path running back over itself \
         (reported <= retraced + 1e-6 m), and travelled - 2 backtracked >= the shortest free \
         path on the true map (visibility graph)",
        back_checks.iter().all(|c| c.0 <= 1e-6) && worst_walk >= -1e-6,
    ));
    Ok(())
}

/// The length of the robot's path that runs back over a stretch it drove earlier, in the
/// opposite direction: each step `p -> q` lying on an earlier step `a -> b` (both ends within 1e-9
/// of its line, between its ends) and pointing against it. Computed from the path alone,
/// independently of the session's own count.
fn retraced_length(path: &[rappel::nalgebra::Point2<f64>]) -> f64 {
    let steps: Vec<_> = path.windows(2).map(|w| (w[0], w[1])).collect();
    let mut total = 0.0;
    for (i, &(p, q)) in steps.iter().enumerate() {
        let d = q - p;
        let len = d.norm();
        if len == 0.0 {
            continue;
        }
        let back = steps[..i].iter().any(|&(a, b)| {
            let e = b - a;
            let l2 = e.norm_squared();
            if l2 == 0.0 || d.dot(&e) >= 0.0 {
                return false;
            }
            let scale = 1e-9 * (1.0 + a.coords.norm().max(b.coords.norm()));
            [p, q].iter().all(|x| {
                let t = (x - a).dot(&e) / l2;
                let off = (x - a - e * t).norm();
                off <= scale && t >= -scale && t <= 1.0 + scale
            })
        });
        if back {
            total += len;
        }
    }
    total
}

fn yes(b: bool) -> &'static str {
    if b { "yes" } else { "no" }
}
