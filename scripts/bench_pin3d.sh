#!/usr/bin/env bash
# The article's inverse pin route in 3D (CalculiX), timed: six loads of the demo campaign on
# this machine's cores, one CalculiX process per core.
#
#   scripts/bench_pin3d.sh GREYBOX DATASET OUT_DIR [STRIDE]
#
# GREYBOX: the greybox binary (target/release/greybox); DATASET: the demo's dataset.csv
# (`greybox demo --out demo-out` writes demo-out/dataset.csv); STRIDE: take every STRIDE-th
# load level from the highest (default 1: the six highest levels, 972-2000 N on the demo
# campaign; 2 is the article's plan, five levels on the demo's ten).
# Prints the wall time, the per-load searches and the mean reduction; docs/benchmarks.md has
# the numbers.
set -euo pipefail
greybox=$1
dataset=$2
out=$3
stride=${4:-1}
mkdir -p "$out"
echo "cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs), $(nproc) cores"
echo "ccx: $(command -v ccx)"
start=$(date +%s)
"$greybox" --quiet adhesive --data "$dataset" --method simulation-3d --sim3d-loads 6 \
    --sim3d-load-stride "$stride" --out "$out/dataset_adhesive_3d.csv"
end=$(date +%s)
echo "six-load inverse (stride $stride): $((end - start)) s wall"
python3 - "$out/dataset_adhesive_3d.pin3d/inverse.json" <<'PY'
import json, sys
for load in json.load(open(sys.argv[1])):
    s = load["search"]
    print(f'{load["normal_force_N"]:7.0f} N  depth {load["depth_um"]:5.1f} um  mu_app {s["mu_apparent"]:.4f}'
          f'  mu_adh {s["mu_adhesive"]:.4f}  share {s["deformation_share"]:.4f}'
          f'  ({s["deformation_share"] / s["mu_apparent"] * 100:.2f} %)  runs {len(s["runs"])}'
          f'  residual {s["residual"]:.4f}')
PY
python3 -c "import json,sys; print('mean reduction over the dataset: %.2f %%' % json.load(open(sys.argv[1]))['mean_reduction_percent'])" \
    "$out/dataset_adhesive_3d.correction.json"
