#!/usr/bin/env bash
# Frame rate of `semap run` with ENet labels (on keyframes every N frames, semantics.enet_every_frames) against
# the same run with label files (ENet off the critical path), under `taskset -c $CPUS`.
# Prints one markdown table (and writes it to OUT/enet_rate.md).
#
#   bench/enet_rate.sh [--every "1 2 4 6"] [--out DIR] [--repeats R]
#
# Sequences: KITTI odometry 04 (51 real frames, $SEMAP_SHARED/data/kitti_odometry_04; its "label files" are
# ENet's own labels of every frame, written beforehand by semap_enet_keyframe_eval --write-labels, outside the
# timings) and a generated street (`semap synth --preset urban --frames 80 --seed 95`, made here outside the
# timings; its label files are the exact labels). Every run: `semap run SEQ --method PS`, defaults otherwise.
# Rows: label files (semantics.source disk), then ENet (semantics.source enet) every N frames for each N of
# --every, then ENet every N at half the input size (512x256) for the smallest N > 1 of --every.
# Columns: f/s (frames / wall time of the run, summary.json), the ratio to the label-file run, CPU seconds per
# frame (all threads), the segment thread's mean time per keyframe and the depth workers' mean wait for labels
# (N = 1 segments in the depth workers: no segment thread, "–").
# Timings are only comparable on an idle machine: the load average before and after is printed; run it again
# when it was not idle. With --repeats R (default 1) every configuration runs once per round, R rounds, and
# each row is its fastest run (the one least disturbed by other processes).
# Environment: SEMAP (default build/tools/semap), EVAL (default build/bench/semap_enet_keyframe_eval),
# SEMAP_SHARED (default ../shared), CPUS (default 0,1).
set -euo pipefail

ROOT="$(cd "$(dirname "$0")/.." && pwd)"
SEMAP="${SEMAP:-$ROOT/build/tools/semap}"
EVAL="${EVAL:-$ROOT/build/bench/semap_enet_keyframe_eval}"
SHARED="${SEMAP_SHARED:-$ROOT/../shared}"
CPUS="${CPUS:-0,1}"
EVERY="1 2 4 6"
OUT=""
REPEATS=1
while (($#)); do
  case "$1" in
    --every) EVERY="${2:?--every needs a list}"; shift 2 ;;
    --out) OUT="${2:?--out needs a folder}"; shift 2 ;;
    --repeats) REPEATS="${2:?--repeats needs a number}"; shift 2 ;;
    -h|--help) sed -n '2,21p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "enet_rate.sh: unknown argument $1 (see --help)" >&2; exit 2 ;;
  esac
done
for n in $EVERY; do
  [[ "$n" =~ ^[1-9][0-9]*$ ]] || { echo "enet_rate.sh: --every takes whole numbers >= 1, got '$n'" >&2; exit 2; }
done
[[ "$REPEATS" =~ ^[1-9][0-9]*$ ]] || { echo "enet_rate.sh: --repeats must be >= 1, got '$REPEATS'" >&2; exit 2; }

fail() { echo "enet_rate.sh: $*" >&2; exit 1; }
[[ -x "$SEMAP" ]] || fail "no semap executable at $SEMAP: build it (scripts/setup) or set SEMAP"
[[ -x "$EVAL" ]] || fail "no semap_enet_keyframe_eval at $EVAL: build the bench targets or set EVAL"
command -v taskset >/dev/null || fail "taskset is missing (Debian package util-linux)"
command -v jq >/dev/null || fail "jq is missing (Debian package jq)"
KITTI="$SHARED/data/kitti_odometry_04"
MODEL="$SHARED/models/enet-cityscapes/enet-model.net"
[[ -d "$KITTI" ]] || fail "$KITTI not found (set SEMAP_SHARED)"
[[ -f "$MODEL" ]] || fail "$MODEL not found (set SEMAP_SHARED)"

OUT="${OUT:-$(mktemp -d "${TMPDIR:-/tmp}/enet_rate.XXXXXX")}"
mkdir -p "$OUT"
echo "enet_rate.sh: working in $OUT" >&2

# Inputs, outside the timings.
URBAN="$OUT/urban80"
if [[ ! -d "$URBAN" ]]; then
  "$SEMAP" synth --preset urban --frames 80 --seed 95 --out "$URBAN" --log-level warn >&2
