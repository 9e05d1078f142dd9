//! The Rust side of the sampling-planner peer comparisons (docs/sampler.md).
//!
//! `cargo run --release -p rappel-benches --example sampler_peer -- worlds` writes the obstacle
//! worlds that both planners read to `benches/ompl_peer/worlds/*.json`: the two hand-made ones
//! and the generated ones nobody tuned on (`peer_worlds::{random_2d, random_3d, narrow_2d,
//! narrow_3d}` at `GENERATED_SEED`).
//!
//! The native comparison with OMPL's C++ library (`benches/ompl_peer/native.sh`):
//! - `header BUDGET_S` prints the TSV header shared with `benches/ompl_peer/native/ompl_peer.cpp`;
//! - `native WORLD.json abit|bit[:k=F] SEED BUDGET_S [PATH_OUT]` runs our planner once, until the
//!   process has used `BUDGET_S` of CPU time, and prints one TSV row: CPU and wall time, state
//!   checks and the number of batches sampled to the first solution, the best cost at fixed
//!   CPU-time checkpoints, the final cost, and the independent re-check of the final path
//!   (written to `PATH_OUT`);
//! - `verify WORLD.json PATH_FILE` re-checks a path file (OMPL's, in the script) with our checker.
//!
//! `anytime WORLD.json [TIME_S] [RUNS]` is the older wall-clock table of the Python smoke test
//! (`benches/ompl_peer/run.sh`).

use std::cell::Cell;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::{Duration, Instant};

use rappel_planners::sampler::peer_worlds::{
    GENERATED_SEED, boxes_2d, boxes_3d, narrow_2d, narrow_3d, random_2d, random_3d,
};
use rappel_planners::sampler::{
    Abit, AbitSettings, MotionValidator, ObstacleWorld, RealVectorSpace, Termination, WorldFile,
};

/// The times (seconds) at which the best cost is reported, shared with the Python peer.
const CHECKPOINTS: [f64; 6] = [0.01, 0.03, 0.1, 0.3, 1.0, 3.0];

/// The world's validator, counting state checks (the language-neutral effort measure: the Python
/// peer counts its checker's calls the same way).
struct Counting<'a, const D: usize> {
    world: &'a ObstacleWorld<D>,
    checks: Cell<u64>,
}

impl<const D: usize> MotionValidator<RealVectorSpace<D>, D> for Counting<'_, D> {
    type History = ();

    fn initial_history(&self, _start: &[f64; D]) {}

    fn state_valid(&self, s: &[f64; D]) -> bool {
        self.checks.set(self.checks.get() + 1);
        self.world.state_valid(s)
    }

    fn motion(&self, from: &[f64; D], _h: &(), to: &[f64; D]) -> Option<(f64, ())> {
        self.world
            .interior_with(from, to, |p| self.state_valid(p))
            .map(|c| (c, ()))
    }
}

/// Iteration cap of the first-solution runs (a bound; never reached on the shipped worlds).
const FIRST_CAP: u64 = 10_000_000;

fn worlds_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("ompl_peer")
        .join("worlds")
}

fn write_worlds() -> Result<(), String> {
    let dir = worlds_dir();
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let seed = GENERATED_SEED;
    for (name, file) in [
        ("boxes_2d", WorldFile::from_world("boxes_2d", &boxes_2d())),
        ("boxes_3d", WorldFile::from_world("boxes_3d", &boxes_3d())),
        (
            "random_2d",
            WorldFile::from_world("random_2d", &random_2d(seed)),
        ),
        (
            "random_3d",
            WorldFile::from_world("random_3d", &random_3d(seed)),
        ),
        (
            "narrow_2d",
            WorldFile::from_world("narrow_2d", &narrow_2d(seed).0),
        ),
        (
            "narrow_3d",
            WorldFile::from_world("narrow_3d", &narrow_3d(seed).0),
        ),
    ] {
        let path = dir.join(format!("{name}.json"));
        let text = serde_json::to_string_pretty(&file).map_err(|e| e.to_string())?;
        std::fs::write(&path, text + "\n").map_err(|e| format!("{}: {e}", path.display()))?;
        println!("wrote {}", path.display());
    }
    Ok(())
}

