#!/usr/bin/env bash
# A split run on simulated hosts: network namespaces joined by a bridge that carries multicast, one for the
# map node (`semap map`) and one per depth node (`semap run --publish-depth`), each node pinned to its own
# core with taskset; then the single process on the same cores for comparison. Needs root (ip netns).
#   bench/split_run.sh SEQ [--depth-cores "1"] [--map-core 0] [--single-cores 0,1] [--args "..."]
#     --depth-cores "1 2": one depth node per core listed (frames shared out by id modulo their number)
#     --args: options for every node and the single run (e.g. "--method PS --set semantics.source=enet")
#     --depth-args: options for the depth nodes and the single run only (e.g. "--realtime")
# Prints each run's frame rate (the split run's: frames over the time from the depth nodes' start to the map
# node's end; a node's own f/s counts from its start, the map node's from before the first frame arrived), the map node's latency to the published mesh, the depth nodes' bytes and
# encoding time per frame, and whether the meshes are equal byte for byte. Outputs stay in the work folder.
set -euo pipefail
cd "$(dirname "$0")/.."
SEMAP=$(realpath "${SEMAP:-build/tools/semap}")
seq=$(realpath "$1")
shift
depth_cores="1" map_core=0 single_cores=0,1 args="" depth_args=""
while [ $# -gt 0 ]; do
  case "$1" in
    --depth-cores) depth_cores=$2; shift 2 ;;
    --map-core) map_core=$2; shift 2 ;;
    --single-cores) single_cores=$2; shift 2 ;;
    --args) args=$2; shift 2 ;;
    --depth-args) depth_args=$2; shift 2 ;;
    *) echo "unknown option $1" >&2; exit 2 ;;
  esac
done
work=$(mktemp -d /tmp/semap_split.XXXXXX)
echo "work folder: $work"
# ttl=1: the datagrams cross the bridge (ttl=0 keeps them on the sending host). A bigger receive buffer than
# Linux's default lets the map node's socket hold a whole frame's burst of datagrams.
url="udpm://239.255.76.67:7667?ttl=1&recv_buf_size=8388608"
nodes=(map)
i=0
for c in $depth_cores; do nodes+=("d$i"); i=$((i + 1)); done
n_depth=$i

rmem_max_before=$(cat /proc/sys/net/core/rmem_max)
cleanup() {
  for ns in "${nodes[@]}" br; do ip netns del "semap_$ns" 2>/dev/null || true; done
  echo "$rmem_max_before" >/proc/sys/net/core/rmem_max
}
trap cleanup EXIT
echo 8388608 >/proc/sys/net/core/rmem_max
ip netns add semap_br
ip -n semap_br link add br0 type bridge mcast_snooping 0
ip -n semap_br link set br0 up
k=1
for n in "${nodes[@]}"; do
  ip netns add "semap_$n"
  ip link add "v_$n" type veth peer name eth0 netns "semap_$n"
  ip link set "v_$n" netns semap_br
  ip -n semap_br link set "v_$n" master br0 up
  ip -n "semap_$n" addr add "10.77.0.$k/24" dev eth0
  ip -n "semap_$n" link set eth0 up
  ip -n "semap_$n" link set lo up
  ip -n "semap_$n" route add 224.0.0.0/4 dev eth0
  k=$((k + 1))
done

# shellcheck disable=SC2086
ip netns exec semap_map taskset -c "$map_core" "$SEMAP" map --lcm-url "$url" --out "$work/map" \
  --progress-interval 5 $args >"$work/map.txt" 2>&1 &
map_pid=$!
sleep 1
t0=$(date +%s.%N)
pids=()
i=0
for c in $depth_cores; do
  # shellcheck disable=SC2086
  ip netns exec "semap_d$i" taskset -c "$c" "$SEMAP" run "$seq" --publish-depth --share "$i/$n_depth" \
    --node "d$i" --lcm-url "$url" --out "$work/d$i" --progress-interval 5 $args $depth_args >"$work/d$i.txt" 2>&1 &
  pids+=($!)
  i=$((i + 1))
done
for p in "${pids[@]}"; do wait "$p"; done
wait "$map_pid"
t1=$(date +%s.%N)
# shellcheck disable=SC2086
taskset -c "$single_cores" "$SEMAP" run "$seq" --out "$work/single" --progress-interval 5 $args $depth_args \
  >"$work/single.txt" 2>&1

python3 - "$work" "$n_depth" "$t0" "$t1" <<'PY'
import json, sys
work, n, t0, t1 = sys.argv[1], int(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4])
def summary(d):
    return json.load(open(f'{work}/{d}/summary.json'))
for d in ['map'] + [f'd{i}' for i in range(n)] + ['single']:
    s = summary(d)
    lat = s.get('latency_ms', {}).get('published', {})
    print(f"{d:7s} frames {s['frames_integrated']:4d} integrated, {s['frames_dropped']:3d} dropped, "
          f"{s['fps']:.2f} f/s, CPU {s['cpu_s']:.1f} s, published latency p50 {lat.get('p50', 0):.0f} "
          f"p95 {lat.get('p95', 0):.0f} ms")
for i in range(n):
    for line in open(f'{work}/d{i}.txt'):
        if 'sent' in line and 'datagrams' in line:
            print(f'd{i}:', line.split('] ', 2)[-1].strip())
for line in open(f'{work}/map.txt'):
    if 'depth frames:' in line:
        print('map:', line.split('] ', 2)[-1].strip())
m = summary('map')
print(f"split run: {m['frames_integrated']} frames in {t1 - t0:.2f} s from the depth nodes' start to the map "
      f"node's end: {m['frames_integrated'] / (t1 - t0):.2f} f/s")
same = open(f'{work}/map/mesh.ply', 'rb').read() == open(f'{work}/single/mesh.ply', 'rb').read()
print('mesh.ply of the map node and of the single process:', 'equal byte for byte' if same else 'DIFFER')
PY
