#!/usr/bin/env bash
# Does the engine keep up with the camera, and what does falling behind cost? `semap run SEQ --realtime S` at
# each speed S (× the sensor's rate), pinned to two cores, beside a batch run of every frame; each mesh is then
# evaluated (`semap eval`: strict, paper and, with labels, static protocols). Prints a markdown table (frames
# integrated, dropped by reason, latency to the published mesh p50 / p95 / max, the map's latency p95, peak
# RSS, RMSE per protocol and its change against the batch run) and draws OUT/realtime_speeds.png (gnuplot):
# the share integrated and the strict RMSE against the speed.
#
#   bench/realtime_speeds.sh SEQ [--speeds "1 2 4"] [--out DIR] [--args "--method PS --set ..."]
#
# Default arguments: --method PS --set semantics.source=enet (the same for every run and for the evaluation).
set -euo pipefail
cd "$(dirname "$0")/.."
SEMAP=${SEMAP:-build/tools/semap}
SEQ=""; SPEEDS="1 2 4"; OUT=realtime_speeds; ARGS="--method PS --set semantics.source=enet"
while (($#)); do
  case $1 in
    --speeds) SPEEDS=$2; shift 2 ;;
    --out) OUT=$2; shift 2 ;;
    --args) ARGS=$2; shift 2 ;;
    -h|--help) sed -n 2,11p "$0"; exit 0 ;;
    -*) echo "realtime_speeds.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
    *) SEQ=$1; shift ;;
  esac
done
[ -n "$SEQ" ] || { echo "realtime_speeds.sh: name the sequence (see --help)" >&2; exit 2; }
for s in $SPEEDS; do
  [[ "$s" =~ ^[0-9]+([.][0-9]+)?$ ]] || { echo "realtime_speeds.sh: a speed must be a positive number, got '$s'" >&2; exit 2; }
done
mkdir -p "$OUT"
# The evaluation takes the run's own settings that bear on it (the label source for the static scene).
EVAL_ARGS=$(grep -o -- '--set semantics[.][^ ]*' <<< "$ARGS" || true)
run_one() {  # NAME [--realtime S]
  local name=$1; shift
  # shellcheck disable=SC2086
  taskset -c 0,1 "$SEMAP" run "$SEQ" $ARGS "$@" --out "$OUT/$name" --log-level warn --progress-interval 0 \
    > "$OUT/$name.log" 2>&1
  # shellcheck disable=SC2086
  rm -f "$OUT/$name/eval.json"
  # A sequence without Velodyne or exact depth has nothing to compare with: no RMSE, the rest stands.
  "$SEMAP" eval "$SEQ" --mesh "$OUT/$name/mesh.ply" $EVAL_ARGS --json "$OUT/$name/eval.json" \
    > "$OUT/$name.eval.log" 2>&1 || echo "realtime_speeds.sh: $name: no evaluation (see $OUT/$name.eval.log)" >&2
}
run_one batch
for s in $SPEEDS; do run_one "speed_$s" --realtime "$s"; done

python3 - "$OUT" "$SPEEDS" <<'PY'
import csv, json, os, sys
out, speeds = sys.argv[1], sys.argv[2].split()

def figures(name):
    d = os.path.join(out, name)
    s = json.load(open(os.path.join(d, "summary.json")))
    path = os.path.join(d, "eval.json")
    e = json.load(open(path)) if os.path.exists(path) else {"protocols": {}}
    rows = list(csv.DictReader(open(os.path.join(d, "frames.csv"))))
    total = s["frames_integrated"] + s["frames_dropped"] + s["frames_failed"]
    rmse = {p: e["protocols"][p]["lidar"]["rmse_m"] for p in e["protocols"] if "lidar" in e["protocols"][p]}
    return {"integrated": s["frames_integrated"], "total": total, "dropped": s.get("dropped_by_reason", {}),
            "fps": s["fps"], "lat": s["latency_ms"], "rss": max(float(r["rss_mb"]) for r in rows),
            "rmse": rmse}

base = figures("batch")
print("| run | integrated | dropped (behind / no labels) | f/s | published p50 / p95 / max ms | map p95 ms | "
      "peak RSS MB | RMSE strict / paper / static m | vs batch |")
print("|---|---|---|---|---|---|---|---|---|")
plot = []
for name, label in [("batch", "batch")] + [("speed_" + s, s + "x") for s in speeds]:
    f = figures(name)
    p, m = f["lat"]["published"], f["lat"]["map"]
    r = [f["rmse"].get(k) for k in ("strict", "paper", "static")]
    vs = " / ".join("%+.1f %%" % (100 * (a / base["rmse"][k] - 1)) if a is not None and k in base["rmse"] else "-"
                    for a, k in zip(r, ("strict", "paper", "static")))
    print("| %s | %d / %d (%.0f %%) | %d / %d | %.2f | %.0f / %.0f / %.0f | %.0f | %.0f | %s | %s |" % (
        label, f["integrated"], f["total"], 100.0 * f["integrated"] / f["total"],
        f["dropped"].get("behind", 0), f["dropped"].get("no_keyframe_labels", 0), f["fps"], p["p50"], p["p95"],
        p["max"], m["p95"], f["rss"], " / ".join("%.3f" % a if a is not None else "-" for a in r), vs))
    if name != "batch":
        plot.append((float(label[:-1]), 100.0 * f["integrated"] / f["total"], f["rmse"].get("strict", float("nan"))))
with open(os.path.join(out, "speeds.dat"), "w") as d:
    for row in plot: d.write("%g %g %g\n" % row)
open(os.path.join(out, "has_rmse"), "w").write("1" if "strict" in base["rmse"] else "0")
PY
if command -v gnuplot >/dev/null; then
  RMSE_CURVE=", \"$OUT/speeds.dat\" using 1:3 axes x1y2 with linespoints lw 2 title \"strict RMSE\""
  [ "$(cat "$OUT/has_rmse")" = 1 ] || RMSE_CURVE=""
  gnuplot <<GP
set terminal pngcairo size 800,450
set output "$OUT/realtime_speeds.png"
set xlabel "speed (x the sensor's rate)"
set ylabel "frames integrated (%)"
set y2label "strict RMSE (m)"
set ytics nomirror
set y2tics
set yrange [0:100]
set grid
set key bottom left
plot "$OUT/speeds.dat" using 1:2 with linespoints lw 2 title "integrated"$RMSE_CURVE
GP
  echo "wrote $OUT/realtime_speeds.png"
fi
