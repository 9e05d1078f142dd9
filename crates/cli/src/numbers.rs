//! Numbers given on the command line: one finite number (`--yaw 30`, a clap value parser) or a
//! comma-separated list of them (`--at X,Y`, `--root X,Y,Z`). A refusal names the option, the
//! text given and what was expected; numbers are echoed as the user typed them, never expanded
//! into hundreds of digits.

use crate::output::CliError;

/// One finite number: the value parser of every `f64` option (NaN and infinities are refused
/// here, where clap's message names the option, instead of deep inside a computation).
pub fn finite(text: &str) -> Result<f64, String> {
    let v: f64 = text
        .trim()
        .parse()
        .map_err(|_| "not a number".to_string())?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err("not a finite number".into())
    }
}

/// `n` finite comma-separated numbers given to `flag` (`--at`, `--root`, …).
pub fn numbers(flag: &str, text: &str, n: usize) -> Result<Vec<f64>, CliError> {
    let parts: Vec<&str> = text.split(',').collect();
    if parts.len() != n {
        return Err(CliError(format!(
            "{flag} {text}: expected {n} comma-separated numbers, found {}",
            parts.len()
        )));
    }
    parts
        .iter()
        .enumerate()
        .map(|(i, t)| {
            finite(t).map_err(|why| {
                CliError(format!(
                    "{flag} {text}: number {} (`{}`) is {why}",
                    i + 1,
                    t.trim()
                ))
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refusals_name_the_flag_and_the_part() {
        assert_eq!(finite(" -2.5 "), Ok(-2.5));
        assert_eq!(finite("NaN").unwrap_err(), "not a finite number");
        assert_eq!(finite("1e400").unwrap_err(), "not a finite number");
        assert_eq!(finite("x").unwrap_err(), "not a number");
        assert_eq!(numbers("--at", "1,-2", 2).unwrap(), vec![1.0, -2.0]);
        let e = numbers("--root", "1,2", 3).unwrap_err().0;
        assert_eq!(e, "--root 1,2: expected 3 comma-separated numbers, found 2");
        let e = numbers("--at", "1,inf", 2).unwrap_err().0;
        assert_eq!(e, "--at 1,inf: number 2 (`inf`) is not a finite number");
    }
}
