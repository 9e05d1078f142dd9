#!/usr/bin/env bash
# A smoke test only: runs rappel's ABIT* and the OMPL Python package's BIT* side by side on the
# 2D and 3D peer worlds (docs/sampler.md, "Peer: OMPL's BIT* (Python smoke test)"). OMPL's
# validity checker is a Python callback here, so its wall times measure Python, not OMPL; the
# fair comparison is benches/ompl_peer/native.sh (OMPL's C++ ABIT* and BIT*, CPU time).
# Usage: benches/ompl_peer/run.sh [TIME_S] [RUNS]
# The OMPL Python package is installed from requirements.txt into a virtual environment
# ($OMPL_VENV, default target/ompl-venv) on first use.
set -euo pipefail
cd "$(dirname "$0")/../.."
time_s="${1:-3}"
runs="${2:-10}"
venv="${OMPL_VENV:-target/ompl-venv}"
if [ ! -x "$venv/bin/python" ]; then
  python3 -m venv "$venv"
  "$venv/bin/pip" install --quiet -r benches/ompl_peer/requirements.txt
fi
cargo run --quiet --release --locked -p rappel-benches --example sampler_peer -- worlds
for w in boxes_2d boxes_3d; do
  echo "== $w: rappel ABIT*"
  cargo run --quiet --release --locked -p rappel-benches --example sampler_peer -- \
    anytime "benches/ompl_peer/worlds/$w.json" "$time_s" "$runs"
  echo "== $w: OMPL BIT*"
  "$venv/bin/python" benches/ompl_peer/bitstar_peer.py \
    "benches/ompl_peer/worlds/$w.json" "$time_s" "$runs" 1
done
