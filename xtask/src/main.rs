//! Project automation, run as `cargo xtask <command>` (the alias lives in `.cargo/config.toml`):
//! `regress` runs the regression suites that reproduce the papers' figures and our invariants,
//! `gen-fixtures` regenerates the generated fixtures from their seeds.

mod fixtures;
mod regress;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// rappel's project automation.
#[derive(Parser)]
#[command(name = "xtask", about = "rappel project automation")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run the regression suites; one table row per case, non-zero exit on any failure.
    Regress {
        /// Only run suites whose name contains this text.
        #[arg(long)]
        suite: Option<String>,
        /// Run the heavy cases at full size (the online completeness study: 200 map pairs).
        #[arg(long)]
        full: bool,
    },
    /// Regenerate the generated fixtures (random maps) from their seeds.
    GenFixtures,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Regress { suite, full } => {
            regress::set_full(full);
            regress::run(suite.as_deref())
        }
        Command::GenFixtures => fixtures::generate(),
    };
    match result {
        Ok(code) => code,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::from(2)
        }
    }
}
