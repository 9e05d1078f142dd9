//! `rappel query MAP --pairs PAIRS.json [--classes K] [--repeat N] [--max-expansions N|auto]
//! [--time-limit SECONDS] [--json] [--progress]`: many start/goal
//! pairs on one map (a scenario file or a map-only file), the BTM built once; each pair's
//! shortest length (or its K shortest classes) and the median time of its query. Exit 0 when
//! every pair is connected, 1 when some pair is not, 2 when a pair or a file is bad. Progress
//! over the pairs goes to stderr when it is a terminal, or always with `--progress`
//! (`crate::progress`). `--time-limit SECONDS` bounds the whole run and Ctrl-C stops it
//! ([`crate::stop`]): the pair being searched and every later one are answered with an error
//! naming the condition (exit 2, as for a spent budget), the answers before are printed.

use crate::output::{Answer, CliError, print_report};
use crate::progress::Show;
use rappel::query::{QueryOptions, answer_observed, load_pairs, read_map};
use std::path::PathBuf;

/// Arguments of `rappel query`.
#[derive(clap::Args)]
pub struct Args {
    /// The map: a scenario file or a map-only file (.ron or .json).
    map: PathBuf,
    /// The pairs: a JSON array of {"start": [x, y], "goal": [x, y]}.
    #[arg(long, value_name = "PAIRS.json")]
    pairs: PathBuf,
    /// Homotopy classes per pair, shortest first (1 ..= 100).
    #[arg(
        long,
        value_name = "K",
        default_value_t = 1,
        allow_negative_numbers = true
    )]
    classes: usize,
    /// Run each query this many times and report the median time (1 ..= 1000).
    #[arg(
        long,
        value_name = "N",
        default_value_t = 1,
        allow_negative_numbers = true
    )]
    repeat: usize,
    /// Print the answers as JSON.
    #[arg(long)]
    json: bool,
    /// Show progress on stderr even when it is not a terminal (plain lines; a bar on a terminal,
    /// where it is shown anyway).
    #[arg(long)]
    progress: bool,
    /// Funnel expansion budget of each pair's search: `auto` (the default) scales it to the map's
    /// triangles and the classes asked for, under a memory cap; a number fixes it. A pair it
    /// stops is answered with an error naming the limit.
    #[arg(long, value_name = "N|auto", default_value = "auto", value_parser = rappel::planners::budget::ExpansionBudget::parse)]
    max_expansions: rappel::planners::budget::ExpansionBudget,
    /// The time limit of the whole run, all pairs together (Ctrl-C stops it too).
    #[command(flatten)]
    time_limit: crate::stop::TimeLimitArg,
}

/// Runs `rappel query`.
pub fn run(args: &Args) -> Result<Answer, CliError> {
    let err = |e: rappel::query::QueryError| CliError(e.to_string());
    let stop = crate::stop::condition(args.max_expansions, &args.time_limit)?;
    // Read, then validated once: the proof carries the valid map to the BTM build.
    let file = read_map(&args.map).map_err(err)?;
    let map = file.validate().map_err(err)?;
    let pairs = load_pairs(&args.pairs).map_err(err)?;
    let show = if args.progress {
        Show::Always
    } else {
        Show::Auto
    };
    let options = QueryOptions {
        classes: args.classes,
        repeat: args.repeat,
        stop,
    };
    let progress = crate::progress::Observer::new(show);
    let answers = answer_observed(map, &pairs, &options, &progress).map_err(err)?;
    crate::stop::say(answers.iter().find_map(|a| a.stop_reason));
    if args.json {
        print_report(&rappel::query::QueryReport {
            answers: answers.clone(),
        })?;
    } else {
        crate::output::outln!("pair  length(s) m                      median us");
        for a in &answers {
            let lengths = match (&a.error, a.lengths_m.is_empty()) {
                (Some(e), _) => format!("error: {e}"),
                (None, true) => "not connected".to_string(),
                (None, false) => a
                    .lengths_m
                    .iter()
                    .map(|l| format!("{l:.3}"))
                    .collect::<Vec<_>>()
                    .join(" "),
            };
            let median = a
                .median_ns
                .map_or_else(|| "-".to_string(), |ns| format!("{:.1}", ns as f64 / 1e3));
            crate::output::outln!("{:>4}  {:<32} {:>9}", a.index, lengths, median);
        }
    }
    if let Some(bad) = answers.iter().find_map(|a| a.error.clone()) {
        return Err(CliError(bad));
    }
    Ok(if answers.iter().all(|a| !a.lengths_m.is_empty()) {
        Answer::Yes
    } else {
        Answer::No
    })
}
