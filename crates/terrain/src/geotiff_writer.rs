//! GeoTIFFs of results in a DEM's grid and coordinate reference system (issue 34), so a GIS drapes
//! them over the DEM: float32 bands (one or two, pixel-interleaved), uncompressed strips,
//! `ModelPixelScale` + `ModelTiepoint` at the grid's north-west corner (`RasterPixelIsArea`),
//! `GDAL_NODATA`, and the CRS as GeoKeys ([`crate::crs`]):
//! - `EPSG:n` as its code; a WKT 1 `PROJCS`, `GEOGCS` or `LOCAL_CS` that [`Crs::to_geokeys`]
//!   writes, as the full user-defined keys (what GDAL writes for a Mars equirectangular);
//! - any other WKT (WKT 2, a projection not in [`crate::crs::PROJECTIONS`]) as a citation, with
//!   the WKT in a GDAL PAM sidecar `<file>.aux.xml` (`<PAMDataset><SRS>`), which GDAL and QGIS
//!   read before the file's own keys;
//! - no CRS: a local engineering grid in metres (`LOCAL_CS`), named so.
//!
//! The image is built in memory ([`GeoTiffImage`]); the caller writes the file and the sidecar.

use std::io::Cursor;

use tiff::encoder::{TiffEncoder, colortype};
use tiff::tags::{PhotometricInterpretation, SampleFormat, Tag};

use crate::crs::{Crs, CrsError, GeoKeyDirectory, GeoKeyValue, UNKNOWN_CRS_NAME, key};
use crate::grid::GridGeometry;

/// A GeoTIFF built in memory, with what it says about its CRS.
#[derive(Debug, Clone, PartialEq)]
pub struct GeoTiffImage {
    /// The `.tif` file's bytes.
    pub bytes: Vec<u8>,
    /// The PAM sidecar (`<file>.aux.xml`) holding the WKT, when the keys could not hold it.
    pub aux_xml: Option<String>,
    /// The CRS written, in one line (`EPSG:32610`, `PROJCS "Mars ..."`, or the local grid's name).
    pub crs_written: String,
}

