#!/usr/bin/env bash
# A step of the whole rig's time (issue 39; make_clock_log.cc: every camera's clock stepped by
# -2 s, -1 h or +20 s, or every frame counter reset, from the middle of the recording on; one
# publisher sending 30 stale messages for every camera id in one burst). mvtrackd must restart
# the stream by itself: at most 10 frames lost after the step (the restart vote needs 8),
# exactly one stream restart (two for the forged burst: into its time and back), and the new
# stream's track ids above the old stream's. Frame-index and utime synchronization.
source "$(dirname "$0")/common.sh"
[ -x "$MAKE_CLOCK_LOG" ] || fail "the clock-fault log writer is missing ($MAKE_CLOCK_LOG)"
# frames_and_ids JSONL: output frames, track-frames, and whether every id first seen after a
# stream restart (a frame whose ids are all new) is above every id seen before it.
frames_and_ids() {
  python3 - "$1" <<'PY'
import json, sys
frames = [json.loads(l) for l in open(sys.argv[1])]
seen, ok, prev = set(), 1, set()
for f in frames:
    ids = {t["id"] for t in f["tracks"]}
    if ids and prev and not (ids & prev):  # every track changed: a new stream
        if min(ids) <= max(seen):
            ok = 0
    seen |= ids
    prev = ids or prev
print(len(frames), sum(len(f["tracks"]) for f in frames), ok)
PY
}
for mode in frame_index utime; do
  write_config "$OUT/daemon_$mode.yaml" "sync:" "  mode: $mode"
  expect_exit 0 "$OUT/ref_$mode.log" "$MVTRACKD" --config "$OUT/daemon_$mode.yaml" --workers 2 \
    --input-log "$P/detections.lcmlog" --tracks-jsonl "$OUT/ref_$mode.jsonl"
  read -r ref_frames ref_tracks _ <<< "$(frames_and_ids "$OUT/ref_$mode.jsonl")"
  expect_ge "$ref_frames" 100 "$mode: reference frames"
  kinds="rig_skew:-2000000 rig_skew:-3600000000 rig_skew:20000000 forged_stale"
  [ "$mode" = frame_index ] && kinds="$kinds rig_reset"
  for kind in $kinds; do
    log=$OUT/${kind//:/_}_$mode
    "$MAKE_CLOCK_LOG" "$P/detections.lcmlog" "$log.lcmlog" "$kind"
    expect_exit 0 "$log.txt" "$MVTRACKD" --config "$OUT/daemon_$mode.yaml" --workers 2 \
      --input-log "$log.lcmlog" --tracks-jsonl "$log.jsonl"
    read -r frames tracks monotonic <<< "$(frames_and_ids "$log.jsonl")"
    echo "$mode $kind: $frames frames, $tracks track-frames (clean: $ref_frames, $ref_tracks)"
    restarts=1
    [ "$kind" = forged_stale ] && restarts=2
    expect_eq "$(summary_value "$log.txt" resyncs)" "$restarts" "$mode $kind: stream restarts"
    expect_grep "input stream restarted" "$log.txt"
    [ "$kind" = forged_stale ] && continue  # its stale frames are published too
    [ $(( frames + 10 )) -ge "$ref_frames" ] ||
      fail "$mode $kind: $frames frames published, more than 10 fewer than the clean $ref_frames"
    [ $(( tracks * 100 )) -ge $(( ref_tracks * 90 )) ] ||
      fail "$mode $kind: $tracks track-frames < 90 % of the clean run's $ref_tracks"
    expect_eq "$monotonic" 1 "$mode $kind: the new stream's ids above the old stream's"
  done
done
echo "ok"
