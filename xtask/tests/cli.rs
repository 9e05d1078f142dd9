//! The xtask command line (`cargo xtask ...`): exit codes and messages on bad input, and the
//! committed JSON Schema documents checked by the binary itself. Being an integration test, this
//! file also makes `cargo test --workspace` build the `xtask` binary with the test build's
//! dependency features, which `.ci/run` then runs (a separate `cargo run -p xtask` would compile
//! the dependencies again with other features).

use std::process::Command;

fn xtask(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_xtask"))
        .args(args)
        .output()
        .expect("the xtask binary runs")
}

#[test]
fn unknown_suite_is_an_error_naming_the_filter() {
    let out = xtask(&["regress", "--suite", "no-such-suite"]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("no regression suite matches \"no-such-suite\""),
        "{stderr}"
    );
    assert!(
        out.stdout.is_empty(),
        "no table is printed: {:?}",
        out.stdout
    );
}

#[test]
fn unknown_command_and_flag_are_usage_errors() {
    for args in [&["regres"][..], &["schemas", "--chek"][..]] {
        let out = xtask(args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(stderr.contains("error:"), "{args:?}: {stderr}");
    }
}

#[test]
fn schemas_check_exits_0_on_the_committed_documents() {
    let out = xtask(&["schemas", "--check"]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(String::from_utf8_lossy(&out.stdout).contains("up to date"));
}

#[test]
fn journeys_fail_on_a_binary_that_answers_nothing() {
    // `true` exits 0 and prints nothing: every journey must fail (no report, no files), so the
    // suite's checks are not satisfied by an exit code alone.
    let out = xtask(&["journeys", "--bin", "/bin/true"]);
    assert_eq!(out.status.code(), Some(1));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("journeys: 0 passed"), "{stdout}");
    assert!(!stdout.lines().any(|l| l.starts_with("ok ")), "{stdout}");
}
