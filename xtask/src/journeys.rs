//! `cargo xtask journeys`: every subcommand of the `rappel` binary run the way a user runs it, on
//! every bundled fixture it accepts and on freshly generated crater strips, each run checked
//! against what the README promises.
//!
//! A **journey** is a short sequence of command lines in a scratch folder of its own (generate a
//! strip, plan on it, check the pair with `homotopic` and `shp`, ...). Each step asserts:
//! - the exit code the README documents for its input (0 yes, 1 a clean no);
//! - the `--json` report parses and conforms to its committed schema in `docs/schemas/`
//!   ([`rappel_schemas`]), and says what the step expects (a chosen pair on every strip,
//!   no error on any query pair, ...), checked independently where a closed form exists: a path
//!   is no shorter than the straight line between its ends, the pair keeps the clearance from
//!   every anchor of its class (distances computed here from the report's points), the pair's
//!   two paths are homotopic (`rappel homotopic`) and the descent's taut tether is the class's
//!   SHP (`rappel shp`);
//! - every picture or export it asked for was written, is non-empty and reads as its format
//!   (SVG and HTML documents closed, GeoJSON a feature collection, CSV rows of the header's
//!   width, a scenario that `rappel validate` accepts); an HTML page is loaded in headless
//!   Chromium when it is there (`--viewer` requires it) and must finish its script without errors;
//! - the input files are byte for byte what they were.
//!
//! One line per journey and a closing `journeys: N passed, M failed`; exit 1 on any failure.
//! Sizes: strips of 100, 1,000 and 10,000 obstacles, seeds 1-5 (`--full`: also 100,000, seed 1).
//! Two journeys run at a time (the machines have two cores). The binary is `target/release/rappel`
//! when it exists, else `target/debug/rappel` (`--bin` names another).

use crate::regress::case::workspace_root;
use rappel_schemas as schema_check;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

/// How the HTML pages are checked.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Viewer {
    /// In headless Chromium when it is installed, else only as documents.
    Auto,
    /// In headless Chromium; its absence fails the run.
    Require,
}

/// What a step's output file must be.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Svg,
    Html,
    GeoJson,
    Csv,
    /// A scenario file `rappel validate` accepts.
    Scenario,
}

/// A check of a step's JSON report beyond its schema, given the journey's folder.
type Check = Box<dyn Fn(&Value, &Path) -> Result<(), String> + Send + Sync>;

/// One command line of a journey.
struct Step {
    args: Vec<String>,
    exit: i32,
    /// The schema (`docs/schemas/NAME.json`) of its `--json` report on stdout, if it prints one.
    report: Option<&'static str>,
    outputs: Vec<(String, Kind)>,
    check: Option<Check>,
    /// Text the one `error:` line of an exit-2 step must contain (the problem named).
    error: Option<&'static str>,
}

impl Step {
    fn new(args: &[&str], exit: i32, report: Option<&'static str>) -> Step {
        Step {
            args: args.iter().map(|s| s.to_string()).collect(),
            exit,
            report,
            outputs: Vec::new(),
            check: None,
            error: None,
        }
    }

    /// Adds `--flag FILE` for a file that must not be written (the step fails).
    fn output_unwritten(mut self, flag: &str, file: &str) -> Step {
        self.args.push(flag.to_string());
        self.args.push(file.to_string());
        self
    }

    /// Expects exit 2 with one `error:` line naming `what`.
    fn error(mut self, what: &'static str) -> Step {
        self.exit = 2;
        self.error = Some(what);
        self.report = None;
        self
    }

    /// Adds `--flag FILE` (in the journey's folder) and expects FILE to be a `kind`.
    fn output(mut self, flag: &str, file: &str, kind: Kind) -> Step {
        self.args.push(flag.to_string());
        self.args.push(file.to_string());
        self.outputs.push((file.to_string(), kind));
        self
    }

    fn check(
        mut self,
        f: impl Fn(&Value, &Path) -> Result<(), String> + Send + Sync + 'static,
    ) -> Step {
        self.check = Some(Box::new(f));
        self
    }
}

/// A named sequence of steps run in one scratch folder; `inputs` must be untouched.
struct Journey {
    name: String,
    steps: Vec<Step>,
    inputs: Vec<PathBuf>,
}

