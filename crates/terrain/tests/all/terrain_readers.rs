//! DEM readers (issue 6, deliverable 1): ESRI ASCII header variants and malformed files, GeoTIFF
//! variants written here with the `tiff` crate's encoder (float32 and int16, strips and tiles,
//! uncompressed, LZW and Deflate, georeference variants, GDAL_NODATA), the real grids in
//! `fixtures/terrain/`, and a little fuzzing: truncated and corrupted files give errors, never a
//! panic.

use std::io::Cursor;

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rappel_terrain::dem::{DemError, read_dem};
use rappel_terrain::esri_ascii::{EsriAsciiError, parse_esri_ascii};
use rappel_terrain::geotiff::{GeoTiffError, decode_geotiff};
use rappel_terrain::grid::{GridGeometry, HeightGrid};
use tiff::encoder::colortype::{self, ColorType};
use tiff::encoder::compression::{CompressionAlgorithm, Deflate, Lzw};
use tiff::encoder::{Compression, DeflateLevel, Predictor, TiffEncoder, TiffValue};
use tiff::tags::Tag;

fn fixture(name: &str) -> String {
    format!(
        "{}/../../fixtures/terrain/{name}",
        env!("CARGO_MANIFEST_DIR")
    )
}

/// Test grid: `h(row, col)`, with every 7th cell unknown when `holes`.
const W: u32 = 37;
const H: u32 = 23;
const NODATA: i16 = -9999;

fn sample(r: u32, c: u32) -> i16 {
    (100 + 3 * r as i32 - 2 * c as i32 + ((r * c) % 5) as i32) as i16
}

fn hole(r: u32, c: u32) -> bool {
    (r * W + c) % 7 == 3
}

fn expected(holes: bool) -> Vec<f64> {
    (0..H)
        .flat_map(|r| (0..W).map(move |c| (r, c)))
        .map(|(r, c)| {
            if holes && hole(r, c) {
                f64::NAN
            } else {
                f64::from(sample(r, c))
            }
        })
        .collect()
}

fn samples_i16(holes: bool) -> Vec<i16> {
    (0..H)
        .flat_map(|r| (0..W).map(move |c| (r, c)))
        .map(|(r, c)| {
            if holes && hole(r, c) {
                NODATA
            } else {
                sample(r, c)
            }
        })
        .collect()
}

fn samples_f32(holes: bool) -> Vec<f32> {
    samples_i16(holes).into_iter().map(f32::from).collect()
}

/// How the raster is georeferenced.
#[derive(Clone, Copy)]
enum Georef {
    /// Pixel scale (2, 3) and tie point (0, 0) -> (1000, 5000).
    ScaleTie,
    /// The same, declared PixelIsPoint.
    ScaleTiePoint,
    /// A ModelTransformation with the same scale and corner.
    Transformation,
    /// A rotated ModelTransformation.
    Rotated,
    /// None.
    Missing,
}

/// The geometry every `ScaleTie` file must decode to.
fn geometry() -> GridGeometry {
    GridGeometry::new(H as usize, W as usize, 2.0, 3.0, 1000.0, 5000.0).unwrap()
}

fn write_georef<W: std::io::Write + std::io::Seek, K: tiff::encoder::TiffKind>(
    enc: &mut tiff::encoder::DirectoryEncoder<'_, W, K>,
    georef: Georef,
    nodata: bool,
) {
    match georef {
        Georef::ScaleTie | Georef::ScaleTiePoint => {
            enc.write_tag(Tag::ModelPixelScaleTag, &[2.0f64, 3.0, 0.0][..])
                .unwrap();
            enc.write_tag(
                Tag::ModelTiepointTag,
                &[0.0f64, 0.0, 0.0, 1000.0, 5000.0, 0.0][..],
            )
            .unwrap();
            if matches!(georef, Georef::ScaleTiePoint) {
                enc.write_tag(Tag::GeoKeyDirectoryTag, &[1u16, 1, 0, 1, 1025, 0, 1, 2][..])
                    .unwrap();
            }
        }
        Georef::Transformation | Georef::Rotated => {
            let shear = if matches!(georef, Georef::Rotated) {
                0.5
            } else {
                0.0
            };
            let m = [
                2.0f64, shear, 0.0, 1000.0, 0.0, -3.0, 0.0, 5000.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
                0.0, 1.0,
            ];
            enc.write_tag(Tag::ModelTransformationTag, &m[..]).unwrap();
        }
        Georef::Missing => {}
    }
    if nodata {
        enc.write_tag(Tag::GdalNodata, "-9999").unwrap();
    }
}

