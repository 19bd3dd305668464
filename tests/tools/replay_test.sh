#!/usr/bin/env bash
# mvtrack replay: writes canonical JSONL and an LCM tracks log, reproduces tracker::Tracker on
# the decoded messages byte for byte, is deterministic, applies --config/--mode, and rejects bad
# command lines and inputs with the documented exit codes.
source "$(dirname "$0")/common.sh"
P=$WORK/poses
B=$WORK/boxes

# Pose mode: both outputs.
expect_exit 0 "$OUT/run1.log" "$MVTRACK" replay --quiet --calibration "$P/calibration.yaml" \
  --mode poses --out "$OUT/run1.lcmlog" --jsonl "$OUT/run1.jsonl" "$P/detections.lcmlog"
expect_grep "output: 240 frame\(s\), 3 track id\(s\)" "$OUT/run1.log"
expect_grep "camera-frames: 720 accepted, 0 rejected" "$OUT/run1.log"
expect_grep "bad messages skipped: 0" "$OUT/run1.log"
expect_grep "tracking: 240 frame\(s\) in .* frames/s" "$OUT/run1.log"
[ "$(wc -l <"$OUT/run1.jsonl")" -eq 240 ] || fail "expected 240 JSONL lines"
# The JSONL is exactly what the single-threaded Tracker gives on the same decoded messages.
cmp "$P/reference.jsonl" "$OUT/run1.jsonl" || fail "replay JSONL differs from tracker::Tracker's"
# The LCM log is a log (sync word) holding the same frames (floats: within 1 mm).
[ "$(head -c 4 "$OUT/run1.lcmlog" | od -An -tx1 | tr -d ' \n')" = "eda1da01" ] ||
  fail "run1.lcmlog does not start with the LCM sync word"
expect_exit 0 "$OUT/diff_formats.log" "$MVTRACK" diff "$OUT/run1.jsonl" "$OUT/run1.lcmlog" --tolerance 0.001
expect_grep "^identical" "$OUT/diff_formats.log"

# Deterministic: a second run gives byte-identical files.
expect_exit 0 "$OUT/run2.log" "$MVTRACK" replay --quiet --calibration "$P/calibration.yaml" \
  --mode poses --out "$OUT/run2.lcmlog" --jsonl "$OUT/run2.jsonl" "$P/detections.lcmlog"
cmp "$OUT/run1.jsonl" "$OUT/run2.jsonl" || fail "JSONL differs between two runs"
cmp "$OUT/run1.lcmlog" "$OUT/run2.lcmlog" || fail "LCM log differs between two runs"

# --jsonl - writes the lines to stdout (the summary then goes to stderr).
"$MVTRACK" replay --quiet --calibration "$P/calibration.yaml" --mode poses --jsonl - \
  "$P/detections.lcmlog" >"$OUT/stdout.jsonl" 2>"$OUT/stdout.err"
cmp "$OUT/run1.jsonl" "$OUT/stdout.jsonl" || fail "--jsonl - differs from the file output"
expect_grep "output: 240 frame" "$OUT/stdout.err"

# Box mode (the default mode) reproduces the Tracker too; layout none.
expect_exit 0 "$OUT/boxes.log" "$MVTRACK" replay --quiet --calibration "$B/calibration.yaml" \
  --jsonl "$OUT/boxes.jsonl" "$B/detections.lcmlog"
cmp "$B/reference.jsonl" "$OUT/boxes.jsonl" || fail "box-mode JSONL differs from tracker::Tracker's"
expect_grep "layout none" "$OUT/boxes.log"

# --config is applied (the example file is box mode with the defaults: --mode poses makes it the
# pose run above); a different window step changes the output.
expect_exit 0 "$OUT/cfg.log" "$MVTRACK" replay --quiet --calibration "$P/calibration.yaml" \
  --config "$SRC/docs/examples/tracker_options.yaml" --mode poses --jsonl "$OUT/cfg.jsonl" \
  "$P/detections.lcmlog"
cmp "$OUT/run1.jsonl" "$OUT/cfg.jsonl" || fail "example options + --mode poses differ from the defaults"
printf 'tracker:\n  mode: poses\n  window_step: 10\n' >"$OUT/step10.yaml"
expect_exit 0 "$OUT/step10.log" "$MVTRACK" replay --quiet --calibration "$P/calibration.yaml" \
  --config "$OUT/step10.yaml" --jsonl "$OUT/step10.jsonl" "$P/detections.lcmlog"
