#!/usr/bin/env bash
# Lifecycle: an idle mvtrackd (memq:// input) answers SIGHUP by reloading its configuration (new
# log level and tracker options applied, restart-only changes reported, a broken file refused
# while it keeps running); mvtrackd reading the recording at a fifth of real time
# (file://...?speed=0.2) answers SIGTERM by stopping its input, finishing the open windows and
# publishing every frame it had accepted, then exiting 0.
# The drain time is printed (a measurement, not asserted: tests make no timing assertions).
source "$(dirname "$0")/common.sh"
CFG=$OUT/daemon.yaml
LOG=$OUT/daemon.log
PID=
trap '[ -n "$PID" ] && kill -KILL $PID 2>/dev/null || true' EXIT

# write_live_config INPUT_URL [EXTRA LINES...]
write_live_config() {
  local url=$1
  shift
  {
    echo "format: mvtrack.daemon/1"
    echo "cameras:"
    echo "  calibration: $P/calibration.yaml"
    echo "input:"
    echo "  lcm_url: \"$url\""
    echo "queues:"
    echo "  camera_overflow: block"
    echo "sync:"
    echo "  idle_flush_s: 0"
    echo "output:"
    echo "  status_period_s: 0.2"
    for line in "$@"; do echo "$line"; done
  } > "$CFG"
}

# wait_for REGEX: until the daemon log matches (hang guard 120 s).
wait_for() {
  for _ in $(seq 1200); do
    grep -qE -- "$1" "$LOG" && return 0
    kill -0 $PID 2>/dev/null || { cat "$LOG" >&2; fail "mvtrackd died waiting for '$1'"; }
    sleep 0.1
  done
  cat "$LOG" >&2
  fail "timed out waiting for '$1'"
}

# 1. SIGHUP, on an idle daemon (memq:// input: it never ends).
write_live_config "memq://" "logging:" "  level: info" "tracker:" "  mode: poses" "  layout: coco17"
"$MVTRACKD" --config "$CFG" --workers 2 > "$LOG" 2>&1 &
PID=$!
wait_for "input memq://"
# Debug logging, other tracker options, and a restart-only change.
write_live_config "memq://" "logging:" "  level: debug" "threads:" "  job_queue: 7" \
  "tracker:" "  mode: poses" "  layout: coco17" "  window_step: 10"
kill -HUP $PID
wait_for "configuration reloaded"
expect_grep "changes to threads need a restart" "$LOG"
wait_for "\[debug\] status:"
# A broken file: refused, the daemon keeps running with its configuration.
echo "sync: [unclosed" >> "$CFG"
kill -HUP $PID
wait_for "reload failed, keeping the running configuration"
kill -0 $PID || fail "mvtrackd died on a broken configuration"
kill -TERM $PID
status=0
wait $PID || status=$?
[ "$status" -eq 0 ] || { cat "$LOG" >&2; fail "exit status $status after SIGTERM (idle)"; }
expect_eq "$(summary_value "$LOG" reloads)" 1 "reloads"

# 2. SIGTERM with data in flight: the recording read at a fifth of real time.
LOG=$OUT/drain.log
write_live_config "file://$P/detections.lcmlog?speed=0.2" "tracker:" "  mode: poses" "  layout: coco17"
"$MVTRACKD" --config "$CFG" --workers 2 --tracks-jsonl "$OUT/tracks.jsonl" > "$LOG" 2>&1 &
PID=$!
wait_for "input file://"
# Two seconds of input (about 12 frames at this speed; the log lasts 40 s) are in flight.
sleep 2
grep -q "end of the input log" "$LOG" && fail "the log ended before SIGTERM"
start=$(date +%s.%N)
kill -TERM $PID
status=0
wait $PID || status=$?
PID=
end=$(date +%s.%N)
[ "$status" -eq 0 ] || { cat "$LOG" >&2; fail "exit status $status after SIGTERM"; }
expect_grep "SIGTERM received: draining" "$LOG"
released=$(summary_value "$LOG" frames_released)
published=$(summary_value "$LOG" published_frames)
expect_ge "$released" 1 "frames released before SIGTERM"
expect_eq "$published" "$released" "every accepted frame published after the drain"
expect_eq "$(wc -l < "$OUT/tracks.jsonl")" "$published" "JSONL lines"
echo "drain: SIGTERM to exit in $(awk "BEGIN { printf \"%.3f\", $end - $start }") s"
echo "ok"
