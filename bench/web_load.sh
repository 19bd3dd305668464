#!/usr/bin/env bash
# mvtrack web under a store's load (issue 15): 32 cameras x 100 people, box mode, 30 fps. Inside
# a private network namespace mvtrackd tracks a simulated recording played in real time
# (--input-speed 1) and publishes over udpm, `mvtrack web` serves it, and a headless Chromium
# keeps the page open (tests/web/page_probe.py). Prints the tracks messages published, received
# by mvtrack web and shown by the page, slow clients dropped, the page's publish -> DOM latency,
# and mvtrack web's CPU time (user + system, /proc) over the run. Needs root (netns).
#
# Usage: bench/web_load.sh [--build-dir DIR] [--frames N] [--cameras C] [--people P]
set -euo pipefail
cd "$(dirname "$0")/.."
build=build/release
frames=900
cameras=32
people=100
while [ $# -gt 0 ]; do
  case $1 in
    --build-dir) build=$2; shift 2 ;;
    --frames) frames=$2; shift 2 ;;
    --cameras) cameras=$2; shift 2 ;;
    --people) people=$2; shift 2 ;;
    -h|--help) sed -n '2,9p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "web_load: unknown argument $1 (see --help)" >&2; exit 2 ;;
  esac
done
M=$(realpath "$build/tools/mvtrack")
D=$(realpath "$build/daemon/mvtrackd")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$M" sim --out "$work/sim" --cameras "$cameras" --people "$people" --frames "$frames" \
  --mode boxes --seed 3 2> /dev/null
URL="udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304"
printf 'format: mvtrack.daemon/1\ncameras:\n  calibration: %s\ntracker:\n  mode: boxes\n' \
  "$work/sim/calibration.yaml" > "$work/daemon.yaml"
export M D work URL frames
SRC=$(pwd)
export SRC
unshare -n bash -euc '
  ip link set lo up
  ip route add 224.0.0.0/4 dev lo
  "$M" web --listen 127.0.0.1:18081 --url "$URL" --calibration "$work/sim/calibration.yaml" \
    > "$work/web.log" 2>&1 &
  WEB=$!
  chromium --headless --no-sandbox --disable-gpu --remote-debugging-port=19223 \
    --window-size=1400,820 about:blank > "$work/chromium.log" 2>&1 &
  BROWSER=$!
  for _ in $(seq 100); do grep -q "serving http" "$work/web.log" && break; sleep 0.1; done
  /usr/bin/python3 "$SRC/tests/web/page_probe.py" 19223 http://127.0.0.1:18081/ 120 \
    "$work/page.png" "$work/phase" "$frames" > "$work/probe.jsonl" 2>&1 &
  PROBE=$!
  sleep 2
  cpu0=$(awk "{print \$14 + \$15}" /proc/$WEB/stat)
  t0=$(date +%s.%N)
  "$D" --config "$work/daemon.yaml" --input-log "$work/sim/detections.lcmlog" --input-speed 1 \
    --output-url "$URL" > "$work/daemon.log" 2>&1
  sleep 1
  cpu1=$(awk "{print \$14 + \$15}" /proc/$WEB/stat)
  t1=$(date +%s.%N)
  curl -s http://127.0.0.1:18081/metrics > "$work/metrics.txt"
  wait $PROBE || true
  kill -TERM $WEB $BROWSER; wait $WEB || true; wait $BROWSER || true
  echo "$cpu0 $cpu1 $t0 $t1" > "$work/cpu.txt"
'
read -r cpu0 cpu1 t0 t1 < "$work/cpu.txt"
hz=$(getconf CLK_TCK)
python3 - "$work" "$cpu0" "$cpu1" "$t0" "$t1" "$hz" "$frames" << 'PY'
import json, sys
work, cpu0, cpu1, t0, t1, hz, frames = sys.argv[1], *map(float, sys.argv[2:7]), int(sys.argv[7])
metrics = {l.split()[0]: float(l.split()[1]) for l in open(f"{work}/metrics.txt")
           if l and not l.startswith("#") and len(l.split()) == 2}
probe = [json.loads(l) for l in open(f"{work}/probe.jsonl") if l.startswith("{")]
page = probe[-1] if probe else {}
cpu = (cpu1 - cpu0) / hz
wall = t1 - t0
print(f"published {frames} tracks messages in {wall:.1f} s; mvtrack web received "
      f"{metrics.get('mvtrack_web_tracks_messages_total', 0):.0f}, sent "
      f"{metrics.get('mvtrack_web_events_sent_total', 0):.0f} events, dropped "
      f"{metrics.get('mvtrack_web_clients_dropped_total', 0):.0f} clients; the page showed "
      f"{page.get('messages', 0)} messages ({len(page.get('tracks', []))} tracks in its last "
      f"frame), publish -> DOM p50 {page.get('latency_p50_ms')} ms, max "
      f"{page.get('latency_max_ms')} ms")
print(f"mvtrack web CPU: {cpu:.2f} s over {wall:.1f} s = {100 * cpu / wall:.1f} % of one core")
PY
