#!/usr/bin/env bash
# Side-by-side SPH speed: greybox against the ETH IWF code mfree_iwf-ul-cut-refine
# (Afrasiabi, Röthlin, Klippel, Wegener, Int J Mech Sci 2019), one thread each, on two of the
# peer's Ti6Al4V orthogonal cuts and greybox's equivalent set-ups:
#   model 1, single resolution (10 µm)             <-> examples/iwf-ti64-cut.toml
#   model 3, dynamic refinement (10 µm, 5 µm in a  <-> examples/iwf-ti64-refined-cut.toml
#            frame that moves with the tool)
# CASES="1 3" (default) picks them.
#
#   scripts/bench_sph_peer.sh PEER_SRC_DIR [OUT_DIR]
#
# PEER_SRC_DIR: a checkout of the peer's public source (the folder holding src/ and
#   Release/). It is only read: everything is copied into OUT_DIR and built there; nothing
#   of the peer ends up in this repository.
# OUT_DIR: where the copy, the build and both runs' logs go (default: a fresh temporary
#   directory, kept and printed at the end).
#
# Environment:
#   FRACTION=0.1   fraction of the 1 mm cut simulated on BOTH sides (default 0.1, i.e. 0.1 mm
#                  of cut). The peer's full cut takes of the order of an hour on one core; both
#                  sides run the same simulated cut length, and the comparison is per
#                  particle-step (particles x time steps / loop wall time), which does not
#                  depend on the time step or particle count each code chooses.
#   GREYBOX=target/release/greybox   the binary to time (build: cargo build --release -p greybox-cli)
#   PEER_GPROF=0   1 keeps the makefile's `-p` (gprof instrumentation, which slows the peer)
#   PEER_VTK=0     1 keeps the peer's VTK frame output (150 frames per run)
#   JOBS=2         parallel compile jobs for the peer build
#
# What is changed in the COPIED peer source (sed, inside OUT_DIR only), and why:
#   1. Release/src/subdir.mk, Release/src/benchmarks/subdir.mk: the makefile's flags are
#      already `-std=c++1y -O3 -march=native -p -Wall`; `-p` (gprof) is dropped, as is the
#      linker's `-p` in Release/makefile, unless PEER_GPROF=1. Otherwise built by its own
#      makefile (`make -C Release`).
#   2. src/benchmarks/test_cuttings.cpp, in cutting_ref_single_resol() and
#      cutting_ref_multi_resol_dynamic() only:
#      `double lc = 1e-3;` (1 mm of cut) becomes `1e-3*FRACTION` -> the same simulated cut
#      length as greybox's --fraction; and `set_log_vtk(true)` becomes false unless
#      PEER_VTK=1, so that the peer's timed loop is computation like greybox's (greybox's
#      `bench sph` times the solver loop, which writes only its first and last VTK frames;
#      the other files are written after the clock stops).
#      Both changes can only make the peer's number better or leave it as it is.
#   3. src/adaptivity.h uses std::vector without `#include <vector>` (older GCCs pulled it
#      in through <algorithm>; GCC 12 does not): the include is added, nothing else.
#   4. src/refine_cut_main.cpp: its last line `printf("Runtime: %f\n", elapsed)` also prints
#      the number of steps taken and of particles, which the particle-steps/s below need.
#      (Model 1's count does not change; model 3's grows, both sides are counted at the end.)
# The cases need no other patch: `refine_paper -m 1` is the single-resolution cut
# (nx = 31 -> 201 x 31 = 6 231 particles), `-m 3` the dynamic refinement (5 µm near the
# surface and in its moving frame, 10 µm elsewhere; its count grows). The peer has no OpenMP
# pragmas and its makefile no -fopenmp, so it runs on one thread anyway; OMP_NUM_THREADS=1
# is set regardless. greybox runs with RAYON_NUM_THREADS=1.
#
# Needs: g++, make, GLM headers (Debian: libglm-dev), python3 (JSON parsing).
set -euo pipefail

