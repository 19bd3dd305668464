#!/usr/bin/env bash
# Determinism: mvtrackd fed the recording through LCM's file:// provider publishes exactly the
# tracks `mvtrack replay` writes for it, with 1, 2 and 8 window-job workers: the canonical
# JSONL is byte-identical, and the tracks3d_t messages it published on LCM (captured by a
# file://...?mode=w output) compare equal, frame by frame, to replay's LCM output. The same
# holds at 2 fps, where both scale the frame counts to the measured rate.
source "$(dirname "$0")/common.sh"
expect_exit 0 "$OUT/replay.log" "$MVTRACK" replay --quiet --calibration "$P/calibration.yaml" \
  --mode poses --jsonl "$OUT/replay.jsonl" --out "$OUT/replay.lcmlog" "$P/detections.lcmlog"
write_config "$OUT/daemon.yaml"
for n in 1 2 8; do
  expect_exit 0 "$OUT/d$n.log" "$MVTRACKD" --config "$OUT/daemon.yaml" --workers "$n" \
    --input-log "$P/detections.lcmlog" --tracks-jsonl "$OUT/d$n.jsonl" \
    --output-url "file://$OUT/d$n.lcmlog?mode=w"
  expect_grep "starting: 3 camera\(s\), $n worker\(s\)" "$OUT/d$n.log"
  cmp "$OUT/replay.jsonl" "$OUT/d$n.jsonl" || fail "--workers $n: JSONL differs from mvtrack replay"
  expect_exit 0 "$OUT/diff$n.log" "$MVTRACK" diff "$OUT/replay.lcmlog" "$OUT/d$n.lcmlog"
  expect_eq "$(summary_value "$OUT/d$n.log" published_frames)" "$(wc -l < "$OUT/replay.jsonl")" \
    "--workers $n: published frames"
  expect_eq "$(summary_value "$OUT/d$n.log" gate_rejected)" 0 "--workers $n: gate rejections"
done
# The published LCM log also holds the status messages (one per period and a final one).
expect_grep "status_messages=[1-9]" "$OUT/d8.log"
# A 2 fps recording: the daemon and replay measure the same rate from the capture times and
# scale the frame counts alike (reference_fps; 3-frame windows: about 30 over 60 frames).
expect_exit 0 "$OUT/sim2.log" "$MVTRACK" sim --out "$OUT/sim2" --cameras 3 --people 4 \
  --frames 60 --fps 2 --mode boxes --seed 3 --quiet
expect_exit 0 "$OUT/replay2.log" "$MVTRACK" replay --calibration "$OUT/sim2/calibration.yaml" \
  --mode boxes --jsonl "$OUT/replay2.jsonl" "$OUT/sim2/detections.lcmlog"
windows=$(grep -o "[0-9]* window(s)" "$OUT/replay2.log" | grep -o "^[0-9]*")
expect_ge "$windows" 25 "2 fps replay: windows of 3 frames"
{
  echo "format: mvtrack.daemon/1"
  echo "cameras:"
  echo "  calibration: $OUT/sim2/calibration.yaml"
  echo "input:"
  echo "  lcm_url: \"memq://\""
  echo "tracker:"
  echo "  mode: boxes"
} > "$OUT/daemon2.yaml"
expect_exit 0 "$OUT/d2fps.log" "$MVTRACKD" --config "$OUT/daemon2.yaml" --workers 2 \
  --input-log "$OUT/sim2/detections.lcmlog" --tracks-jsonl "$OUT/d2fps.jsonl"
cmp "$OUT/replay2.jsonl" "$OUT/d2fps.jsonl" || fail "2 fps: the daemon's JSONL differs from replay"
echo "ok"
