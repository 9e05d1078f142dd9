//! Project automation, run as `cargo xtask <command>` (the alias lives in `.cargo/config.toml`):
//! `regress` runs the regression suites that reproduce the papers' figures and our invariants,
//! `journeys` runs every subcommand the way a user does and checks the outcomes,
//! `gen-fixtures` regenerates the generated fixtures from their seeds, `schemas` writes (or with
//! `--check` checks) the JSON Schema documents in `docs/schemas/` (`docs/output-format.md`),
//! `growth` measures the growth table of `docs/planner.md` (first SHP, BTM and `plan` at 1k-1M
//! obstacles beside the peers).

mod fixtures;
mod growth;
mod journeys;
mod readme;
mod regress;
mod tidy;

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
    /// Run every subcommand the way a user does, on the bundled fixtures and generated strips,
    /// and check each outcome against the README (xtask/src/journeys.rs).
    Journeys {
        /// Also the 100,000-obstacle strip.
        #[arg(long)]
        full: bool,
        /// The rappel binary (default: target/release/rappel if built, else target/debug/rappel).
        #[arg(long)]
        bin: Option<std::path::PathBuf>,
        /// Require headless Chromium for the HTML pages (else they are checked when it is there).
        #[arg(long)]
        viewer: bool,
    },
    /// Regenerate the generated fixtures (random maps) from their seeds.
    GenFixtures,
    /// Measure the growth table (first SHP beside polyanya, BTM beside spade, whole `rappel plan`
    /// runs at K = 1, 10, 100) on the 1k, 10k and 100k strips; release builds; needs GNU time.
    Growth {
        /// Also the 1,000,000-obstacle strip (10-15 minutes, several GB).
        #[arg(long)]
        full: bool,
        /// Put the table into docs/planner.md between its growth markers.
        #[arg(long)]
        write: bool,
    },
    /// Write the JSON Schema documents of the scenario and every report to docs/schemas/.
    Schemas {
        /// Write nothing; fail when the committed documents differ from the code.
        #[arg(long)]
        check: bool,
    },
    /// Check that no module imports another that imports it back, inside any crate; prints each
    /// circle with the names each module takes from the others, exit 1 if there is any.
    Tidy,
    /// Run every `rappel` command of the README's examples (checking the exit code each states)
    /// and check the command table against the binary's subcommands and flags.
    Readme {
        /// The rappel binary (default: target/debug/rappel).
        #[arg(long)]
        bin: Option<std::path::PathBuf>,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Regress { suite, full } => {
            regress::case::set_full(full);
            regress::run(suite.as_deref())
        }
        Command::Journeys { full, bin, viewer } => journeys::run(
            full,
            bin,
            if viewer {
                journeys::Viewer::Require
            } else {
                journeys::Viewer::Auto
            },
        ),
        Command::GenFixtures => fixtures::generate(),
        Command::Growth { full, write } => growth::run(full, write),
        Command::Schemas { check } => schemas(check),
        Command::Tidy => tidy::run(),
        Command::Readme { bin } => readme::run(bin),
    };
    match result {
        Ok(code) => code,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::from(2)
        }
    }
}

/// `cargo xtask schemas [--check]`.
fn schemas(check: bool) -> Result<ExitCode, String> {
    let dir = regress::case::workspace_root().join("docs/schemas");
    if check {
        let stale = rappel_schemas::stale_schema_files(&dir);
        if stale.is_empty() {
            println!("docs/schemas: up to date");
            return Ok(ExitCode::SUCCESS);
        }
        for line in &stale {
            eprintln!("docs/schemas/{line}");
        }
        return Err("docs/schemas is stale: run `cargo xtask schemas` and commit".into());
    }
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    for (name, text) in rappel_schemas::schema_files() {
        let path = dir.join(&name);
        rappel::io::write_atomically(&path, text.as_bytes())
            .map_err(|e| format!("{}: {e}", path.display()))?;
        println!("wrote docs/schemas/{name}");
    }
    Ok(ExitCode::SUCCESS)
}
