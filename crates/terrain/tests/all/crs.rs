//! The coordinate reference system a DEM declares: GeoTIFF GeoKeys (an EPSG code, or a
//! user-defined system's citation) and an ESRI grid's `.prj` file.

use rappel_terrain::dem::dem_crs;
use std::io::Cursor;
use tiff::encoder::{TiffEncoder, colortype};
use tiff::tags::Tag;

/// A 4 x 3 float32 GeoTIFF with the given GeoKey entries (after the header) and ASCII params.
fn tiff_with_keys(entries: &[[u16; 4]], ascii: Option<&str>) -> Vec<u8> {
    let mut keys = vec![1u16, 1, 0, entries.len() as u16];
    for e in entries {
        keys.extend_from_slice(e);
    }
    let mut bytes = Vec::new();
    {
        let mut tiff = TiffEncoder::new(Cursor::new(&mut bytes)).expect("encoder");
        let mut image = tiff
            .new_image::<colortype::Gray32Float>(4, 3)
            .expect("image");
        let enc = image.encoder();
        enc.write_tag(Tag::ModelPixelScaleTag, &[1.0f64, 1.0, 0.0][..])
            .expect("scale");
        enc.write_tag(
            Tag::ModelTiepointTag,
            &[0.0f64, 0.0, 0.0, 0.0, 3.0, 0.0][..],
        )
        .expect("tie");
        enc.write_tag(Tag::GeoKeyDirectoryTag, &keys[..])
            .expect("keys");
        if let Some(a) = ascii {
            enc.write_tag(Tag::GeoAsciiParamsTag, a).expect("ascii");
        }
        image.write_data(&[0.0f32; 12]).expect("data");
    }
    bytes
}

#[test]
fn geotiff_keys_and_prj_files_name_the_crs() {
    let dir = std::env::temp_dir().join(format!("rappel-crs-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let write = |name: &str, bytes: &[u8]| {
        let p = dir.join(name);
        std::fs::write(&p, bytes).expect("write");
        p
    };
    // ProjectedCSTypeGeoKey = 32611 (UTM 11N).
    let utm = write("utm.tif", &tiff_with_keys(&[[3072, 0, 1, 32611]], None));
    assert_eq!(dem_crs(&utm).expect("reads").as_deref(), Some("EPSG:32611"));
    // User-defined with a citation in GeoAsciiParams (offset 0, 21 characters with the `|`).
    let mars = write(
        "mars.tif",
        &tiff_with_keys(
            &[[3072, 0, 1, 32767], [1026, 34737, 21, 0]],
            Some("Equirectangular MARS|"),
        ),
    );
    assert_eq!(
        dem_crs(&mars).expect("reads").as_deref(),
        Some("Equirectangular MARS")
    );
    // No keys at all.
    let none = write("none.tif", &tiff_with_keys(&[], None));
    assert_eq!(dem_crs(&none).expect("reads"), None);
    // An ESRI grid with a .prj beside it.
    let asc = write(
        "g.asc",
        b"ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2\n3 4\n",
    );
    assert_eq!(dem_crs(&asc).expect("reads"), None);
    write("g.prj", b"PROJCS[\"WGS 84 / UTM zone 10N\"]\n");
    assert_eq!(
        dem_crs(&asc).expect("reads").as_deref(),
        Some("PROJCS[\"WGS 84 / UTM zone 10N\"]")
    );
    let _ = std::fs::remove_dir_all(&dir);
}