if [[ $# -lt 1 || $# -gt 2 ]]; then
    sed -n '2,14p' "$0" | sed 's/^# \{0,1\}//'
    exit 2
fi
PEER_SRC=$(cd "$1" && pwd)
OUT=${2:-$(mktemp -d /tmp/bench_sph_peer.XXXXXX)}
mkdir -p "$OUT"
OUT=$(cd "$OUT" && pwd)
REPO=$(cd "$(dirname "$0")/.." && pwd)
FRACTION=${FRACTION:-0.1}
GREYBOX=${GREYBOX:-$REPO/target/release/greybox}
PEER_GPROF=${PEER_GPROF:-0}
PEER_VTK=${PEER_VTK:-0}
JOBS=${JOBS:-2}

[[ -f "$PEER_SRC/src/refine_cut_main.cpp" && -f "$PEER_SRC/Release/makefile" ]] ||
    { echo "error: $PEER_SRC does not look like mfree_iwf-ul-cut-refine (src/, Release/)" >&2; exit 2; }
[[ -x "$GREYBOX" ]] || { echo "error: $GREYBOX missing: cargo build --release -p greybox-cli" >&2; exit 2; }
[[ -f /usr/include/glm/glm.hpp ]] || echo "warning: GLM headers not in /usr/include/glm (apt-get install libglm-dev)" >&2

# ---------------------------------------------------------------- the machine
CPU=$(grep -m1 '^model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//')
if grep -qw avx512f /proc/cpuinfo; then AVX512=yes; else AVX512=no; fi
if grep -qw avx2 /proc/cpuinfo; then AVX2=yes; else AVX2=no; fi

# ---------------------------------------------------------------- peer: copy, patch, build
PEER="$OUT/peer"
rm -rf "$PEER"
mkdir -p "$PEER"
cp -a "$PEER_SRC/src" "$PEER_SRC/Release" "$PEER/"

if [[ "$PEER_GPROF" != 1 ]]; then
    sed -i 's/ -march=native -p -Wall/ -march=native -Wall/' \
        "$PEER/Release/src/subdir.mk" "$PEER/Release/src/benchmarks/subdir.mk"
    sed -i 's/g++ -p -o/g++ -o/' "$PEER/Release/makefile"
fi
# The compile flags actually used (checked, so a changed makefile is noticed).
grep -q -- '-O3 -march=native' "$PEER/Release/src/subdir.mk" ||
    { echo "error: peer subdir.mk no longer has -O3 -march=native; check the build" >&2; exit 1; }

# Simulated cut length (only inside the two cases' set-up functions, up to their closing
# braces).
for fn in cutting_ref_single_resol cutting_ref_multi_resol_dynamic; do
    sed -i "/^ *body \*${fn}(/,/^}/ s|double lc = 1e-3;|double lc = 1e-3*${FRACTION};|" \
        "$PEER/src/benchmarks/test_cuttings.cpp"
    if [[ "$PEER_VTK" != 1 ]]; then
        sed -i "/^ *body \*${fn}(/,/^}/ s|set_log_vtk(true)|set_log_vtk(false)|" \
            "$PEER/src/benchmarks/test_cuttings.cpp"
    fi
done
# A missing standard include (the build fails on GCC 12 without it).
grep -q '#include <vector>' "$PEER/src/adaptivity.h" ||
    sed -i 's|^#include <glm/glm.hpp>|#include <vector>\n#include <glm/glm.hpp>|' "$PEER/src/adaptivity.h"
# Steps and particles at the end of the run.
sed -i 's|printf("Runtime: %f\\n", elapsed);|printf("Runtime: %f\\nSteps: %u\\nParticles: %u\\n", elapsed, time->get_step(), b->get_num_part());|' \
    "$PEER/src/refine_cut_main.cpp"
[[ $(grep -c "double lc = 1e-3\*${FRACTION};" "$PEER/src/benchmarks/test_cuttings.cpp") -ge 2 ]] &&
    grep -q 'Steps: %u' "$PEER/src/refine_cut_main.cpp" ||
    { echo "error: patching the peer source failed (source changed upstream?)" >&2; exit 1; }

echo "== building the peer (make -C Release, $(grep -m1 -o 'g++ -std[^"]*-c' "$PEER/Release/src/subdir.mk"))"
make -C "$PEER/Release" -j"$JOBS" all > "$OUT/peer-build.log" 2>&1 ||
    { tail -30 "$OUT/peer-build.log" >&2; exit 1; }

# ---------------------------------------------------------------- both sides, per case
# run_case MODEL CONFIG: the peer's model MODEL and greybox's CONFIG, one thread each, the
# same fraction of the cut; writes OUT/case-MODEL.txt.
run_case() {
    local model=$1 config=$2
    mkdir -p "$OUT/peer-run-$model"
    echo "== running the peer: model $model, ${FRACTION} of 1 mm, one thread"
    (cd "$OUT/peer-run-$model" && OMP_NUM_THREADS=1 "$PEER/Release/refine_paper" -m "$model") \
        > "$OUT/peer-$model.log" 2>&1 || { tail -20 "$OUT/peer-$model.log" >&2; exit 1; }
    local peer_s peer_steps peer_part peer_dt
    peer_s=$(awk '/^Runtime:/ {print $2}' "$OUT/peer-$model.log")
    peer_steps=$(awk '/^Steps:/ {print $2}' "$OUT/peer-$model.log")
    peer_part=$(awk '/^Particles:/ {print $2}' "$OUT/peer-$model.log")
    peer_dt=$(grep -m1 -o 'dt [0-9.e+-]*' "$OUT/peer-$model.log" | cut -d' ' -f2)

    echo "== running greybox: bench sph --config $config --fraction ${FRACTION}, one thread"
    (cd "$REPO" && RAYON_NUM_THREADS=1 "$GREYBOX" -q bench sph --config "$config" \
        --fraction "$FRACTION" --json) > "$OUT/greybox-$model.json" 2> "$OUT/greybox-$model.log" ||
        { tail -20 "$OUT/greybox-$model.log" >&2; exit 1; }

    python3 - "$model" "$config" "$peer_part" "$peer_steps" "$peer_s" "$peer_dt" \
        "$OUT/greybox-$model.json" "$CPU" "$AVX2" "$AVX512" "$FRACTION" <<'EOF' | tee "$OUT/case-$model.txt"
import json, sys
(model, config, pp, ps, pw, pdt, gjson, cpu, avx2, avx512, frac) = sys.argv[1:]
pp, ps, pw = int(pp), int(ps), float(pw)
d = json.load(open(gjson))
s = d.get("summary", d)
# Steps that did the particle passes: the tool's idle approach (`idle_steps`, no particle
# work, see docs/simulator.md step 8) is left out; the peer computes every step in full.
gp, gs, gw = int(s["particles"]), int(s["steps"] - s.get("idle_steps", 0)), float(s["wall_s"])
# Particle-steps as the peer can be measured: the particle count at the end times the steps
# (a refined run's count grows, so both sides are overstated alike); greybox also reports
# its exact sum over the steps.
peer = pp * ps / pw
gb = gp * gs / gw
print(f"CPU: {cpu} (AVX2: {avx2}, AVX-512: {avx512}); one thread each; {frac} of the 1 mm cut on both sides")
print(f"peer    model {model}: {pp} particles at the end x {ps} steps (dt {pdt} s) in {pw:.2f} s "
      f"-> {peer:.3e} particle-steps/s")
print(f"greybox {config}: {gp} particles at the end x {gs} working steps (dt {float(s['dt_s']):.3e} s) "
      f"in {gw:.2f} s -> {gb:.3e} particle-steps/s (exact sum over the steps: "
      f"{float(s['particle_steps_per_s']):.3e})")
print(f"model {model}: ratio greybox/peer per particle-step {gb / peer:.2f}x, wall time {pw / gw:.2f}x")
EOF
}

# CASES: the peer's models to run: 1 (single resolution, against examples/iwf-ti64-cut.toml)
# and 3 (dynamic refinement, against examples/iwf-ti64-refined-cut.toml).
for model in ${CASES:-1 3}; do
    case $model in
        1) run_case 1 examples/iwf-ti64-cut.toml ;;
        3) run_case 3 examples/iwf-ti64-refined-cut.toml ;;
        *) echo "error: CASES holds $model; the cases are 1 and 3" >&2; exit 2 ;;
    esac
done
cat "$OUT"/case-*.txt > "$OUT/result.txt"
echo "logs: $OUT"
