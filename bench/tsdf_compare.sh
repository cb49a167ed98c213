#!/usr/bin/env bash
# semap against a voxel TSDF on the same input: Open3D's ScalableTSDFVolume (0.1 m and 0.05 m voxels)
# fusing semap's own SGBM depth maps with the same poses, beside `semap run` with PS and with O. Every method
# runs under `taskset -c $CPUS` (default 0,1: two cores), timed end to end by the wall clock; every mesh is
# evaluated by `semap eval` against the same frames. Prints one markdown table and writes it to OUT/tsdf_compare.md.
#
#   bench/tsdf_compare.sh [SEQUENCE] [--frames N] [--out DIR]
#
# SEQUENCE: a dataset folder semap reads (with poses); default: generated here, outside the timings, with
# `semap synth --preset urban --frames 80 --seed 95` (or --frames N frames).
# --frames N: use the first N frames of SEQUENCE (0 = all; default 0, or 80 when generating).
# --out DIR: working folder (default: a new folder under ${TMPDIR:-/tmp}).
# Environment: SEMAP (the semap executable, default build/tools/semap), PYTHON (a Python with open3d; default:
# python3 when it has open3d, else /usr/bin/python3, Debian's, where python3-open3d installs), CPUS (taskset list),
# SEMAP_ARGS (more options of the semap runs, e.g. "--set map.visibility=depth").
#
# TSDF parameters: voxel 0.1 m and 0.05 m; sdf_trunc = 4 voxels (Open3D's examples use 4-5 voxels: thin enough
# not to merge the two sides of a wall or a car, thick enough to bridge SGBM's few-centimetre noise at 10-20 m);
# depth_trunc = semap's depth.max_depth_m, so both see the same depth range.
# What the TSDF is timed on: `semap depth --all` (SGBM and semap's point filters, labels and sky removal as in
# `semap run`; dense: semap's per-frame point budget is not applied; writing the depth PNGs included) then
# bench/tsdf_fuse.py (reading the PNGs, integration, marching cubes, writing the OFF). semap's rows are the
# wall time of `semap run` (reading, depth, simplification, map, writing the mesh). Nothing is installed here.
set -euo pipefail

ROOT="$(cd "$(dirname "$0")/.." && pwd)"
SEMAP="${SEMAP:-$ROOT/build/tools/semap}"
CPUS="${CPUS:-0,1}"
SEQ=""
FRAMES=""
OUT=""
while (($#)); do
  case "$1" in
    --frames) FRAMES="${2:?--frames needs a number}"; shift 2 ;;
    --out) OUT="${2:?--out needs a folder}"; shift 2 ;;
    -h|--help) sed -n '2,22p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "tsdf_compare.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
    *) [[ -z "$SEQ" ]] || { echo "tsdf_compare.sh: one SEQUENCE only" >&2; exit 2; }; SEQ="$1"; shift ;;
  esac
done
if [[ -n "$FRAMES" && ! "$FRAMES" =~ ^[0-9]+$ ]]; then
  echo "tsdf_compare.sh: --frames must be a whole number >= 0, got '$FRAMES'" >&2; exit 2
fi

fail() { echo "tsdf_compare.sh: $*" >&2; exit 1; }
[[ -x "$SEMAP" ]] || fail "no semap executable at $SEMAP: build it (scripts/setup) or set SEMAP"
command -v taskset >/dev/null || fail "taskset is missing (Debian package util-linux)"
if [[ -z "${PYTHON:-}" ]]; then
  for candidate in python3 /usr/bin/python3; do
    if command -v "$candidate" >/dev/null && "$candidate" -c 'import open3d' 2>/dev/null; then
      PYTHON="$candidate"; break
    fi
  done
fi
if [[ -z "${PYTHON:-}" ]] || ! "$PYTHON" -c 'import open3d' 2>/dev/null; then
  fail "Open3D for Python is missing: install Debian's python3-open3d (apt-get install python3-open3d; it goes" \
       "into /usr/bin/python3) or set PYTHON to a Python that has open3d. This script installs nothing."
fi

OUT="${OUT:-$(mktemp -d "${TMPDIR:-/tmp}/tsdf_compare.XXXXXX")}"
mkdir -p "$OUT"
OUT="$(cd "$OUT" && pwd)"
if [[ -z "$SEQ" ]]; then
  FRAMES="${FRAMES:-80}"
  SEQ="$OUT/urban${FRAMES}_seed95"
  if [[ ! -e "$SEQ/done" ]]; then
    echo "== generating $FRAMES urban frames (seed 95) into $SEQ (not timed)"
    "$SEMAP" synth --preset urban --frames "$FRAMES" --seed 95 --out "$SEQ" --log-level warn
    touch "$SEQ/done"
  fi
fi
FRAMES="${FRAMES:-0}"
[[ -d "$SEQ" ]] || fail "no sequence folder $SEQ"
MAX_DEPTH_M="$("$SEMAP" config | awk '/^depth:/ {d = 1; next} /^[a-z]/ {d = 0} d && $1 == "max_depth_m:" {print $2; exit}')"
[[ -n "$MAX_DEPTH_M" ]] || fail "could not read depth.max_depth_m from 'semap config'"

now() { date +%s.%N; }
seconds() { "$PYTHON" -c "import sys; print(f'{float(sys.argv[2]) - float(sys.argv[1]):.3f}')" "$1" "$2"; }
evaluate() {  # MESH JSON
  "$SEMAP" eval "$SEQ" --mesh "$1" --json "$2" --set "input.max_frames=$FRAMES" --log-level warn > "${2%.json}.txt"
}

