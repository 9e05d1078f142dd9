//! `--window XMIN,YMIN,XMAX,YMAX`: crop a picture to a box of the map frame (metres), for the
//! subcommands whose pictures honour it (`btm`, `shp`, `plan`, `stability`); the numbers are read
//! by [`crate::numbers::numbers`], like every comma-separated option.

use crate::numbers::numbers;
use crate::output::CliError;

/// The `--window` option.
#[derive(clap::Args, Debug, Default)]
pub struct WindowArg {
    /// Crop the picture to this box of the map frame: XMIN,YMIN,XMAX,YMAX (metres).
    #[arg(long, value_name = "XMIN,YMIN,XMAX,YMAX", allow_hyphen_values = true)]
    pub window: Option<String>,
}

impl WindowArg {
    /// The box, when given: four finite numbers with `XMIN < XMAX` and `YMIN < YMAX`.
    pub fn aabb(&self) -> Result<Option<rappel::geometry::polygon::Aabb>, CliError> {
        let Some(text) = &self.window else {
            return Ok(None);
        };
        let v = numbers("--window", text, 4)?;
        let [x0, y0, x1, y1] = v[..] else {
            unreachable!("numbers returns exactly the count asked for");
        };
        if !(x0 < x1 && y0 < y1) {
            return Err(CliError(format!(
                "--window {text}: XMIN must be below XMAX and YMIN below YMAX"
            )));
        }
        Ok(Some(rappel::geometry::polygon::Aabb {
            min: rappel::nalgebra::Point2::new(x0, y0),
            max: rappel::nalgebra::Point2::new(x1, y1),
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_window_is_four_ordered_finite_numbers() {
        let w = |s: &str| {
            WindowArg {
                window: Some(s.into()),
            }
            .aabb()
        };
        let b = w("-1,2,3.5,4").unwrap().unwrap();
        assert_eq!((b.min.x, b.min.y, b.max.x, b.max.y), (-1.0, 2.0, 3.5, 4.0));
        assert_eq!(
            w("1,2,3").unwrap_err().0,
            "--window 1,2,3: expected 4 comma-separated numbers, found 3"
        );
        assert!(
            w("3,0,1,4")
                .unwrap_err()
                .0
                .contains("XMIN must be below XMAX")
        );
        assert_eq!(
            w("0,0,inf,4").unwrap_err().0,
            "--window 0,0,inf,4: number 3 (`inf`) is not a finite number"
        );
        assert!(w("a,b,c,d").unwrap_err().0.contains("is not a number"));
        assert!(WindowArg::default().aabb().unwrap().is_none());
    }
}
