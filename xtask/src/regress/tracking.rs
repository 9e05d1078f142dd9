//! Regression cases of tether tracking and two robots on one tether (Kumar Alg. 1, Problem 1,
//! Fig. 5): Kumar's environment (S0 flat with two obstacles, S1 55 deg, S2 65 deg, S3 flat;
//! m1 = m2 = 35 kg, mu = 0.4), Robot 1's three paths built as §IV describes them (5a partly round
//! one obstacle, 5b partly round both, 5c partly round one and almost a full round round the
//! other), `T_2max` from their tracked windings against the paper's 200 / 300 / 500 N, and Robot
//! 2's stability grids on S1 and S2 against what §IV says of each panel, in two models: rappel's
//! (`TrackModel::default`) and Kumar's text as written (`TrackModel::kumar`: ground anchors at
//! valleys, Robot 2 as the free body of Fig. 4, the pyramid of eq. 3c).
//!
//! References come from outside the code under test: the paper's numbers and verdicts, and the
//! homotopy crate's shortest homotopic path (an independent oracle for the tracked tether). Where
//! our faithful model disagrees with the paper, the row says DIFFERS with the reason; those rows
//! are listed, with their reasons, in the runner's [`super::KNOWN_DIFFERENCES`].
//!
//! The geometry the paper does not give numerically is chosen here: surfaces 16 m wide
//! (`x` in `[-8, 8]`), S0 14 m deep, S1 and S2 8 m long, S3 4 m; obstacle O1 the square
//! `[-4, -2] x [22, 24]`, O2 the square `[2, 4] x [19, 21]` (frame metres, `y` up the fall line);
//! Robot 2 starts at `(3, 17)` on S0, Robot 1 at `(5, 18)`; Robot 1's paths (below) wind the
//! tether as the paper describes, all three leaving Robot 2 the same last anchor (O2's corner
//! `(4, 19)`, as §IV sets up). `F_0 = 0`: Robot 1 holds with its wheels' friction only, so
//! `T_1 <= mu m1 g = 137.3 N` (eq. 1); a larger `F_0` only raises every `T_2max`.

use super::case::Case;
use rappel::geometry::btm::Btm;
use rappel::geometry::map::Map;
use rappel::geometry::polygon::Polygon;
use rappel::homotopy::path::Path;
use rappel::homotopy::shp::shortest_homotopic_path;
use rappel::mechanics::four_wheel::FourWheelRover;
use rappel::mechanics::robot::{RobotModel, STANDARD_GRAVITY};
use rappel::mechanics::tension_limit::HoldingRobot;
use rappel::nalgebra::Point2;
use rappel::planners::tether_tracking::two_robots::{TrackModel, TwoRobots, WaypointReport};
use rappel::planners::tether_tracking::{AnchorKind, TetherTracker, windings_of};
use rappel::terrain::kumar::{kumar_obstacles, kumar_scene};
use rappel::terrain::plane_series_terrain::PlaneSeriesTerrain;

const SUITE: &str = "tracking";

fn p(x: f64, y: f64) -> Point2<f64> {
    Point2::new(x, y)
}

fn kumar_terrain() -> Result<PlaneSeriesTerrain, String> {
    kumar_scene().map_err(|e| e.to_string())
}

const ROBOT2_START: (f64, f64) = (3.0, 17.0);

/// The three scenarios: name, the paper's `T_2max`, Robot 1's path (as §IV describes it).
fn scenarios() -> Vec<(&'static str, f64, Vec<Point2<f64>>)> {
    vec![
        // "Robot 1 partially winds around one obstacle": up O2's right side and over its top.
        ("5a", 200.0, vec![p(5.0, 18.0), p(5.0, 23.0), p(3.0, 23.0)]),
        // "partially winds around 2 obstacles": O2's right side, then over O1's top.
        (
            "5b",
            300.0,
            vec![
                p(5.0, 18.0),
                p(5.0, 23.0),
                p(0.0, 25.0),
                p(-5.0, 25.0),
                p(-5.5, 24.0),
            ],
        ),
        // "partially winds around one obstacle, completes almost one round of winding around the
        // other": partly round O2 (its right side), then over, down, under and up O1 until just
        // short of the tether's own segment arriving at O1 (a full round would cross it).
        (
            "5c",
            500.0,
            vec![
                p(5.0, 18.0),
                p(5.0, 23.0),
                p(0.0, 25.0),
                p(-5.0, 25.0),
                p(-5.0, 21.0),
                p(-1.5, 21.0),
                p(-1.8, 23.8),
            ],
        ),
    ]
}

