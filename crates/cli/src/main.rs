//! The `rappel` command: argument parsing and printing only; the work happens in the facade crate.

fn main() {}
