//! Writes the lidar fixture `fixtures/lidar/boulder_slope_utm10n.laz` (issue 34): a synthetic
//! terrestrial scan of a 20 m x 30 m slope in UTM zone 10N (EPSG:32610, as GeoTIFF keys in the
//! LAS 1.2 `LASF_Projection` records), rising 0.7 m per metre northwards from 1,000 m at
//! (562,000 E, 5,121,000 N), with a boulder (a spherical cap 1.2 m high, 1.5 m in radius) at
//! (562,010, 5,121,015) and the scanner's shadow north of it (no returns in the 2 m x 3 m box
//! behind the boulder). Returns every 0.25 m, jittered by up to 0.1 m with a seeded RNG, heights
//! in millimetres: about 9,600 points.
//!
//! Run: `cargo run -p rappel-terrain --example lidar_fixture -- fixtures/lidar/boulder_slope_utm10n.laz`.
//! `crates/cli/tests/all/lidar.rs` checks the grid rappel makes of it against these closed forms.

use rand::{RngExt, SeedableRng};

/// The scene's closed forms (shared with the test by value: see its constants).
const X0: f64 = 562_000.0;
const Y0: f64 = 5_121_000.0;
const SLOPE: f64 = 0.7;
const BASE: f64 = 1000.0;
const BOULDER: (f64, f64, f64, f64) = (X0 + 10.0, Y0 + 15.0, 1.5, 1.2);
const SHADOW: (f64, f64, f64, f64) = (X0 + 9.0, Y0 + 16.5, X0 + 11.0, Y0 + 19.5);

fn ground(x: f64, y: f64) -> f64 {
    let (bx, by, r, h) = BOULDER;
    let d2 = (x - bx).powi(2) + (y - by).powi(2);
    let cap = if d2 < r * r {
        h * (1.0 - d2 / (r * r)).sqrt()
    } else {
        0.0
    };
    BASE + SLOPE * (y - Y0) + cap
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args()
        .nth(1)
        .ok_or("usage: lidar_fixture OUT.laz")?;
    let mut builder = las::Builder::from((1, 2));
    builder.transforms = las::Vector {
        x: las::Transform {
            scale: 0.001,
            offset: X0,
        },
        y: las::Transform {
            scale: 0.001,
            offset: Y0,
        },
        z: las::Transform {
            scale: 0.001,
            offset: BASE,
        },
    };
    // GeoKeyDirectory: version 1.1.0, 3 keys: GTModelType projected, GTRasterType area,
    // ProjectedCSType 32610.
    let keys: [u16; 16] = [1, 1, 0, 3, 1024, 0, 1, 1, 1025, 0, 1, 1, 3072, 0, 1, 32610];
    builder.vlrs.push(las::Vlr {
        user_id: "LASF_Projection".into(),
        record_id: 34735,
        description: "GeoKeyDirectoryTag".into(),
        data: keys.iter().flat_map(|k| k.to_le_bytes()).collect(),
    });
    builder.generating_software = "rappel lidar_fixture example".into();
    let header = builder.into_header()?;
    let mut writer = las::Writer::from_path(&out, header)?;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(34);
    let mut n = 0;
    for j in 0..120 {
        for i in 0..80 {
            let x = X0 + 0.125 + 0.25 * f64::from(i) + rng.random_range(-0.1..0.1);
            let y = Y0 + 0.125 + 0.25 * f64::from(j) + rng.random_range(-0.1..0.1);
            let (sx0, sy0, sx1, sy1) = SHADOW;
            if x > sx0 && x < sx1 && y > sy0 && y < sy1 {
                continue;
            }
            writer.write_point(las::Point {
                x,
                y,
                z: ground(x, y),
                ..Default::default()
            })?;
            n += 1;
        }
    }
    writer.close()?;
    println!("wrote {out}: {n} points");
    Ok(())
}