fi
KITTI_LABELS="$OUT/kitti04_enet_labels"
if [[ ! -d "$KITTI_LABELS" ]]; then
  echo "enet_rate.sh: ENet labels of every KITTI 04 frame (the label files of the comparison)..." >&2
  "$EVAL" "$KITTI" --every 1 --model "$MODEL" --write-labels "$KITTI_LABELS" > "$OUT/kitti04_labels_eval.md"
fi

LOAD_BEFORE="$(cut -d' ' -f1-3 /proc/loadavg)"

# measure NAME SEQ ARGS...: one run; appends "fps cpu_per_frame segment_ms wait_ms" to OUT/results/NAME.
measure() {
  local name="$1" seq="$2"
  shift 2
  local dir="$OUT/runs/$name.$r"
  rm -rf "$dir"
  taskset -c "$CPUS" "$SEMAP" run "$seq" --method PS --out "$dir" --log-level warn --progress-interval 100000 \
    --set semantics.enet_model_path="$MODEL" "$@" >&2
  jq -r '[.fps, .cpu_s / .frames_processed, (.stages.segment.mean_ms // 0),
          (.stages["depth.label_wait"].mean_ms // 0)] | @tsv' "$dir/summary.json" >> "$OUT/results/$name"
}
# best NAME: the line of the fastest run.
best() { sort -g -r -k1,1 "$OUT/results/$1" | head -n 1; }

SMALL_N=""
for n in $EVERY; do
  if ((n > 1)) && [[ -z "$SMALL_N" || n -lt SMALL_N ]]; then SMALL_N="$n"; fi
done
rm -rf "$OUT/results"
mkdir -p "$OUT/results"
# Every configuration once per round, rounds one after the other: a change of the machine's load during the
# measurement hits every row alike.
for ((r = 1; r <= REPEATS; r++)); do
  for tag in KITTI generated; do
    if [[ "$tag" == KITTI ]]; then
      seq="$KITTI"; files=(--set semantics.source=disk --set input.labels_dir="$KITTI_LABELS")
    else
      seq="$URBAN"; files=(--set semantics.source=disk)
    fi
    measure "$tag.files" "$seq" "${files[@]}"
    for n in $EVERY; do
      measure "$tag.enet$n" "$seq" --set semantics.source=enet --set semantics.enet_every_frames="$n"
    done
    if [[ -n "$SMALL_N" ]]; then
      measure "$tag.enet$SMALL_N.half" "$seq" --set semantics.source=enet --set semantics.enet_every_frames="$SMALL_N" \
        --set semantics.enet_input_width_px=512 --set semantics.enet_input_height_px=256
    fi
  done
done

TABLE="$OUT/enet_rate.md"
{
  echo "| sequence | labels | ENet every N | ENet input | f/s | vs label files | CPU s / frame | ENet ms / keyframe | label wait ms / frame |"
  echo "|---|---|---:|---|---:|---:|---:|---:|---:|"
} > "$TABLE"
row() {  # row SEQ_NAME LABELS N INPUT BASE_FPS "fps cpu seg wait"
  local fps cpu seg wait
  read -r fps cpu seg wait <<< "$6"
  awk -v s="$1" -v l="$2" -v n="$3" -v i="$4" -v base="$5" -v f="$fps" -v c="$cpu" -v g="$seg" -v w="$wait" \
    'BEGIN { printf "| %s | %s | %s | %s | %.2f | %.2f | %.3f | %s | %s |\n", s, l, n, i, f, f / base, c,
             (g > 0 ? sprintf("%.0f", g) : "–"), (g > 0 ? sprintf("%.0f", w) : "–") }' >> "$TABLE"
}
for tag in KITTI generated; do
  seq_name="KITTI 04 (51 frames)"
  [[ "$tag" == KITTI ]] || seq_name="generated (80 frames)"
  base="$(best "$tag.files")"
  base_fps="$(cut -f1 <<< "$base")"
  row "$seq_name" "label files" "–" "–" "$base_fps" "$base"
  for n in $EVERY; do
    row "$seq_name" "ENet" "$n" "1024x512" "$base_fps" "$(best "$tag.enet$n")"
  done
  if [[ -n "$SMALL_N" ]]; then
    row "$seq_name" "ENet" "$SMALL_N" "512x256" "$base_fps" "$(best "$tag.enet$SMALL_N.half")"
  fi
done
{
  echo
  echo "$(date -u '+%Y-%m-%d %H:%M UTC'), $(nproc) CPUs visible, taskset -c $CPUS, runs per row: $REPEATS (the fastest);" \
       "load average before: $LOAD_BEFORE, after: $(cut -d' ' -f1-3 /proc/loadavg)"
} >> "$TABLE"
cat "$TABLE"
