//! The `rappel` command: argument parsing and printing only; the work happens in the facade crate.
//! Every subcommand lives in its own module; errors print one `error:` line on stderr and exit 2.

mod btm;
mod dem;
mod gen_map;
mod output;
mod plan;
mod shp;
mod stability;
mod track;
mod validate;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// Motion planning for tethered robots on extreme terrain.
#[derive(Parser)]
#[command(name = "rappel", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Check a scenario file: schema, map, start, goal, terrain planes and robot.
    Validate(validate::Args),
    /// Build the boundary-triangulated 2-manifold (constrained Delaunay) of a scenario's map.
    Btm(btm::Args),
    /// Generate a random crater-strip scenario with non-overlapping convex obstacles.
    GenMap(gen_map::Args),
    /// Turn a digital elevation model (.asc or .tif) into a planning scenario.
    Dem(dem::Args),
    /// Map where the robot can stand on the scenario's planes: wheel/tether QP or tension-limited LP.
    Stability(stability::Args),
    /// The shortest homotopic path (taut tether) of a path: length, anchors, crossings, H-signature.
    Shp(shp::Args),
    /// Whether two paths with the same endpoints are homotopic.
    Homotopic(shp::HomotopicArgs),
    /// Homotopy classes shortest first, ascent feasibility and an ascent/descent path pair.
    Plan(plan::Args),
    /// Two robots on one tether on multi-slope terrain: tether tracking and Robot 2's stability.
    Track(track::Args),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Validate(args) => validate::run(&args),
        Command::Btm(args) => btm::run(&args),
        Command::GenMap(args) => gen_map::run(&args),
        Command::Dem(args) => dem::run(&args),
        Command::Stability(args) => stability::run(&args),
        Command::Shp(args) => shp::run(&args),
        Command::Homotopic(args) => shp::run_homotopic(&args),
        Command::Plan(args) => plan::run(&args),
        // Exit 1 is the clean "no": Robot 2 is unstable at a waypoint.
        Command::Track(args) => match track::run(&args) {
            Ok(true) => Ok(()),
            Ok(false) => return ExitCode::from(1),
            Err(e) => Err(e),
        },
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}
