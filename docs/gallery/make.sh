#!/usr/bin/env bash
# Regenerates the gallery's pictures from the bundled fixtures with the release CLI:
#   bash docs/gallery/make.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
cargo build -q --release -p rappel-cli
r=target/release/rappel
g=docs/gallery
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
$r plan fixtures/thesis-fig-2-7.ron --svg $g/plan-fig-2-7.svg >/dev/null
$r plan fixtures/plan/shortest-infeasible.ron --svg $g/plan-shortest-infeasible.svg >/dev/null
$r stability fixtures/online-example.ron --grid 4 --tension-limit 300 --svg $g/stability-online-example.svg >/dev/null
$r plan fixtures/friction/slip_then_wrap.ron --svg $g/friction-slip-then-wrap.svg >/dev/null
$r online fixtures/online-example.ron --truth fixtures/online-example-discovered.ron --svg $g/online-example.svg >/dev/null
$r dem fixtures/terrain/mars_hirise_dteec_010228_1490_crop.asc --out "$tmp/mars.ron" \
    --ptfo-friction 0.4 --sticking-svg $g/mars-sticking.svg --phi-svg $g/mars-phi.svg --hill-svg $g/mars-hill.svg >/dev/null
$r track fixtures/tracking/kumar.json --robot1 fixtures/tracking/robot1-partial.json \
    --robot2 fixtures/tracking/robot2-descent.json --svg $g/track-kumar.svg --svg3d $g/track-kumar-3d.svg >/dev/null || true
# The GIS exports drawn by GDAL (docs/geospatial.md): the stability GeoTIFF's margin over a
# hillshade of the Mars equirectangular DEM, the plan's tethers (FlatGeobuf) burnt in blue.
if command -v gdaldem >/dev/null 2>&1; then
    dem=fixtures/terrain/mars_equirectangular_crop.tif
    $r dem $dem --out "$tmp/eqc.ron" >/dev/null
    $r stability "$tmp/eqc.ron" --grid 0.7 --geotiff "$tmp/stab.tif" >/dev/null 2>&1
    $r plan "$tmp/eqc.ron" --export "$tmp/plan.fgb" >/dev/null
    gdaldem hillshade -q -compute_edges -z 2 $dem "$tmp/hs.tif"
    gdal_translate -q -b 1 -b 1 -b 1 -colorinterp red,green,blue -a_nodata none "$tmp/hs.tif" "$tmp/hs_rgb.tif"
    printf "nv 0 0 0\n0.2 215 25 28\n0.3 253 174 97\n0.4 166 217 106\n0.5 26 150 65\n" > "$tmp/ramp.txt"
    gdaldem color-relief -q -b 2 "$tmp/stab.tif" "$tmp/ramp.txt" "$tmp/margin.tif"
    gdalbuildvrt -q -srcnodata "0 0 0" -vrtnodata none "$tmp/both.vrt" "$tmp/hs_rgb.tif" "$tmp/margin.tif"
    gdal_translate -q -outsize 400% 400% -r nearest "$tmp/both.vrt" "$tmp/both.tif"
    gdal_rasterize -q -b 1 -b 2 -b 3 -burn 30 -burn 60 -burn 230 -where "layer='tether'" "$tmp/plan.fgb" "$tmp/both.tif"
    gdal_translate -q -of PNG "$tmp/both.tif" $g/geospatial-mars-stability.png
    rm -f $g/geospatial-mars-stability.png.aux.xml
    # `rappel dem --geotiff`: the obstacle mask (foot orange, raised red, sunken blue) and the
    # PTFO labels (green) over the same hillshade.
    $r dem $dem --out "$tmp/det.ron" --ptfo-friction 0.4,0.6 --geotiff "$tmp/det.tif" >/dev/null 2>&1
    printf "nv 0 0 0\n0 0 0 0\n1 253 174 97\n2 215 25 28\n3 44 123 182\n" > "$tmp/mask.txt"
    printf "nv 0 0 0\n0 0 0 0\n1 26 150 65\n200 26 150 65\n" > "$tmp/ptfo.txt"
    gdaldem color-relief -q -nearest_color_entry -b 1 "$tmp/det.tif" "$tmp/mask.txt" "$tmp/mask.tif"
    gdaldem color-relief -q -b 2 "$tmp/det.tif" "$tmp/ptfo.txt" "$tmp/ptfo.tif"
    gdalbuildvrt -q -srcnodata "0 0 0" -vrtnodata none "$tmp/det.vrt" "$tmp/hs_rgb.tif" "$tmp/ptfo.tif" "$tmp/mask.tif"
    gdal_translate -q -outsize 400% 400% -r nearest -of PNG "$tmp/det.vrt" $g/geospatial-mars-detection.png
    rm -f $g/geospatial-mars-detection.png.aux.xml
fi
echo "gallery written to $g"
