#!/usr/bin/env bash
# The clock-fault table of docs/DAEMON.md at any scene size (tests/daemon/clock_faults_test.sh
# runs it at 3 cameras in CI): a simulated recording, one camera's time broken in each way
# make_clock_log knows, replayed through mvtrackd (--input-log, frame_index and utime sync);
# prints each fault's track-frames against the same recording without that camera.
#
# Usage: tools/dev/clock_faults_table.sh [--build-dir DIR] [--cameras C] [--people P]
#                                        [--frames N] [--seed S]   (default: build/ci, 8, 20, 600, 3)
set -euo pipefail
cd "$(dirname "$0")/../.."
build=build/ci cameras=8 people=20 frames=600 seed=3
while [ $# -gt 0 ]; do
  case $1 in
    --build-dir) build=$2 ;;
    --cameras) cameras=$2 ;;
    --people) people=$2 ;;
    --frames) frames=$2 ;;
    --seed) seed=$2 ;;
    -h|--help) sed -n '2,8p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "clock_faults_table: unknown argument $1 (see --help)" >&2; exit 2 ;;
  esac
  shift 2
done
D=$build/daemon/mvtrackd
G=$build/tests/daemon/mvtrack_make_clock_log
for p in "$D" "$G" "$build/tools/mvtrack"; do
  [ -x "$p" ] || { echo "clock_faults_table: $p not found (build first)" >&2; exit 2; }
done
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$build/tools/mvtrack" sim --out "$work/sim" --cameras "$cameras" --people "$people" \
  --frames "$frames" --seed "$seed" 2> /dev/null > /dev/null
track_frames() {
  python3 -c 'import json, sys; print(sum(len(json.loads(l)["tracks"]) for l in open(sys.argv[1])))' "$1"
}
"$G" "$work/sim/detections.lcmlog" "$work/drop.lcmlog" drop
echo "| sync | fault | track-frames | without the camera | ratio | stream restarts |"
echo "|---|---|---:|---:|---:|---:|"
for mode in frame_index utime; do
  printf 'format: mvtrack.daemon/1\ncameras:\n  calibration: %s\ninput:\n  lcm_url: "memq://"\nsync:\n  mode: %s\ntracker:\n  mode: poses\n' \
    "$work/sim/calibration.yaml" "$mode" > "$work/d.yaml"
  "$D" --config "$work/d.yaml" --input-log "$work/drop.lcmlog" --tracks-jsonl "$work/ref.jsonl" \
    > "$work/ref.log" 2>&1
  ref=$(track_frames "$work/ref.jsonl")
  kinds="skew:250000 skew:-250000 skew:2000000 skew:-2000000 skew:3600000000 first_future stale_future burst"
  [ "$mode" = frame_index ] && kinds="$kinds fast_counter"
  for kind in $kinds; do
    "$G" "$work/sim/detections.lcmlog" "$work/x.lcmlog" "$kind"
    "$D" --config "$work/d.yaml" --input-log "$work/x.lcmlog" --tracks-jsonl "$work/x.jsonl" \
      > "$work/x.log" 2>&1
    got=$(track_frames "$work/x.jsonl")
    resyncs=$(grep -o 'resyncs=[0-9]*' "$work/x.log" | head -1 | sed 's/.*=//')
    python3 -c "print(f'| $mode | $kind | $got | $ref | {100 * $got / $ref:.1f} % | $resyncs |')"
  done
done
