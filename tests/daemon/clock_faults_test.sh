#!/usr/bin/env bash
# Clock faults (issue 14): one camera's time broken in the recording (make_clock_log.cc: its
# clock skewed by +-250 ms, +-2 s or +1 h, its first message 1 h ahead, 99 stale messages then
# one 1 h ahead, a burst of 100 out-of-order messages, its frame counter running ten times
# fast). mvtrackd must keep tracking the other cameras' people: track-frames >= 95 % of the
# reference run without that camera, no stream restart, and the broken camera counted
# (clock_offset, far_future, backwards or late) rather than the healthy ones. Frame-index and
# utime synchronization.
source "$(dirname "$0")/common.sh"
[ -x "$MAKE_CLOCK_LOG" ] || fail "the clock-fault log writer is missing ($MAKE_CLOCK_LOG)"
track_frames() {
  python3 -c 'import json, sys; print(sum(len(json.loads(l)["tracks"]) for l in open(sys.argv[1])))' "$1"
}
for mode in frame_index utime; do
  write_config "$OUT/daemon_$mode.yaml" "sync:" "  mode: $mode"
  "$MAKE_CLOCK_LOG" "$P/detections.lcmlog" "$OUT/drop.lcmlog" drop
  expect_exit 0 "$OUT/ref_$mode.log" "$MVTRACKD" --config "$OUT/daemon_$mode.yaml" --workers 2 \
    --input-log "$OUT/drop.lcmlog" --tracks-jsonl "$OUT/ref_$mode.jsonl"
  reference=$(track_frames "$OUT/ref_$mode.jsonl")
  expect_ge "$reference" 500 "$mode: reference track-frames"
  kinds="skew:250000 skew:-250000 skew:2000000 skew:-2000000 skew:3600000000 first_future"
  kinds="$kinds stale_future burst"
  [ "$mode" = frame_index ] && kinds="$kinds fast_counter"
  for kind in $kinds; do
    log=$OUT/${kind//:/_}_$mode
    "$MAKE_CLOCK_LOG" "$P/detections.lcmlog" "$log.lcmlog" "$kind"
    expect_exit 0 "$log.txt" "$MVTRACKD" --config "$OUT/daemon_$mode.yaml" --workers 2 \
      --input-log "$log.lcmlog" --tracks-jsonl "$log.jsonl"
    got=$(track_frames "$log.jsonl")
    echo "$mode $kind: $got track-frames (reference without the camera: $reference)"
    [ $(( got * 100 )) -ge $(( reference * 95 )) ] ||
      fail "$mode $kind: $got track-frames < 95 % of the reference $reference (see $log.txt)"
    expect_eq "$(summary_value "$log.txt" resyncs)" 0 "$mode $kind: stream restarts"
  done
  # A first message an hour ahead is not published as a frame of its own once its camera
  # restarted alone (issue 39: one extra frame stamped an hour ahead that replay did not have).
  expect_eq "$(wc -l < "$OUT/first_future_$mode.jsonl")" "$(wc -l < "$OUT/ref_$mode.jsonl")" \
    "$mode first_future: frames published (as many as the reference's)"
  if [ "$mode" = utime ]; then  # by frame index it is frame 0 with a wrong utime
    expect_ge "$(summary_value "$OUT/first_future_$mode.txt" far_future)" 1 \
      "$mode first_future: the message an hour ahead counted as far future"
  fi
  # The skewed clock is flagged (counted as clock offset), not the healthy cameras' frames.
  expect_ge "$(summary_value "$OUT/skew_2000000_$mode.txt" clock_offset)" 100 \
    "$mode skew 2 s: camera-frames rejected as clock offset"
  expect_grep "clock is 2[0-9][0-9][0-9] ms .* off the other cameras" "$OUT/skew_2000000_$mode.txt"
done
echo "ok"
