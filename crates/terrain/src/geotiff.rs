//! Single-band GeoTIFF DEMs (the raster form of HiRISE DTMs, thesis §2.5.1), decoded by the `tiff`
//! crate: strips or tiles, uncompressed, LZW, Deflate (and the crate's other codecs); samples of any
//! integer or floating type (float32 and int16 are the usual ones).
//!
//! Georeference, from the GeoTIFF tags:
//! - `ModelPixelScale` (33550) gives the cell size `(sx, sy)`, and `ModelTiepoint` (33922) ties
//!   raster point `(i, j)` to model point `(x, y)`; the grid's west edge is `x - i * sx` and its north
//!   edge `y + j * sy`. When the `GTRasterTypeGeoKey` (1025) of the `GeoKeyDirectory` (34735) says
//!   `PixelIsPoint`, raster point `(i, j)` is a cell centre and the edges move out by half a cell.
//! - Without a pixel scale, a `ModelTransformation` (34264) without rotation is accepted.
//! - `GDAL_NODATA` (42113), when present, is the value of unknown cells; NaN samples are unknown too.
//!   Unknown cells stay unknown, never zero.

use std::io::{Read, Seek};

use tiff::ColorType;
use tiff::decoder::{Decoder, DecodingResult};
use tiff::tags::Tag;

use crate::dem::{GridError, GridGeometry, HeightGrid};

/// `GTRasterTypeGeoKey` in the GeoKey directory.
const GT_RASTER_TYPE_GEO_KEY: u16 = 1025;
/// Its value for `RasterPixelIsPoint`.
const RASTER_PIXEL_IS_POINT: u16 = 2;

/// Why a GeoTIFF could not be read as a DEM. Fixes: convert multi-band or rotated rasters with
/// `gdal_translate -b 1` / `gdalwarp` first; add a georeference with `gdal_edit.py -a_ullr`.
#[derive(Debug, thiserror::Error)]
pub enum GeoTiffError {
    /// The TIFF structure or its compressed data is broken (truncated file, bad offsets...), or uses
    /// a feature the decoder does not support.
    #[error("TIFF decoding failed: {0}")]
    Tiff(#[from] tiff::TiffError),
    /// More than one sample per pixel.
    #[error("the image has colour type {what}; a DEM must be a single band")]
    NotSingleBand {
        /// The colour type found.
        what: String,
    },
    /// The decoded data do not cover the image.
    #[error("decoded {found} samples for a {width} x {height} image")]
    SampleCount {
        /// Samples decoded.
        found: usize,
        /// Image width.
        width: u32,
        /// Image height.
        height: u32,
    },
    /// An uncompressed strip holds fewer bytes than its rows need (a short strip: the decoder would
    /// read past it and invent samples).
    #[error(
        "strip {strip} holds {found} bytes; its {rows} rows of {width} samples need {expected}"
    )]
    ShortStrip {
        /// Strip index.
        strip: usize,
        /// Bytes declared in StripByteCounts.
        found: u64,
        /// Bytes the rows need.
        expected: u64,
        /// Rows in the strip.
        rows: u64,
        /// Image width.
        width: u32,
    },
    /// No georeference: the cell size is unknown.
    #[error(
        "no georeference: the file has neither ModelPixelScale (tag 33550) with ModelTiepoint (tag 33922) nor ModelTransformation (tag 34264), so the cell size is unknown"
    )]
    MissingGeoreference,
    /// A georeferencing tag with too few values.
    #[error("tag {tag} has {found} values; at least {expected} are needed")]
    ShortTag {
        /// The tag's name.
        tag: &'static str,
        /// Values present.
        found: usize,
        /// Values needed.
        expected: usize,
    },
    /// A `ModelTransformation` that rotates or shears the grid.
    #[error("the ModelTransformation tag rotates or shears the grid; only north-up grids are read")]
    RotatedGrid,
    /// A `GDAL_NODATA` tag that is not a number.
    #[error("the GDAL_NODATA tag `{text}` is not a number")]
    BadNodata {
        /// The tag's text.
        text: String,
    },
    /// The georeference or the samples make an unusable grid (zero or negative cell size,
    /// infinite heights...).
    #[error("unusable grid: {0}")]
    Grid(#[from] GridError),
}

