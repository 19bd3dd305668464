#!/usr/bin/env bash
# mvtrackd's command line: --version, --help, usage errors (exit 2), configuration errors
# (exit 1, naming file, line and key), a missing input log, and the example configuration
# shipped in docs/examples running over a recorded log through file:// to its end.
source "$(dirname "$0")/common.sh"

expect_exit 0 "$OUT/version.log" "$MVTRACKD" --version
expect_grep "^mvtrackd [0-9]+\.[0-9]+\.[0-9]+" "$OUT/version.log"
expect_exit 0 "$OUT/help.log" "$MVTRACKD" --help
expect_grep "SIGHUP reloads" "$OUT/help.log"
expect_exit 2 "$OUT/noconfig.log" "$MVTRACKD"
expect_grep "--config is required" "$OUT/noconfig.log"
expect_exit 2 "$OUT/unknown.log" "$MVTRACKD" --config x.yaml --frobnicate
expect_grep "unknown argument '--frobnicate'" "$OUT/unknown.log"
expect_exit 2 "$OUT/workers.log" "$MVTRACKD" --config x.yaml --workers many
expect_grep "--workers must be an integer" "$OUT/workers.log"

# Strict configuration: a typo is an error naming the file, line, key and a suggestion.
write_config "$OUT/typo.yaml" "sync:" "  deadline_usec: 5"
expect_exit 1 "$OUT/typo.log" "$MVTRACKD" --config "$OUT/typo.yaml"
expect_grep "typo.yaml:[0-9]+:[0-9]+: sync.deadline_usec: unknown key \(did you mean 'deadline_us'\?\)" "$OUT/typo.log"
write_config "$OUT/range.yaml" "threads:" "  workers: -3"
expect_exit 1 "$OUT/range.log" "$MVTRACKD" --config "$OUT/range.yaml"
expect_grep "range.yaml:[0-9]+:[0-9]+: threads.workers: " "$OUT/range.log"
expect_exit 1 "$OUT/nolog.log" "$MVTRACKD" --config "$OUT/range.yaml" --input-log "$OUT/missing.lcmlog"

# The example configuration, with the recording's calibration, tracks the log to its end.
expect_exit 0 "$OUT/example.log" "$MVTRACKD" --config "$SRC/docs/examples/mvtrackd.yaml" \
  --calibration "$P/calibration.yaml" --input-log "$P/detections.lcmlog" \
  --tracks-jsonl "$OUT/example.jsonl"
expect_grep "effective configuration \(hash [0-9a-f]{16}\)" "$OUT/example.log"
expect_grep "end of the input log" "$OUT/example.log"
frames=$(summary_value "$OUT/example.log" published_frames)
expect_eq "$frames" 240 "frames published by the example configuration"
expect_eq "$(wc -l < "$OUT/example.jsonl")" 240 "JSONL lines"
expect_ge "$(summary_value "$OUT/example.log" tracks_born)" 3 "tracks born"

# mvtrack check-config validates daemon configurations too (recognised by content).
expect_exit 0 "$OUT/check.log" "$MVTRACK" check-config "$SRC/docs/examples/mvtrackd.yaml"
expect_grep "^# ok: .*mvtrackd.yaml: daemon configuration, 3 camera\(s\) \(ids 0, 1, 2\)" "$OUT/check.log"
expect_grep "^  deadline_us: 200000$" "$OUT/check.log"
# Its effective configuration is itself a valid configuration with the same hash.
grep -v "^#" "$OUT/check.log" > "$OUT/effective.yaml"
expect_exit 0 "$OUT/check2.log" "$MVTRACK" check-config "$OUT/effective.yaml"
hash1=$(grep -o "hash [0-9a-f]*" "$OUT/check.log")
expect_grep "$hash1" "$OUT/check2.log"
expect_exit 0 "$OUT/check3.log" "$MVTRACK" check-config "$SRC/docs/examples/mvtrackd.yaml" \
  --calibration "$P/calibration.yaml"
expect_grep "from $P/calibration.yaml" "$OUT/check3.log"
# The live example for one's own cameras (docs/PYTHON.md) is valid with a calibration given.
expect_exit 0 "$OUT/check_own.log" "$MVTRACK" check-config \
  "$SRC/docs/examples/mvtrackd_own_cameras.yaml" --calibration "$P/calibration.yaml"
expect_grep "^# ok: .*mvtrackd_own_cameras.yaml: daemon configuration, .* sync utime" "$OUT/check_own.log"
expect_exit 1 "$OUT/check_typo.log" "$MVTRACK" check-config "$OUT/typo.yaml"
expect_grep "invalid: .*typo.yaml:[0-9]+:[0-9]+: sync.deadline_usec: unknown key" "$OUT/check_typo.log"
sed 's/mvtrack.daemon\/1/mvtrack.daemon\/9/' "$OUT/range.yaml" > "$OUT/version.yaml"
expect_exit 1 "$OUT/check_version.log" "$MVTRACK" check-config "$OUT/version.yaml"
expect_grep "format: expected 'mvtrack.daemon/1'" "$OUT/check_version.log"

# A log none of whose cameras is in the calibration: exit 1 naming the calibration's cameras.
sed -E 's/^(\s*-?\s*id:\s*)([0-9]+)/\17\2/' "$P/calibration.yaml" > "$OUT/other_ids.yaml"
write_config "$OUT/plain.yaml"
expect_exit 1 "$OUT/other_ids.log" "$MVTRACKD" --config "$OUT/plain.yaml" \
  --calibration "$OUT/other_ids.yaml" --input-log "$P/detections.lcmlog"
expect_grep "no camera-frame was tracked \([0-9]+ message\(s\), [0-9]+ of unknown cameras, 0 undecodable; the calibration's cameras: 70, 71, 72\)" \
  "$OUT/other_ids.log"
echo "ok"
