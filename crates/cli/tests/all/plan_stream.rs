//! `rappel plan --jsonl` and the end of a failed stream (issue 10): every line parses as a
//! `plan_stream` line, prints back to the same text, and conforms to the committed JSON Schema
//! `docs/schemas/plan_stream.json` (checked here by a small validator of the keywords schemars
//! writes, which refuses any keyword it does not know); the class lines are the classes `--json`
//! reports and the summary carries its verdict; a run that fails after its classes were printed
//! ends with an error marker (text) or an `error` object (JSON lines) and exit code 2; and
//! `--progress` writes progress lines on a stderr that is not a terminal, nothing without it.

use crate::common;

use common::{fixture, rappel, stderr, stdout, temp_dir};
use rappel::plan_stream::PlanStreamLine;
use rappel::report::read_report;
use rappel_schemas::conforms;
use serde_json::Value;

/// The committed schema of the stream.
fn schema() -> Value {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../docs/schemas/plan_stream.json");
    let text = std::fs::read_to_string(&path).expect("docs/schemas/plan_stream.json");
    serde_json::from_str(&text).expect("schema is JSON")
}

/// The lines of a `--jsonl` run, each read back, printed back to the same text and checked
/// against the schema.
fn checked_lines(text: &str) -> Vec<PlanStreamLine> {
    let root = schema();
    text.lines()
        .map(|line| {
            let parsed: PlanStreamLine =
                read_report(line).unwrap_or_else(|e| panic!("{e}: {line}"));
            assert_eq!(parsed.to_line(), line, "not the same text once read back");
            let v: Value = serde_json::from_str(line).expect("JSON");
            conforms(&v, &root, &root, "line").unwrap_or_else(|e| panic!("{e}\n{line}"));
            parsed
        })
        .collect()
}

#[test]
fn jsonl_lines_parse_match_the_schema_and_agree_with_json() {
    let file = fixture("plan/golden-queen-two-anchors.ron");
    let args = ["plan", file.as_str(), "--classes", "3"];
    let o = rappel(&[&args[..], &["--jsonl"]].concat());
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let lines = checked_lines(&stdout(&o));
    let json = rappel(&[&args[..], &["--json"]].concat());
    let report: rappel::plan::PlanReport = read_report(&stdout(&json)).expect("plan report");
    assert_eq!(lines.len(), report.classes.len() + 1);
    for (line, class) in lines.iter().zip(&report.classes) {
        assert_eq!(line, &PlanStreamLine::Class(Box::new(class.clone())));
    }
    match lines.last() {
        Some(PlanStreamLine::Summary(s)) => {
            assert_eq!(s.class_count, report.classes.len());
            assert_eq!(s.outcome.verdict, report.outcome.verdict);
            assert_eq!(s.outcome.chosen, report.outcome.chosen);
        }
        other => panic!("the last line is not the summary: {other:?}"),
    }
    // A document that breaks the schema is refused by the validator (the check can fail).
    let root = schema();
    let bad: Value =
        serde_json::from_str(r#"{"schema_version": 1, "report": "plan_stream", "type": "error"}"#)
            .expect("JSON");
    assert!(conforms(&bad, &root, &root, "bad").is_err());
    // --jsonl streams: it cannot be combined with --json or a picture.
    let o = rappel(&[&args[..], &["--jsonl", "--json"]].concat());
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn a_run_failing_after_its_classes_ends_with_an_error_marker() {
    // The export is written after the classes were streamed; a regular file where its directory
    // should be makes that write fail.
    let dir = temp_dir("stream-fail");
    let blocker = dir.join("blocker");
    std::fs::write(&blocker, "a file, not a directory").expect("write");
    let export = blocker.join("plan.geojson").display().to_string();
    let file = fixture("plan/golden-queen-two-anchors.ron");

    let o = rappel(&["plan", &file, "--classes", "3", "--export", &export]);
    assert_eq!(o.status.code(), Some(2), "{}", stdout(&o));
    let text = stdout(&o);
    assert!(
        text.contains("class 1 "),
        "the classes were streamed: {text}"
    );
    let last = text.lines().last().unwrap_or_default();
    assert!(
        last.starts_with("error        ") && last.ends_with("(the output above is incomplete)"),
        "{text}"
    );
    assert!(last.contains("cannot write"), "{last}");
    assert!(
        !text.contains("verdict"),
        "no verdict on a failed run: {text}"
    );
    let err = stderr(&o);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.starts_with("error: "), "{err}");

    let o = rappel(&[
        "plan",
        &file,
        "--classes",
        "3",
        "--export",
        &export,
        "--jsonl",
    ]);
    assert_eq!(o.status.code(), Some(2));
    let lines = checked_lines(&stdout(&o));
    assert!(matches!(lines.first(), Some(PlanStreamLine::Class(_))));
    match lines.last() {
        Some(PlanStreamLine::Error { message }) => assert!(message.contains("cannot write")),
        other => panic!("the last line is not an error: {other:?}"),
    }
    assert!(
        !lines
            .iter()
            .any(|l| matches!(l, PlanStreamLine::Summary(_)))
    );
}

#[test]
fn progress_is_forced_by_the_flag_and_silent_otherwise() {
    let file = fixture("plan/golden-queen-two-anchors.ron");
    let o = rappel(&["plan", &file, "--classes", "3"]);
    assert_eq!(o.status.code(), Some(0));
    assert!(stderr(&o).is_empty(), "{}", stderr(&o));
    let o = rappel(&["plan", &file, "--classes", "3", "--progress"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let err = stderr(&o);
    for k in 1..=3 {
        assert!(err.contains(&format!("classes {k}/3 (")), "{err}");
    }
    // Progress never reaches stdout: the report is the same as without the flag.
    let quiet = rappel(&["plan", &file, "--classes", "3"]);
    assert_eq!(stdout(&o), stdout(&quiet));

    let map = fixture("thesis-fig-2-7.ron");
    let pairs = fixture("queries/fig-2-7-pairs.json");
    let o = rappel(&["query", &map, "--pairs", &pairs]);
    assert!(stderr(&o).is_empty(), "{}", stderr(&o));
    let o = rappel(&["query", &map, "--pairs", &pairs, "--progress"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(stderr(&o).contains("pairs 3/3 ("), "{}", stderr(&o));
}
