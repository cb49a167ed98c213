#!/usr/bin/env bash
# The dense map's figures: `semap run` on a generated urban sequence, exhaustive, pinned to two cores,
# for each configuration below, one after the other; then `semap eval` of each mesh. Prints a markdown table:
# frames per second, per-step mean ms of the map, CPU use, peak RSS, mesh size, accuracy.
#
#   bench/dense_map.sh [SEQ] [--frames N] [--out DIR] [--configs "name:--set ... ;name2:..."]
#
# SEQ defaults to a generated `synth --preset urban --frames 200 --seed 1` (made once in DIR). The default
# configurations: the depth-vote map (the default) with PS and O at full resolution, PS at half resolution,
# and the exact ray map with PS (the reference; `map.visibility=rays`).
set -euo pipefail
cd "$(dirname "$0")/.."
SEMAP=${SEMAP:-build/tools/semap}
SEQ=""; FRAMES=200; OUT=bench_dense
CONFIGS="depth_PS:--method PS;depth_O:--method O;depth_PS_half:--method PS --set depth.half_resolution=true;rays_PS:--method PS --set map.visibility=rays"
while (($#)); do
  case $1 in
    --frames) FRAMES=$2; shift 2 ;;
    --out) OUT=$2; shift 2 ;;
    --configs) CONFIGS=$2; shift 2 ;;
    -h|--help) sed -n 2,10p "$0"; exit 0 ;;
    *) SEQ=$1; shift ;;
  esac
done
mkdir -p "$OUT"
if [ -z "$SEQ" ]; then
  SEQ="$OUT/seq_urban_$FRAMES"
  [ -e "$SEQ/done" ] || { "$SEMAP" synth --preset urban --frames "$FRAMES" --seed 1 --out "$SEQ" >/dev/null && touch "$SEQ/done"; }
fi
echo "| run | f/s | map ms | votes | carve | mesh | locate+insert | finalise | depth ms | simplify ms | CPU % | peak RSS MB | triangles | OFF MB | RMSE vs Velodyne (strict / paper) | median | RMSE vs exact depth | area within 0.2 m / beyond 2 m | completeness (truth at 0.2 m, else Velodyne px) |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
IFS=';' read -ra RUNS <<< "$CONFIGS"
for run in "${RUNS[@]}"; do
  name=${run%%:*}; args=${run#*:}
  # shellcheck disable=SC2086
  /usr/bin/time -f "%M %P" -o "$OUT/$name.time" taskset -c 0,1 "$SEMAP" run "$SEQ" --frames "$FRAMES" $args \
    --out "$OUT/$name" --log-level warn > "$OUT/$name.log" 2>&1
  "$SEMAP" eval "$SEQ" --mesh "$OUT/$name/mesh.ply" --set input.max_frames="$FRAMES" --json "$OUT/$name/eval.json" \
    > "$OUT/$name/eval.txt" 2>&1
  python3 - "$OUT/$name" "$OUT/$name.time" "$name" <<'PY'
import json, sys, os
run, timef, name = sys.argv[1:4]
s = json.load(open(os.path.join(run, "summary.json")))
e = json.load(open(os.path.join(run, "eval.json")))
rss_kb, cpu = open(timef).read().split()[:2]
st = s["stages"]
m = lambda k: st.get(k, {}).get("mean_ms", 0.0)
def find(d, *keys):
    for k in keys:
        if not isinstance(d, dict) or k not in d: return None
        d = d[k]
    return d
txt = open(os.path.join(run, "eval.txt")).read()
def grab(prefix, field):
    for line in txt.splitlines():
        if line.startswith(prefix) and field in line:
            return line.split(field)[1].split()[0]
    return "?"
paper = "?"
for line in txt.splitlines():
    if line.strip().startswith("paper"):
        paper = line.split("RMSE")[1].split()[0]; break
area = txt.split("accuracy")[1].split("%")[0].strip() if "accuracy" in txt else "?"
beyond2 = txt.split("beyond 0.50 m, ")[1].split("%")[0] if "beyond 0.50 m, " in txt else "?"
# Completeness against the scene mesh (τ = 0.2 m) where the sequence has one, else the Velodyne pixels covered
# (strict protocol).
scene = e.get("scene_mesh")
compl_share = scene["completeness"] if scene else find(e, "lidar", "completeness")
compl = f"{100.0 * compl_share:.1f}" if compl_share is not None else "?"
off_mb = os.path.getsize(os.path.join(run, "mesh.off")) / 1e6
print(f"| {name} | {s['fps']:.3f} | {m('map'):.0f} | {m('map.votes'):.0f} | {m('map.carve'):.0f} | {m('map.mesh'):.0f} | "
      f"{m('map.locate') + m('map.insert'):.0f} | {m('map.finalise'):.0f} | {m('depth'):.0f} | {m('simplify'):.0f} | {cpu} | "
      f"{int(rss_kb) / 1024:.0f} | {s['mesh_triangles']:,} | {off_mb:.1f} | {grab('vs Velodyne', 'RMSE')} / {paper} | "
      f"{grab('vs Velodyne', 'median')} | {grab('vs exact depth', 'RMSE')} | {area} % / {beyond2} % | {compl} % |")
PY
done
