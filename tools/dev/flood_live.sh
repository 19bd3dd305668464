#!/usr/bin/env bash
# Measures a live flood (issue 14's table): one of 3 cameras sends, from frame 10 on, 9 extra
# messages per frame of 10,000 detections each (~340 kB; about 90 MB/s at 30 fps) over udpm://
# inside a private network namespace (never on the machine's network; needs root). Prints the
# daemon's counters and the other cameras' track-frames against a run without that camera.
#
# Usage: tools/dev/flood_live.sh [--build-dir DIR] [--recv-buf-size BYTES]
#   --build-dir DIR        the build holding daemon/mvtrackd, tools/mvtrack and
#                          tests/daemon/mvtrack_make_clock_log (default: build/ci)
#   --recv-buf-size BYTES  the udpm URL's recv_buf_size (default: none, the kernel's default)
# Writes ~700 MB of temporary files (removed at the end).
set -euo pipefail
cd "$(dirname "$0")/../.."
build=build/ci
buf=
while [ $# -gt 0 ]; do
  case $1 in
    --build-dir) build=$2; shift 2 ;;
    --recv-buf-size) buf=$2; shift 2 ;;
    -h|--help) sed -n '2,11p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "flood_live: unknown argument $1 (see --help)" >&2; exit 2 ;;
  esac
done
for p in "$build/daemon/mvtrackd" "$build/tools/mvtrack" "$build/tests/daemon/mvtrack_make_clock_log"; do
  [ -x "$p" ] || { echo "flood_live: $p not found (build first, or --build-dir)" >&2; exit 2; }
done
command -v lcm-logplayer > /dev/null || { echo "flood_live: lcm-logplayer not installed" >&2; exit 2; }
unshare -n true 2> /dev/null || { echo "flood_live: cannot create a network namespace" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$build/tools/mvtrack" sim --out "$work/sim" --cameras 3 --people 3 --frames 240 --mode poses \
  --seed 5 2> /dev/null
"$build/tests/daemon/mvtrack_make_clock_log" "$work/sim/detections.lcmlog" "$work/flood.lcmlog" flood
"$build/tests/daemon/mvtrack_make_clock_log" "$work/sim/detections.lcmlog" "$work/drop.lcmlog" drop
URL="udpm://239.255.76.67:7667?ttl=0${buf:+&recv_buf_size=$buf}"
cat > "$work/daemon.yaml" << EOF
format: mvtrack.daemon/1
cameras:
  calibration: $work/sim/calibration.yaml
input:
  lcm_url: "$URL"
tracker:
  mode: poses
EOF
daemon=$(realpath "$build/daemon/mvtrackd")
"$daemon" --config "$work/daemon.yaml" --input-log "$work/drop.lcmlog" \
  --tracks-jsonl "$work/ref.jsonl" > "$work/ref.log" 2>&1
export daemon work URL
unshare -n bash -euc '
  ip link set lo up
  ip route add 224.0.0.0/4 dev lo
  "$daemon" --config "$work/daemon.yaml" --tracks-jsonl "$work/live.jsonl" > "$work/live.log" 2>&1 &
  pid=$!
  for _ in $(seq 100); do grep -q "input udpm" "$work/live.log" && break; sleep 0.1; done
  sleep 0.3
  lcm-logplayer --lcm-url="$URL" -s 1 "$work/flood.lcmlog" > /dev/null
  sleep 0.5
  kill -TERM $pid
  wait $pid
'
grep -E "input: (UDP receive buffer|recv_buf_size|no recv_buf_size)" "$work/live.log" | sed 's/^\[[^]]*\] //'
grep -o "summary: .*" "$work/live.log" |
  grep -oE " (messages|decode_errors|late|flood|kernel_drops|published_frames)=[-0-9]+" | tr '\n' ' '
echo
python3 - "$work/ref.jsonl" "$work/live.jsonl" << 'EOF'
import json, sys
frames = lambda p: sum(len(json.loads(l)["tracks"]) for l in open(p) if l.strip())
ref, got = frames(sys.argv[1]), frames(sys.argv[2])
print(f"track-frames {got}, without the flooding camera {ref}: {100.0 * got / ref:.1f} %")
EOF