fn anytime<const D: usize>(world: &ObstacleWorld<D>, time: f64, runs: u64) -> Result<(), String> {
    println!(
        "seed  first_s  checks_first  {}",
        CHECKPOINTS.map(|t| format!("c@{t}s")).join("  ")
    );
    for seed in 0..runs {
        let counting = Counting {
            world,
            checks: Cell::new(0),
        };
        let settings = AbitSettings::default().with_seed(seed);
        let mut first_run = Abit::new(
            &world.space,
            &counting,
            world.start,
            world.goal,
            settings.clone(),
        )
        .map_err(|e| e.to_string())?;
        first_run
            .solve(Termination::iterations(FIRST_CAP).or_cost_at_most(f64::MAX))
            .map_err(|e| e.to_string())?;
        let checks_first = counting.checks.get();
        let mut p = Abit::new(&world.space, world, world.start, world.goal, settings)
            .map_err(|e| e.to_string())?;
        let st = p
            .solve(Termination::time(Duration::from_secs_f64(time)))
            .map_err(|e| e.to_string())?;
        let first = st.events.first().map_or("-".to_string(), |e| {
            format!("{:.4}", e.elapsed.as_secs_f64())
        });
        let costs = CHECKPOINTS.map(|t| {
            st.events
                .iter()
                .take_while(|e| e.elapsed.as_secs_f64() <= t)
                .last()
                .map_or("-".to_string(), |e| format!("{:.4}", e.cost))
        });
        println!(
            "{seed:4}  {first:>7}  {checks_first:>12}  {}",
            costs.join("  ")
        );
    }
    Ok(())
}

/// CPU-time checkpoints (ms) of the native cost table, shared with `ompl_peer.cpp`; those up to
/// the budget are printed.
const CHECKPOINTS_MS: [f64; 7] = [10.0, 30.0, 100.0, 300.0, 1000.0, 3000.0, 10000.0];

/// Iterations between two reads of the CPU clock (a system call); OMPL's side reads it once per
/// as many evaluations of its termination condition (about one per iteration).
const CLOCK_EVERY: u64 = 64;

/// Relative tolerance of "the reported cost is the path's length" (summation order differs).
const COST_TOLERANCE: f64 = 1e-9;

/// CPU time used by this process (all threads), `clock_gettime(CLOCK_PROCESS_CPUTIME_ID)` as on
/// OMPL's side.
#[cfg(unix)]
fn cpu_now() -> Result<Duration, String> {
    use nix::time::{ClockId, clock_gettime};
    let t = clock_gettime(ClockId::CLOCK_PROCESS_CPUTIME_ID)
        .map_err(|e| format!("clock_gettime(CLOCK_PROCESS_CPUTIME_ID): {e}"))?;
    let secs = u64::try_from(t.tv_sec()).map_err(|e| format!("CPU clock: {e}"))?;
    let nanos = u32::try_from(t.tv_nsec()).map_err(|e| format!("CPU clock: {e}"))?;
    Ok(Duration::new(secs, nanos))
}

#[cfg(not(unix))]
fn cpu_now() -> Result<Duration, String> {
    Err("the native comparison reads the process CPU clock, available on unix only".into())
}

fn checkpoints(budget_s: f64) -> Vec<f64> {
    CHECKPOINTS_MS
        .into_iter()
        .filter(|&c| c <= budget_s * 1000.0 + 1e-9)
        .collect()
}

fn header(budget_s: f64) -> String {
    let mut h = String::from(
        "side\tplanner\tworld\tseed\tsolved\tfirst_cpu_ms\tfirst_wall_ms\tchecks_first\tcost_first\tbatches_first",
    );
    for c in checkpoints(budget_s) {
        h += &format!("\tc@{c}ms");
    }
    h + "\tfinal_cost\tchecks_total\tcpu_total_ms\tpath_states\tpath_check"
}