fn fixture(rel: &str) -> String {
    workspace_root()
        .join("fixtures")
        .join(rel)
        .to_string_lossy()
        .into_owned()
}

/// Every scenario fixture (the files `rappel validate` accepts).
const SCENARIOS: &[&str] = &[
    "thesis-fig-2-7.ron",
    "online-example.ron",
    "online-example-discovered.ron",
    "friction/capstan_holds.ron",
    "friction/slip_then_wrap.ron",
    "generated/crater-strip-100.ron",
    "generated/crater-strip-1000.ron",
    "generated/crater-strip-10000.ron",
    "online/case-1-blocked-flat.prior.ron",
    "online/case-1-blocked-flat.ron",
    "online/case-1-blocked.ron",
    "online/case-2-geometry.ron",
    "online/case-3-shp.ron",
    "online/case-4-split.ron",
    "online/friction-weaker.prior.ron",
    "online/friction-weaker.ron",
    "online/removal-anchors.ron",
    "online/removal-opened.prior.ron",
    "plan/garni-straight.ron",
    "plan/golden-queen-two-anchors.ron",
    "plan/multi-plane.ron",
    "plan/none-feasible.ron",
    "plan/shortest-infeasible.ron",
];

/// Scenarios without terrain planes (flat maps for the online cases): `stability` has nothing to
/// stand on and says so (exit 2 naming `terrain.planes`).
const NO_PLANES: &[&str] = &[
    "online/case-1-blocked-flat.prior.ron",
    "online/case-1-blocked-flat.ron",
];

/// Scenarios on which no class is feasible by design (their headers say why): `plan` exits 1.
const NO_FEASIBLE_CLASS: &[&str] = &["plan/none-feasible.ron", "online/case-1-blocked.ron"];

/// The points of a JSON array of `[x, y]` pairs.
fn points(v: &Value) -> Result<Vec<[f64; 2]>, String> {
    v.as_array()
        .ok_or("not an array of points")?
        .iter()
        .map(|p| match (p[0].as_f64(), p[1].as_f64()) {
            (Some(x), Some(y)) => Ok([x, y]),
            _ => Err(format!("{p} is not a point")),
        })
        .collect()
}

fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

fn length(p: &[[f64; 2]]) -> f64 {
    p.windows(2).map(|w| dist(w[0], w[1])).sum()
}