echo "== semap depth --all (SGBM depth maps and poses for the TSDF), on CPUs $CPUS"
t0="$(now)"
taskset -c "$CPUS" "$SEMAP" depth "$SEQ" --all --frames "$FRAMES" --out "$OUT/depth" --log-level warn \
  | tee "$OUT/depth.txt"
t1="$(now)"
DEPTH_S="$(seconds "$t0" "$t1")"

declare -A WALL_S
for voxel in 0.1 0.05; do
  name="tsdf_$voxel"
  mkdir -p "$OUT/$name"
  echo "== Open3D TSDF, voxel $voxel m, sdf_trunc 4 voxels, depth_trunc $MAX_DEPTH_M m, on CPUs $CPUS"
  t0="$(now)"
  taskset -c "$CPUS" "$PYTHON" "$ROOT/bench/tsdf_fuse.py" "$OUT/depth" --voxel-m "$voxel" --sdf-trunc-voxels 4 \
    --depth-trunc-m "$MAX_DEPTH_M" --out "$OUT/$name/mesh.off" | tee "$OUT/$name/fuse.json"
  t1="$(now)"
  WALL_S[$name]="$(seconds "$t0" "$t1")"
  evaluate "$OUT/$name/mesh.off" "$OUT/$name/eval.json"
done

for method in PS O; do
  name="semap_$method"
  echo "== semap run --method $method, on CPUs $CPUS"
  t0="$(now)"
  mkdir -p "$OUT/$name"
  # shellcheck disable=SC2086
  taskset -c "$CPUS" "$SEMAP" run "$SEQ" --method "$method" --frames "$FRAMES" --out "$OUT/$name" \
    --progress-interval 0 --log-level warn ${SEMAP_ARGS:-} > "$OUT/$name/run.txt"
  t1="$(now)"
  WALL_S[$name]="$(seconds "$t0" "$t1")"
  evaluate "$OUT/$name/mesh.ply" "$OUT/$name/eval.json"
done

# The table, from the timings and the eval JSON files.
"$PYTHON" - "$OUT" "$DEPTH_S" "${WALL_S[tsdf_0.1]}" "${WALL_S[tsdf_0.05]}" "${WALL_S[semap_PS]}" \
  "${WALL_S[semap_O]}" "$SEQ" "$CPUS" <<'PYTHON' | tee "$OUT/tsdf_compare.md"
import json, sys
out, depth_s, tsdf01_s, tsdf005_s, ps_s, o_s, seq, cpus = sys.argv[1:]
depth_s = float(depth_s)
rows = [("Open3D TSDF 0.1 m", "tsdf_0.1", depth_s, float(tsdf01_s)),
        ("Open3D TSDF 0.05 m", "tsdf_0.05", depth_s, float(tsdf005_s)),
        ("semap PS", "semap_PS", None, float(ps_s)),
        ("semap O", "semap_O", None, float(o_s))]

def fig(value, fmt):
    return "–" if value is None else fmt.format(value)

print(f"Sequence: {seq}; every method under `taskset -c {cpus}`, wall clock end to end.\n")
print("| method | frames | f/s end to end | depth (s) | fusion / map (s) | total (s) | triangles | OFF (MB) | "
      "RMSE vs Velodyne, strict (m) | RMSE vs Velodyne, paper (m) | median vs Velodyne (m) | completeness vs Velodyne | "
      "RMSE vs exact depth, strict (m) | area within 0.2 m | area beyond 2 m | scene completeness (0.2 m) |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
for label, name, depth, work in rows:
    e = json.load(open(f"{out}/{name}/eval.json"))
    frames = e["frames"]
    total = (depth or 0.0) + work
    lidar = e.get("lidar")
    paper = e.get("protocols", {}).get("paper", {}).get("lidar")
    exact = e.get("exact_depth")
    scene = e.get("scene_mesh")
    print(f"| {label} | {frames} | {frames / total:.2f} | {fig(depth, '{:.2f}')} | {work:.2f} | {total:.2f} | "
          f"{e['triangles']} | {e['off_bytes'] / 1e6:.2f} | "
          f"{fig(lidar and lidar['rmse_m'], '{:.4f}')} | {fig(paper and paper['rmse_m'], '{:.4f}')} | "
          f"{fig(lidar and lidar['median_abs_m'], '{:.4f}')} | "
          f"{fig(lidar and 100 * lidar['completeness'], '{:.1f} %')} | "
          f"{fig(exact and exact['rmse_m'], '{:.4f}')} | {fig(scene and 100 * scene['accuracy'], '{:.1f} %')} | "
          f"{fig(scene and 100 * scene['area_beyond_far'], '{:.1f} %')} | "
          f"{fig(scene and 100 * scene['completeness'], '{:.1f} %')} |")
print("\nTSDF rows: depth = `semap depth --all` (SGBM, semap's point filters, dense, PNGs written); fusion = "
      "bench/tsdf_fuse.py (PNGs read, integration, marching cubes, OFF written). semap rows: `semap run` as a whole. "
      "Strict = every error of reference depths in eval's range; paper = <= 15 m, |error| <= 2 m. Area columns: "
      "the mesh sampled by area against the exact scene mesh (generated sequences only).")
PYTHON
echo "== wrote $OUT/tsdf_compare.md"
