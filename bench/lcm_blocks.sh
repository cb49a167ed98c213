#!/usr/bin/env bash
# Mesh over LCM in blocks, measured on real UDP multicast with the kernel's default receive buffers: a short
# `semap run` of a generated sequence recorded by lcm-logger from the start, in a private network namespace
# (needs root); then the bytes per frame (changes and re-sends), the largest message, and how long a
# subscriber that joins after half the frames takes to hold everything one listening from the start holds.
#   bench/lcm_blocks.sh [SEQ] [--set lcm.resend_bytes_per_s=...]   (SEQ default: a 20-frame urban sequence)
set -euo pipefail
cd "$(dirname "$0")/.."
SEMAP=${SEMAP:-build/tools/semap}
work=$(mktemp -d)
seq=${1:-}
[ $# -gt 0 ] && shift
if [ -z "$seq" ]; then
  seq=$work/seq
  "$SEMAP" synth --preset urban --frames 20 --seed 95 --out "$seq" >/dev/null
fi
url='udpm://239.255.76.67:7667?ttl=0'
unshare -n bash -c "set -e; ip link set lo up; ip route add 224.0.0.0/4 dev lo
  echo \"rmem_default \$(cat /proc/sys/net/core/rmem_default)\"
  lcm-logger -q -f --lcm-url='$url' $work/run.lcmlog >$work/logger.txt 2>&1 & logger=\$!
  trap 'kill -INT \$logger; wait \$logger' EXIT; sleep 0.5
  /usr/bin/time -f 'run: %e s wall' $SEMAP run $seq --out $work/out --lcm-url '$url' $* 2>&1 | grep -E 'frames processed|mesh:|LCM:|run:'
  sleep 0.5"
python3 - "$work/run.lcmlog" <<'PY'
import struct, sys
data = open(sys.argv[1], 'rb').read()
pos, events = 0, []
while pos + 28 <= len(data):
    sync, num, ts, cl, dl = struct.unpack('>IqqII', data[pos:pos + 28])
    events.append((ts, data[pos + 28:pos + 28 + cl].decode(), data[pos + 28 + cl:pos + 28 + cl + dl]))
    pos += 28 + cl + dl
stats = [ts for ts, ch, d in events if ch.endswith('FRAME_STATS')]
seen, kinds = set(), {}
largest = 0
for ts, ch, d in events:
    if not (ch.endswith('MESH_BLOCK') or ch.endswith('MESH_END')):
        continue
    largest = max(largest, len(d))
    if ch.endswith('MESH_END'):
        kind = 'index'
    else:
        # A change is the first message of a block version: its delta, or each part of its whole state
        # when no delta announced it; anything else is a re-send.
        block, version, delta = d[44:60], d[64:68], struct.unpack('>i', d[68:72])[0] > 0
        if delta:
            kind = 'resend' if (block, version) in seen else 'delta'
            seen.add((block, version))
        else:
            key = (block, version, d[73:77])
            kind = 'resend' if key in seen or (block, version) in seen else 'whole'
            seen.add(key)
    during = stats[0] <= ts <= stats[-1]
    k = (kind, 'run' if during else 'closing')
    kinds[k] = kinds.get(k, 0) + len(d)
frames = len(stats) - 1  # the last stats message is the run's summary
t = (stats[-1] - stats[0]) / 1e6
print(f'frames {frames}, {t:.1f} s from the first to the last frame stats; largest mesh message {largest} bytes')
for k in sorted(kinds):
    print(f'  {k[0]:7s} {k[1]:8s} {kinds[k]:>12,d} bytes' + (f'  = {kinds[k] / frames:,.0f} bytes/frame' if k[1] == 'run' else ''))
changes = sum(v for k, v in kinds.items() if k[1] == 'run' and k[0] in ('delta', 'whole'))
resends = sum(v for k, v in kinds.items() if k[1] == 'run' and k[0] in ('resend', 'index'))
print(f'during the run: changes {changes / frames:,.0f} bytes/frame, re-sends {resends / t:,.0f} bytes/s')
print(f'half the frames at {(stats[frames // 2] - events[0][0]) / 1e6:.2f} s into the log')
PY
half=$(python3 -c "
import struct,sys
d=open('$work/run.lcmlog','rb').read();p=0;s=[];t0=None
while p+28<=len(d):
  sy,n,ts,cl,dl=struct.unpack('>IqqII',d[p:p+28]);t0=ts if t0 is None else t0
  if d[p+28:p+28+cl].decode().endswith('FRAME_STATS'): s.append(ts)
  p+=28+cl+dl
print((s[(len(s)-1)//2]-t0)/1e6)")
"$SEMAP" lcm-mesh "$work/run.lcmlog" --out "$work/all.ply" 2>&1 | grep -E 'events|lacking' | sed 's/^\[[^]]*\] //'
"$SEMAP" lcm-mesh "$work/run.lcmlog" --join-after "$half" --out "$work/late.ply" 2>&1 | grep -E 'converged|lacking' | sed 's/^\[[^]]*\] //'
echo "(joined at $half s)"
[ -n "${KEEP:-}" ] && echo "kept $work" || rm -rf "$work"
