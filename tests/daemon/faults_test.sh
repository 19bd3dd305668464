#!/usr/bin/env bash
# Fault injection: the recording with bad input injected around the good messages (see
# make_fault_log.cc: truncated and foreign-type messages, NaN/inf, boxes outside the image,
# unknown cameras, 10,000 detections in one message, one camera flooding at 10x its rate, time
# going backwards, far-future and duplicate frames) is replayed through mvtrackd. Every fault
# is counted, the good data is tracked exactly as without the faults (the output equals
# `mvtrack replay` on the clean recording), memory stays within the clean run's, the daemon
# runs to the end of the log and exits 0. --record captures input and output for
# `mvtrack replay`.
source "$(dirname "$0")/common.sh"
F=$P/faults.txt
expect_exit 0 "$OUT/replay.log" "$MVTRACK" replay --quiet --calibration "$P/calibration.yaml" \
  --mode poses --jsonl "$OUT/clean.jsonl" "$P/detections.lcmlog"
write_config "$OUT/daemon.yaml" "logging:" "  repeat_interval_s: 3600"
expect_exit 0 "$OUT/clean.log" "$MVTRACKD" --config "$OUT/daemon.yaml" --workers 2 \
  --input-log "$P/detections.lcmlog" --tracks-jsonl "$OUT/clean_daemon.jsonl" \
  --record "$OUT/record.lcmlog"
expect_exit 0 "$OUT/faulted.log" "$MVTRACKD" --config "$OUT/daemon.yaml" --workers 2 \
  --input-log "$P/faulted.lcmlog" --tracks-jsonl "$OUT/faulted.jsonl"

# The good data is still tracked, exactly.
cmp "$OUT/clean.jsonl" "$OUT/faulted.jsonl" || fail "the faults changed the tracks"

# Every fault is counted.
L=$OUT/faulted.log
decode=$(( $(count_value "$F" truncated) + $(count_value "$F" foreign) + $(count_value "$F" oversized) ))
expect_eq "$(summary_value "$L" decode_errors)" "$decode" "decode errors"
expect_grep "truncated $(count_value "$F" truncated)" "$L"
expect_grep "bad fingerprint $(count_value "$F" foreign)" "$L"
expect_grep "limit exceeded $(count_value "$F" oversized)" "$L"
expect_eq "$(summary_value "$L" unknown_camera)" "$(count_value "$F" unknown)" "unknown cameras"
expect_eq "$(summary_value "$L" backwards)" "$(count_value "$F" backwards)" "time backwards"
expect_eq "$(summary_value "$L" far_future)" "$(count_value "$F" far_future)" "far future"
expect_eq "$(summary_value "$L" duplicates)" \
  "$(( $(count_value "$F" flood) + $(count_value "$F" duplicate) ))" "duplicates (flood + repeat)"
bad_detections=$(( $(count_value "$F" nan) + $(count_value "$F" outside) ))
expect_eq "$(( $(summary_value "$L" rejected) - $(summary_value "$OUT/clean.log" rejected) ))" \
  "$bad_detections" "detections rejected by validation (NaN/inf, outside the image)"
expect_eq "$(summary_value "$L" resyncs)" 0 "stream restarts"
# Warnings are rate limited: with a one-hour interval each kind is logged once per camera.
expect_ge "$(summary_value "$L" suppressed_warnings)" 300 "suppressed warnings"
warnings=$(grep -c "\[warning\]" "$L")
[ "$warnings" -le 20 ] || fail "$warnings warnings logged: not rate limited"

# Bounded memory: the faulted run needs no more than the clean run plus a small margin.
clean_rss=$(summary_value "$OUT/clean.log" max_rss_kb)
faulted_rss=$(summary_value "$L" max_rss_kb)
[ "$faulted_rss" -le $(( clean_rss + clean_rss / 2 + 65536 )) ] ||
  fail "max RSS $faulted_rss kB on the faulted log vs $clean_rss kB on the clean one"

# The record log (input and output of the clean run) replays to the same tracks, and holds the
# published tracks and status messages.
expect_exit 0 "$OUT/record_replay.log" "$MVTRACK" replay --quiet --calibration "$P/calibration.yaml" \
  --mode poses --jsonl "$OUT/recorded.jsonl" "$OUT/record.lcmlog"
cmp "$OUT/clean.jsonl" "$OUT/recorded.jsonl" || fail "replaying the record log gives other tracks"
expect_grep "MVTRACK_TRACKS $(wc -l < "$OUT/clean.jsonl")" "$OUT/record_replay.log"
expect_grep "MVTRACK_STATUS [1-9]" "$OUT/record_replay.log"
expect_exit 0 "$OUT/record_diff.log" "$MVTRACK" diff "$OUT/clean.jsonl" "$OUT/record.lcmlog" --tolerance 0.001
echo "ok"