/// A striped GeoTIFF of `data`, `rows_per_strip` rows per strip.
fn striped<C: ColorType>(
    data: &[C::Inner],
    compression: Compression,
    predictor: Predictor,
    rows_per_strip: u32,
    georef: Georef,
    nodata: bool,
) -> Vec<u8>
where
    [C::Inner]: TiffValue,
{
    let mut bytes = Vec::new();
    {
        let mut tiff = TiffEncoder::new(Cursor::new(&mut bytes))
            .unwrap()
            .with_compression(compression)
            .with_predictor(predictor);
        let mut image = tiff.new_image::<C>(W, H).unwrap();
        image.rows_per_strip(rows_per_strip).unwrap();
        write_georef(image.encoder(), georef, nodata);
        image.write_data(data).unwrap();
    }
    bytes
}

/// A tiled single-band int16 GeoTIFF (the encoder writes strips only, so the directory is written
/// by hand): 16 x 16 tiles, edge tiles padded.
fn tiled_i16(data: &[i16], compression: u16, georef: Georef) -> Vec<u8> {
    const T: u32 = 16;
    let (tx, ty) = (W.div_ceil(T), H.div_ceil(T));
    let mut bytes = Vec::new();
    {
        let mut tiff = TiffEncoder::new(Cursor::new(&mut bytes)).unwrap();
        let mut dir = tiff.image_directory().unwrap();
        let (mut offsets, mut counts) = (Vec::new(), Vec::new());
        for j in 0..ty {
            for i in 0..tx {
                let mut raw = Vec::with_capacity((T * T * 2) as usize);
                for r in 0..T {
                    for c in 0..T {
                        let (rr, cc) = (j * T + r, i * T + c);
                        let v = if rr < H && cc < W {
                            data[(rr * W + cc) as usize]
                        } else {
                            0
                        };
                        raw.extend_from_slice(&v.to_ne_bytes());
                    }
                }
                let mut packed = Vec::new();
                match compression {
                    1 => packed = raw,
                    5 => {
                        Lzw.write_to(&mut packed, &raw).unwrap();
                    }
                    8 => {
                        Deflate::with_level(DeflateLevel::Balanced)
                            .write_to(&mut packed, &raw)
                            .unwrap();
                    }
                    other => panic!("no codec {other}"),
                }
                offsets.push(dir.write_data(&packed[..]).unwrap() as u32);
                counts.push(packed.len() as u32);
            }
        }
        dir.write_tag(Tag::ImageWidth, W).unwrap();
        dir.write_tag(Tag::ImageLength, H).unwrap();
        dir.write_tag(Tag::BitsPerSample, 16u16).unwrap();
        dir.write_tag(Tag::SampleFormat, 2u16).unwrap();
        dir.write_tag(Tag::SamplesPerPixel, 1u16).unwrap();
        dir.write_tag(Tag::PhotometricInterpretation, 1u16).unwrap();
        dir.write_tag(Tag::Compression, compression).unwrap();
        dir.write_tag(Tag::TileWidth, T).unwrap();
        dir.write_tag(Tag::TileLength, T).unwrap();
        dir.write_tag(Tag::TileOffsets, &offsets[..]).unwrap();
        dir.write_tag(Tag::TileByteCounts, &counts[..]).unwrap();
        write_georef(&mut dir, georef, true);
        dir.finish().unwrap();
    }
    bytes
}

/// The decoded grid has the expected geometry and heights (unknown exactly where expected).
fn check(bytes: Vec<u8>, holes: bool, geometry: GridGeometry) {
    let dem = decode_geotiff(Cursor::new(bytes)).unwrap();
    assert_eq!(dem, HeightGrid::new(geometry, expected(holes)).unwrap());
}

#[test]
fn float32_and_int16_strips_every_codec() {
    let g = geometry();
    let codecs = [
        Compression::Uncompressed,
        Compression::Lzw,
        Compression::Deflate(DeflateLevel::Fast),
    ];
    for compression in codecs {
        for rows in [1, 5, H] {
            let f = samples_f32(true);
            let b = striped::<colortype::Gray32Float>(
                &f,
                compression,
                Predictor::None,
                rows,
                Georef::ScaleTie,
                true,
            );
            check(b, true, g);
            let i = samples_i16(true);
            for predictor in [Predictor::None, Predictor::Horizontal] {
                let b = striped::<colortype::GrayI16>(
                    &i,
                    compression,
                    predictor,
                    rows,
                    Georef::ScaleTie,
                    true,
                );
                check(b, true, g);
            }
        }
    }
}

