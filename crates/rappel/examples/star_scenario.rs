//! Writes the long-obstacle scenario of issue 10 (`rappel::generated::star_scenario`: one star
//! obstacle of N vertices) to a scenario file, for timing `rappel plan` on it:
//! `cargo run --release -p rappel --example star_scenario -- 10000 /tmp/star-10000.ron`
//! (the format from the extension, `.ron` or `.json`).

use rappel::generated::star_scenario;
use rappel::scenario::Format;
use std::path::PathBuf;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let usage = "usage: star_scenario VERTICES OUT.ron|OUT.json";
    let vertices: usize = args.next().ok_or(usage)?.parse()?;
    let out = PathBuf::from(args.next().ok_or(usage)?);
    let format = Format::of_path(&out).ok_or("the output must end in .ron or .json")?;
    let scenario = star_scenario(vertices)?;
    rappel::io::write_atomically(&out, scenario.to_text(format).as_bytes())?;
    println!("{}: {vertices} star vertices", out.display());
    Ok(())
}