/// Why a GeoTIFF could not be built.
#[derive(Debug, thiserror::Error)]
pub enum GeoTiffWriteError {
    /// A band's length is not the grid's cell count, or the band count is not 1 or 2.
    #[error("{0}")]
    Shape(String),
    /// The encoder failed.
    #[error("TIFF encoding failed: {0}")]
    Tiff(#[from] tiff::TiffError),
    /// The CRS could not be written.
    #[error(transparent)]
    Crs(#[from] CrsError),
}

/// Two float32 samples per pixel (`BlackIsZero` with one extra sample): a two-band raster.
struct TwoBandFloat;

impl colortype::ColorType for TwoBandFloat {
    type Inner = f32;
    const TIFF_VALUE: PhotometricInterpretation = PhotometricInterpretation::BlackIsZero;
    const BITS_PER_SAMPLE: &'static [u16] = &[32, 32];
    const SAMPLE_FORMAT: &'static [SampleFormat] = &[SampleFormat::IEEEFP, SampleFormat::IEEEFP];

    fn horizontal_predict(row: &[f32], result: &mut Vec<f32>) {
        // No predictor is ever asked of these images; copying keeps the samples unchanged.
        result.extend_from_slice(row);
    }
}

/// Builds a GeoTIFF of `bands` (row-major from the north-west cell, one value per cell of
/// `grid`; NaN or `nodata` for no value) with `crs` (module docs).
///
/// ```
/// use rappel_terrain::crs::Crs;
/// use rappel_terrain::geotiff_writer::geotiff_image;
/// use rappel_terrain::grid::GridGeometry;
/// let g = GridGeometry::new(2, 3, 10.0, 10.0, 562_000.0, 5_121_220.0).unwrap();
/// let band = [1.0f32, 2.0, f32::NAN, 4.0, 5.0, 6.0];
/// let img = geotiff_image(&g, &[&band], -9999.0, Some(&Crs::Epsg(32610))).unwrap();
/// assert_eq!(img.crs_written, "EPSG:32610");
/// assert!(img.aux_xml.is_none());
/// // It reads back as a DEM in the same grid, the NaN cell unknown.
/// let back = rappel_terrain::geotiff::decode_geotiff(std::io::Cursor::new(img.bytes)).unwrap();
/// assert_eq!(back.geometry(), &g);
/// assert_eq!(back.height(1, 0), Some(4.0));
/// assert_eq!(back.height(0, 2), None);
/// ```
pub fn geotiff_image(
    grid: &GridGeometry,
    bands: &[&[f32]],
    nodata: f32,
    crs: Option<&Crs>,
) -> Result<GeoTiffImage, GeoTiffWriteError> {
    let n = grid.len();
    if !(1..=2).contains(&bands.len()) || bands.iter().any(|b| b.len() != n) {
        return Err(GeoTiffWriteError::Shape(format!(
            "{} bands of lengths {:?} for a grid of {n} cells; 1 or 2 bands of {n} are written",
            bands.len(),
            bands.iter().map(|b| b.len()).collect::<Vec<_>>()
        )));
    }
    let (keys, aux_xml, crs_written) = match crs {
        None => (
            Crs::local(UNKNOWN_CRS_NAME).to_geokeys()?,
            None,
            UNKNOWN_CRS_NAME.to_string(),
        ),
        Some(c) => match c.to_geokeys() {
            Ok(k) => (k, None, c.describe()),
            Err(_) => {
                let keys = GeoKeyDirectory {
                    keys: vec![
                        (
                            key::MODEL_TYPE,
                            GeoKeyValue::Short(crate::crs::USER_DEFINED),
                        ),
                        (key::RASTER_TYPE, GeoKeyValue::Short(1)),
                        (key::CITATION, GeoKeyValue::Ascii(c.describe())),
                    ],
                };
                (keys, Some(pam_sidecar(&c.to_string())), c.describe())
            }
        },
    };
    let (dir, doubles, ascii) = keys.encode();
    let (w, h) = (
        u32::try_from(grid.ncols).map_err(|_| GeoTiffWriteError::Shape("too wide".into()))?,
        u32::try_from(grid.nrows).map_err(|_| GeoTiffWriteError::Shape("too tall".into()))?,
    );
    let clean = |v: f32| if v.is_nan() { nodata } else { v };
    let mut bytes = Vec::new();
    {
        let mut tiff = TiffEncoder::new(Cursor::new(&mut bytes))?;
        let tags = |enc: &mut tiff::encoder::DirectoryEncoder<'_, _, _>| -> tiff::TiffResult<()> {
            enc.write_tag(
                Tag::ModelPixelScaleTag,
                &[grid.cell_x, grid.cell_y, 0.0][..],
            )?;
            enc.write_tag(
                Tag::ModelTiepointTag,
                &[0.0, 0.0, 0.0, grid.west, grid.north, 0.0][..],
            )?;
            enc.write_tag(Tag::GeoKeyDirectoryTag, &dir[..])?;
            if !doubles.is_empty() {
                enc.write_tag(Tag::GeoDoubleParamsTag, &doubles[..])?;
            }
            if !ascii.is_empty() {
                enc.write_tag(Tag::GeoAsciiParamsTag, ascii.as_str())?;
            }
            enc.write_tag(Tag::GdalNodata, format!("{nodata}").as_str())?;
            Ok(())
        };
        if let [band] = bands {
            let mut image = tiff.new_image::<colortype::Gray32Float>(w, h)?;
            tags(image.encoder())?;
            let data: Vec<f32> = band.iter().map(|&v| clean(v)).collect();
            image.write_data(&data)?;
        } else {
            let mut image = tiff.new_image::<TwoBandFloat>(w, h)?;
            tags(image.encoder())?;
            // ExtraSamples = [0]: the second sample is an unspecified band, not alpha.
            image.encoder().write_tag(Tag::ExtraSamples, &[0u16][..])?;
            let data: Vec<f32> = (0..n)
                .flat_map(|i| [clean(bands[0][i]), clean(bands[1][i])])
                .collect();
            image.write_data(&data)?;
        }
    }
    Ok(GeoTiffImage {
        bytes,
        aux_xml,
        crs_written,
    })
}

/// GDAL's PAM sidecar holding a WKT.
fn pam_sidecar(wkt: &str) -> String {
    let escaped = wkt
        .replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;");
    format!("<PAMDataset>\n  <SRS>{escaped}</SRS>\n</PAMDataset>\n")
}