/// Distance from `p` to the segment `a b`.
fn to_segment(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let l2 = dx * dx + dy * dy;
    let t = if l2 > 0.0 {
        (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    dist(p, [a[0] + t * dx, a[1] + t * dy])
}

/// Relative slack of the journeys' own floating-point comparisons (lengths and distances that
/// the code under test computed in another order).
const SLACK: f64 = 1e-9;

/// The checks of a plan report with a chosen pair: the paths join the right ends, are no shorter
/// than the straight line, keep the clearance from every anchor of the chosen class (computed
/// here), and are written as path files for the `homotopic` and `shp` steps that follow.
fn check_chosen_pair(v: &Value, dir: &Path) -> Result<(), String> {
    let chosen = &v["chosen"];
    if chosen.is_null() {
        return Err(format!("no chosen pair: {}", v["verdict"]));
    }
    let start = points(&Value::Array(vec![v["start"].clone()]))?[0];
    let goal = points(&Value::Array(vec![v["goal"].clone()]))?[0];
    let ascent = points(&chosen["ascent"])?;
    let descent = points(&chosen["descent"])?;
    let ends =
        |p: &[[f64; 2]], a: [f64; 2], b: [f64; 2]| p.first() == Some(&a) && p.last() == Some(&b);
    if !ends(&descent, start, goal) || !ends(&ascent, goal, start) {
        return Err("the pair does not join start and goal the right way round".into());
    }
    let straight = dist(start, goal);
    for (which, p) in [("ascent", &ascent), ("descent", &descent)] {
        if length(p) < straight * (1.0 - SLACK) {
            return Err(format!("the {which} is shorter than the straight line"));
        }
    }
    let rank = chosen["rank"].as_u64().ok_or("no rank")? as usize;
    let class = &v["classes"][rank - 1];
    let clearance = v["clearance_m"].as_f64().ok_or("no clearance_m")?;
    for a in class["anchors"].as_array().ok_or("no anchors")? {
        let a = points(&Value::Array(vec![a["point"].clone()]))?[0];
        for p in [&ascent, &descent] {
            for w in p.windows(2) {
                let d = to_segment(a, w[0], w[1]);
                if d < clearance * (1.0 - SLACK) {
                    return Err(format!(
                        "a path passes {d:.9} m from the anchor at ({}, {}), inside the clearance {clearance}",
                        a[0], a[1]
                    ));
                }
            }
        }
    }
    let write = |name: &str, p: &[[f64; 2]]| {
        std::fs::write(dir.join(name), serde_json::to_string(p).expect("points"))
            .map_err(|e| format!("{name}: {e}"))
    };
    let mut up = ascent.clone();
    up.reverse();
    write("descent.json", &descent)?;
    write("ascent-reversed.json", &up)?;
    let shp = class["length_m"].as_f64().ok_or("no class length")?;
    std::fs::write(dir.join("class-length.txt"), format!("{shp}")).map_err(|e| e.to_string())
}

/// The `shp` of the descent is the chosen class's SHP: same length.
fn check_descent_tether(v: &Value, dir: &Path) -> Result<(), String> {
    let want: f64 = std::fs::read_to_string(dir.join("class-length.txt"))
        .map_err(|e| e.to_string())?
        .parse()
        .map_err(|e| format!("class length: {e}"))?;
    let got = v["length_m"].as_f64().ok_or("no length_m")?;
    if (got - want).abs() > 1e-6 * want.max(1.0) {
        return Err(format!(
            "the descent's taut tether is {got} m, the class's SHP {want} m"
        ));
    }
    Ok(())
}

/// A plan step on `file` with its pictures and export, and the pair checks when `exit` is 0.
fn plan_steps(file: &str, exit: i32, svg: bool) -> Vec<Step> {
    let mut plan = Step::new(&["plan", file, "--json"], exit, Some("plan"));
    if svg {
        plan = plan.output("--svg", "plan.svg", Kind::Svg).output(
            "--export",
            "plan.geojson",
            Kind::GeoJson,
        );
    }
    if exit != 0 {
        return vec![plan.check(|v, _| match v["chosen"].is_null() {
            true => Ok(()),
            false => Err("exit 1 but a pair was chosen".into()),
        })];
    }
    vec![
        plan.check(check_chosen_pair),
        homotopic(file, "descent.json", "ascent-reversed.json", 0),
        Step::new(
            &["shp", file, "--path", "descent.json", "--json"],
            0,
            Some("shp"),
        )
        .check(check_descent_tether),
    ]
}

/// `rappel homotopic MAP --path A --path B --json`, expecting `exit` (0 yes, 1 no).
fn homotopic(map: &str, a: &str, b: &str, exit: i32) -> Step {
    Step::new(
        &["homotopic", map, "--path", a, "--path", b, "--json"],
        exit,
        Some("homotopic"),
    )
}

/// Every journey of a run.
fn journeys(full: bool) -> Vec<Journey> {
    let mut out = Vec::new();
    let mut add = |name: String, inputs: &[&str], steps: Vec<Step>| {
        out.push(Journey {
            name,
            steps,
            inputs: inputs.iter().map(PathBuf::from).collect(),
        })
    };
    // Every scenario: validate, btm, plan (with its pair checked), stability.
    for rel in SCENARIOS {
        let f = fixture(rel);
        let exit = if NO_FEASIBLE_CLASS.contains(rel) {
            1
        } else {
            0
        };
        let mut steps = vec![
            Step::new(&["validate", &f, "--json"], 0, Some("validate")),
            Step::new(&["btm", &f, "--json"], 0, Some("btm")).output("--svg", "btm.svg", Kind::Svg),
        ];
        steps.extend(plan_steps(&f, exit, true));
        let strip = rel.starts_with("generated/");
        let mut stability = vec!["stability", f.as_str(), "--json", "--grid"];
        stability.push(if strip { "10" } else { "4" });
        if strip {
            stability.extend(["--window", "0,0,200,60"]);
        }
        let stability = Step::new(&stability, 0, Some("stability"));
        steps.push(if NO_PLANES.contains(rel) {
            stability
                .error("terrain.planes")
                .output_unwritten("--svg", "stability.svg")
        } else {
            stability.output("--svg", "stability.svg", Kind::Svg)
        });
        add(format!("scenario {rel}"), &[&f], steps);
    }
    // Pictures as interactive pages.
    let thesis = fixture("thesis-fig-2-7.ron");
    let east = fixture("paths/fig-2-7-east.json");
    let west = fixture("paths/fig-2-7-west.json");
    let detour = fixture("paths/fig-2-7-west-detour.json");
    add(
        "pages thesis-fig-2-7 (btm, shp, plan, stability)".into(),
        &[&thesis, &east],
        vec![
            Step::new(&["btm", &thesis], 0, None).output("--html", "btm.html", Kind::Html),
            Step::new(&["shp", &thesis, "--path", &east, "--json"], 0, Some("shp"))
                .output("--svg", "shp.svg", Kind::Svg)
                .output("--html", "shp.html", Kind::Html),
            Step::new(&["plan", &thesis], 0, None)
                .output("--html", "plan.html", Kind::Html)
                .output("--export", "plan.csv", Kind::Csv),
            Step::new(
                &[
                    "stability",
                    &thesis,
                    "--grid",
                    "8",
                    "--tension-limit",
                    "300",
                ],
                0,
                None,
            )
            .output("--html", "stability.html", Kind::Html),
        ],
    );
    add(
        "homotopic thesis west/detour (yes) and west/east (no)".into(),
        &[&thesis, &east, &west, &detour],
        vec![
            homotopic(&thesis, &west, &detour, 0),
            homotopic(&thesis, &west, &east, 1),
        ],
    );
    let pairs = fixture("queries/fig-2-7-pairs.json");
    add(
        "query thesis pairs".into(),
        &[&thesis, &pairs],
        vec![
            Step::new(
                &[
                    "query",
                    &thesis,
                    "--pairs",
                    &pairs,
                    "--classes",
                    "3",
                    "--json",
                ],
                0,
                Some("query"),
            )
            .check(check_query),
        ],
    );
    // Online: the prior and the truth of each bundled case.
    let cases: &[(&str, &str, i32)] = &[
        ("online-example.ron", "online-example.ron", 0),
        ("online-example.ron", "online-example-discovered.ron", 0),
        ("online-example.ron", "online/case-1-blocked.ron", 1),
        ("online-example.ron", "online/case-2-geometry.ron", 0),
        ("online-example.ron", "online/case-3-shp.ron", 0),
        ("online-example.ron", "online/case-4-split.ron", 0),
        ("online-example.ron", "online/removal-anchors.ron", 0),
        (
            "online/case-1-blocked-flat.prior.ron",
            "online/case-1-blocked-flat.ron",
            0,
        ),
        (
            "online/friction-weaker.prior.ron",
            "online/friction-weaker.ron",
            0,
        ),
        ("online/removal-opened.prior.ron", "online-example.ron", 0),
    ];
    for (i, (prior, truth, exit)) in cases.iter().enumerate() {
        let (p, t) = (fixture(prior), fixture(truth));
        let mut step = Step::new(
            &["online", &p, "--truth", &t, "--json"],
            *exit,
            Some("online"),
        )
        .output("--svg", "online.svg", Kind::Svg);
        if i == 1 {
            step = step.output("--html", "online.html", Kind::Html);
        }
        add(format!("online {prior} -> {truth}"), &[&p, &t], vec![step]);
    }
    // Two robots on one tether (Kumar): exit 1 at the first unstable waypoint.
    let kumar = fixture("tracking/kumar.json");
    let robot2 = fixture("tracking/robot2-descent.json");
    for (robot1, exit) in [
        ("robot1-fixed", 1),
        ("robot1-partial", 0),
        ("robot1-nearly-full-turn", 0),
    ] {
        let r1 = fixture(&format!("tracking/{robot1}.json"));
        add(
            format!("track kumar {robot1}"),
            &[&kumar, &r1, &robot2],
            vec![
                Step::new(
                    &[
                        "track", &kumar, "--robot1", &r1, "--robot2", &robot2, "--json",
                    ],
                    exit,
                    Some("track"),
                )
                .output("--svg", "track.svg", Kind::Svg),
            ],
        );
    }
    // Paton's scenes: settle, settle-map, navigate.
    for scene in ["paton/ledge.ron", "paton/ledge-pole.ron"] {
        let s = fixture(scene);
        add(
            format!("rover {scene}"),
            &[&s],
            vec![
                Step::new(
                    &["settle", &s, "--at", "-1,0", "--yaw", "0", "--json"],
                    0,
                    Some("settle"),
                )
                .output("--svg", "settle.svg", Kind::Svg),
                Step::new(
                    &["settle-map", &s, "--test", "1", "--json"],
                    0,
                    Some("settle_map"),
                )
                .output("--svg", "settle-map.svg", Kind::Svg),
                Step::new(
                    &["navigate", &s, "--seed", "2", "--json"],
                    0,
                    Some("navigate"),
                )
                .output("--svg", "navigate.svg", Kind::Svg),
            ],
        );
    }
    // Real elevation models: a scenario from each, then the main job on it.
    for dem in [
        "terrain/earth_mt_st_helens_landslide_10m.asc",
        "terrain/mars_hirise_dteec_010228_1490_crop.asc",
        "terrain/mars_hirise_dteec_010228_1490_crop.tif",
    ] {
        let d = fixture(dem);
        let mut steps = vec![
            Step::new(&["dem", &d, "--json"], 0, Some("dem"))
                .output("--out", "dem.ron", Kind::Scenario)
                .output("--svg", "dem.svg", Kind::Svg),
        ];
        if dem.ends_with(".tif") {
            steps[0].args.extend(["--html".into(), "dem.html".into()]);
            steps[0].outputs.push(("dem.html".into(), Kind::Html));
        }
        steps.extend(plan_steps("dem.ron", 0, true));
        add(format!("dem {dem} -> plan"), &[&d], steps);
    }
    // Generated strips: gen-map, then plan (a pair on every strip), query, stability.
    let mut sizes = vec![(100, 1..=5), (1000, 1..=5), (10000, 1..=5)];
    if full {
        sizes.push((100_000, 1..=1));
    }
    for (n, seeds) in sizes {
        for seed in seeds {
            let (ns, ss) = (n.to_string(), seed.to_string());
            let mut steps = vec![
                Step::new(
                    &["gen-map", "--obstacles", &ns, "--seed", &ss, "--json"],
                    0,
                    Some("gen_map"),
                )
                .output("--out", "strip.ron", Kind::Scenario)
                .check(write_strip_pairs),
            ];
            steps.extend(plan_steps("strip.ron", 0, n <= 1000));
            steps.push(
                Step::new(
                    &["query", "strip.ron", "--pairs", "pairs.json", "--json"],
                    0,
                    Some("query"),
                )
                .check(check_query),
            );
            steps.push(Step::new(
                &[
                    "stability",
                    "strip.ron",
                    "--grid",
                    "10",
                    "--window",
                    "0,0,200,60",
                    "--json",
                ],
                0,
                Some("stability"),
            ));
            add(format!("strip {n} obstacles seed {seed}"), &[], steps);
        }
    }
    out
}

/// After `gen-map`: a pairs file for `query` with the strip's start and goal both ways.
fn write_strip_pairs(_: &Value, dir: &Path) -> Result<(), String> {
    let s = rappel::scenario::Scenario::load(dir.join("strip.ron")).map_err(|e| e.to_string())?;
    let pairs = serde_json::json!([
        {"start": [s.start.x, s.start.y], "goal": [s.goal.x, s.goal.y]},
        {"start": [s.goal.x, s.goal.y], "goal": [s.start.x, s.start.y]},
    ]);
    std::fs::write(dir.join("pairs.json"), pairs.to_string()).map_err(|e| e.to_string())
}

/// Every query pair answered, each length no shorter than the straight line.
fn check_query(v: &Value, _: &Path) -> Result<(), String> {
    for a in v["answers"].as_array().ok_or("no answers")? {
        if !a["error"].is_null() {
            return Err(format!("pair {}: {}", a["index"], a["error"]));
        }
        let ends = points(&Value::Array(vec![a["start"].clone(), a["goal"].clone()]))?;
        let lengths = a["lengths_m"].as_array().ok_or("no lengths")?;
        if lengths.is_empty() {
            return Err(format!("pair {}: no length", a["index"]));
        }
        for l in lengths {
            let l = l.as_f64().ok_or("length not a number")?;
            if l < dist(ends[0], ends[1]) * (1.0 - SLACK) {
                return Err(format!(
                    "pair {}: {l} m is shorter than the straight line",
                    a["index"]
                ));
            }
        }
    }
    Ok(())
}

/// Checks one output file.
fn check_output(bin: &Path, path: &Path, kind: Kind, viewer: bool) -> Result<(), String> {
    let bytes = std::fs::read(path).map_err(|e| format!("{}: not written: {e}", path.display()))?;
    if bytes.is_empty() {
        return Err(format!("{}: empty", path.display()));
    }
    let text = String::from_utf8(bytes).map_err(|_| format!("{}: not UTF-8", path.display()))?;
    let trimmed = text.trim_end();
    let ok = match kind {
        Kind::Svg => trimmed.contains("<svg") && trimmed.ends_with("</svg>"),
        Kind::Html => trimmed.starts_with("<!DOCTYPE html>") && trimmed.ends_with("</html>"),
        Kind::GeoJson => serde_json::from_str::<Value>(&text).is_ok_and(|v| {
            v["type"] == "FeatureCollection"
                && v["features"].as_array().is_some_and(|f| !f.is_empty())
        }),
        Kind::Csv => {
            let mut lines = text.lines();
            let width = lines.next().map_or(0, |h| h.split(',').count());
            width > 1 && lines.clone().count() > 0 && lines.all(|l| l.split(',').count() == width)
        }
        Kind::Scenario => {
            let out = Command::new(bin)
                .arg("validate")
                .arg(path)
                .output()
                .map_err(|e| e.to_string())?;
            out.status.code() == Some(0)
        }
    };
    if !ok {
        return Err(format!("{}: not a readable {kind:?}", path.display()));
    }
    if kind == Kind::Html && viewer {
        check_page(path)?;
    }
    Ok(())
}

/// Loads a page in headless Chromium: its script must finish (`data-viewer-ready="yes"`) with no
/// errors recorded (`data-viewer-errors`), as `.ci/viewer-check` requires.
fn check_page(path: &Path) -> Result<(), String> {
    let profile = path.with_extension("chromium-profile");
    let out = Command::new("timeout")
        .args([
            "120",
            "chromium",
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
            "--no-first-run",
        ])
        .args([
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg("--dump-dom")
        .arg(format!("file://{}", path.display()))
        .output()
        .map_err(|e| format!("chromium: {e}"))?;
    let dom = String::from_utf8_lossy(&out.stdout);
    let body = dom
        .split("<body")
        .nth(1)
        .and_then(|b| b.split('>').next())
        .unwrap_or("");
    if !body.contains("data-viewer-ready=\"yes\"") || body.contains("data-viewer-errors") {
        return Err(format!(
            "{}: the viewer did not load cleanly: <body{body}>",
            path.display()
        ));
    }
    Ok(())
}

/// Runs one journey in `dir`; the time it took, or what went wrong.
fn run_journey(j: &Journey, bin: &Path, dir: &Path, viewer: bool) -> Result<f64, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let before: Vec<Vec<u8>> = j
        .inputs
        .iter()
        .map(|p| std::fs::read(p).unwrap_or_default())
        .collect();
    let t0 = Instant::now();
    for step in &j.steps {
        let line = step.args.join(" ");
        let out = Command::new(bin)
            .args(&step.args)
            .current_dir(dir)
            .output()
            .map_err(|e| format!("`rappel {line}`: {e}"))?;
        let code = out.status.code().unwrap_or(-1);
        let stderr = String::from_utf8_lossy(&out.stderr);
        if code != step.exit {
            return Err(format!(
                "`rappel {line}`: exit {code}, expected {}: {}",
                step.exit,
                stderr.trim()
            ));
        }
        if let Some(what) = step.error {
            let lines: Vec<&str> = stderr.lines().collect();
            if lines.len() != 1 || !lines[0].starts_with("error:") || !lines[0].contains(what) {
                return Err(format!(
                    "`rappel {line}`: expected one error line naming {what}, got {stderr:?}"
                ));
            }
            if !out.stdout.is_empty() {
                return Err(format!("`rappel {line}`: an error printed a report"));
            }
        }
        if let Some(name) = step.report {
            let v: Value = serde_json::from_slice(&out.stdout)
                .map_err(|e| format!("`rappel {line}`: the report is not JSON: {e}"))?;
            let schema_path = workspace_root()
                .join("docs/schemas")
                .join(format!("{name}.json"));
            let schema: Value = serde_json::from_str(
                &std::fs::read_to_string(&schema_path)
                    .map_err(|e| format!("{}: {e}", schema_path.display()))?,
            )
            .map_err(|e| format!("{}: {e}", schema_path.display()))?;
            schema_check::check(&v, &schema)
                .map_err(|e| format!("`rappel {line}`: docs/schemas/{name}.json: {e}"))?;
            if v["report"] != name {
                return Err(format!(
                    "`rappel {line}`: report {} is not {name}",
                    v["report"]
                ));
            }
            if let Some(check) = &step.check {
                check(&v, dir).map_err(|e| format!("`rappel {line}`: {e}"))?;
            }
        } else if let Some(check) = &step.check {
            check(&Value::Null, dir).map_err(|e| format!("`rappel {line}`: {e}"))?;
        }
        if step.exit == 2 {
            for a in step
                .args
                .iter()
                .filter(|a| a.ends_with(".svg") || a.ends_with(".html"))
            {
                if dir.join(a).exists() {
                    return Err(format!(
                        "`rappel {line}`: {a} written although the run failed"
                    ));
                }
            }
        }
        for (file, kind) in &step.outputs {
            check_output(bin, &dir.join(file), *kind, viewer)
                .map_err(|e| format!("`rappel {line}`: {e}"))?;
        }
    }
    for (p, b) in j.inputs.iter().zip(&before) {
        if std::fs::read(p).unwrap_or_default() != *b {
            return Err(format!("{} changed", p.display()));
        }
    }
    Ok(t0.elapsed().as_secs_f64())
}

/// `cargo xtask journeys`: runs every journey, prints one line each and the summary.
pub fn run(full: bool, bin: Option<PathBuf>, viewer: Viewer) -> Result<ExitCode, String> {
    let root = workspace_root();
    let bin = bin.unwrap_or_else(|| {
        let release = root.join("target/release/rappel");
        if release.exists() {
            release
        } else {
            root.join("target/debug/rappel")
        }
    });
    // The steps run in scratch folders: a relative path would name nothing there.
    let bin = std::fs::canonicalize(&bin).map_err(|e| {
        format!(
            "{}: no rappel binary ({e}; build one with `cargo build --release -p rappel-cli`, or name it with --bin)",
            bin.display()
        )
    })?;
    let chromium = Command::new("chromium")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if viewer == Viewer::Require && !chromium {
        return Err("--viewer: chromium is not installed (Debian's package `chromium`)".into());
    }
    println!(
        "journeys with {} (pages in Chromium: {})",
        bin.display(),
        if chromium {
            "yes"
        } else {
            "no, documents only"
        }
    );
    let scratch = std::env::temp_dir().join(format!("rappel-journeys-{}", std::process::id()));
    let all = journeys(full);
    let next = AtomicUsize::new(0);
    let failed = Mutex::new(Vec::new());
    let workers = 2;
    std::thread::scope(|s| {
        for _ in 0..workers {
            s.spawn(|| {
                loop {
                    let i = next.fetch_add(1, Ordering::SeqCst);
                    let Some(j) = all.get(i) else { break };
                    match run_journey(j, &bin, &scratch.join(i.to_string()), chromium) {
                        Ok(t) => println!("ok    {:<62} {t:>7.2} s", j.name),
                        Err(e) => {
                            println!("FAIL  {}: {e}", j.name);
                            failed
                                .lock()
                                .expect("no panics hold it")
                                .push(j.name.clone());
                        }
                    }
                }
            });
        }
    });
    let _ = std::fs::remove_dir_all(&scratch);
    let failed = failed.into_inner().expect("no panics hold it");
    println!(
        "journeys: {} passed, {} failed",
        all.len() - failed.len(),
        failed.len()
    );
    Ok(if failed.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}
