//! The coordinate reference system a DEM declares: GeoTIFF GeoKeys (an EPSG code, or the WKT a
//! user-defined system's keys define) and an ESRI grid's `.prj` file; WKT back to GeoKeys. GDAL's
//! own reading of the shipped fixtures is checked in the CLI's `gdal` tests.

use rappel_terrain::crs::{Crs, CrsError, GeoKeyDirectory, GeoKeyValue, key};
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
    // A user-defined system with a name and nothing else: a local grid of that name.
    assert!(
        dem_crs(&mars)
            .expect("reads")
            .is_some_and(|c| c.starts_with("LOCAL_CS[\"Equirectangular MARS\"")),
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

/// The shipped Mars fixture made by GDAL (`fixtures/terrain/README.md`): its keys give the
/// projection GDAL was given, parameter by parameter, and the WKT goes back to the same keys.
#[test]
fn gdal_written_mars_equirectangular_keys_give_its_wkt_and_back() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../fixtures/terrain/mars_equirectangular_crop.tif"
    );
    let crs = dem_crs(path.as_ref()).expect("reads").expect("a CRS");
    for part in [
        "PROJCS[\"Mars 2000 Equirectangular, clon 180, lat_ts -30\"",
        "SPHEROID[\"Mars_2000_Sphere_IAU_IAG\",3396190,0]",
        "PROJECTION[\"Equirectangular\"]",
        "PARAMETER[\"central_meridian\",180]",
        "PARAMETER[\"standard_parallel_1\",-30]",
        "UNIT[\"metre\",1",
    ] {
        assert!(crs.contains(part), "{part} missing from {crs}");
    }
    let keys = Crs::parse(&crs).expect("text").to_geokeys().expect("keys");
    assert_eq!(keys.get(key::COORD_TRANS), Some(&GeoKeyValue::Short(17)));
    assert_eq!(
        keys.get(key::SEMI_MAJOR_AXIS),
        Some(&GeoKeyValue::Double(vec![3_396_190.0]))
    );
    assert_eq!(
        keys.get(key::CENTER_LONG),
        Some(&GeoKeyValue::Double(vec![180.0]))
    );
    // Encoded and parsed again, the directory gives the same WKT.
    let (dir, doubles, ascii) = keys.encode();
    let again = GeoKeyDirectory::parse(&dir, &doubles, &ascii).expect("parse");
    assert_eq!(again.to_crs().expect("crs").expect("some").to_string(), crs);
}

#[test]
fn epsg_codes_round_trip_and_geographic_codes_stay_geographic() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../fixtures/terrain/earth_mt_st_helens_utm10n.tif"
    );
    assert_eq!(
        dem_crs(path.as_ref()).expect("reads").as_deref(),
        Some("EPSG:32610")
    );
    for (code, model, id) in [
        (32610, 1, key::PROJECTED_CS_TYPE),
        (4326, 2, key::GEOGRAPHIC_TYPE),
    ] {
        let keys = Crs::Epsg(code).to_geokeys().expect("keys");
        assert_eq!(keys.get(key::MODEL_TYPE), Some(&GeoKeyValue::Short(model)));
        assert_eq!(keys.get(id), Some(&GeoKeyValue::Short(code as u16)));
        assert_eq!(keys.to_crs().expect("crs"), Some(Crs::Epsg(code)));
    }
    assert!(Crs::Epsg(70_000).to_geokeys().is_err());
}

/// A Moon polar stereographic and a Mars geographic system (ellipsoid by its inverse
/// flattening) survive WKT -> GeoKeys -> WKT with every number.
#[test]
fn planetary_polar_and_geographic_systems_round_trip() {
    let moon = r#"PROJCS["Moon south polar",GEOGCS["Moon 2000",DATUM["D_Moon_2000",SPHEROID["Moon_2000_IAU_IAG",1737400,0]],PRIMEM["Reference_Meridian",0],UNIT["degree",0.0174532925199433]],PROJECTION["Polar_Stereographic"],PARAMETER["latitude_of_origin",-90],PARAMETER["central_meridian",0],PARAMETER["scale_factor",1],PARAMETER["false_easting",0],PARAMETER["false_northing",0],UNIT["metre",1]]"#;
    let mars = r#"GEOGCS["Mars 2000",DATUM["D_Mars_2000",SPHEROID["Mars_2000_IAU_IAG",3396190,169.894447223612]],PRIMEM["Reference_Meridian",0],UNIT["degree",0.0174532925199433]]"#;
    for (wkt, parts) in [
        (
            moon,
            &[
                "PROJECTION[\"Polar_Stereographic\"]",
                "PARAMETER[\"latitude_of_origin\",-90]",
                "1737400,0",
            ][..],
        ),
        (
            mars,
            &[
                "GEOGCS[\"Mars 2000\"",
                "SPHEROID[\"Mars_2000_IAU_IAG\",3396190,169.894447223612]",
            ][..],
        ),
    ] {
        let keys = Crs::parse(wkt).expect("text").to_geokeys().expect("keys");
        let (dir, doubles, ascii) = keys.encode();
        let back = GeoKeyDirectory::parse(&dir, &doubles, &ascii)
            .expect("parse")
            .to_crs()
            .expect("crs")
            .expect("some")
            .to_string();
        for p in parts {
            assert!(back.contains(p), "{p} missing from {back}");
        }
    }
}

/// Keys or texts that are not honoured are typed errors, never panics or guesses.
#[test]
fn unsupported_and_malformed_keys_are_errors() {
    // Oblique Mercator (coordinate transformation 3) is not in the table.
    let keys = GeoKeyDirectory::parse(&[1, 1, 0, 2, 1024, 0, 1, 1, 3075, 0, 1, 3], &[], "")
        .expect("parse");
    assert!(matches!(
        keys.to_crs(),
        Err(CrsError::Unsupported { key: 3075, .. })
    ));
    // A projected model naming an EPSG projection (UTM 11N, 16011) without its parameters.
    let keys = GeoKeyDirectory::parse(&[1, 1, 0, 2, 1024, 0, 1, 1, 3074, 0, 1, 16011], &[], "")
        .expect("parse");
    assert!(matches!(
        keys.to_crs(),
        Err(CrsError::Unsupported { key: 3074, .. })
    ));
    // A key pointing past the doubles; a header declaring more keys than it holds.
    assert!(GeoKeyDirectory::parse(&[1, 1, 0, 1, 2057, 34736, 1, 5], &[1.0], "").is_err());
    assert!(GeoKeyDirectory::parse(&[1, 1, 0, 9, 1024, 0, 1, 1], &[], "").is_err());
    assert!(GeoKeyDirectory::parse(&[1, 1], &[], "").is_err());
    // WKT 2 and broken WKT are not written as keys.
    assert!(
        Crs::parse(r#"PROJCRS["x",BASEGEOGCRS["y"]]"#)
            .expect("text")
            .to_geokeys()
            .is_err()
    );
    assert!(Crs::Wkt("PROJCS[\"x\",".into()).to_geokeys().is_err());
    let deep = "A[".repeat(100) + &"]".repeat(100);
    assert!(Crs::Wkt(deep).to_geokeys().is_err());
}
