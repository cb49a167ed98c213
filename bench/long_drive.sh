#!/usr/bin/env bash
# The long-drive figures: is the map's time per frame flat and its memory bounded over a long
# drive? `semap run` on a generated urban drive (default 2,000 frames, 1242×375, labels from the sequence),
# exhaustive, pinned to two cores; then per-frame map time, live map size and RSS from the run's frames.csv.
# Prints a markdown summary by block of N/10 frames (map ms of the second block against the last one: for 2,000
# frames, frames 200–400 against the last 200; RSS and live cells at each block's end) and draws
# OUT/long_drive.png (gnuplot).
#
#   bench/long_drive.sh [SEQ] [--frames N] [--out DIR] [--args "--method PS --set ..."]
#
# SEQ defaults to `semap synth --preset urban --frames N --seed 1`, made once in DIR (about 9 minutes and
# 7 GB for 2,000 frames). Default arguments: --method PS (the defaults otherwise).
set -euo pipefail
cd "$(dirname "$0")/.."
SEMAP=${SEMAP:-build/tools/semap}
SEQ=""; FRAMES=2000; OUT=long_drive; ARGS="--method PS"
while (($#)); do
  case $1 in
    --frames) FRAMES=$2; shift 2 ;;
    --out) OUT=$2; shift 2 ;;
    --args) ARGS=$2; shift 2 ;;
    -h|--help) sed -n 2,11p "$0"; exit 0 ;;
    -*) echo "long_drive.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
    *) SEQ=$1; shift ;;
  esac
done
[[ "$FRAMES" =~ ^[0-9]+$ ]] && ((FRAMES >= 20)) || { echo "long_drive.sh: --frames must be a whole number >= 20, got '$FRAMES'" >&2; exit 2; }
mkdir -p "$OUT"
if [ -z "$SEQ" ]; then
  SEQ="$OUT/seq_urban_$FRAMES"
  [ -e "$SEQ/done" ] || { "$SEMAP" synth --preset urban --frames "$FRAMES" --seed 1 --out "$SEQ" >/dev/null && touch "$SEQ/done"; }
fi
RUN="$OUT/run"
# shellcheck disable=SC2086
/usr/bin/time -f "%M %P %e" -o "$OUT/time.txt" taskset -c 0,1 "$SEMAP" run "$SEQ" --frames "$FRAMES" $ARGS \
  --out "$RUN" --log-level warn --progress-interval 0 > "$OUT/run.log" 2>&1
python3 - "$RUN/frames.csv" "$OUT/time.txt" "$RUN/summary.json" "$ARGS" <<'PY'
import csv, json, statistics, sys
frames_csv, time_txt, summary_json, args = sys.argv[1:5]
rows = list(csv.DictReader(open(frames_csv)))
n = len(rows)
rss_kb, cpu, wall = open(time_txt).read().split()[:3]
s = json.load(open(summary_json))
col = lambda k, a, b: [float(r[k]) for r in rows[a:b]]
mean = lambda k, a, b: statistics.fmean(col(k, a, b))
block = n // 10  # the issue's blocks: 200 of 2,000 frames
early, late = mean("map_ms", block, 2 * block), mean("map_ms", n - block, n)
print(f"`semap run SEQ --frames {n} {args}`: {s['fps']:.3f} f/s over {n} frames, CPU {cpu}, peak RSS {int(rss_kb) / 1024:.0f} MiB, "
      f"{s['mesh_triangles']:,} triangles in the written mesh.\n")
print(f"Map time per frame, frames {block}–{2 * block}: {early:.1f} ms; last {block} frames: {late:.1f} ms "
      f"({100 * (late / early - 1):+.1f} %; the issue's bound: within 10 %).\n")
print("| frames | map ms | votes ms | carve ms | mesh ms | finalise ms | depth ms | CPU ms per frame | live cells (end) | live vertices (end) | RSS MB (end) |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
for a in range(0, n - n % block, block):
    b = n if a + 2 * block > n else a + block
    cpu_ms = 1000 * (float(rows[b - 1]["cpu_s"]) - (float(rows[a - 1]["cpu_s"]) if a else 0.0)) / (b - a)
    print(f"| {a}–{b} | {mean('map_ms', a, b):.1f} | {mean('map.votes_ms', a, b):.1f} | {mean('map.carve_ms', a, b):.1f} | "
          f"{mean('map.mesh_ms', a, b):.1f} | {mean('map.finalise_ms', a, b):.1f} | {mean('depth_ms', a, b):.1f} | {cpu_ms:.1f} | "
          f"{int(rows[b - 1]['map_cells']):,} | {int(rows[b - 1]['map_vertices']):,} | {float(rows[b - 1]['rss_mb']):.0f} |")
PY
gnuplot <<GNUPLOT
set terminal pngcairo size 1400,600 font ",10"
set output "$OUT/long_drive.png"
set datafile separator ","
set key top left
set grid
set xlabel "frame"
set multiplot layout 1,2 title "semap long drive: $FRAMES generated urban frames, $ARGS, taskset -c 0,1"
set ylabel "ms per frame (mean of 20)"
plot "$RUN/frames.csv" every ::1 using (floor(\$1/20)*20):(\$14) smooth unique with lines lw 2 title "map", \
     "" every ::1 using (floor(\$1/20)*20):(\$18) smooth unique with lines lw 2 title "votes"
set ylabel "MB / thousand cells"
plot "$RUN/frames.csv" every ::1 using 1:28 with lines lw 2 title "RSS (MB)", \
     "" every ::1 using 1:(\$25/1000) with lines lw 2 title "live cells (thousands)"
unset multiplot
GNUPLOT
echo "Wrote $OUT/long_drive.png"