/// The models the grids are judged in: a label for the row names and the model.
fn models() -> [(&'static str, TrackModel); 2] {
    [
        ("rappel's model", TrackModel::default()),
        (
            "Kumar's text: valley anchors, free body, eq. 3c",
            TrackModel::kumar(),
        ),
    ]
}

/// Robot 2's grid on a surface band `(y_bottom, y_top)`: 1 m steps, half a metre in from the
/// edges, `x` in `[-7, 7]`.
fn grid(y_bottom: f64, y_top: f64) -> Vec<Point2<f64>> {
    let mut out = Vec::new();
    let mut y = y_bottom + 0.5;
    while y < y_top {
        for i in -7..=7 {
            out.push(p(i as f64, y));
        }
        y += 1.0;
    }
    out
}

/// Robot 2's verdicts over one grid.
struct Counts {
    red: usize,
    green: usize,
    yellow: usize,
    /// The stable poses (green or yellow).
    stable: Vec<Point2<f64>>,
}

impl Counts {
    /// Stable poses left of the centre line (`x < 0`), on it, and right of it.
    fn by_side(&self) -> [usize; 3] {
        let mut s = [0; 3];
        for q in &self.stable {
            s[if q.x < 0.0 {
                0
            } else if q.x == 0.0 {
                1
            } else {
                2
            }] += 1;
        }
        s
    }

    /// "red / green / yellow of n; stable x in [a, b], y in [c, d]".
    fn describe(&self) -> String {
        let n = self.red + self.green + self.yellow;
        let head = format!("{} / {} / {} of {n}", self.red, self.green, self.yellow);
        if self.stable.is_empty() {
            return head;
        }
        let lo_hi = |f: fn(&Point2<f64>) -> f64| {
            let v = self.stable.iter().map(f);
            (
                v.clone().fold(f64::INFINITY, f64::min),
                v.fold(f64::NEG_INFINITY, f64::max),
            )
        };
        let (x0, x1) = lo_hi(|q| q.x);
        let (y0, y1) = lo_hi(|q| q.y);
        format!("{head}; stable x {x0}..{x1}, y {y0}..{y1}")
    }
}

/// Robot 2 walks straight from its start to each grid pose; red unstable, green stable with the
/// obstacle windings alone, yellow stable only with the ground anchors' gain (Kumar's yellow).
fn classify(
    two: &TwoRobots<'_, PlaneSeriesTerrain>,
    path1: &[Point2<f64>],
    poses: &[Point2<f64>],
) -> Result<Counts, String> {
    let mut c = Counts {
        red: 0,
        green: 0,
        yellow: 0,
        stable: Vec::new(),
    };
    let start = p(ROBOT2_START.0, ROBOT2_START.1);
    for q in poses {
        let reports = two
            .run(path1, &[start, p(q.x, 16.0), *q])
            .map_err(|e| e.to_string())?;
        let r: &WaypointReport = reports.last().ok_or("no report")?;
        if r.stable {
            c.stable.push(*q);
        }
        if !r.stable {
            c.red += 1;
        } else if r
            .required_tension_n
            .is_some_and(|t| t > r.t2max_obstacles_n && r.ground_anchored)
        {
            c.yellow += 1;
        } else {
            c.green += 1;
        }
    }
    Ok(c)
}

/// What §IV says of Robot 2 on one surface in one panel: the quote and the test of our verdicts.
fn paper_says(fig: &str, surface: &str) -> (&'static str, fn(&Counts) -> bool) {
    match (fig, surface) {
        ("5a", _) => (
            "none stable: 'there is not enough friction either on the wheels or due to the \
             capstan effect to support Robot 2'",
            |c| c.stable.is_empty(),
        ),
        ("5b", "S1") => (
            "stable only in the right section: 'Robot 2 is stable at the right section of the \
             surface S1' (some right of centre, none left)",
            |c| {
                let [left, _, right] = c.by_side();
                left == 0 && right > 0
            },
        ),
        ("5b", _) => (
            "none stable: only 5c is 'stable even on the steeper surface S2'",
            |c| c.stable.is_empty(),
        ),
        _ => (
            "some stable: 'the Robot 2 is stable even on the steeper surface S2' (so on S1 too)",
            |c| !c.stable.is_empty(),
        ),
    }
}

/// The suite.
pub fn suite() -> Result<Vec<Case>, String> {
    let terrain = kumar_terrain()?;
    let rover = FourWheelRover::default();
    let holding = HoldingRobot {
        max_pull: 0.0,
        friction: 0.4,
        mass: 35.0,
    };
    let two_in = |model| TwoRobots {
        terrain: &terrain,
        holding,
        gravity: STANDARD_GRAVITY,
        robot2: &rover as &dyn RobotModel,
        tether_height: rover.params().tether_exit.z,
        model,
    };
    let two = two_in(TrackModel::default());
    let map = Map::new(
        Polygon::rectangle(-8.0, -4.0, 16.0, 34.0),
        kumar_obstacles(),
    );
    let btm = Btm::from_map(&map).map_err(|e| e.to_string())?;
    let start2 = p(ROBOT2_START.0, ROBOT2_START.1);
    let t1 = holding
        .holding_limit(STANDARD_GRAVITY)
        .map_err(|e| e.to_string())?;
    let mut cases = Vec::new();
    let s1 = grid(8.0, 16.0);
    let s2 = grid(0.0, 8.0);
    let mut last_anchors = Vec::new();
    for (name, paper, path1) in scenarios() {
        // The tracked tether of Robot 1's path equals the SHP of that path from Robot 2's start.
        let mut tr = TetherTracker::new(&terrain, start2, path1[0]).map_err(|e| e.to_string())?;
        tr.follow(&path1[1..]).map_err(|e| e.to_string())?;
        let mut walk = vec![start2];
        walk.extend(&path1);
        let shp = shortest_homotopic_path(&btm, &Path::new(walk).map_err(|e| e.to_string())?)
            .map_err(|e| e.to_string())?;
        let anchors = tr.obstacle_anchors().len();
        let len = tr.length();
        cases.push(Case::oracle(
            SUITE,
            format!("Kumar Fig. {name}: Robot 1's tracked tether vs the SHP (homotopy crate)"),
            format!("{anchors} anchors, {len:.6} m"),
            format!(
                "{} anchors, {:.6} m (rel. 1e-9)",
                shp.taut.anchors.len(),
                shp.taut.length
            ),
            anchors == shp.taut.anchors.len()
                && (len - shp.taut.length).abs() <= 1e-9 * shp.taut.length,
        ));
        last_anchors.push(tr.obstacle_anchors().first().map(|a| a.point));
        // The winding on each obstacle, from the tracked windings (Robot 2 at its start).
        let at_start = two.run(&path1, &[start2]).map_err(|e| e.to_string())?;
        let w = &at_start[0];
        let mut per_obstacle = [0.0f64; 2];
        for (a, (_, phi)) in w.configuration[1..]
            .iter()
            .zip(windings_of(&terrain, &w.configuration))
        {
            if let AnchorKind::Obstacle { obstacle, .. } = a.kind {
                per_obstacle[obstacle] += phi;
            }
        }
        let t2 = w.t2max_n;
        let row = Case::paper_number(
            SUITE,
            format!("Kumar Fig. {name}: T2max from Robot 1's windings (eq. 2), Robot 2 at start"),
            format!(
                "{t2:.1} N (winding {:.1} deg: O1 {:.1}, O2 {:.1})",
                w.total_winding.to_degrees(),
                per_obstacle[0].to_degrees(),
                per_obstacle[1].to_degrees()
            ),
            format!("{paper:.0} N +- 10% (paper)"),
            (t2 - paper).abs() <= 0.1 * paper,
        );
        cases.push(if name == "5c" {
            // Eq. 2 with mu = 0.4 and F_0 >= 0: 500 N needs at most ln(500 / 137.3) / 0.4 =
            // 185 deg in all, while almost one round (>= 270 deg) on one obstacle alone gives
            // >= 137.3 exp(0.4 * 3 pi / 2) = 904 N.
            let least = t1 * (0.4 * 1.5 * std::f64::consts::PI).exp();
            row.differs_within(
                format!(
                    "1,500..=2,600 N, >= 270 deg on one obstacle (alone >= {least:.0} N); the \
                     paper's 500 N allows <= 185 deg in all"
                ),
                (1500.0..=2600.0).contains(&t2)
                    && per_obstacle
                        .iter()
                        .any(|p| *p >= 1.5 * std::f64::consts::PI),
            )
        } else {
            row
        });
    }
    // The paper's set-up: "the initial tether configuration [has] the same last anchor point
    // from Robot 2's end" in all three scenarios.
    let same = last_anchors.windows(2).all(|w| w[0] == w[1]) && last_anchors[0].is_some();
    cases.push(Case::property(
        SUITE,
        "Kumar Fig. 5: Robot 2's last anchor is the same in all three panels (§IV set-up)",
        format!("{last_anchors:?}"),
        "one and the same obstacle corner (paper's set-up)",
        same,
    ));
    for (label, model) in models() {
        let two = two_in(model);
        let mut stable_sets: Vec<Vec<Point2<f64>>> = Vec::new();
        for (name, _, path1) in scenarios() {
            let mut all = Vec::new();
            for (surface, poses) in [("S1", &s1), ("S2", &s2)] {
                let c = classify(&two, &path1, poses)?;
                let (quote, holds) = paper_says(name, surface);
                let row = Case::paper_verdict(
                    SUITE,
                    format!(
                        "Kumar Fig. {name}, Robot 2 on {surface} ({label}): red / green / yellow"
                    ),
                    c.describe(),
                    format!("paper: {quote}"),
                    holds(&c),
                );
                cases.push(match band(label, name, surface) {
                    Some(b) => {
                        let inside = b.green.contains(&c.green) && b.yellow.contains(&c.yellow);
                        row.differs_within(
                            format!("green {:?}, yellow {:?} of 120", b.green, b.yellow),
                            inside,
                        )
                    }
                    None => row,
                });
                all.extend(c.stable);
            }
            stable_sets.push(all);
        }
        // Same last anchor, growing T2max: every pose stable in 5a is stable in 5b, and every
        // one stable in 5b is stable in 5c (the LP's feasible set grows with its limit).
        let nested = stable_sets
            .windows(2)
            .all(|w| w[0].iter().all(|q| w[1].contains(q)));
        cases.push(Case::property(
            SUITE,
            format!("Kumar Fig. 5 ({label}): stable poses nested 5a in 5b in 5c"),
            format!(
                "{} / {} / {} stable",
                stable_sets[0].len(),
                stable_sets[1].len(),
                stable_sets[2].len()
            ),
            "nested (same last anchor, T2max growing)",
            nested,
        ));
    }
    Ok(cases)
}

/// The band a known difference of Fig. 5 is expected in: green and yellow counts of Robot 2's
/// 120 poses.
struct FigBand {
    green: std::ops::RangeInclusive<usize>,
    yellow: std::ops::RangeInclusive<usize>,
}

/// The bands of the known differences (`super::KNOWN_DIFFERENCES`), around the measured counts
/// (see each entry there): the count that makes the difference stays within about a third of
/// its measured value, the other at its measured value; a row outside its band (more or fewer)
/// fails until the list is updated.
fn band(model: &str, fig: &str, surface: &str) -> Option<FigBand> {
    let kumar = model != "rappel's model";
    match (kumar, fig, surface) {
        (false, "5a", "S1") => Some(FigBand {
            green: 0..=0,
            yellow: 24..=46,
        }),
        (false, "5a", "S2") => Some(FigBand {
            green: 0..=0,
            yellow: 19..=37,
        }),
        (false, "5b", "S2") => Some(FigBand {
            green: 14..=26,
            yellow: 19..=37,
        }),
        // Measured 11 / 0: the free body's pyramid corners (7.7 to 16.3 deg off the line).
        (true, "5a", "S1") => Some(FigBand {
            green: 7..=15,
            yellow: 0..=0,
        }),
        // Measured 48 / 0: the whole lateral wedge below the anchor holds at 300 N.
        (true, "5b", "S2") => Some(FigBand {
            green: 32..=64,
            yellow: 0..=0,
        }),
        _ => None,
    }
}