/// Reads a georeferencing tag as doubles, `None` when absent.
fn f64_tag<R: Read + Seek>(
    dec: &mut Decoder<R>,
    tag: Tag,
    name: &'static str,
    expected: usize,
) -> Result<Option<Vec<f64>>, GeoTiffError> {
    let Some(v) = dec.find_tag(tag)? else {
        return Ok(None);
    };
    let v = v.into_f64_vec()?;
    if v.len() < expected {
        return Err(GeoTiffError::ShortTag {
            tag: name,
            found: v.len(),
            expected,
        });
    }
    Ok(Some(v))
}

/// `true` when the GeoKey directory declares `RasterPixelIsPoint`.
fn pixel_is_point<R: Read + Seek>(dec: &mut Decoder<R>) -> Result<bool, GeoTiffError> {
    let Some(v) = dec.find_tag(Tag::GeoKeyDirectoryTag)? else {
        return Ok(false);
    };
    let keys = v.into_u16_vec()?;
    // Header of 4 shorts, then entries (key id, location, count, value).
    Ok(keys
        .get(4..)
        .unwrap_or(&[])
        .chunks_exact(4)
        .any(|k| k[0] == GT_RASTER_TYPE_GEO_KEY && k[1] == 0 && k[3] == RASTER_PIXEL_IS_POINT))
}

/// The grid's cell size and north-west corner from the georeferencing tags.
fn georeference<R: Read + Seek>(
    dec: &mut Decoder<R>,
) -> Result<(f64, f64, f64, f64), GeoTiffError> {
    let scale = f64_tag(dec, Tag::ModelPixelScaleTag, "ModelPixelScale", 2)?;
    let tie = f64_tag(dec, Tag::ModelTiepointTag, "ModelTiepoint", 6)?;
    match (scale, tie) {
        (Some(s), Some(t)) => {
            let half = if pixel_is_point(dec)? { 0.5 } else { 0.0 };
            let (sx, sy) = (s[0], s[1]);
            Ok((sx, sy, t[3] - (t[0] + half) * sx, t[4] + (t[1] + half) * sy))
        }
        (None, None) | (None, Some(_)) => {
            let Some(m) = f64_tag(dec, Tag::ModelTransformationTag, "ModelTransformation", 16)?
            else {
                return Err(GeoTiffError::MissingGeoreference);
            };
            // x = m0 i + m1 j + m3, y = m4 i + m5 j + m7.
            if m[1] != 0.0 || m[4] != 0.0 {
                return Err(GeoTiffError::RotatedGrid);
            }
            Ok((m[0], -m[5], m[3], m[7]))
        }
        (Some(_), None) => Err(GeoTiffError::MissingGeoreference),
    }
}

/// The `GDAL_NODATA` value, if any.
fn gdal_nodata<R: Read + Seek>(dec: &mut Decoder<R>) -> Result<Option<f64>, GeoTiffError> {
    let Some(v) = dec.find_tag(Tag::GdalNodata)? else {
        return Ok(None);
    };
    let text = v.into_string()?;
    let trimmed = text.trim_matches(|c: char| c == '\0' || c.is_whitespace());
    trimmed
        .parse::<f64>()
        .map(Some)
        .map_err(|_| GeoTiffError::BadNodata {
            text: trimmed.chars().take(40).collect(),
        })
}

