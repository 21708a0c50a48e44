#!/usr/bin/env bash
# Reproduces docs/seed001_study.md: runs the seed 001 drape scenes with the FEM shell, measures
# drape coefficient, folds and extents of each result (test_seed001_drapes'
# DISABLED_MeasureStudyOutputs) and prints the table.
#   scripts/seed001_study.sh [OUT_DIR] [SCENE.yaml ...]
# Defaults: OUT_DIR=/tmp/seed001_study, all study scenes. TIMEOUT (s, default 900) caps each run;
# a run the timeout kills is listed as such. Results stay in OUT_DIR/<scene>/.
set -u
cd "$(dirname "$0")/.."
OUT=${1:-/tmp/seed001_study}
shift || true
SCENES=("$@")
if [ ${#SCENES[@]} -eq 0 ]; then
  SCENES=(scenes/disc_254_on_127.yaml scenes/disc_254_on_127_fine.yaml
          scenes/pedestal_square_24.yaml scenes/square_50_on_disc_20.yaml)
fi
TIMEOUT=${TIMEOUT:-900}
BUILD=build_s001
export PATH=/usr/bin:$PATH
cmake -S . -B $BUILD -DCMAKE_BUILD_TYPE=Release -DPYTHON_EXECUTABLE=/usr/bin/python3 \
  -DPython3_EXECUTABLE=/usr/bin/python3 -DCMAKE_CXX_COMPILER_LAUNCHER=ccache >/dev/null || exit 1
cmake --build $BUILD -j2 --target drape test_seed001_drapes >/dev/null || exit 1
DRAPE=$BUILD/devel/lib/cloth_hair_sim/drape
MEASURE=$BUILD/devel/lib/cloth_hair_sim/test_seed001_drapes

mkdir -p "$OUT"
: >"$OUT/cases.txt"
for s in "${SCENES[@]}"; do
  name=$(basename "$s" .yaml)
  echo "== $name"
  timeout "$TIMEOUT" "$DRAPE" "$s" --out "$OUT/$name" >"$OUT/$name.log" 2>&1
  rc=$?
  echo "$rc" >"$OUT/$name.rc"  # 0 converged, 2 not converged, 124 killed by the timeout
  tail -n 2 "$OUT/$name.log"
  [ -f "$OUT/$name/draped.obj" ] && echo "$s $OUT/$name" >>"$OUT/cases.txt"
done

CHS_SEED001_CASES="$OUT/cases.txt" "$MEASURE" --gtest_also_run_disabled_tests \
  --gtest_filter='*MeasureStudyOutputs' | grep -v '^\['

python3 - "$OUT" "${SCENES[@]}" <<'EOF'
import json, os, sys
out, scenes = sys.argv[1], sys.argv[2:]
print("| case | nodes | converged | load steps | iterations | wall time (s) | DC | folds |"
      " lowest z (mm) | outline r (mm) |")
print("|---|---|---|---|---|---|---|---|---|---|")
for s in scenes:
    name = os.path.splitext(os.path.basename(s))[0]
    d = os.path.join(out, name)
    rc = open(d + ".rc").read().strip()
    try:
        r = json.load(open(os.path.join(d, "report.json")))
        m = json.load(open(os.path.join(d, "metrics.json")))
    except OSError:
        print(f"| {name} | | killed (rc {rc}) | | | | | | | |")
        continue
    conv = "yes" if r["converged"] else "NO"
    print(f"| {name} | {r['mesh']['vertices']} | {conv} | {r['load_steps']} | {r['iterations']} |"
          f" {r['wall_time_s']:.0f} | {m['drape_coefficient']:.3f} | {m['folds']} |"
          f" {1e3 * m['lowest_z']:.1f} | {1e3 * m['min_outline_radius']:.0f}-"
          f"{1e3 * m['max_outline_radius']:.0f} |")
EOF