#[test]
fn int16_tiles_every_codec() {
    for compression in [1, 5, 8] {
        check(
            tiled_i16(&samples_i16(true), compression, Georef::ScaleTie),
            true,
            geometry(),
        );
    }
}

#[test]
fn without_gdal_nodata_every_value_is_a_height() {
    let i = samples_i16(true);
    let b = striped::<colortype::GrayI16>(
        &i,
        Compression::Lzw,
        Predictor::None,
        4,
        Georef::ScaleTie,
        false,
    );
    let dem = decode_geotiff(Cursor::new(b)).unwrap();
    assert_eq!(dem.unknown_count(), 0);
    assert_eq!(dem.height(0, 3), Some(-9999.0));
}

#[test]
fn georeference_variants() {
    let f = samples_f32(false);
    let file = |georef| {
        striped::<colortype::Gray32Float>(
            &f,
            Compression::Uncompressed,
            Predictor::None,
            H,
            georef,
            false,
        )
    };
    check(file(Georef::Transformation), false, geometry());
    // PixelIsPoint: the tie point is the first cell's centre, so the edges move out half a cell.
    let g = GridGeometry::new(H as usize, W as usize, 2.0, 3.0, 999.0, 5001.5).unwrap();
    check(file(Georef::ScaleTiePoint), false, g);
    assert!(matches!(
        decode_geotiff(Cursor::new(file(Georef::Rotated))),
        Err(GeoTiffError::RotatedGrid)
    ));
    assert!(matches!(
        decode_geotiff(Cursor::new(file(Georef::Missing))),
        Err(GeoTiffError::MissingGeoreference)
    ));
}

#[test]
fn multiband_is_refused() {
    let rgb: Vec<u8> = vec![7; (W * H * 3) as usize];
    let b = striped::<colortype::RGB8>(
        &rgb,
        Compression::Uncompressed,
        Predictor::None,
        H,
        Georef::ScaleTie,
        false,
    );
    let err = decode_geotiff(Cursor::new(b)).unwrap_err();
    assert!(matches!(err, GeoTiffError::NotSingleBand { .. }), "{err}");
}

