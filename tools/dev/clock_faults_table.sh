#!/usr/bin/env bash
# The clock-fault tables of docs/DAEMON.md at any scene size (tests/daemon/clock_faults_test.sh
# and rig_clock_test.sh run them at 3 cameras in CI): a simulated recording replayed through
# mvtrackd (--input-log, frame_index and utime sync) with time broken in each way
# make_clock_log knows.
#   default: one camera's time broken; prints each fault's track-frames against the same
#            recording without that camera.
#   --rig:   every camera's time stepped at the middle frame (rig_skew:US, rig_reset) and one
#            publisher's burst of stale messages for every camera id (forged_stale); prints the
#            track-frames after the step against the clean recording's and the frames published.
#
# Usage: tools/dev/clock_faults_table.sh [--rig] [--build-dir DIR] [--cameras C] [--people P]
#                                        [--frames N] [--seed S]   (default: build/ci, 8, 20, 600, 3)
set -euo pipefail
cd "$(dirname "$0")/../.."
build=build/ci cameras=8 people=20 frames=600 seed=3 rig=0
while [ $# -gt 0 ]; do
  case $1 in
    --rig) rig=1; shift; continue ;;
    --build-dir) build=$2 ;;
    --cameras) cameras=$2 ;;
    --people) people=$2 ;;
    --frames) frames=$2 ;;
    --seed) seed=$2 ;;
    -h|--help) sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
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
step=$(( (frames - 1) / 2 ))
# counts JSONL: track-frames in all, track-frames in the first $step output frames, frames.
counts() {
  python3 - "$1" "$step" <<'PY'
import json, sys
frames = [json.loads(l) for l in open(sys.argv[1])]
step = int(sys.argv[2])
print(sum(len(f["tracks"]) for f in frames), sum(len(f["tracks"]) for f in frames[:step]),
      len(frames))
PY
}
if [ $rig = 1 ]; then
  reference=$work/sim/detections.lcmlog
  echo "| sync | fault | track-frames after the step | clean | ratio | frames | stream restarts |"
else
  reference=$work/drop.lcmlog
  "$G" "$work/sim/detections.lcmlog" "$reference" drop
  echo "| sync | fault | track-frames | without the camera | ratio | stream restarts |"
fi
[ $rig = 1 ] && echo "|---|---|---:|---:|---:|---:|---:|" || echo "|---|---|---:|---:|---:|---:|"
for mode in frame_index utime; do
  printf 'format: mvtrack.daemon/1\ncameras:\n  calibration: %s\ninput:\n  lcm_url: "memq://"\nsync:\n  mode: %s\ntracker:\n  mode: poses\n' \
    "$work/sim/calibration.yaml" "$mode" > "$work/d.yaml"
  "$D" --config "$work/d.yaml" --input-log "$reference" --tracks-jsonl "$work/ref.jsonl" \
    > "$work/ref.log" 2>&1
  read -r ref_all ref_before ref_frames <<< "$(counts "$work/ref.jsonl")"
  if [ $rig = 1 ]; then
    kinds="rig_skew:-500000 rig_skew:-2000000 rig_skew:-3600000000 rig_skew:500000"
    kinds="$kinds rig_skew:20000000 rig_skew:3600000000 rig_reset forged_stale"
  else
    kinds="skew:250000 skew:-250000 skew:2000000 skew:-2000000 skew:3600000000 first_future"
    kinds="$kinds stale_future burst"
    [ "$mode" = frame_index ] && kinds="$kinds fast_counter"
  fi
  for kind in $kinds; do
    "$G" "$work/sim/detections.lcmlog" "$work/x.lcmlog" "$kind"
    "$D" --config "$work/d.yaml" --input-log "$work/x.lcmlog" --tracks-jsonl "$work/x.jsonl" \
      > "$work/x.log" 2>&1
    read -r all _ n <<< "$(counts "$work/x.jsonl")"
    resyncs=$(grep -o 'resyncs=[0-9]*' "$work/x.log" | head -1 | sed 's/.*=//')
    if [ $rig = 1 ]; then
      after=$(( all - ref_before )) clean=$(( ref_all - ref_before ))
      python3 -c "print(f'| $mode | $kind | $after | $clean | {100 * $after / $clean:.1f} % | $n / $ref_frames | $resyncs |')"
    else
      python3 -c "print(f'| $mode | $kind | $all | $ref_all | {100 * $all / $ref_all:.1f} % | $resyncs |')"
    fi
  done
done