expect_exit 1 "$OUT/step10.diff" "$MVTRACK" diff "$OUT/run1.jsonl" "$OUT/step10.jsonl"
expect_grep "^DIFFERENT" "$OUT/step10.diff"

# Detections whose image size differs from the calibration are used (validated against the
# calibration) and counted, with one warning.
sed 's/image_size: \[1280, 720\]/image_size: [1920, 1080]/' "$P/calibration.yaml" >"$OUT/big_images.yaml"
"$MVTRACK" replay --jsonl "$OUT/x.jsonl" --quiet --calibration "$OUT/big_images.yaml" --mode poses "$P/detections.lcmlog" \
  >"$OUT/sizes.log" 2>"$OUT/sizes.err" || fail "replay with another image size failed"
expect_grep "image size differs from calibration: 720" "$OUT/sizes.log"
expect_grep "camera-frames: 720 accepted" "$OUT/sizes.log"
expect_grep "warning: .*image size 1280x720 differs from the calibration's 1920x1080" "$OUT/sizes.err"

# Runs that cannot do their job fail, saying why (exit 1): an empty log, a tracks log, a log
# whose camera ids the calibration does not have.
: >"$OUT/empty.lcmlog"
expect_exit 1 "$OUT/empty.log" "$MVTRACK" replay --quiet --calibration "$P/calibration.yaml" \
  --jsonl "$OUT/empty.jsonl" "$OUT/empty.lcmlog"
expect_grep "0 event\(s\), 0 on detections channels; log end of log" "$OUT/empty.log"
expect_grep "replay: error: nothing to track: the log is empty" "$OUT/empty.log"
[ ! -s "$OUT/empty.jsonl" ] || fail "frames out of an empty log"
expect_exit 1 "$OUT/tracks_in.log" "$MVTRACK" replay --jsonl "$OUT/x.jsonl" --quiet --calibration "$P/calibration.yaml" \
  "$OUT/run1.lcmlog"
expect_grep "nothing to track: no event is on a detections channel \(it holds MVTRACK_TRACKS: a tracks log" \
  "$OUT/tracks_in.log"
sed -E 's/^(\s*-?\s*id:\s*)([0-9]+)/\15\2/' "$P/calibration.yaml" > "$OUT/other_ids.yaml"
expect_exit 1 "$OUT/other_ids.log" "$MVTRACK" replay --jsonl "$OUT/x.jsonl" --quiet --calibration "$OUT/other_ids.yaml" \
  "$P/detections.lcmlog"
expect_grep "replay: error: no camera-frame was accepted \(unknown_camera [0-9]+\); the log's cameras: 0, 1, 2, the calibration's: 50, 51, 52" \
  "$OUT/other_ids.log"

# Usage errors (exit 2) and failures (exit 1), each naming the problem.
expect_exit 2 "$OUT/e0" "$MVTRACK" replay --calibration "$P/calibration.yaml" "$P/detections.lcmlog"
expect_grep "nothing would be written: give --jsonl TRACKS.jsonl \('-': stdout\) and/or --out TRACKS.lcmlog" "$OUT/e0"
expect_exit 1 "$OUT/poses_on_boxes" "$MVTRACK" replay --calibration "$B/calibration.yaml" --mode poses \
  --jsonl "$OUT/x.jsonl" "$B/detections.lcmlog"
expect_grep "replay: error: the tracker runs in pose mode, but none of the log's [0-9]+ detections carries keypoints \(a log of boxes\): --mode boxes tracks them" \
  "$OUT/poses_on_boxes"