/// The settings of the planner named on the command line: `abit` is our ABIT* with its
/// defaults (OMPL's ABIT* parameters: initial inflation 1e6, inflation scaling 10, truncation
/// scaling 5); `bit` is the same planner with OMPL's BIT* parameters (initial inflation 1,
/// inflation and truncation scaling 0, no cascading rewirings), which is how OMPL derives its
/// ABIT* from its BIT*.
/// A suffix `:k=F` sets `rgg_k_factor` (OMPL's rewire factor; the default is OMPL's 1.1).
fn planner_settings(planner: &str) -> Result<AbitSettings, String> {
    let (name, k) = match planner.split_once(":k=") {
        Some((name, k)) => (
            name,
            Some(
                k.parse::<f64>()
                    .map_err(|e| format!("PLANNER `{planner}`: k factor: {e}"))?,
            ),
        ),
        None => (planner, None),
    };
    let s = AbitSettings::default();
    let s = match name {
        "abit" => Ok(s),
        "bit" => s
            .with_initial_inflation(1.0)
            .and_then(|s| s.with_inflation_scaling(0.0))
            .and_then(|s| s.with_truncation_scaling(0.0))
            .map(|s| s.with_cascading_rewirings(false))
            .map_err(|e| e.to_string()),
        other => Err(format!("PLANNER: `{other}` is neither abit nor bit")),
    }?;
    match k {
        Some(k) => s.with_rgg_k_factor(k).map_err(|e| e.to_string()),
        None => Ok(s),
    }
}

/// The independent re-check of a path (not the planner's validator, not counted): it starts at
/// the start and ends at the goal, every state is valid, every segment's states at `j / n`,
/// `n = ceil(length / (resolution * diagonal))`, are valid (plain order), and `cost` is the
/// path's length.
fn check_path<const D: usize>(
    world: &ObstacleWorld<D>,
    path: &[[f64; D]],
    cost: f64,
) -> Result<(), String> {
    let (Some(first), Some(last)) = (path.first(), path.last()) else {
        return Err("empty path".into());
    };
    if path.len() < 2 || *first != world.start || *last != world.goal {
        return Err("does not run from the start to the goal".into());
    }
    let mut length = 0.0;
    for (k, p) in path.iter().enumerate() {
        if !world.state_valid(p) {
            return Err(format!("state {k} {p:?} is invalid"));
        }
    }
    for (k, w) in path.windows(2).enumerate() {
        let (a, b) = (w[0], w[1]);
        let len = (0..D).map(|i| (a[i] - b[i]).powi(2)).sum::<f64>().sqrt();
        length += len;
        let n = (len / world.step()).ceil() as usize;
        for j in 1..n {
            let t = j as f64 / n as f64;
            let p: [f64; D] = std::array::from_fn(|i| a[i] + (b[i] - a[i]) * t);
            if !world.state_valid(&p) {
                return Err(format!("segment {} is invalid at {j}/{n}", k + 1));
            }
        }
    }
    if (length - cost).abs() > COST_TOLERANCE * length.max(1.0) {
        return Err(format!(
            "reported cost {cost} differs from the path length {length}"
        ));
    }
    Ok(())
}

