//! `cargo xtask readme --bin PATH`: the README's promises about the command line, checked
//! against the binary.
//!
//! 1. Every `rappel` command in the README's `sh` blocks runs (continuation lines joined, `cargo
//!    run ... -p rappel-cli --` replaced by the binary) and exits with the code its trailing
//!    `# exit N` comment names (0 when none). Outputs under `out/` go to a scratch folder.
//! 2. The command table lists every subcommand `rappel --help` knows, every `--flag` a row names
//!    is a flag of that subcommand (`rappel SUB --help`), and every flag of the subcommand is in
//!    its row (`--help` itself aside).

use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};

/// Most commands the README may hold (a bound on the work, far above the dozen it has).
const MAX_COMMANDS: usize = 200;

/// The README's `rappel` commands: `(the arguments after the binary, the expected exit code)`.
pub fn commands(readme: &str) -> Vec<(Vec<String>, i32)> {
    let mut out = Vec::new();
    let mut in_sh = false;
    let mut pending = String::new();
    for line in readme.lines() {
        let t = line.trim();
        if t.starts_with("```") {
            in_sh = t == "```sh";
            pending.clear();
            continue;
        }
        if !in_sh {
            continue;
        }
        if let Some(head) = t.strip_suffix('\\') {
            pending.push_str(head);
            pending.push(' ');
            continue;
        }
        let whole = format!("{pending}{t}");
        pending.clear();
        let (cmd, comment) = match whole.split_once('#') {
            Some((c, k)) => (c.trim().to_string(), k.trim().to_string()),
            None => (whole.trim().to_string(), String::new()),
        };
        let Some(args) = cmd.split_once(" -p rappel-cli -- ").map(|(_, a)| a) else {
            continue;
        };
        let expect = comment
            .strip_prefix("exit ")
            .and_then(|n| n.trim().parse().ok())
            .unwrap_or(0);
        out.push((args.split_whitespace().map(String::from).collect(), expect));
    }
    out
}

/// The command table's rows: `(subcommand, flags named in its usage cell)`.
pub fn table_rows(readme: &str) -> Vec<(String, Vec<String>)> {
    readme
        .lines()
        .filter_map(|l| l.strip_prefix("| `rappel "))
        .filter_map(|rest| {
            let usage = rest.split('`').next()?;
            let sub = usage.split_whitespace().next()?.to_string();
            let flags = usage
                .split(|c: char| c.is_whitespace() || "[]()|".contains(c))
                .filter(|w| w.starts_with("--"))
                .map(|w| {
                    w.trim_end_matches(|c: char| !c.is_alphanumeric())
                        .to_string()
                })
                .filter(|w| w.len() > 2)
                .collect();
            Some((sub, flags))
        })
        .collect()
}

/// The subcommands `rappel --help` lists.
fn subcommands(bin: &Path) -> Result<Vec<String>, String> {
    let help = run_help(bin, &[])?;
    let mut subs = Vec::new();
    let mut listing = false;
    for line in help.lines() {
        if line.starts_with("Commands:") {
            listing = true;
            continue;
        }
        if listing {
            if !line.starts_with("  ") {
                break;
            }
            if let Some(name) = line.split_whitespace().next()
                && name != "help"
            {
                subs.push(name.to_string());
            }
        }
    }
    Ok(subs)
}

/// The long flags a `--help` text lists (option lines start with `-x, --flag` or `--flag`),
/// `--help` and `--version` aside.
fn help_flags(help: &str) -> Vec<String> {
    help.lines()
        .map(str::trim_start)
        .filter(|l| l.starts_with('-'))
        .filter_map(|l| {
            l.split(|c: char| c.is_whitespace() || c == ',' || c == '=')
                .find(|w| w.starts_with("--"))
        })
        .filter(|f| *f != "--help" && *f != "--version")
        .map(String::from)
        .collect()
}

fn run_help(bin: &Path, sub: &[&str]) -> Result<String, String> {
    let out = Command::new(bin)
        .args(sub)
        .arg("--help")
        .output()
        .map_err(|e| format!("{}: {e}", bin.display()))?;
    Ok(String::from_utf8_lossy(&out.stdout).into_owned())
}