#[test]
fn read_dem_dispatches_on_extension() {
    let dir = std::env::temp_dir().join(format!("rappel-terrain-readers-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let tif = striped::<colortype::Gray32Float>(
        &samples_f32(true),
        Compression::Deflate(DeflateLevel::Balanced),
        Predictor::None,
        3,
        Georef::ScaleTie,
        true,
    );
    let want = HeightGrid::new(geometry(), expected(true)).unwrap();
    for name in ["a.tif", "b.TIFF"] {
        std::fs::write(dir.join(name), &tif).unwrap();
        assert_eq!(read_dem(dir.join(name)).unwrap(), want);
    }
    std::fs::write(dir.join("c.asc"), b"ncols 1\nnrows 1\nxllcorner 0\n").unwrap();
    let err = read_dem(dir.join("c.asc")).unwrap_err();
    assert!(matches!(
        err,
        DemError::EsriAscii {
            source: EsriAsciiError::MissingKey { key: "cellsize" },
            ..
        }
    ));
    assert!(err.to_string().contains("c.asc"), "{err}");
    assert!(matches!(
        read_dem(dir.join("missing.asc")),
        Err(DemError::Input(
            rappel_terrain::input::InputError::Io { .. }
        ))
    ));
    assert!(matches!(
        read_dem(dir.join("a.png")),
        Err(DemError::UnknownFormat { .. })
    ));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn real_grids_read_and_agree() {
    let asc = read_dem(fixture("mars_hirise_dteec_010228_1490_crop.asc")).unwrap();
    let tif = read_dem(fixture("mars_hirise_dteec_010228_1490_crop.tif")).unwrap();
    assert_eq!(asc.geometry().nrows, 120);
    assert_eq!(asc.geometry().ncols, 70);
    let (ga, gt) = (asc.geometry(), tif.geometry());
    assert_eq!((ga.nrows, ga.ncols), (gt.nrows, gt.ncols));
    for (a, b) in [
        (ga.cell_x, gt.cell_x),
        (ga.west, gt.west),
        (ga.north, gt.north),
    ] {
        assert!((a - b).abs() < 1e-9, "{a} {b}");
    }
    // The GeoTIFF holds the same heights in float32.
    for (a, b) in asc.heights().iter().zip(tif.heights()) {
        assert_eq!(*a as f32, *b as f32);
    }
    let (lo, hi) = asc.height_range().unwrap();
    assert!(
        (lo - 753.25).abs() < 0.01 && (hi - 792.32).abs() < 0.01,
        "{lo} {hi}"
    );

    let earth = read_dem(fixture("earth_mt_st_helens_landslide_10m.asc")).unwrap();
    let g = earth.geometry();
    assert_eq!((g.nrows, g.ncols, g.cell_x), (122, 80, 10.0));
    // The README: 122 NODATA cells (the east column), unknown, never zero.
    assert_eq!(earth.unknown_count(), 122);
    assert!((0..122).all(|r| earth.height(r, 79).is_none()));
    let (lo, hi) = earth.height_range().unwrap();
    assert!(
        (lo - 189.0).abs() < 0.1 && (hi - 582.4).abs() < 0.1,
        "{lo} {hi}"
    );
}

#[test]
fn ascii_edge_case_fixtures() {
    let centre = read_dem(fixture("edge-cases/xllcenter_no_nodata.asc")).unwrap();
    let g = centre.geometry();
    assert_eq!((g.west, g.south(), g.cell_x), (-0.25, 9.75, 0.5));
    assert_eq!(centre.unknown_count(), 0);
    assert_eq!(centre.height(0, 0), Some(-9999.0));
    let wrapped = read_dem(fixture("edge-cases/values_spanning_lines.asc")).unwrap();
    assert_eq!(wrapped.geometry().ncols, 5);
    assert_eq!(wrapped.height(1, 4), Some(10.0));
    assert_eq!(wrapped.height(1, 0), None);
    let err = read_dem(fixture("edge-cases/malformed_value.asc")).unwrap_err();
    let text = err.to_string();
    assert!(
        text.contains("malformed_value.asc") && text.contains("line 8"),
        "{text}"
    );
}

#[test]
fn truncated_and_corrupted_ascii_never_panics() {
    let bytes = std::fs::read(fixture("mars_hirise_dteec_010228_1490_crop.asc")).unwrap();
    let last_token = bytes
        .iter()
        .rposition(|b| !b.is_ascii_whitespace())
        .unwrap();
    let last_start = bytes[..last_token]
        .iter()
        .rposition(|b| b.is_ascii_whitespace())
        .unwrap();
    // Every truncation before the last value starts loses values: an error; after it, the file
    // reads (the last value may be cut short, but it is still a number).
    for cut in (0..bytes.len())
        .step_by(97)
        .chain([last_start, last_token + 1])
    {
        let r = parse_esri_ascii(&bytes[..cut]);
        assert_eq!(r.is_err(), cut <= last_start, "cut at {cut}");
    }
    let mut rng = ChaCha8Rng::seed_from_u64(6);
    for _ in 0..300 {
        let mut b = bytes.clone();
        for _ in 0..rng.random_range(1..8) {
            let i = rng.random_range(0..b.len());
            b[i] = rng.random_range(0..=255u8);
        }
        let _ = parse_esri_ascii(&b);
    }
    let garbage: Vec<u8> = (0..4000).map(|_| rng.random_range(0..=255u8)).collect();
    assert!(parse_esri_ascii(&garbage).is_err());
}

#[test]
fn truncated_and_corrupted_geotiff_never_panics() {
    let bytes = std::fs::read(fixture("mars_hirise_dteec_010228_1490_crop.tif")).unwrap();
    let tiled = tiled_i16(&samples_i16(true), 5, Georef::ScaleTie);
    for file in [&bytes, &tiled] {
        let mut errors = 0;
        let cuts: Vec<usize> = (0..file.len()).step_by(61).collect();
        for &cut in &cuts {
            errors += usize::from(decode_geotiff(Cursor::new(file[..cut].to_vec())).is_err());
        }
        // Every cut loses image data or the directory (both files end with their directory or
        // their data), so every cut is an error.
        assert_eq!(errors, cuts.len());
    }
    let mut rng = ChaCha8Rng::seed_from_u64(6);
    for file in [&bytes, &tiled] {
        for _ in 0..300 {
            let mut b = file.clone();
            for _ in 0..rng.random_range(1..6) {
                // Mostly in the header and directory, where corruption is interesting.
                let span = if rng.random_range(0..2) == 0 {
                    512.min(b.len())
                } else {
                    b.len()
                };
                let i = rng.random_range(0..span);
                b[i] = rng.random_range(0..=255u8);
            }
            let _ = decode_geotiff(Cursor::new(b));
        }
    }
    let garbage: Vec<u8> = (0..2000).map(|_| rng.random_range(0..=255u8)).collect();
    assert!(decode_geotiff(Cursor::new(garbage)).is_err());
}
