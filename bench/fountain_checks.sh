#!/usr/bin/env bash
# The two checks of a fountain-P11 map that need no laser truth (bench/fountain_checks.cc):
# - sparse truth: the O and PS meshes of the whole set against SIFT points triangulated with the set's cameras;
# - leave one out: the PS mesh of the set without one view (a copy of the set without images/NNNN.jpg and
#   gt_dense_cameras/NNNN.jpg.camera), seen from the left-out camera, against that view's own plane-sweep
#   depth from the other views. That depth is swept with REFERENCE_PLANES planes (default 256; the maps sweep
#   64): the program prints its own error at the sparse points the view sees; a reference swept as coarsely
#   as the maps is as far off as the meshes and hides their errors.
# O and PS come from bench/fountain.sh (half resolution, 64 planes, at most 100,000 points a view, ENet labels:
# its table of OFF size and wall and ground points kept), the set without the view is mapped the same way, all
# at the lowest priority; runs already in OUT (fountain.md, <run>/summary.json) are kept. Prints the checks'
# tables (also written to OUT/fountain_checks.md); the sparse points and their distances to each mesh go to
# OUT/sparse_points.csv.
#
#   bench/fountain_checks.sh [--out DIR] [--leave-out N] [-- extra `semap run` options]
#
# Environment: SEMAP (default build/tools/semap, also for fountain.sh), CHECKS (default
# build/bench/semap_fountain_checks), SEMAP_SHARED (default ../shared), REFERENCE_PLANES (default 256).
set -euo pipefail

ROOT="$(cd "$(dirname "$0")/.." && pwd)"
export SEMAP="${SEMAP:-$ROOT/build/tools/semap}"
CHECKS="${CHECKS:-$ROOT/build/bench/semap_fountain_checks}"
export SEMAP_SHARED="${SEMAP_SHARED:-$ROOT/../shared}"
SHARED="$SEMAP_SHARED"
OUT=""
LEAVE_OUT=5
EXTRA=()
while (($#)); do
  case "$1" in
    --out) OUT="$2"; shift 2 ;;
    --leave-out) LEAVE_OUT="$2"; shift 2 ;;
    --) shift; EXTRA=("$@"); break ;;
    *) echo "fountain_checks.sh: unknown argument '$1'" >&2; exit 2 ;;
  esac
done
OUT="${OUT:-$(mktemp -d /tmp/semap_fountain_checks.XXXXXX)}"
mkdir -p "$OUT"
SET="$SHARED/data/strecha_fountain_p11"
[ -d "$SET" ] || { echo "fountain_checks.sh: $SET not found" >&2; exit 1; }
STEM="$(printf '%04d' "$LEAVE_OUT")"
[ -f "$SET/images/$STEM.jpg" ] || { echo "fountain_checks.sh: no view $STEM in $SET" >&2; exit 1; }
cd "$ROOT"  # the ENet model path is relative to the repository

# The set without the left-out view.
LOO_SET="$OUT/set_without_$STEM"
rm -rf "$LOO_SET"
cp -r "$SET" "$LOO_SET"
rm "$LOO_SET/images/$STEM.jpg" "$LOO_SET/gt_dense_cameras/$STEM.jpg.camera"

# O and PS of the whole set, with fountain.sh's table of their time, OFF size and kept wall and ground points.
[ -f "$OUT/fountain.md" ] || nice -n 19 "$ROOT/bench/fountain.sh" --out "$OUT" -- "${EXTRA[@]}"

# PS without the left-out view, as fountain.sh maps.
SWEEP=(--set depth.half_resolution=true --set plane_sweep.num_planes=64)
LOO="PS_without_$STEM"
if [ ! -f "$OUT/$LOO/summary.json" ]; then
  nice -n 19 "$SEMAP" run "$LOO_SET" --method PS --out "$OUT/$LOO" --progress-interval 0 \
    --set semantics.source=enet --set depth.max_points_per_frame=100000 "${SWEEP[@]}" "${EXTRA[@]}" \
    > "$OUT/$LOO.log" 2>&1 || { tail -20 "$OUT/$LOO.log" >&2; exit 1; }
fi

echo
nice -n 19 "$CHECKS" "$SET" --mesh "O=$OUT/O/mesh.ply" --mesh "PS=$OUT/PS/mesh.ply" \
  --leave-out-mesh "$LOO=$OUT/$LOO/mesh.ply" --leave-out "$LEAVE_OUT" --points-csv "$OUT/sparse_points.csv" \
  --set depth.half_resolution=true --set plane_sweep.num_planes="${REFERENCE_PLANES:-256}" \
  | tee "$OUT/fountain_checks.md"
