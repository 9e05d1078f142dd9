//! The `rappel` command: argument parsing and printing only; the work happens in the facade crate.
//! Every subcommand lives in its own module. Exit codes: 0 = the answer is yes (a valid file, a
//! feasible plan, homotopic paths, the output written), 1 = a clean no (no feasible class, not
//! homotopic), 2 = an error (one `error:` line on stderr), including a report that could not be
//! written to stdout.

mod btm;
mod closed_stdout;
mod dem;
mod field_arg;
mod friction_out;
mod gen_map;
mod gis_out;
mod navigate;
mod numbers;
mod online;
mod output;
mod plan;
mod progress;
mod query;
mod settle;
mod settle_map;
mod shp;
mod stability;
mod stop;
mod track;
mod validate;
mod window;

use clap::{Parser, Subcommand};
use output::{Answer, CliError};
use std::process::ExitCode;

/// Every large array on 2 MiB pages (`rappel::huge_pages`): a long search is bound by TLB misses.
#[global_allocator]
static ALLOC: rappel::huge_pages::HugePageAlloc = rappel::huge_pages::HugePageAlloc;

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
    /// Many start/goal pairs on one map: shortest lengths (or K classes) and query times.
    Query(query::Args),
    /// Online planning: descend by the prior map's plan while the true map is discovered.
    Online(online::Args),
    /// Two robots on one tether on multi-slope terrain: tether tracking and Robot 2's stability.
    Track(track::Args),
    /// Settle Axel on 3D ground (a Paton scene or a DEM): pose, contacts, optional stability.
    Settle(settle::Args),
    /// Stability map of settled Axel poses with predicted anchor histories (Paton Fig. 8).
    SettleMap(settle_map::Args),
    /// Plan the tethered rover's path on a Paton scene with ABIT* (Paton §V-VI).
    Navigate(navigate::Args),
}

fn main() -> ExitCode {
    // A closed standard output (`>&-`) must not pass for a delivered report.
    if closed_stdout::stdout_closed_at_start() {
        eprintln!("error: standard output is closed; redirect it to a file or to /dev/null");
        return ExitCode::from(2);
    }
    // A usage error is one `error:` line and exit 2 like every other error (clap adds a blank
    // line, a usage and a hint); help and version print as clap prints them.
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e)
            if !e.use_stderr()
                || e.kind() == clap::error::ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand =>
        {
            e.exit()
        }
        Err(e) => {
            let text = e.render().to_string();
            let first = text
                .lines()
                .find(|l| !l.trim().is_empty())
                .unwrap_or("error: bad usage");
            eprintln!("{first}");
            return ExitCode::from(2);
        }
    };
    let yes = |r: Result<(), CliError>| r.map(|()| Answer::Yes);
    let result = match cli.command {
        Command::Validate(args) => yes(validate::run(&args)),
        Command::Btm(args) => yes(btm::run(&args)),
        Command::GenMap(args) => yes(gen_map::run(&args)),
        Command::Dem(args) => yes(dem::run(&args)),
        Command::Stability(args) => stability::run(&args),
        Command::Shp(args) => yes(shp::run(&args)),
        Command::Homotopic(args) => shp::run_homotopic(&args),
        Command::Plan(args) => plan::run(&args),
        Command::Query(args) => query::run(&args),
        Command::Online(args) => online::run(&args),
        Command::Settle(args) => settle::run(&args),
        Command::SettleMap(args) => settle_map::run(&args),
        Command::Navigate(args) => navigate::run(&args),
        // The clean "no": Robot 2 is unstable at a waypoint.
        Command::Track(args) => {
            track::run(&args).map(|stable| if stable { Answer::Yes } else { Answer::No })
        }
    };
    // A report that did not reach stdout is a failure, whatever the answer was.
    let result = result.and_then(|answer| output::finish_stdout().map(|()| answer));
    match result {
        Ok(Answer::Yes) => ExitCode::SUCCESS,
        Ok(Answer::No) => ExitCode::from(1),
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}
