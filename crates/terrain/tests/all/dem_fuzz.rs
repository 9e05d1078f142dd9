//! The DEM readers' fuzz harness (issue 9): seeded byte flips, truncations and overflowing values
//! in the shipped ESRI ASCII and GeoTIFF fixtures, each decoded and, when it decodes, ingested.
//! Every outcome must be a typed error or a result, with no panic, in bounded time; a spike far
//! beyond the grid's extent is refused as implausible relief.

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rappel_terrain::esri_ascii::parse_esri_ascii;
use rappel_terrain::geotiff::decode_geotiff;
use rappel_terrain::grid::{GridGeometry, HeightGrid};
use rappel_terrain::ingest::{IngestError, IngestOptions, ingest};
use std::io::Cursor;
use std::time::{Duration, Instant};

/// Generous wall-clock bound per mutated input (debug build, shared cores); the defects this
/// harness guards against ran for minutes.
const BOUND: Duration = Duration::from_secs(30);

fn fixture(name: &str) -> Vec<u8> {
    std::fs::read(format!(
        "{}/../../fixtures/terrain/{name}",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap()
}

/// Decodes then ingests; returns whether it ended in an error, after checking the time bound.
fn outcome(what: &str, decoded: Option<HeightGrid>, start: Instant) -> bool {
    let ok = match decoded {
        None => false,
        Some(grid) => ingest(&grid, &IngestOptions::default()).is_ok(),
    };
    let took = start.elapsed();
    assert!(took < BOUND, "{what}: took {took:?}");
    ok
}

fn mutate(bytes: &[u8], rng: &mut ChaCha8Rng) -> (String, Vec<u8>) {
    let mut b = bytes.to_vec();
    match rng.random_range(0..3u8) {
        0 => {
            let i = rng.random_range(0..b.len());
            let bit = rng.random_range(0..8u8);
            b[i] ^= 1 << bit;
            (format!("bit {bit} of byte {i} flipped"), b)
        }
        1 => {
            let n = rng.random_range(0..b.len());
            b.truncate(n);
            (format!("truncated to {n} bytes"), b)
        }
        _ => {
            let i = rng.random_range(0..b.len());
            b[i] = 0xff;
            (format!("byte {i} set to 0xff"), b)
        }
    }
}

#[test]
fn mutated_geotiffs_end_in_a_result_or_a_typed_error() {
    let tif = fixture("mars_hirise_dteec_010228_1490_crop.tif");
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    for _ in 0..24 {
        let (what, b) = mutate(&tif, &mut rng);
        let t = Instant::now();
        outcome(&what, decode_geotiff(Cursor::new(b)).ok(), t);
    }
}

#[test]
fn mutated_ascii_grids_end_in_a_result_or_a_typed_error() {
    let asc = fixture("mars_hirise_dteec_010228_1490_crop.asc");
    let mut rng = ChaCha8Rng::seed_from_u64(13);
    for _ in 0..24 {
        let (what, b) = mutate(&asc, &mut rng);
        let t = Instant::now();
        outcome(&what, parse_esri_ascii(&b).ok(), t);
    }
}

#[test]
fn a_spike_far_beyond_the_extent_is_implausible_relief() {
    let g = GridGeometry::new(10, 12, 1.0, 1.0, 0.0, 10.0).unwrap();
    for spike in [1e12, -1e12, 1e300, 5e3] {
        let mut v: Vec<f64> = (0..120).map(|i| (i / 12) as f64 * 0.5).collect();
        v[40] = spike;
        let t = Instant::now();
        let r = ingest(&HeightGrid::new(g, v).unwrap(), &IngestOptions::default());
        assert!(t.elapsed() < BOUND);
        // The grid's diagonal is about 15.6 m: 100 times that is 1.56 km.
        assert!(
            matches!(
                r,
                Err(IngestError::ImplausibleRelief { row: 3, col: 4, .. })
            ),
            "{spike}: {r:?}"
        );
    }
    // 1 km of relief over the same grid is steep but plausible: not refused for relief.
    let mut v: Vec<f64> = (0..120).map(|i| (i / 12) as f64 * 0.5).collect();
    v[40] = 1e3;
    let r = ingest(&HeightGrid::new(g, v).unwrap(), &IngestOptions::default());
    assert!(!matches!(r, Err(IngestError::ImplausibleRelief { .. })));
}

/// An uncompressed float32 GeoTIFF of 8 x 6 cells in one strip, with its StripByteCounts entry
/// patched to `count` bytes.
fn one_strip_tiff(count: Option<u32>) -> Vec<u8> {
    use tiff::encoder::{TiffEncoder, colortype};
    use tiff::tags::Tag;
    let data: Vec<f32> = (0..48).map(|i| i as f32 * 0.1).collect();
    let mut bytes = Vec::new();
    {
        let mut tiff = TiffEncoder::new(Cursor::new(&mut bytes)).unwrap();
        let mut image = tiff.new_image::<colortype::Gray32Float>(8, 6).unwrap();
        image.rows_per_strip(6).unwrap();
        let enc = image.encoder();
        enc.write_tag(Tag::ModelPixelScaleTag, &[1.0f64, 1.0, 0.0][..])
            .unwrap();
        enc.write_tag(
            Tag::ModelTiepointTag,
            &[0.0f64, 0.0, 0.0, 0.0, 6.0, 0.0][..],
        )
        .unwrap();
        image.write_data(&data).unwrap();
    }
    if let Some(count) = count {
        // Little-endian classic TIFF: IFD offset at byte 4, 12-byte entries after a u16 count.
        assert_eq!(&bytes[..2], b"II");
        let ifd = u32::from_le_bytes(bytes[4..8].try_into().unwrap()) as usize;
        let n = u16::from_le_bytes(bytes[ifd..ifd + 2].try_into().unwrap()) as usize;
        let entry = (0..n)
            .map(|k| ifd + 2 + 12 * k)
            .find(|&e| u16::from_le_bytes(bytes[e..e + 2].try_into().unwrap()) == 279)
            .expect("StripByteCounts");
        let ty = u16::from_le_bytes(bytes[entry + 2..entry + 4].try_into().unwrap());
        match ty {
            3 => bytes[entry + 8..entry + 10].copy_from_slice(&(count as u16).to_le_bytes()),
            _ => bytes[entry + 8..entry + 12].copy_from_slice(&count.to_le_bytes()),
        }
    }
    bytes
}

#[test]
fn a_short_strip_is_refused() {
    use rappel_terrain::geotiff::GeoTiffError;
    let grid = decode_geotiff(Cursor::new(one_strip_tiff(None))).expect("the intact file reads");
    assert_eq!(grid.heights().len(), 48);
    // 48 float32 samples need 192 bytes; the strip declares 100.
    let r = decode_geotiff(Cursor::new(one_strip_tiff(Some(100))));
    assert!(
        matches!(
            r,
            Err(GeoTiffError::ShortStrip {
                strip: 0,
                found: 100,
                expected: 192,
                ..
            })
        ),
        "{r:?}"
    );
}

/// A tiled Deflate float32 GeoTIFF declaring `width` x `height` cells in tiles of `t` x `t`, the
/// directory written by hand, with one stored block: 256 x 256 zeros, compressed. With `shared`,
/// every tile points at that block (a few kilobytes declaring gigabytes); otherwise only the first
/// tile does and the rest point past the end of the file.
fn bomb_tiff(width: u32, height: u32, t: u32, shared: bool) -> Vec<u8> {
    use tiff::encoder::compression::{CompressionAlgorithm, Deflate};
    use tiff::encoder::{DeflateLevel, TiffEncoder};
    use tiff::tags::Tag;
    const T: u32 = 256;
    let tiles = (width.div_ceil(t) * height.div_ceil(t)) as usize;
    let zeros = vec![0u8; (T * T * 4) as usize];
    let mut packed = Vec::new();
    Deflate::with_level(DeflateLevel::Best)
        .write_to(&mut packed, &zeros[..])
        .unwrap();
    let mut bytes = Vec::new();
    {
        let mut tiff = TiffEncoder::new(Cursor::new(&mut bytes)).unwrap();
        let mut dir = tiff.image_directory().unwrap();
        let at = dir.write_data(&packed[..]).unwrap() as u32;
        let offsets: Vec<u32> = (0..tiles)
            .map(|k| if shared || k == 0 { at } else { 1 << 30 })
            .collect();
        let counts = vec![packed.len() as u32; tiles];
        dir.write_tag(Tag::ImageWidth, width).unwrap();
        dir.write_tag(Tag::ImageLength, height).unwrap();
        dir.write_tag(Tag::BitsPerSample, 32u16).unwrap();
        dir.write_tag(Tag::SampleFormat, 3u16).unwrap();
        dir.write_tag(Tag::SamplesPerPixel, 1u16).unwrap();
        dir.write_tag(Tag::PhotometricInterpretation, 1u16).unwrap();
        dir.write_tag(Tag::Compression, 8u16).unwrap();
        dir.write_tag(Tag::TileWidth, t).unwrap();
        dir.write_tag(Tag::TileLength, t).unwrap();
        dir.write_tag(Tag::TileOffsets, &offsets[..]).unwrap();
        dir.write_tag(Tag::TileByteCounts, &counts[..]).unwrap();
        dir.write_tag(Tag::ModelPixelScaleTag, &[1.0f64, 1.0, 0.0][..])
            .unwrap();
        dir.write_tag(
            Tag::ModelTiepointTag,
            &[0.0f64, 0.0, 0.0, 0.0, f64::from(height), 0.0][..],
        )
        .unwrap();
        dir.finish().unwrap();
    }
    bytes
}

#[test]
fn a_small_file_declaring_a_huge_raster_is_refused_before_allocating() {
    use rappel_terrain::geotiff::{GeoTiffError, decode_geotiff_with};
    use rappel_terrain::grid::{DemLimits, GridError, MAX_CELLS};
    let start = Instant::now();
    // 11,000 x 12,000 cells (the case): over the default work cap.
    let bomb = bomb_tiff(11_000, 12_000, 256, true);
    assert!(bomb.len() < 200_000, "{} bytes", bomb.len());
    let r = decode_geotiff(Cursor::new(bomb.clone()));
    assert!(
        matches!(
            r,
            Err(GeoTiffError::Grid(GridError::OverWorkCap {
                nrows: 12_000,
                ncols: 11_000,
                ..
            }))
        ),
        "{r:?}"
    );
    // With the cap raised to its ceiling, the shared blocks are found instead.
    let all = DemLimits::with_max_cells(MAX_CELLS).unwrap();
    let r = decode_geotiff_with(Cursor::new(bomb), &all);
    assert!(
        matches!(r, Err(GeoTiffError::OverlappingBlocks { kind: "tile", .. })),
        "{r:?}"
    );
    // Tiles declared beyond the end of the file.
    let r = decode_geotiff_with(Cursor::new(bomb_tiff(11_000, 12_000, 256, false)), &all);
    assert!(
        matches!(
            r,
            Err(GeoTiffError::OutsideFile {
                kind: "tile",
                index: 1,
                ..
            })
        ),
        "{r:?}"
    );
    // One tile of 2,048 x 2,048 whose block holds a few hundred bytes: even at Deflate's largest
    // ratio it cannot expand to the 16 MB raster declared.
    let r = decode_geotiff_with(Cursor::new(bomb_tiff(2_000, 2_000, 2_048, true)), &all);
    assert!(
        matches!(
            r,
            Err(GeoTiffError::ImplausibleCompression {
                compression: 8,
                declared: 16_000_000,
                ratio: 1032,
                ..
            })
        ),
        "{r:?}"
    );
    let took = start.elapsed();
    assert!(took < Duration::from_secs(5), "took {took:?}");
}
