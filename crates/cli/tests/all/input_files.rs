//! Every reader refuses what is not a regular file and what is over the input size cap, before
//! reading it (issue 30): `/dev/zero` (a character device that never ends), a FIFO, and a file
//! over `RAPPEL_MAX_INPUT_BYTES`, through each command that reads a file; a bad cap is an error,
//! not ignored. One `error:` line naming the file and exit 2, nothing written.

use crate::common;
use common::*;
use std::process::Command;

/// The commands and where their input file goes (`{}`).
fn readers(dir: &std::path::Path) -> Vec<Vec<String>> {
    let strip = fixture("generated/crater-strip-100.ron");
    let out = dir.join("out.ron").display().to_string();
    let pairs = fixture("queries/fig-2-7-pairs.json");
    let kumar = fixture("tracking/kumar.json");
    let r1 = fixture("tracking/robot1-fixed.json");
    let r2 = fixture("tracking/robot2-descent.json");
    [
        vec!["validate", "{}.ron"],
        vec!["plan", "{}.json"],
        vec!["btm", "{}.ron"],
        vec!["query", "{}.ron", "--pairs", &pairs],
        vec!["query", &strip, "--pairs", "{}.json"],
        vec!["shp", &strip, "--path", "{}.json"],
        vec!["dem", "{}.asc", "--out", &out],
        vec!["dem", "{}.tif", "--out", &out],
        vec!["settle", "{}.ron", "--at", "0,0", "--yaw", "0"],
        vec!["settle", "{}.stl", "--at", "0,0", "--yaw", "0"],
        vec!["settle", "{}.ply", "--at", "0,0", "--yaw", "0"],
        vec!["settle", "{}.obj", "--at", "0,0", "--yaw", "0"],
        vec!["online", "{}.ron", "--truth", &strip],
        vec!["online", &strip, "--truth", "{}.ron"],
        vec!["track", "{}.json", "--robot1", &r1, "--robot2", &r2],
        vec!["track", &kumar, "--robot1", "{}.json", "--robot2", &r2],
    ]
    .into_iter()
    .map(|a| a.into_iter().map(String::from).collect())
    .collect()
}

fn run(args: &[String], file: &str, env: Option<&str>) -> std::process::Output {
    let args: Vec<String> = args.iter().map(|a| a.replace("{}", file)).collect();
    let mut c = Command::new(env!("CARGO_BIN_EXE_rappel"));
    c.args(&args);
    if let Some(v) = env {
        c.env("RAPPEL_MAX_INPUT_BYTES", v);
    }
    c.output().expect("runs")
}

fn one_error(o: &std::process::Output, what: &str, args: &[String]) {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
    assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
    assert!(
        err.starts_with("error: ") && err.contains(what),
        "{args:?}: {err}"
    );
}

#[test]
fn devices_and_fifos_are_refused_before_reading() {
    let dir = temp_dir("input-devices");
    // Links with each reader's extension to /dev/zero: a file of unknown, endless size.
    let zero = dir.join("zero");
    for ext in [".json", ".asc", ".tif", ".ron", ".stl", ".ply", ".obj"] {
        std::os::unix::fs::symlink("/dev/zero", format!("{}{ext}", zero.display())).unwrap();
    }
    for args in readers(&dir) {
        let o = run(&args, zero.to_str().unwrap(), None);
        one_error(&o, "is a character device, not a regular file", &args);
    }
    assert!(!dir.join("out.ron").exists());
    // A FIFO nobody writes to would block a reader for ever.
    let fifo = dir.join("pipe.ron");
    let made = Command::new("mkfifo").arg(&fifo).status().expect("mkfifo");
    assert!(made.success());
    let args: Vec<String> = ["validate", "{}"].map(String::from).to_vec();
    one_error(&run(&args, fifo.to_str().unwrap(), None), "a FIFO", &args);
}

#[test]
fn files_over_the_cap_are_refused_and_the_cap_can_be_raised() {
    let dir = temp_dir("input-cap");
    let strip = fixture("generated/crater-strip-100.ron");
    let size = std::fs::metadata(&strip).unwrap().len();
    let args: Vec<String> = ["validate", "{}"].map(String::from).to_vec();
    let small = (size - 1).to_string();
    let o = run(&args, &strip, Some(&small));
    one_error(
        &o,
        &format!("{size} bytes, more than the input limit of {small} bytes"),
        &args,
    );
    assert!(stderr(&o).contains("RAPPEL_MAX_INPUT_BYTES"));
    // Raised to the file's size, it is read.
    let o = run(&args, &strip, Some(&size.to_string()));
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    // A DEM and a mesh over the cap, through their own readers.
    let mesh = dir.join("m.stl");
    std::fs::write(&mesh, vec![b' '; 4096]).unwrap();
    let settle: Vec<String> = ["settle", "{}", "--at", "0,0", "--yaw", "0"]
        .map(String::from)
        .to_vec();
    one_error(
        &run(&settle, mesh.to_str().unwrap(), Some("100")),
        "more than the input limit of 100 bytes",
        &settle,
    );
    let dem = fixture("terrain/mars_hirise_dteec_010228_1490_crop.tif");
    let out = dir.join("out.ron").display().to_string();
    let dem_args: Vec<String> = ["dem", "{}", "--out", &out].map(String::from).to_vec();
    one_error(
        &run(&dem_args, &dem, Some("1000")),
        "more than the input limit of 1000 bytes",
        &dem_args,
    );
    assert!(!dir.join("out.ron").exists());
    // A cap that is not a positive whole number is an error, not ignored.
    for bad in ["0", "-5", "1e9", "lots"] {
        one_error(
            &run(&args, &strip, Some(bad)),
            "RAPPEL_MAX_INPUT_BYTES",
            &args,
        );
    }
}