expect_exit 2 "$OUT/e1" "$MVTRACK" replay "$P/detections.lcmlog"
expect_grep "\-\-calibration is required" "$OUT/e1"
expect_exit 2 "$OUT/e2" "$MVTRACK" replay --jsonl "$OUT/x.jsonl" --calibration "$P/calibration.yaml" --mode cars "$P/detections.lcmlog"
expect_grep "\-\-mode must be 'boxes' or 'poses'" "$OUT/e2"
expect_exit 2 "$OUT/e3" "$MVTRACK" replay --jsonl "$OUT/x.jsonl" --calibration "$P/calibration.yaml" --threads -1 "$P/detections.lcmlog"
expect_grep "\-\-threads must be in \[0, 256\]" "$OUT/e3"
expect_exit 2 "$OUT/e4" "$MVTRACK" replay --jsonl "$OUT/x.jsonl" --calibration "$P/calibration.yaml" --mode poses --layout none "$P/detections.lcmlog"
expect_grep "tracker options: .*layout" "$OUT/e4"
expect_exit 2 "$OUT/e5" "$MVTRACK" replay --calibration "$P/calibration.yaml" --out "$P/detections.lcmlog" "$P/detections.lcmlog"
expect_grep "would overwrite the input" "$OUT/e5"
expect_exit 1 "$OUT/e6" "$MVTRACK" replay --jsonl "$OUT/x.jsonl" --calibration "$P/calibration.yaml" "$OUT/missing.lcmlog"
expect_grep "missing.lcmlog" "$OUT/e6"
expect_exit 1 "$OUT/e7" "$MVTRACK" replay --jsonl "$OUT/x.jsonl" --calibration "$P/calibration.yaml" "$P/gt.jsonl"
expect_grep "gt.jsonl.*not an LCM log" "$OUT/e7"
expect_exit 1 "$OUT/e8" "$MVTRACK" replay --jsonl "$OUT/x.jsonl" --calibration "$P/gt.jsonl" "$P/detections.lcmlog"
expect_grep "gt.jsonl" "$OUT/e8"
printf 'tracker:\n  window_stpe: 10\n' >"$OUT/typo.yaml"
expect_exit 1 "$OUT/e9" "$MVTRACK" replay --jsonl "$OUT/x.jsonl" --calibration "$P/calibration.yaml" --config "$OUT/typo.yaml" "$P/detections.lcmlog"
expect_grep "typo.yaml:2:.*tracker.window_stpe: unknown key" "$OUT/e9"

# A pose recording replayed in box mode, or with another layout, runs with a warning saying how.
expect_exit 0 "$OUT/as_boxes.log" "$MVTRACK" replay --quiet --calibration "$P/calibration.yaml" \
  --mode boxes --jsonl "$OUT/x.jsonl" "$P/detections.lcmlog"
expect_grep "warning: the log's detections carry keypoints \(coco17 [0-9]+\) but the tracker runs in box mode: --mode poses --layout coco17" \
  "$OUT/as_boxes.log"
expect_exit 0 "$OUT/as_body25.log" "$MVTRACK" replay --quiet --calibration "$P/calibration.yaml" \
  --mode poses --layout body25 --jsonl "$OUT/x.jsonl" "$P/detections.lcmlog"
expect_grep "warning: the log's keypoints are coco17 [0-9]+, the tracker's layout is body25" \
  "$OUT/as_body25.log"

# A calibration in millimetres is refused with the unit named (tracking it would track nobody);
# with `units: mm` it is converted and tracks.
awk '{ if ($1 == "t:") { gsub(/[\[\],]/, " "); printf "    t: [%.1f, %.1f, %.1f]\n", $2 * 1000, $3 * 1000, $4 * 1000 } else print }' \
  "$P/calibration.yaml" > "$OUT/mm.yaml"
expect_exit 1 "$OUT/mm.log" "$MVTRACK" replay --quiet --calibration "$OUT/mm.yaml" --mode poses \
  --jsonl "$OUT/mm.jsonl" "$P/detections.lcmlog"
expect_grep "mm.yaml:2:8: units: the cameras are up to [0-9]+ m apart and [0-9]+ m from the floor plane: the translations t look like millimetres, not metres; write 'units: mm'" \
  "$OUT/mm.log"
sed 's/^units: m$/units: mm/' "$OUT/mm.yaml" > "$OUT/mm_said.yaml"
expect_exit 0 "$OUT/mm_said.log" "$MVTRACK" replay --calibration "$OUT/mm_said.yaml" --mode poses \
  --jsonl "$OUT/mm_said.jsonl" "$P/detections.lcmlog"
expect_grep "output: [0-9]+ frame\(s\), [1-9][0-9]* track id\(s\)" "$OUT/mm_said.log"
echo "ok"
