#!/usr/bin/env bash
# Measures what `kill -9` of a live mvtrackd loses (docs/DAEMON.md, "Ids across restarts"): a
# simulated 30 fps recording is played in real time (LCM file://...?speed=1), the daemon is
# killed after each delay, and the frames it had received (estimated from the wall clock since
# it opened its input, so +-1 frame) are compared with the frames it had published (its tracks
# JSONL is flushed per frame).
#
# Usage: tools/dev/kill9_loss.sh [--build-dir DIR] [--mode poses|boxes] [DELAY_S ...]
#   --build-dir DIR  the build holding daemon/mvtrackd and tools/mvtrack (default: build/ci)
#   --mode M         tracker mode of the recording and the daemon (default: poses)
#   DELAY_S          seconds before the kill, each one run (default: 1.5 2.5 3.5 4.5 5.5 6.5)
# Output: one line per run, then the range of frames lost.
set -euo pipefail
cd "$(dirname "$0")/../.."
build=build/ci
mode=poses
delays=()
while [ $# -gt 0 ]; do
  case $1 in
    --build-dir) build=$2; shift 2 ;;
    --mode) mode=$2; shift 2 ;;
    -h|--help) sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "kill9_loss: unknown option $1 (see --help)" >&2; exit 2 ;;
    *) delays+=("$1"); shift ;;
  esac
done
[ ${#delays[@]} -gt 0 ] || delays=(1.5 2.5 3.5 4.5 5.5 6.5)
for p in "$build/daemon/mvtrackd" "$build/tools/mvtrack"; do
  [ -x "$p" ] || { echo "kill9_loss: $p not found (build first, or --build-dir)" >&2; exit 2; }
done
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$build/tools/mvtrack" sim --out "$work/sim" --cameras 3 --people 3 --frames 300 --mode "$mode" \
  --seed 5 > /dev/null
{
  echo "format: mvtrack.daemon/1"
  echo "cameras:"
  echo "  calibration: $work/sim/calibration.yaml"
  echo "input:"
  echo "  lcm_url: \"file://$work/sim/detections.lcmlog?speed=1\""
  echo "tracker:"
  echo "  mode: $mode"
} > "$work/live.yaml"
for d in "${delays[@]}"; do
  rm -f "$work/k.jsonl"
  "$build/daemon/mvtrackd" --config "$work/live.yaml" --tracks-jsonl "$work/k.jsonl" \
    > "$work/k.log" 2>&1 &
  pid=$!
  sleep "$d"
  killed_at=$(date +%s.%N)
  kill -9 "$pid"
  wait "$pid" 2>/dev/null || true
  python3 - "$killed_at" "$work/k.log" "$work/k.jsonl" "$work/sim/gt.jsonl" <<'PY'
import datetime, json, sys
killed_at, log, tracks, gt = float(sys.argv[1]), sys.argv[2], sys.argv[3], sys.argv[4]
opened = None
for line in open(log):
    if "] [info] input " in line:
        opened = datetime.datetime.strptime(line[1:24], "%Y-%m-%dT%H:%M:%S.%f").replace(
            tzinfo=datetime.timezone.utc).timestamp()
if opened is None:
    sys.exit("kill9_loss: the daemon never opened its input (see " + log + ")")
utimes = [json.loads(l)["utime"] for l in open(gt) if l.strip()]
period_s = (utimes[1] - utimes[0]) / 1e6
published = sum(1 for l in open(tracks) if l.strip())
received = min(len(utimes), int((killed_at - opened) / period_s) + 1)
print(f"killed {killed_at - opened:.2f} s after start: received ~{received}, "
      f"published {published}, lost ~{received - published} frames "
      f"({(received - published) * period_s:.2f} s)")
PY
done
