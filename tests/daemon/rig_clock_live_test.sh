#!/usr/bin/env bash
# A step of the whole rig's time, live (issue 39), only inside a private network namespace (never
# on the machine's network; ../shared/TOOLCHAIN.md): lcm-logplayer publishes the recording with
# every camera's clock stepped back 2 s from its middle on (make_clock_log rig_skew), mvtrackd
# tracks it live over udpm://. The daemon must restart the stream once by itself and publish
# at most 10 frames fewer than it does for the clean recording played the same way. Skipped
# (exit 77, with a message) where no namespace can be created.
source "$(dirname "$0")/common.sh"
[ -x "$MAKE_CLOCK_LOG" ] || fail "the clock-fault log writer is missing ($MAKE_CLOCK_LOG)"
require_netns
"$MAKE_CLOCK_LOG" "$P/detections.lcmlog" "$OUT/step.lcmlog" rig_skew:-2000000
URL="udpm://239.255.76.67:7667?ttl=0"
write_udpm_config "$OUT/daemon.yaml" "$URL"
export MVTRACKD OUT P URL
unshare -n bash -euc '
  ip link set lo up
  ip route add 224.0.0.0/4 dev lo
  for run in clean step; do
    log=$P/detections.lcmlog
    [ $run = step ] && log=$OUT/step.lcmlog
    "$MVTRACKD" --config "$OUT/daemon.yaml" --workers 2 --tracks-jsonl "$OUT/$run.jsonl" \
      > "$OUT/$run.log" 2>&1 &
    DAEMON=$!
    for _ in $(seq 100); do grep -q "input udpm" "$OUT/$run.log" && break; sleep 0.1; done
    sleep 0.3
    lcm-logplayer --lcm-url="$URL" -s 2 "$log"
    sleep 0.5
    kill -TERM $DAEMON
    wait $DAEMON
  done
' || fail "the namespace run failed (see $OUT/step.log)"
clean=$(summary_value "$OUT/clean.log" published_frames)
step=$(summary_value "$OUT/step.log" published_frames)
echo "live: $step frames published with the rig's clock stepped back 2 s, $clean without"
expect_eq "$(summary_value "$OUT/clean.log" resyncs)" 0 "clean run: stream restarts"
expect_eq "$(summary_value "$OUT/step.log" resyncs)" 1 "stepped run: stream restarts"
expect_grep "input stream restarted" "$OUT/step.log"
[ $(( step + 10 )) -ge "$clean" ] ||
  fail "live: $step frames published with the step, more than 10 fewer than $clean"
echo "ok"