/// One native run: returns the TSV row, and whether the path check failed.
fn native<const D: usize>(
    world: &ObstacleWorld<D>,
    name: &str,
    planner: &str,
    seed: u64,
    budget_s: f64,
    path_out: Option<&str>,
) -> Result<(String, bool), String> {
    let settings = planner_settings(planner)?.with_seed(seed);
    let budget = Duration::from_secs_f64(budget_s);
    let counting = Counting {
        world,
        checks: Cell::new(0),
    };
    // The clock starts before the planner exists (OMPL's side: before its constructor); the
    // counter counts from there (start and goal checks, samples, motions).
    let cpu0 = cpu_now()?;
    let wall0 = Instant::now();
    let mut p = Abit::new(&world.space, &counting, world.start, world.goal, settings)
        .map_err(|e| e.to_string())?;
    // (iterations done, CPU time) after each chunk: an improvement is dated at the end of the
    // chunk it came in (at most CLOCK_EVERY iterations late, never early).
    let mut marks: Vec<(u64, Duration)> = Vec::new();
    // (CPU time, wall time, state checks, cost, batches) at the first solution.
    let mut first: Option<(Duration, Duration, u64, f64, u64)> = None;
    let mut cpu = cpu_now()? - cpu0;
    while cpu < budget {
        let chunk = Termination::iterations(CLOCK_EVERY);
        // Until the first solution, stop right at it: its time and checks are exact.
        let chunk = if first.is_none() {
            chunk.or_cost_at_most(f64::MAX)
        } else {
            chunk
        };
        let st = p.solve(chunk).map_err(|e| e.to_string())?;
        cpu = cpu_now()? - cpu0;
        marks.push((st.iterations, cpu));
        if first.is_none()
            && let Some(sol) = &st.solution
        {
            first = Some((
                cpu,
                wall0.elapsed(),
                counting.checks.get(),
                sol.cost,
                st.batches,
            ));
        }
    }
    let checks_total = counting.checks.get();
    let st = p.status();
    let dated: Vec<(Duration, f64)> = st
        .events
        .iter()
        .map(|e| {
            let at = marks
                .iter()
                .find(|m| m.0 >= e.iteration)
                .map_or(cpu, |m| m.1);
            (at, e.cost)
        })
        .collect();
    let ms = |d: Duration| d.as_secs_f64() * 1e3;
    let mut row = format!("rappel\t{planner}\t{name}\t{seed}");
    match first {
        Some((c, w, checks, cost, batches)) => {
            row += &format!(
                "\tyes\t{:.4}\t{:.4}\t{checks}\t{cost:.6}\t{batches}",
                ms(c),
                ms(w)
            )
        }
        None => row += "\tno\t-\t-\t-\t-\t-",
    }
    for c in checkpoints(budget_s) {
        let best = dated.iter().take_while(|(t, _)| ms(*t) <= c).last();
        row += &best.map_or("\t-".into(), |(_, cost)| format!("\t{cost:.6}"));
    }
    let (final_cost, states, check) = match &st.solution {
        Some(sol) => {
            let check = match check_path(world, &sol.path, sol.cost) {
                Ok(()) => "ok".to_string(),
                Err(e) => e,
            };
            if let Some(out) = path_out {
                let mut text = format!("cost {}\n", sol.cost);
                for s in &sol.path {
                    let coords: Vec<String> = s.iter().map(f64::to_string).collect();
                    text += &coords.join(" ");
                    text.push('\n');
                }
                std::fs::write(out, text).map_err(|e| format!("{out}: {e}"))?;
            }
            (format!("{:.6}", sol.cost), sol.path.len(), check)
        }
        None => ("-".into(), 0, "-".into()),
    };
    let failed = check != "ok" && check != "-";
    row += &format!(
        "\t{final_cost}\t{checks_total}\t{:.1}\t{states}\t{check}",
        ms(cpu)
    );
    Ok((row, failed))
}

/// Reads a path file (`cost C`, then one state per line) and re-checks it with our checker.
fn verify<const D: usize>(world: &ObstacleWorld<D>, file: &str) -> Result<(), String> {
    let text = std::fs::read_to_string(file).map_err(|e| format!("{file}: {e}"))?;
    let mut lines = text.lines();
    let cost: f64 = lines
        .next()
        .and_then(|l| l.strip_prefix("cost "))
        .ok_or(format!("{file}: line 1: expected `cost C`"))?
        .trim()
        .parse()
        .map_err(|e| format!("{file}: line 1: {e}"))?;
    let mut path = Vec::new();
    for (n, line) in lines.enumerate() {
        let coords = line
            .split_whitespace()
            .map(str::parse::<f64>)
            .collect::<Result<Vec<f64>, _>>()
            .map_err(|e| format!("{file}: line {}: {e}", n + 2))?;
        let s: [f64; D] = coords
            .try_into()
            .map_err(|_| format!("{file}: line {}: expected {D} numbers", n + 2))?;
        path.push(s);
    }
    check_path(world, &path, cost).map_err(|e| format!("{file}: {e}"))
}

fn read_world(path: &str) -> Result<WorldFile, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{path}: {e}"))?;
    serde_json::from_str(&text).map_err(|e| format!("{path}: {e}"))
}

