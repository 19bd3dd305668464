#!/usr/bin/env bash
# mvtrack replay on a damaged log (foreign channels, bad fingerprint, truncated message, camera id
# contradicting its channel, unknown camera, log cut inside the last event): exit 0, every kind
# of damage counted exactly as injected (damage.txt from make_sim_log), the first bad messages
# printed with their event, and the tracks still match the ground truth.
source "$(dirname "$0")/common.sh"
P=$WORK/poses
get() { sed -n "s/^$1=//p" "$P/damage.txt"; }
[ -n "$(get foreign)" ] || fail "damage.txt lacks the injected counts"

"$MVTRACK" replay --quiet --calibration "$P/calibration.yaml" --mode poses \
  --jsonl "$OUT/damaged.jsonl" "$P/damaged.lcmlog" >"$OUT/summary" 2>"$OUT/stderr" ||
  { cat "$OUT/summary" "$OUT/stderr"; fail "replay of the damaged log failed"; }
cat "$OUT/summary"
expect_grep "$(get foreign) on other channels ignored" "$OUT/summary"
expect_grep "log truncated \(.*event .* needs .* bytes" "$OUT/summary"
bad=$(( $(get bad_fingerprint) + $(get truncated) + $(get channel_mismatch) ))
expect_grep "bad messages skipped: $bad \(bad fingerprint $(get bad_fingerprint), camera id differs from channel $(get channel_mismatch), truncated $(get truncated)\)" "$OUT/summary"
expect_grep "rejected \(unknown_camera $(get unknown_camera)\)" "$OUT/summary"
expect_grep "output: 240 frame\(s\), 3 track id\(s\)" "$OUT/summary"
# The first bad messages are printed with where they are and why.
expect_grep "skipped: .*damaged.lcmlog: event [0-9]+ on MVTRACK_DETECTIONS_1 .*bad fingerprint" "$OUT/stderr"
expect_grep "skipped: .*event [0-9]+ on MVTRACK_DETECTIONS_2 .*camera_id 1 on the channel of camera 2" "$OUT/stderr"
expect_grep "rejected camera-frame \(camera 99, frame 0\): unknown_camera" "$OUT/stderr"

# Still tracks: against the ground truth, MOTA stays above the floor of the clean log.
expect_exit 0 "$OUT/eval.log" "$MVTRACK" eval --gt "$P/gt.jsonl" --pred "$OUT/damaged.jsonl" --json "$OUT/eval.json"
mota=$(json_get "$OUT/eval.json" 'd["tracking"]["clear_mot"]["mota"]')
float_ge "$mota" 0.95 || fail "MOTA $mota on the damaged log is below 0.95"
echo "ok (MOTA $mota)"
