#!/usr/bin/env bash
# fountain-P11 (the paper's second experiment, $SEMAP_SHARED/data/strecha_fountain_p11: 11 views, 1536x1024)
# mapped from plane-sweep depth with PS and O, ENet labels (Cityscapes: building/wall/fence are walls,
# road/sidewalk/terrain ground): per method the run's wall time and CPU time, the mesh's size as OFF, its
# triangles, and the share of the wall and ground points the simplification kept; an oblique picture of each
# mesh (docs/fountain_PS.png, docs/fountain_O.png with --pictures). Prints one markdown table (also written to
# OUT/fountain.md).
#
#   bench/fountain.sh [--out DIR] [--full] [--pictures] [-- extra `semap run` options]
#
# Default: the sweep at half resolution (depth.half_resolution: 768x512), 64 planes, at most 100,000 points
# a view; --full sweeps the views at 1536x1024. Timings are only comparable on an idle machine: the load
# average before and after is printed. Environment: SEMAP (default build/tools/semap), SEMAP_SHARED (default
# ../shared), CPUS (default 0,1).
set -euo pipefail

ROOT="$(cd "$(dirname "$0")/.." && pwd)"
SEMAP="${SEMAP:-$ROOT/build/tools/semap}"
SHARED="${SEMAP_SHARED:-$ROOT/../shared}"
CPUS="${CPUS:-0,1}"
OUT=""
FULL=0
PICTURES=0
EXTRA=()
while (($#)); do
  case "$1" in
    --out) OUT="$2"; shift 2 ;;
    --full) FULL=1; shift ;;
    --pictures) PICTURES=1; shift ;;
    --) shift; EXTRA=("$@"); break ;;
    *) echo "fountain.sh: unknown argument '$1'" >&2; exit 2 ;;
  esac
done
OUT="${OUT:-$(mktemp -d /tmp/semap_fountain.XXXXXX)}"
mkdir -p "$OUT"
SET="$SHARED/data/strecha_fountain_p11"
[ -d "$SET" ] || { echo "fountain.sh: $SET not found" >&2; exit 1; }
RES=(--set depth.half_resolution=true)
((FULL)) && RES=(--set depth.half_resolution=false)
cd "$ROOT"  # the ENet model path is relative to the repository

echo "load average before: $(cut -d' ' -f1-3 /proc/loadavg)"
for method in PS O; do
  /usr/bin/time -f "%e %U %S %M" -o "$OUT/$method.time" taskset -c "$CPUS" "$SEMAP" run "$SET" \
    --method "$method" --out "$OUT/$method" --progress-interval 0 --set semantics.source=enet \
    --set plane_sweep.num_planes=64 --set depth.max_points_per_frame=100000 "${RES[@]}" "${EXTRA[@]}" \
    > "$OUT/$method.log" 2>&1 || { tail -20 "$OUT/$method.log" >&2; exit 1; }
  if ((PICTURES)); then
    "$SEMAP" render "$OUT/$method/mesh.ply" --out "$ROOT/docs/fountain_$method.png" --up -z --elevation 25 \
      --azimuth 0 --width 1000 --height 700 > /dev/null
  fi
done
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"

python3 - "$OUT" <<'PY' | tee "$OUT/fountain.md"
import json, os, sys
out = sys.argv[1]
WALL = {3, 4, 5}      # Cityscapes building, wall, fence
GROUND = {1, 2, 10}   # road, sidewalk, terrain
print("| method | frames | wall s | CPU s | mesh OFF MB | triangles | wall kept | ground kept | points kept |")
print("|---|---|---|---|---|---|---|---|---|")
for method in ("PS", "O"):
    s = json.load(open(os.path.join(out, method, "summary.json")))
    frames = [json.loads(line) for line in open(os.path.join(out, method, "frames.jsonl")) if line.strip()]
    classes = {}
    for f in frames:  # each frame's points per class, in and kept
        for k, c in f.get("classes", {}).items():
            t = classes.setdefault(int(k), [0, 0])
            t[0] += c["in"]
            t[1] += c["kept"]
    wall_s, user_s, sys_s, _ = open(os.path.join(out, method + ".time")).read().split()
    off_mb = os.path.getsize(os.path.join(out, method, "mesh.off")) / 1e6
    def kept(ids):
        n_in = sum(c[0] for k, c in classes.items() if k in ids)
        n_kept = sum(c[1] for k, c in classes.items() if k in ids)
        return f"{100.0 * n_kept / n_in:.1f} % of {n_in}" if n_in else "–"
    print(f"| {method} | {s['frames_integrated']} | {float(wall_s):.1f} | {float(user_s) + float(sys_s):.1f} | "
          f"{off_mb:.2f} | {s['mesh_triangles']} | {kept(WALL)} | {kept(GROUND)} | {sum(c[1] for c in classes.values())} |")
PY
