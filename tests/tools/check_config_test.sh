#!/usr/bin/env bash
# mvtrack check-config: the example options (and calibration) pass and print the effective
# options, which read back to the same options; broken files fail with exit 1 naming the file,
# line and key.
source "$(dirname "$0")/common.sh"
EX=$SRC/docs/examples

expect_exit 0 "$OUT/example.txt" "$MVTRACK" check-config "$EX/tracker_options.yaml"
expect_grep "^tracker:" "$OUT/example.txt"
expect_grep "^  window_size: 30$" "$OUT/example.txt"
expect_grep "^    lambda: 0.3$" "$OUT/example.txt"
expect_grep "^# ok: .*tracker_options.yaml: mode boxes, box point center_ends, window 30/20 frames$" "$OUT/example.txt"
# The printed document is itself a valid options file with the same effective options.
"$MVTRACK" check-config "$EX/tracker_options.yaml" >"$OUT/effective.yaml" 2>/dev/null
expect_exit 0 "$OUT/again.txt" "$MVTRACK" check-config "$OUT/effective.yaml"
diff <(grep -v '^#' "$OUT/example.txt") <(grep -v '^#' "$OUT/again.txt") ||
  fail "the effective options do not read back to the same options"
# A changed value shows up in the effective options.
printf 'tracker:\n  mode: poses\n  layout: shelf14\n  association:\n    lambda: 0.25\n' >"$OUT/custom.yaml"
expect_exit 0 "$OUT/custom.txt" "$MVTRACK" check-config "$OUT/custom.yaml"
expect_grep "^    lambda: 0.25$" "$OUT/custom.txt"
expect_grep "mode poses, layout shelf14" "$OUT/custom.txt"

# With the calibration: the rig and the combination are validated.
expect_exit 0 "$OUT/calib.txt" "$MVTRACK" check-config "$EX/tracker_options.yaml" --calibration "$EX/calibration.example.yaml"
expect_grep "calibration.example.yaml: 3 camera\(s\) \(ids 0, 1, 2\)$" "$OUT/calib.txt"
expect_exit 0 "$OUT/sim.txt" "$MVTRACK" check-config "$EX/tracker_options.yaml" --calibration "$WORK/poses/calibration.yaml"

# Broken options: exit 1, the message names file, line and key.
printf 'tracker:\n  mode: poses\n  association:\n    lamda: 0.3\n' >"$OUT/typo.yaml"
expect_exit 1 "$OUT/typo.txt" "$MVTRACK" check-config "$OUT/typo.yaml"
expect_grep "typo.yaml:4:5: tracker.association.lamda: unknown key \(did you mean 'lambda'\?\)" "$OUT/typo.txt"
printf 'tracker:\n  window_size: 30\n  window_step: 40\n' >"$OUT/step.yaml"
expect_exit 1 "$OUT/step.txt" "$MVTRACK" check-config "$OUT/step.yaml"
expect_grep "step.yaml:3:.*tracker.window_step" "$OUT/step.txt"
printf 'tracker:\n  sort:\n    iou_threshold: "0.3"\n' >"$OUT/quoted.yaml"
expect_exit 1 "$OUT/quoted.txt" "$MVTRACK" check-config "$OUT/quoted.yaml"
expect_grep "quoted.yaml:3:.*tracker.sort.iou_threshold" "$OUT/quoted.txt"
expect_exit 1 "$OUT/missing.txt" "$MVTRACK" check-config "$OUT/nope.yaml"
expect_grep "nope.yaml" "$OUT/missing.txt"

# Broken calibration, and a rig the tracker refuses (one camera).
sed 's/^    t: \[0.0, 1.5, 4.0\]$/    tt: [0.0, 1.5, 4.0]/' "$EX/calibration.example.yaml" >"$OUT/badcal.yaml"
expect_exit 1 "$OUT/badcal.txt" "$MVTRACK" check-config "$EX/tracker_options.yaml" --calibration "$OUT/badcal.yaml"
expect_grep "badcal.yaml:[0-9]+:[0-9]+: cameras\[0\]" "$OUT/badcal.txt"
py -c '
import sys
print("{\"format\": \"mvtrack.calibration/1\", \"cameras\": [{\"id\": 0, \"image_size\": [640, 480],"
      " \"K\": [[500, 0, 320], [0, 500, 240], [0, 0, 1]],"
      " \"R\": [[1, 0, 0], [0, 1, 0], [0, 0, 1]], \"t\": [0, 0, 5]}]}")' >"$OUT/one.json"
expect_exit 1 "$OUT/one.txt" "$MVTRACK" check-config "$EX/tracker_options.yaml" --calibration "$OUT/one.json"
expect_grep "one.json with .*tracker_options.yaml: .*2" "$OUT/one.txt"
echo "ok"
