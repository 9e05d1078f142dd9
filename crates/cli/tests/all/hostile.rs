//! The hostile corpus (issue 30): `fixtures/hostile/cases.json` lists command lines built to
//! break the tool (FIFOs and devices as input, headers that lie, coordinates of 1e300, anchors
//! under the ground, a closed standard output, NaN options, points with three numbers) with the
//! exit code and the message fragment each must give. Every case must also keep the README's
//! general promises: no panic, an error is exactly one `error:` line, no Debug dump, no number
//! of 25 digits, no `u64::MAX` for an index, and nothing written when the run fails.
//!
//! Placeholders in the arguments: `{fixtures}`, `{hostile}` (`fixtures/hostile`), `{out}` (a
//! fresh directory per case, which must stay empty when `no_files` is set) and `{base}`, the
//! harness's directory, which holds `fifo.ron` (a named pipe no one writes to: a reader that
//! waits on it would hang, so every case runs under a 60 s watchdog) and `zero.ron`, `zero.obj`
//! (links to `/dev/zero`, endless input behind a known extension).

use crate::common::{fixture, stderr, stdout, temp_dir};
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The longest a case may run.
const WATCHDOG: Duration = Duration::from_secs(60);

/// One case of the corpus.
#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Case {
    class: String,
    name: String,
    args: Vec<String>,
    exit: i32,
    message: String,
    #[serde(default)]
    stream: Option<String>,
    #[serde(default)]
    no_files: bool,
    #[serde(default)]
    stdout_closed: bool,
    #[serde(default)]
    env: std::collections::BTreeMap<String, String>,
}

/// What no output may contain, whatever the case.
fn general_promises(what: &str, text: &str) {
    assert!(!text.contains("panicked"), "{what}: a panic: {text}");
    for debug in ["Custom {", "Os {", "{ kind:", "18446744073709551615"] {
        assert!(
            !text.contains(debug),
            "{what}: a Debug dump `{debug}`: {text}"
        );
    }
    let mut run = 0;
    for c in text.chars() {
        run = if c.is_ascii_digit() { run + 1 } else { 0 };
        assert!(run < 25, "{what}: a number of 25 digits or more: {text}");
    }
}

/// Runs `args` (with stdout closed when asked) under the watchdog.
fn run(case: &Case, args: &[String]) -> std::process::Output {
    let bin = env!("CARGO_BIN_EXE_rappel");
    let mut cmd = if case.stdout_closed {
        let mut c = Command::new("/bin/sh");
        c.arg("-c")
            .arg("exec \"$0\" \"$@\" >&-")
            .arg(bin)
            .args(args);
        c
    } else {
        let mut c = Command::new(bin);
        c.args(args);
        c
    };
    cmd.envs(&case.env)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    let mut child = cmd.spawn().expect("the binary runs");
    let start = Instant::now();
    loop {
        if child.try_wait().expect("wait").is_some() {
            return child.wait_with_output().expect("output");
        }
        if start.elapsed() > WATCHDOG {
            let _ = child.kill();
            panic!("{}: still running after {WATCHDOG:?}", case.name);
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

#[test]
fn every_hostile_case_gives_its_exit_code_and_message() {
    let hostile = fixture("hostile");
    let text = std::fs::read_to_string(Path::new(&hostile).join("cases.json")).expect("corpus");
    let cases: Vec<Case> = serde_json::from_str(&text).expect("the corpus parses");
    assert!(cases.len() >= 40, "{} cases", cases.len());
    let base = temp_dir("hostile");
    let made = Command::new("mkfifo")
        .arg(base.join("fifo.ron"))
        .status()
        .expect("mkfifo runs");
    assert!(made.success());
    for link in ["zero.ron", "zero.obj"] {
        std::os::unix::fs::symlink("/dev/zero", base.join(link)).expect("a link to /dev/zero");
    }
    let mut failed = Vec::new();
    for (k, case) in cases.iter().enumerate() {
        let checked = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            check_case(case, k, &base, &hostile)
        }));
        if checked.is_err() {
            failed.push(format!("[{}] {}", case.class, case.name));
        }
    }
    assert!(
        failed.is_empty(),
        "{} failed cases: {failed:#?}",
        failed.len()
    );
    // Every file of the corpus is used by a case.
    for entry in std::fs::read_dir(&hostile).expect("corpus dir") {
        let name = entry
            .expect("entry")
            .file_name()
            .to_string_lossy()
            .into_owned();
        if name != "cases.json" && name != "README.md" {
            assert!(
                text.contains(&name),
                "{name} is in fixtures/hostile but no case uses it"
            );
        }
    }
    let _ = std::fs::remove_dir_all(&base);
}

/// Runs one case and checks its promises (panics on a broken one).
fn check_case(case: &Case, k: usize, base: &Path, hostile: &str) {
    {
        let out = base.join(format!("out-{k}"));
        std::fs::create_dir_all(&out).expect("out dir");
        let args: Vec<String> = case
            .args
            .iter()
            .map(|a| {
                a.replace("{fixtures}", &fixture(""))
                    .replace("{hostile}", hostile)
                    .replace("{out}", &out.display().to_string())
                    .replace("{base}", &base.display().to_string())
            })
            .collect();
        let what = format!("[{}] {}", case.class, case.name);
        let o = run(case, &args);
        let (so, se) = (stdout(&o), stderr(&o));
        assert_eq!(
            o.status.code(),
            Some(case.exit),
            "{what}: {args:?}\n{se}{so}"
        );
        general_promises(&what, &se);
        general_promises(&what, &so);
        match case.stream.as_deref().unwrap_or("stderr") {
            "stdout" => assert!(so.contains(&case.message), "{what}: stdout {so}"),
            _ => {
                let lines: Vec<&str> = se.lines().collect();
                assert_eq!(lines.len(), 1, "{what}: one error line: {se}");
                assert!(
                    lines[0].starts_with("error: ") && lines[0].contains(&case.message),
                    "{what}: expected `{}` in {se}",
                    case.message
                );
                assert!(so.is_empty(), "{what}: nothing on stdout: {so}");
            }
        }
        if case.no_files {
            let left: Vec<_> = std::fs::read_dir(&out).expect("out").collect();
            assert!(left.is_empty(), "{what}: files left behind: {left:?}");
        }
    }
}