/// Refuses uncompressed strips shorter than their rows (compressed strips are checked by the
/// decoder's sample count). Tiled images have no StripByteCounts and pass.
fn check_strips<R: Read + Seek>(
    dec: &mut Decoder<R>,
    width: u32,
    height: u32,
) -> Result<(), GeoTiffError> {
    let compression: u16 = dec.find_tag_unsigned(Tag::Compression)?.unwrap_or(1);
    if compression != 1 {
        return Ok(());
    }
    let Some(counts) = dec.find_tag_unsigned_vec::<u64>(Tag::StripByteCounts)? else {
        return Ok(());
    };
    let rows_per_strip = dec
        .find_tag_unsigned::<u64>(Tag::RowsPerStrip)?
        .unwrap_or(u64::from(height))
        .clamp(1, u64::from(height).max(1));
    let bits: u64 = dec
        .find_tag_unsigned_vec::<u64>(Tag::BitsPerSample)?
        .and_then(|b| b.first().copied())
        .unwrap_or(1);
    let row_bytes = (u64::from(width) * bits).div_ceil(8);
    for (strip, &found) in counts.iter().enumerate() {
        let first = strip as u64 * rows_per_strip;
        let rows = rows_per_strip.min(u64::from(height).saturating_sub(first));
        let expected = rows * row_bytes;
        if found < expected {
            return Err(GeoTiffError::ShortStrip {
                strip,
                found,
                expected,
                rows,
                width,
            });
        }
    }
    Ok(())
}

/// Converts decoded samples to heights, NODATA and NaN to unknown.
fn to_heights(data: DecodingResult, nodata: Option<f64>) -> Vec<f64> {
    fn conv<T: Copy>(v: Vec<T>, f: impl Fn(T) -> f64, nodata: Option<f64>) -> Vec<f64> {
        v.into_iter()
            .map(|x| {
                let h = f(x);
                if Some(h) == nodata { f64::NAN } else { h }
            })
            .collect()
    }
    // Compare float32 samples with the NODATA value rounded to float32, as GDAL writes it.
    let nodata32 = nodata.map(|v| f64::from(v as f32));
    match data {
        DecodingResult::U8(v) => conv(v, f64::from, nodata),
        DecodingResult::U16(v) => conv(v, f64::from, nodata),
        DecodingResult::U32(v) => conv(v, f64::from, nodata),
        DecodingResult::U64(v) => conv(v, |x| x as f64, nodata),
        DecodingResult::I8(v) => conv(v, f64::from, nodata),
        DecodingResult::I16(v) => conv(v, f64::from, nodata),
        DecodingResult::I32(v) => conv(v, f64::from, nodata),
        DecodingResult::I64(v) => conv(v, |x| x as f64, nodata),
        DecodingResult::F16(v) => conv(v, |x| x.to_f64(), nodata32),
        DecodingResult::F32(v) => conv(v, f64::from, nodata32),
        DecodingResult::F64(v) => conv(v, |x| x, nodata),
    }
}

/// Decodes a single-band GeoTIFF DEM from any seekable reader (see the module docs).
///
/// ```
/// use rappel_terrain::geotiff::decode_geotiff;
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/terrain/mars_hirise_dteec_010228_1490_crop.tif");
/// let dem = decode_geotiff(std::fs::File::open(path).unwrap()).unwrap();
/// assert_eq!((dem.geometry().nrows, dem.geometry().ncols), (120, 70));
/// assert!((dem.geometry().cell_x - 1.01).abs() < 1e-12);
/// assert!(decode_geotiff(std::io::Cursor::new(b"II*\0garbage".to_vec())).is_err());
/// ```
pub fn decode_geotiff<R: Read + Seek>(reader: R) -> Result<HeightGrid, GeoTiffError> {
    let mut dec = Decoder::new(reader)?;
    let (width, height) = dec.dimensions()?;
    match dec.colortype()? {
        ColorType::Gray(_) | ColorType::Multiband { num_samples: 1, .. } => {}
        other => {
            return Err(GeoTiffError::NotSingleBand {
                what: format!("{other:?}"),
            });
        }
    }
    let (cell_x, cell_y, west, north) = georeference(&mut dec)?;
    let geometry = GridGeometry::new(height as usize, width as usize, cell_x, cell_y, west, north)?;
    let nodata = gdal_nodata(&mut dec)?;
    check_strips(&mut dec, width, height)?;
    let heights = to_heights(dec.read_image()?, nodata);
    if heights.len() != geometry.len() {
        return Err(GeoTiffError::SampleCount {
            found: heights.len(),
            width,
            height,
        });
    }
    Ok(HeightGrid::new(geometry, heights)?)
}