/// Runs both checks; exit 1 when one fails, naming each failure.
pub fn run(bin: Option<PathBuf>) -> Result<ExitCode, String> {
    let root = crate::regress::case::workspace_root();
    let bin = bin.unwrap_or_else(|| root.join("target/debug/rappel"));
    let readme =
        std::fs::read_to_string(root.join("README.md")).map_err(|e| format!("README.md: {e}"))?;
    let scratch = std::env::temp_dir().join(format!("rappel-readme-{}", std::process::id()));
    std::fs::create_dir_all(&scratch).map_err(|e| format!("{}: {e}", scratch.display()))?;
    let mut failures = Vec::new();
    let cmds = commands(&readme);
    if cmds.is_empty() || cmds.len() > MAX_COMMANDS {
        return Err(format!(
            "README.md: {} rappel commands found (expected 1..={MAX_COMMANDS})",
            cmds.len()
        ));
    }
    for (args, expect) in &cmds {
        let args: Vec<String> = args
            .iter()
            .map(|a| match a.strip_prefix("out/") {
                Some(f) => scratch.join(f).display().to_string(),
                None => a.clone(),
            })
            .collect();
        let out = Command::new(&bin)
            .args(&args)
            .current_dir(&root)
            .output()
            .map_err(|e| format!("{}: {e}", bin.display()))?;
        let code = out.status.code().unwrap_or(-1);
        let line = format!("rappel {}", args.join(" "));
        if code == *expect {
            println!("readme: ok (exit {code}): {line}");
        } else {
            failures.push(format!(
                "{line}: exit {code}, the README says {expect}: {}",
                String::from_utf8_lossy(&out.stderr).trim()
            ));
        }
    }
    let rows = table_rows(&readme);
    let subs = subcommands(&bin)?;
    for sub in &subs {
        if !rows.iter().any(|(s, _)| s == sub) {
            failures.push(format!(
                "the README's command table has no row for `rappel {sub}`"
            ));
        }
    }
    for (sub, flags) in &rows {
        if !subs.contains(sub) {
            failures.push(format!(
                "the README's command table names `rappel {sub}`, which the binary does not know"
            ));
            continue;
        }
        let help = run_help(&bin, &[sub])?;
        for flag in flags {
            let known = help
                .split(|c: char| c.is_whitespace() || c == ',' || c == '=')
                .any(|w| w == flag);
            if !known {
                failures.push(format!(
                    "the README's row for `rappel {sub}` names {flag}, which `rappel {sub} --help` does not list"
                ));
            }
        }
        for flag in help_flags(&help) {
            if !flags.contains(&flag) {
                failures.push(format!(
                    "the README's row for `rappel {sub}` does not name {flag} (`rappel {sub} --help` has it)"
                ));
            }
        }
        println!(
            "readme: table row `rappel {sub}`: {} flags known",
            flags.len()
        );
    }
    let _ = std::fs::remove_dir_all(&scratch);
    for f in &failures {
        eprintln!("readme: FAILED: {f}");
    }
    println!(
        "readme: {} commands run, {} table rows checked against {} subcommands, {} failures",
        cmds.len(),
        rows.len(),
        subs.len(),
        failures.len()
    );
    Ok(if failures.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const SAMPLE: &str = "text\n```sh\n# a comment\ncargo run --release -p rappel-cli -- plan a.ron --svg out/x.svg\ncargo run --release -p rappel-cli -- homotopic a.ron \\\n    --path p.json --path q.json   # exit 1\ncargo test --workspace\n```\n\n| command | what |\n|---|---|\n| `rappel plan FILE [--classes K] [--json]` | plans |\n| `rappel query MAP --pairs P.json [--max-expansions N\\|auto]` | queries |\n";

    #[test]
    fn commands_are_joined_and_carry_their_exit_codes() {
        let c = commands(SAMPLE);
        assert_eq!(c.len(), 2);
        assert_eq!(c[0].0, ["plan", "a.ron", "--svg", "out/x.svg"]);
        assert_eq!(c[0].1, 0);
        assert_eq!(
            c[1].0,
            ["homotopic", "a.ron", "--path", "p.json", "--path", "q.json"]
        );
        assert_eq!(c[1].1, 1);
    }

    #[test]
    fn table_rows_name_their_flags() {
        let rows = table_rows(SAMPLE);
        assert_eq!(rows.len(), 2);
        assert_eq!(
            rows[0],
            (
                "plan".to_string(),
                vec!["--classes".into(), "--json".into()]
            )
        );
        assert_eq!(
            rows[1],
            (
                "query".to_string(),
                vec!["--pairs".into(), "--max-expansions".into()]
            )
        );
    }
}
