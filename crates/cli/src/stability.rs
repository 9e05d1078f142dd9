//! `rappel stability FILE [--tension-limit N] [--grid STEP] [--time-limit SECONDS] [--json]
//! [--svg OUT] [--html OUT] [--window XMIN,YMIN,XMAX,YMAX] [--geotiff OUT.tif]`: a stability map over the scenario's
//! terrain planes (Kumar Fig. 5): stable poses as discs coloured by margin on a colour scale,
//! unstable poses as rings, sized to the grid step; the JSON lists each dot with its margin.
//! `--time-limit SECONDS` bounds the map and Ctrl-C stops it ([`crate::stop`]): the map is then
//! partial (the poses assessed before), `stopped_by` names the condition, and the exit code is 1;
//! a whole map exits 0. `--geotiff` also writes the map in the DEM's grid and CRS
//! ([`rappel_render::raster_export`]; a scenario made by `rappel dem`), and says on stderr which
//! CRS it wrote.

use crate::gis_out::GeoTiffOut;
use crate::output::{Answer, CliError, PictureArgs, print_report, refuse_clashing_outputs};
use crate::window::WindowArg;
use rappel::scenario::Scenario;
use rappel::stability::{StabilityOptions, stability_observed};
use std::path::PathBuf;

/// Arguments of `rappel stability`.
#[derive(clap::Args)]
pub struct Args {
    /// The scenario file (.ron or .json).
    file: PathBuf,
    /// Largest tether tension, N (uses Kumar's tension-limited LP; default: Paton's QP).
    #[arg(long, value_parser = crate::numbers::finite, value_name = "N", allow_negative_numbers = true)]
    tension_limit: Option<f64>,
    /// Grid step, m.
    #[arg(
        long,
        value_parser = crate::numbers::finite,
        value_name = "STEP",
        default_value_t = 1.0,
        allow_negative_numbers = true
    )]
    grid: f64,
    /// The time limit of the map (Ctrl-C stops it too): a partial map is reported.
    #[command(flatten)]
    time_limit: crate::stop::TimeLimitArg,
    /// Print every dot as JSON.
    #[arg(long)]
    json: bool,
    /// The picture: the map with the dots.
    #[command(flatten)]
    picture: PictureArgs,
    /// The picture's crop.
    #[command(flatten)]
    window: WindowArg,
    /// Also write the map as a GeoTIFF in the DEM's grid and CRS: band 1 the verdict (1 stable,
    /// 0 not), band 2 the smallest margin, -9999 where no pose was assessed (a scenario made by
    /// `rappel dem`).
    #[arg(long, value_name = "OUT.tif")]
    geotiff: Option<PathBuf>,
}

/// Runs `rappel stability`.
pub fn run(args: &Args) -> Result<Answer, CliError> {
    let mut outputs = args.picture.outputs();
    let geotiff = args
        .geotiff
        .as_ref()
        .map(|p| GeoTiffOut::new("--geotiff", p));
    if let Some(g) = &geotiff {
        outputs.extend(g.outputs());
    }
    refuse_clashing_outputs(&outputs, &[&args.file])?;
    let stop = crate::stop::condition(
        rappel::planners::budget::ExpansionBudget::Auto,
        &args.time_limit,
    )?;
    let window = args.window.aabb()?;
    // Read, then validated once: the proof carries the valid map to the BTM build.
    let s = Scenario::read(&args.file)?;
    let valid = s.validate_at(&args.file)?;
    // The DEM's grid, read before the map is made: a scenario without one fails at once.
    let dem_grid = match &args.geotiff {
        None => None,
        Some(_) => {
            let Some(geo) = &s.georeference else {
                return Err(CliError(format!(
                    "--geotiff: {} has no georeference (it was not made by `rappel dem`), so there is no DEM grid to write in",
                    args.file.display()
                )));
            };
            let dem = geo.dem_path(&args.file);
            let grid = rappel::terrain::dem::read_dem(&dem)
                .map_err(|e| CliError(format!("--geotiff: {e}")))?;
            Some((geo.clone(), grid))
        }
    };
    let options = StabilityOptions {
        grid_step: args.grid,
        tension_limit: args.tension_limit,
        stop,
    };
    let report = stability_observed(valid, &options, &crate::progress::Observer::default())
        .map_err(|e| CliError(format!("{}: {e}", args.file.display())))?;
    crate::stop::say(report.stopped_by);
    let answer = match report.stopped_by {
        Some(_) => Answer::No,
        None => Answer::Yes,
    };
    if args.picture.wanted() {
        let title = format!(
            "stability of {}: {} of {} poses stable",
            args.file.display(),
            report.stable,
            report.assessed
        );
        args.picture.write(
            &rappel_render::stability::picture(&report, &s, window.as_ref(), &title),
            &title,
        )?;
    }
    if let (Some(out), Some((geo, grid))) = (&geotiff, &dem_grid) {
        let (image, outside) =
            rappel_render::raster_export::stability_geotiff(&report, geo, grid.geometry())
                .map_err(|e| CliError(format!("{}: {e}", out.context())))?;
        out.write(&image, "verdict and margin in the DEM's grid")?;
        if outside > 0 {
            eprintln!(
                "warning: {outside} poses fall outside the DEM's grid and are not in the GeoTIFF"
            );
        }
    }
    if args.json {
        return print_report(&report).map(|()| answer);
    }
    crate::output::outln!("scenario    {}", args.file.display());
    crate::output::outln!("robot       {} ({})", report.robot, report.criterion);
    if let Some(what) = &report.stand_in_for {
        crate::output::outln!(
            "stand-in    the {} model is judged in place of {what}",
            report.robot
        );
    }
    if let Some(l) = report.tether_length_m {
        let beyond = report.dots.iter().filter(|d| d.beyond_tether).count();
        crate::output::outln!("tether      {l} m: {beyond} poses beyond its reach (unstable)");
    }
    crate::output::outln!("grid step   {} m", report.grid_step_m);
    if let Some(t) = report.tension_limit_n {
        crate::output::outln!("tension     <= {t} N");
    }
    for (i, p) in s.terrain.planes.iter().enumerate() {
        let on: Vec<_> = report.dots.iter().filter(|d| d.plane == i).collect();
        let stable = on.iter().filter(|d| d.stable).count();
        crate::output::outln!(
            "plane {i}     {:.1} deg, mu {}: {stable} of {} poses stable",
            p.slope_deg,
            p.friction,
            on.len()
        );
    }
    crate::output::outln!("stable      {} of {} poses", report.stable, report.assessed);
    if let Some(r) = report.stopped_by {
        crate::output::outln!("stopped     the map stopped at {r}: a partial map");
    }
    Ok(answer)
}
