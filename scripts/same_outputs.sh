#!/usr/bin/env bash
# Runs `greybox demo` and a bundled validation subset into DIR, and with a second DIR compares
# the two runs file by file, apart from what no two runs share (wall times, provenance).
# Used around refactors that must not change a result (docs/architecture.md):
#   scripts/same_outputs.sh run BEFORE_DIR [greybox binary]
#   scripts/same_outputs.sh run AFTER_DIR  [greybox binary]
#   scripts/same_outputs.sh compare BEFORE_DIR AFTER_DIR
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
case "${1:-}" in
run)
  dest=$2; bin=${3:-$root/target/release/greybox}
  # One place for every run, so that paths written into the outputs are the same.
  out=${TMPDIR:-/tmp}/greybox-same-outputs
  rm -rf "$out" "$dest"; mkdir -p "$out"
  "$bin" demo --out "$out/demo" -q
  v=$root/validation
  printf 'data = "%s"\n[[material]]\nname = "Ti6Al4V"\nsetup = "%s"\nrun_speed_m_per_min = 600.0\ncalibration = ["D08"]\nmu_bracket = [0.2, 0.8]\n' \
    "$v/orthogonal-cutting.csv" "$v/ti64-setup.toml" > "$out/suite.toml"
  "$bin" bench validate --suite "$out/suite.toml" --out "$out/validate" --only D09,D16 \
    --tool thermal --fraction 0.3 -q
  mv "$out" "$dest"
  ;;
compare)
  exec python3 "$root/scripts/same_outputs_compare.py" "$2" "$3"
  ;;
*) echo "usage: $0 run DIR [binary] | compare DIR_A DIR_B" >&2; exit 2 ;;
esac
