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
//!
//! Before any sample is allocated, the declared raster is checked against the work cap of
//! [`DemLimits`] and against the file itself: every strip or tile inside the file, no blocks
//! sharing bytes, uncompressed strips holding all their rows, and compressed data able to expand
//! to the declared raster at the codec's largest ratio. So a corrupt or hostile file costs at most
//! a few times its own size (or the cap) before it is refused.

use std::io::{Read, Seek, SeekFrom};

use tiff::ColorType;
use tiff::decoder::{Decoder, DecodingResult};
use tiff::tags::Tag;

use crate::crs::{Crs, CrsError, GeoKeyDirectory};
use crate::grid::{DemLimits, GridError, GridGeometry, HeightGrid};

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
    /// A strip or tile whose declared bytes lie (partly) beyond the end of the file.
    #[error(
        "{kind} {index} is declared at bytes {offset} .. {offset} + {count}, beyond the file's {file_len} bytes (a truncated or corrupt file)"
    )]
    OutsideFile {
        /// `strip` or `tile`.
        kind: &'static str,
        /// Its index.
        index: usize,
        /// Its declared offset.
        offset: u64,
        /// Its declared byte count.
        count: u64,
        /// The file's length.
        file_len: u64,
    },
    /// Strips or tiles declaring more bytes in all than the file has: blocks share or overlap
    /// their bytes (one small compressed block repeated to declare a huge raster).
    #[error(
        "the {kind}s declare {total} bytes in all, more than the file's {file_len}: blocks overlap (a corrupt or hostile file)"
    )]
    OverlappingBlocks {
        /// `strip` or `tile`.
        kind: &'static str,
        /// Bytes declared by all blocks.
        total: u64,
        /// The file's length.
        file_len: u64,
    },
    /// Compressed data too small to expand to the raster the header declares, even at the codec's
    /// largest possible ratio.
    #[error(
        "{compressed} compressed bytes (compression {compression}) cannot hold the {declared} bytes the header declares (at most {ratio}:1); the file is corrupt or hostile"
    )]
    ImplausibleCompression {
        /// The TIFF compression code.
        compression: u16,
        /// The strips' or tiles' declared bytes, summed.
        compressed: u64,
        /// Bytes of the raster as declared (width x height x bytes per sample).
        declared: u64,
        /// The codec's largest expansion ratio.
        ratio: u64,
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
    /// GeoKeys that are malformed or declare a system this reader does not honour.
    #[error("coordinate reference system: {0}")]
    Crs(#[from] CrsError),
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

/// The GeoTIFF's whole GeoKey directory ([`crate::crs`]), `None` when it has none.
fn geokeys<R: Read + Seek>(dec: &mut Decoder<R>) -> Result<Option<GeoKeyDirectory>, GeoTiffError> {
    let Some(v) = dec.find_tag(Tag::GeoKeyDirectoryTag)? else {
        return Ok(None);
    };
    let dir = v.into_u16_vec()?;
    let doubles = match dec.find_tag(Tag::GeoDoubleParamsTag)? {
        Some(v) => v.into_f64_vec()?,
        None => Vec::new(),
    };
    let ascii = match dec.find_tag(Tag::GeoAsciiParamsTag)? {
        Some(v) => v.into_string()?,
        None => String::new(),
    };
    Ok(Some(GeoKeyDirectory::parse(&dir, &doubles, &ascii)?))
}

/// The coordinate reference system a GeoTIFF declares in its GeoKeys ([`crate::crs`]):
/// `EPSG:n` for a system with an EPSG code, else the WKT its keys define (user-defined projected
/// or geographic systems such as a Mars equirectangular, engineering grids); `None` when it
/// declares none.
///
/// ```
/// use rappel_terrain::geotiff::geotiff_crs;
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/terrain/mars_hirise_dteec_010228_1490_crop.tif");
/// // The shipped crop is a projected model with metres and no projection: a local grid.
/// let crs = geotiff_crs(std::fs::File::open(path).unwrap()).unwrap().unwrap();
/// assert!(crs.to_string().starts_with("LOCAL_CS[\"unnamed\""), "{crs}");
/// ```
pub fn geotiff_crs<R: Read + Seek>(reader: R) -> Result<Option<Crs>, GeoTiffError> {
    geotiff_crs_and_ignored(reader).map(|(crs, _)| crs)
}

/// [`geotiff_crs`] with the GeoKeys present that it does not use, one message each
/// ([`crate::crs::GeoKeyDirectory::ignored_keys`]: vertical CRS keys, projection parameters the
/// system does not take, a linear unit other than the metre).
///
/// ```
/// use rappel_terrain::geotiff::geotiff_crs_and_ignored;
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/terrain/earth_mt_st_helens_utm10n.tif");
/// let (crs, ignored) = geotiff_crs_and_ignored(std::fs::File::open(path).unwrap()).unwrap();
/// assert_eq!(crs.unwrap().to_string(), "EPSG:32610");
/// assert!(ignored.is_empty(), "{ignored:?}");
/// ```
pub fn geotiff_crs_and_ignored<R: Read + Seek>(
    reader: R,
) -> Result<(Option<Crs>, Vec<String>), GeoTiffError> {
    let mut dec = Decoder::new(reader)?;
    match geokeys(&mut dec)? {
        Some(keys) => Ok((keys.to_crs()?, keys.ignored_keys())),
        None => Ok((None, Vec::new())),
    }
}

/// `true` when the GeoKey directory declares `RasterPixelIsPoint`.
fn pixel_is_point<R: Read + Seek>(dec: &mut Decoder<R>) -> Result<bool, GeoTiffError> {
    Ok(geokeys(dec)?.is_some_and(|k| k.pixel_is_point()))
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

/// The most bytes one compressed byte can expand to, per TIFF compression code, from the codecs'
/// definitions: Deflate (8 and the old 32946) at most 1032:1 (a maximal-length match of 258
/// bytes coded in at least 2 bits); LZW (5) at most 4096 bytes from one 12-bit code, so 2731:1;
/// PackBits (32773) at most 128 bytes from a 2-byte run. Other codecs (ZSTD, JPEG...) have no
/// bound here and are limited only by the work cap.
fn max_expansion(compression: u16) -> Option<u64> {
    match compression {
        8 | 32946 => Some(1032),
        5 => Some(2731),
        32773 => Some(64),
        _ => None,
    }
}

/// Checks the declared layout against the file before anything is decoded: every strip or tile
/// lies inside the file and together they fit in it (no shared or overlapping blocks); uncompressed strips hold all their rows (a short strip would make the
/// decoder invent samples); and compressed data could expand to the raster they declare (a
/// few kilobytes declaring gigabytes are refused). `file_len` is the file's length in bytes.
fn check_declared_sizes<R: Read + Seek>(
    dec: &mut Decoder<R>,
    file_len: u64,
    width: u32,
    height: u32,
) -> Result<(), GeoTiffError> {
    let compression: u16 = dec.find_tag_unsigned(Tag::Compression)?.unwrap_or(1);
    let bits: u64 = dec
        .find_tag_unsigned_vec::<u64>(Tag::BitsPerSample)?
        .and_then(|b| b.first().copied())
        .unwrap_or(1);
    let (kind, offsets, counts) = match dec.find_tag_unsigned_vec::<u64>(Tag::TileOffsets)? {
        Some(offsets) => (
            "tile",
            offsets,
            dec.find_tag_unsigned_vec::<u64>(Tag::TileByteCounts)?
                .unwrap_or_default(),
        ),
        None => (
            "strip",
            dec.find_tag_unsigned_vec::<u64>(Tag::StripOffsets)?
                .unwrap_or_default(),
            dec.find_tag_unsigned_vec::<u64>(Tag::StripByteCounts)?
                .unwrap_or_default(),
        ),
    };
    for (index, (&offset, &count)) in offsets.iter().zip(&counts).enumerate() {
        if offset.checked_add(count).is_none_or(|end| end > file_len) {
            return Err(GeoTiffError::OutsideFile {
                kind,
                index,
                offset,
                count,
                file_len,
            });
        }
    }
    let total: u64 = counts.iter().fold(0u64, |a, &c| a.saturating_add(c));
    if total > file_len {
        return Err(GeoTiffError::OverlappingBlocks {
            kind,
            total,
            file_len,
        });
    }
    let raster_bytes = (u64::from(width) * bits).div_ceil(8) * u64::from(height);
    if compression == 1 && kind == "strip" {
        let rows_per_strip = dec
            .find_tag_unsigned::<u64>(Tag::RowsPerStrip)?
            .unwrap_or(u64::from(height))
            .clamp(1, u64::from(height).max(1));
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
    } else if let Some(ratio) = max_expansion(compression)
        && total.saturating_mul(ratio) < raster_bytes
    {
        return Err(GeoTiffError::ImplausibleCompression {
            compression,
            compressed: total,
            declared: raster_bytes,
            ratio,
        });
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
    decode_geotiff_with(reader, &DemLimits::default())
}

/// [`decode_geotiff`] under explicit [`DemLimits`]: the declared raster is checked against the
/// work cap and against the file (strips and tiles inside it, compressed data able to expand to
/// the declared size) before the samples are allocated.
///
/// ```
/// use rappel_terrain::grid::DemLimits;
/// use rappel_terrain::geotiff::decode_geotiff_with;
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/terrain/mars_hirise_dteec_010228_1490_crop.tif");
/// let bytes = std::fs::read(path).unwrap();
/// let cap = DemLimits::with_max_cells(1_000).unwrap();
/// let err = decode_geotiff_with(std::io::Cursor::new(bytes), &cap).unwrap_err();
/// assert!(err.to_string().contains("work cap of 1000 cells"));
/// ```
pub fn decode_geotiff_with<R: Read + Seek>(
    mut reader: R,
    limits: &DemLimits,
) -> Result<HeightGrid, GeoTiffError> {
    let file_len = reader
        .seek(SeekFrom::End(0))
        .and_then(|n| reader.seek(SeekFrom::Start(0)).map(|_| n))
        .map_err(|e| GeoTiffError::Tiff(tiff::TiffError::IoError(e)))?;
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
    limits.check(&geometry)?;
    let nodata = gdal_nodata(&mut dec)?;
    check_declared_sizes(&mut dec, file_len, width, height)?;
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
