#!/usr/bin/env bash
# The `semap map-sfm --incremental` benchmark of bench/RESULTS.md: synthetic streets of 100 keyframes (1 m
# apart) with 300, 1,000 and 5,000 new points per keyframe, written by bench/sfm_bench as COLMAP binary models
# (1 cm noise, each point observed again by up to 10 later keyframes while in view), each mapped in its own
# process. Prints per size: time per keyframe (mean, p50, p95, max; first and last 10 keyframes), total wall
# and CPU time, and peak RSS (/usr/bin/time).
# Usage: bench/sfm_bench.sh [BUILD_DIR] [OUT_DIR] [POINTS_PER_KEYFRAME...]
set -euo pipefail
BUILD=${1:-build}
OUT=${2:-sfm_bench_out}
shift $(($# > 2 ? 2 : $#))
SIZES=("$@")
((${#SIZES[@]})) || SIZES=(300 1000 5000)
KEYFRAMES=${KEYFRAMES:-100}
METHOD=${METHOD:-O}
mkdir -p "$OUT"

for n in "${SIZES[@]}"; do
  model="$OUT/street_${n}"
  run="$OUT/run_${n}"
  "$BUILD/bench/sfm_bench" --out "$model" --keyframes "$KEYFRAMES" --points "$n"
  /usr/bin/time -v "$BUILD/tools/semap" map-sfm "$model" --format colmap --incremental --method "$METHOD" \
    --out "$run" --progress-interval 60 >"$run.log" 2>&1
  echo "== $n new points per keyframe, $KEYFRAMES keyframes, method $METHOD"
  grep -E "per keyframe mean|extra rays|mesh:" "$run.log" | sed 's/^\[[^]]*\] \[info\] /  /'
  # frames.csv: simplify_ms (8), map_ms (10), live_ms (12), mesh_ms (14) per keyframe.
  awk -F, 'NR > 1 { t = $8 + $10 + $12 + $14; all[NR - 1] = t; n = NR - 1; live += $12 }
           END { for (i = 1; i <= 10 && i <= n; ++i) a += all[i]; for (i = n - 9; i <= n; ++i) b += all[i];
                 printf "  first 10 keyframes %.0f ms each, last 10 %.0f ms each; live-point refresh %.1f s in all\n",
                        a / 10, b / 10, live / 1000 }' "$run/frames.csv"
  grep -E "Elapsed|User time|System time|Maximum resident" "$run.log" | sed 's/^\s*/  /'
done
