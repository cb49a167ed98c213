#!/usr/bin/env bash
# One-frame maps of the KITTI stereo-2015 frames (each frame on its own: `semap run --frames 1` from that
# frame, then `semap eval` of its mesh against its own Velodyne scan). Prints one markdown row per frame and
# the totals over all frames and over frames 2, 44, 76 and 123 (the four the fusion issue names).
#
#   bench/one_frame_maps.sh [SEQ] [--out DIR] [--name NAME] [-- extra semap run options]
#
# SEQ defaults to ../shared/data/kitti_stereo2015_subset; the run uses PS and ENet labels unless the extra
# options say otherwise. Completeness is the strict protocol's (Velodyne pixels at 1-40 m that the mesh
# covers); the paper protocol's RMSE is that of the errors up to 2 m at 1-15 m. Totals pool the pixels.
set -euo pipefail
cd "$(dirname "$0")/.."
SEMAP=${SEMAP:-build/tools/semap}
SEQ=../shared/data/kitti_stereo2015_subset; OUT=bench_one_frame; NAME=default
while (($#)); do
  case $1 in
    --out) OUT=$2; shift 2 ;;
    --name) NAME=$2; shift 2 ;;
    --) shift; break ;;
    -h|--help) sed -n 2,10p "$0"; exit 0 ;;
    *) SEQ=$1; shift ;;
  esac
done
EXTRA=("$@")
# The frame ids as numbered on disk (input.first_frame counts in them): image_2/NNNNNN_10.png.
ids=$(find "$SEQ/image_2" -name '*_10.png' -printf '%f\n' | sed 's/_10\.png$//' | sort -n | sed 's/^0*\([0-9]\)/\1/')
[ -n "$ids" ] || { echo "one_frame_maps: $SEQ/image_2: no frames NNNNNN_10.png" >&2; exit 1; }
mkdir -p "$OUT/$NAME"
for k in $ids; do
  run="$OUT/$NAME/frame_$k"
  "$SEMAP" run "$SEQ" --set input.first_frame=$k --frames 1 --method PS --set semantics.source=enet \
    --out "$run" --progress-interval 0 --log-level warn "${EXTRA[@]}" >"$run.log" 2>&1
  "$SEMAP" eval "$SEQ" --mesh "$run/mesh.ply" --set input.first_frame=$k --set input.max_frames=1 \
    --json "$run/eval.json" >/dev/null 2>>"$run.log"
done
python3 - "$OUT/$NAME" $ids <<'PY'
import json, math, sys
folder, ids = sys.argv[1], [int(k) for k in sys.argv[2:]]
rows, named = [], {2, 44, 76, 123}
for k in ids:
    d = json.load(open(f"{folder}/frame_{k}/eval.json"))
    assert d["per_frame"][0]["frame_id"] == k, f"frame {k}: the eval read frame {d['per_frame'][0]['frame_id']}"
    rows.append((k, d["protocols"]["strict"]["lidar"],
                 d["protocols"]["paper"]["lidar"], d["triangles"]))

def pooled(ss):  # completeness and RMSE over the pixels of all the frames
    ref = sum(s["reference_pixels"] for s in ss)
    compared = sum(s["compared_pixels"] for s in ss)
    return compared / ref, math.sqrt(sum(s["rmse_m"] ** 2 * s["compared_pixels"] for s in ss) / compared)

def line(name, rs):
    c, r = pooled([x[1] for x in rs])
    pc, pr = pooled([x[2] for x in rs])
    print(f"| {name} | {100 * c:.1f} % | {r:.3f} m | {pr:.3f} m | {100 * pc:.1f} % | {sum(x[3] for x in rs)} |")

print("| frame | completeness (strict) | strict RMSE | paper RMSE (errors <= 2 m, 1-15 m) | paper completeness | triangles |")
print("|---|---|---|---|---|---|")
for r in rows:
    line(str(r[0]), [r])
line("**all frames (pooled)**", rows)
line("**frames 2, 44, 76, 123 (pooled)**", [r for r in rows if r[0] in named])
PY
