#!/usr/bin/env bash
# The native OMPL comparison (issue 33; docs/sampler.md, "Native peer: OMPL's ABIT* and BIT*"):
# OMPL's own C++ ABIT* and BIT* (Debian's libompl-dev, driven by native/ompl_peer.cpp) against
# rappel's ABIT* and its BIT* configuration (benches/examples/sampler_peer.rs), on every world of
# benches/ompl_peer/worlds, with state checkers of the same semantics on both sides.
#
# Usage: benches/ompl_peer/native.sh [SEEDS] [BUDGET_S] [WORLD_NAME...]
#   SEEDS     seeds 1..SEEDS per world, planner and side (default 20)
#   BUDGET_S  CPU seconds per run (default 1); costs are reported at 10, 30, 100, 300 ms, ...
#   WORLD_NAME  names under benches/ompl_peer/worlds (default: all)
# Output: $OMPL_NATIVE_OUT (default target/ompl_native): rows.tsv (one row per run and side),
# paths/ (every final path), summary.md (the table compare.py prints). Each side's final path
# is re-checked in its own program and then by the other side's checker (`verify`); the script
# exits non-zero if any check fails. Installs libompl-dev, nlohmann-json3-dev, g++, pkg-config
# and python3 with apt-get when they are missing. Takes about 2 x 2 x SEEDS x BUDGET_S CPU
# seconds per world (about 9 minutes for the defaults); not part of .ci/run.
set -euo pipefail
cd "$(dirname "$0")/../.."
seeds="${1:-20}"
budget="${2:-1}"
shift $(( $# < 2 ? $# : 2 ))
out="${OMPL_NATIVE_OUT:-target/ompl_native}"
target="${CARGO_TARGET_DIR:-target}"

need=()
command -v g++ >/dev/null || need+=(g++)
command -v pkg-config >/dev/null || need+=(pkg-config)
command -v python3 >/dev/null || need+=(python3)
if ! command -v pkg-config >/dev/null || ! pkg-config --exists ompl; then need+=(libompl-dev); fi
[ -f /usr/include/nlohmann/json.hpp ] || need+=(nlohmann-json3-dev)
if [ "${#need[@]}" -gt 0 ]; then
  echo "installing ${need[*]}" >&2
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${need[@]}"
fi

mkdir -p "$out/paths"
# Debian's ompl.pc lists the boost libraries' unversioned .so files, which only the boost -dev
# packages provide; libompl.so links them itself, so -lompl is all the program needs.
g++ -O2 -DNDEBUG -Wall -Wextra -Werror -o "$out/ompl_peer" \
  benches/ompl_peer/native/ompl_peer.cpp $(pkg-config --cflags ompl) -lompl
cargo build --quiet --release --locked -p rappel-benches --example sampler_peer
ours="$target/release/examples/sampler_peer"
theirs="$out/ompl_peer"

if [ "$#" -gt 0 ]; then worlds=("$@"); else
  worlds=(); for f in benches/ompl_peer/worlds/*.json; do worlds+=("$(basename "$f" .json)"); done
fi
h_ours="$("$ours" header "$budget")"
h_theirs="$("$theirs" header "$budget")"
if [ "$h_ours" != "$h_theirs" ]; then
  echo "error: the two sides print different headers:" >&2
  printf '%s\n%s\n' "$h_ours" "$h_theirs" >&2
  exit 2
fi
rows="$out/rows.tsv"
echo "$h_ours" > "$rows"
failed=0
for w in "${worlds[@]}"; do
  world="benches/ompl_peer/worlds/$w.json"
  [ -f "$world" ] || { echo "error: $world: no such world" >&2; exit 2; }
  echo "== $w" >&2
  for planner in abit bit; do
    for seed in $(seq 1 "$seeds"); do
      # Interleaved, so that a change of load on the shared machine meets both sides alike.
      p_ours="$out/paths/rappel_${planner}_${w}_$seed.txt"
      p_theirs="$out/paths/ompl_${planner}_${w}_$seed.txt"
      rm -f "$p_ours" "$p_theirs"
      "$ours" native "$world" "$planner" "$seed" "$budget" "$p_ours" >> "$rows" || failed=1
      "$theirs" run "$world" "$planner" "$seed" "$budget" "$p_theirs" >> "$rows" || failed=1
      # Each side's answer re-checked by the other side's checker.
      if [ -f "$p_theirs" ]; then "$ours" verify "$world" "$p_theirs" || failed=1; fi
      if [ -f "$p_ours" ]; then "$theirs" verify "$world" "$p_ours" || failed=1; fi
    done
  done
done
python3 benches/ompl_peer/native/compare.py "$rows" | tee "$out/summary.md" || failed=1
if [ "$failed" -ne 0 ]; then
  echo "error: a run failed or a path did not pass its check (see above and $rows)" >&2
  exit 1
fi
