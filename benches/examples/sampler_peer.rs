//! The Rust side of the sampling-planner peer comparison (docs/sampler.md).
//!
//! `cargo run --release -p rappel-benches --example sampler_peer -- worlds` writes the obstacle
//! worlds that both planners read to `benches/ompl_peer/worlds/*.json`;
//! `cargo run --release -p rappel-benches --example sampler_peer -- anytime WORLD.json [TIME_S] [RUNS]`
//! runs our ABIT* on one world and prints, per seed, the time to the first solution and the best
//! cost at fixed times, in the same table as `benches/ompl_peer/bitstar_peer.py`.

use std::cell::Cell;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Duration;

use rappel_planners::sampler::peer_worlds::{boxes_2d, boxes_3d};
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
            .motion_with(from, to, |p| self.state_valid(p))
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
    for (name, file) in [
        ("boxes_2d", WorldFile::from_world("boxes_2d", &boxes_2d())),
        ("boxes_3d", WorldFile::from_world("boxes_3d", &boxes_3d())),
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

fn run(args: &[String]) -> Result<(), String> {
    match args.first().map(String::as_str) {
        Some("worlds") => write_worlds(),
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
        _ => Err("usage: sampler_peer worlds | anytime WORLD.json [TIME_S] [RUNS]".into()),
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
