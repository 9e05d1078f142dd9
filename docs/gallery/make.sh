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
echo "gallery written to $g"