fn parse<T: std::str::FromStr>(args: &[String], i: usize, what: &str) -> Result<T, String>
where
    T::Err: std::fmt::Display,
{
    let s = args.get(i).ok_or(format!("missing {what}"))?;
    s.parse().map_err(|e| format!("{what} `{s}`: {e}"))
}

/// Runs `f` on the world in its dimension (2 or 3).
fn in_dimension(
    path: &str,
    file: &WorldFile,
    f2: impl FnOnce(&ObstacleWorld<2>) -> Result<(), String>,
    f3: impl FnOnce(&ObstacleWorld<3>) -> Result<(), String>,
) -> Result<(), String> {
    match file.lo.len() {
        2 => f2(&file.to_world::<2>().map_err(|e| format!("{path}: {e}"))?),
        3 => f3(&file.to_world::<3>().map_err(|e| format!("{path}: {e}"))?),
        n => Err(format!(
            "{path}: lo: {n} dimensions, only 2 and 3 are supported"
        )),
    }
}

fn native_mode(args: &[String]) -> Result<(), String> {
    let path = args.get(1).ok_or("native needs WORLD.json")?;
    let planner = args.get(2).ok_or("native needs PLANNER (abit or bit)")?;
    let seed: u64 = parse(args, 3, "SEED")?;
    let budget: f64 = parse(args, 4, "BUDGET_S")?;
    if !(budget.is_finite() && budget > 0.0) {
        return Err(format!("BUDGET_S: {budget} is not a positive time"));
    }
    let path_out = args.get(5).map(String::as_str);
    if args.len() > 6 {
        return Err("native: too many arguments".into());
    }
    let file = read_world(path)?;
    let print = |(row, failed): (String, bool)| {
        println!("{row}");
        if failed {
            Err(format!(
                "{path}: seed {seed}: the final path failed its re-check"
            ))
        } else {
            Ok(())
        }
    };
    in_dimension(
        path,
        &file,
        |w| print(native(w, &file.name, planner, seed, budget, path_out)?),
        |w| print(native(w, &file.name, planner, seed, budget, path_out)?),
    )
}

fn run(args: &[String]) -> Result<(), String> {
    match args.first().map(String::as_str) {
        Some("worlds") => write_worlds(),
        Some("header") => {
            let budget: f64 = parse(args, 1, "BUDGET_S")?;
            println!("{}", header(budget));
            Ok(())
        }
        Some("native") => native_mode(args),
        Some("verify") => {
            let path = args.get(1).ok_or("verify needs WORLD.json")?;
            let file_path = args.get(2).ok_or("verify needs PATH_FILE")?;
            let file = read_world(path)?;
            in_dimension(
                path,
                &file,
                |w| verify(w, file_path),
                |w| verify(w, file_path),
            )
        }
        Some("anytime") => {
            let path = args.get(1).ok_or("anytime needs WORLD.json")?;
            let time: f64 = args
                .get(2)
                .map_or(Ok(1.0), |s| s.parse())
                .map_err(|e| format!("TIME_S: {e}"))?;
            let runs: u64 = args
                .get(3)
                .map_or(Ok(10), |s| s.parse())
                .map_err(|e| format!("RUNS: {e}"))?;
            let text = std::fs::read_to_string(path).map_err(|e| format!("{path}: {e}"))?;
            let file: WorldFile =
                serde_json::from_str(&text).map_err(|e| format!("{path}: {e}"))?;
            match file.lo.len() {
                2 => anytime(
                    &file.to_world::<2>().map_err(|e| format!("{path}: {e}"))?,
                    time,
                    runs,
                ),
                3 => anytime(
                    &file.to_world::<3>().map_err(|e| format!("{path}: {e}"))?,
                    time,
                    runs,
                ),
                n => Err(format!(
                    "{path}: lo: {n} dimensions, only 2 and 3 are supported"
                )),
            }
        }
        _ => Err(
            "usage: sampler_peer worlds | header BUDGET_S | native WORLD.json abit|bit[:k=F] SEED \
             BUDGET_S [PATH_OUT] | verify WORLD.json PATH_FILE | anytime WORLD.json [TIME_S] [RUNS]"
                .into(),
        ),
    }
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}
