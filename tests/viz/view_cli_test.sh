#!/usr/bin/env bash
# mvtrack view: --help, every output kind on the simulated recording of tests/tools (tracks JSONL
# and an LCM tracks log, with calibration and detections), and clear errors (exit 1 naming the
# file, exit 2 for usage) on bad input.
# shellcheck source=../tools/common.sh
source "$3/tests/tools/common.sh"
IN=$WORK/poses

expect_exit 0 "$OUT/help.txt" "$MVTRACK" view --help
expect_grep "^usage: mvtrack view TRACKS" "$OUT/help.txt"
expect_grep "contact sheet" "$OUT/help.txt"
expect_exit 0 "$OUT/top.txt" "$MVTRACK" --help
expect_grep "^  view " "$OUT/top.txt"

# One picture of one frame: floor view + 3 camera panels.
expect_exit 0 "$OUT/png.txt" "$MVTRACK" view "$IN/reference.jsonl" --calibration "$IN/calibration.yaml" \
  --detections "$IN/detections.lcmlog" --frame 100 --png "$OUT/frame100.png" --height 360
expect_grep "wrote .*frame100.png" "$OUT/png.txt"
[ -s "$OUT/frame100.png" ] || fail "no PNG written"
py - "$OUT/frame100.png" <<'PY' || fail "frame100.png is not the expected PNG"
import struct, sys
data = open(sys.argv[1], "rb").read()
assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
width, height = struct.unpack(">II", data[16:24])
# 360 px high plus the 30 px title band; floor view + a column of three 16:9 panels.
assert height == 390, height
assert width > 360 + 190, width
PY

# With a site file: the same picture with its regions and lines (pixels differ), and a broken
# site file is an error naming it.
printf 'format: mvtrack.site/1\nregions:\n  - name: shelf\n    polygon: [[0, 0], [2, 0], [2, 2]]\n' \
  > "$OUT/site.yaml"
expect_exit 0 "$OUT/png_site.txt" "$MVTRACK" view "$IN/reference.jsonl" --calibration \
  "$IN/calibration.yaml" --frame 100 --png "$OUT/frame100_site.png" --height 360 \
  --regions "$OUT/site.yaml" --no-detections-panels
cmp -s "$OUT/frame100_site.png" "$OUT/frame100.png" && fail "--regions drew nothing"
printf 'format: mvtrack.site/1\nregion: []\n' > "$OUT/bad_site.yaml"
expect_exit 1 "$OUT/bad_site.txt" "$MVTRACK" view "$IN/reference.jsonl" --frame 100 \
  --png "$OUT/x.png" --regions "$OUT/bad_site.yaml"
expect_grep "bad_site.yaml:2:1: region: unknown key" "$OUT/bad_site.txt"

# PNG frames of a range, every 10th frame.
expect_exit 0 "$OUT/dir.txt" "$MVTRACK" view "$IN/reference.jsonl" --calibration "$IN/calibration.yaml" \
  --frames 40:99 --every 10 --png-dir "$OUT/frames" --height 200 --quiet
[ "$(ls "$OUT/frames" | wc -l)" -eq 6 ] || fail "expected 6 PNG frames, got $(ls "$OUT/frames" | wc -l)"
[ -s "$OUT/frames/frame_000040.png" ] || fail "frame_000040.png missing"
[ -s "$OUT/frames/frame_000090.png" ] || fail "frame_000090.png missing"

# A contact sheet from an LCM tracks log (replay --out), floor view only.
"$MVTRACK" replay --calibration "$IN/calibration.yaml" --mode poses --layout coco17 \
  --out "$OUT/tracks.lcmlog" --quiet "$IN/detections.lcmlog" >"$OUT/replay.txt" 2>&1 ||
  { cat "$OUT/replay.txt" >&2; fail "replay failed"; }
expect_exit 0 "$OUT/sheet.txt" "$MVTRACK" view "$OUT/tracks.lcmlog" --sheet "$OUT/sheet.png" \
  --sheet-tiles 6 --sheet-columns 3 --sheet-width 200 --height 200
expect_grep "contact sheet of 6 frame" "$OUT/sheet.txt"
py - "$OUT/sheet.png" <<'PY' || fail "sheet.png has the wrong size"
import struct, sys
data = open(sys.argv[1], "rb").read()
width, height = struct.unpack(">II", data[16:24])
assert width == 3 * 200 + 4 * 4, width   # 3 tiles of 200 px and 4 px gaps
PY

# MP4 (when this OpenCV can encode it).
if "$MVTRACK" view "$IN/reference.jsonl" --frames 0:29 --mp4 "$OUT/v.mp4" --height 160 >"$OUT/mp4.txt" 2>&1; then
  expect_grep "wrote 30 frame\(s\) to .*v.mp4, (H.264 \(avc1\)|MPEG-4 Part 2 \(mp4v\): this OpenCV/FFmpeg build has no H.264 encoder)" "$OUT/mp4.txt"
  [ -s "$OUT/v.mp4" ] || fail "empty MP4"
  # The file holds the codec the output names: an avcC box (H.264) or an esds one (mp4v).
  box=esds; grep -q "H.264 (avc1)" "$OUT/mp4.txt" && box=avcC
  grep -q "$box" "$OUT/v.mp4" || fail "the MP4 has no $box box although the output said so"
else
  expect_grep "MP4" "$OUT/mp4.txt"
  echo "view_cli: MP4 output skipped: $(cat "$OUT/mp4.txt")"
fi

# Usage errors: exit 2.
expect_exit 2 "$OUT/e_noout.txt" "$MVTRACK" view "$IN/reference.jsonl"
expect_grep "no output" "$OUT/e_noout.txt"
expect_exit 2 "$OUT/e_png.txt" "$MVTRACK" view "$IN/reference.jsonl" --png "$OUT/x.png"
expect_grep "--png needs --frame" "$OUT/e_png.txt"
expect_exit 2 "$OUT/e_det.txt" "$MVTRACK" view "$IN/reference.jsonl" --detections "$IN/detections.lcmlog" --sheet "$OUT/x.png"
expect_grep "--detections needs --calibration" "$OUT/e_det.txt"
expect_exit 2 "$OUT/e_range.txt" "$MVTRACK" view "$IN/reference.jsonl" --frames 9:3 --sheet "$OUT/x.png"
expect_grep "FIRST is after LAST" "$OUT/e_range.txt"
expect_exit 2 "$OUT/e_opt.txt" "$MVTRACK" view "$IN/reference.jsonl" --colour red --sheet "$OUT/x.png"
expect_grep "unknown option --colour" "$OUT/e_opt.txt"

# Bad input: exit 1 naming the file.
expect_exit 1 "$OUT/e_missing.txt" "$MVTRACK" view "$OUT/nope.jsonl" --sheet "$OUT/x.png"
expect_grep "nope.jsonl" "$OUT/e_missing.txt"
printf '{"frame": 1, "tracks": [' >"$OUT/broken.jsonl"
expect_exit 1 "$OUT/e_broken.txt" "$MVTRACK" view "$OUT/broken.jsonl" --sheet "$OUT/x.png"
expect_grep "broken.jsonl:1" "$OUT/e_broken.txt"
expect_exit 1 "$OUT/e_noframe.txt" "$MVTRACK" view "$IN/reference.jsonl" --frame 99999 --png "$OUT/x.png"
expect_grep "no frame in the selected range" "$OUT/e_noframe.txt"
expect_exit 1 "$OUT/e_calib.txt" "$MVTRACK" view "$IN/reference.jsonl" --calibration "$IN/reference.jsonl" --sheet "$OUT/x.png"
expect_grep "reference.jsonl" "$OUT/e_calib.txt"
expect_exit 1 "$OUT/e_detlog.txt" "$MVTRACK" view "$IN/reference.jsonl" --calibration "$IN/calibration.yaml" \
  --detections "$IN/reference.jsonl" --sheet "$OUT/x.png"
expect_grep "not an LCM log|sync" "$OUT/e_detlog.txt"
expect_exit 1 "$OUT/e_write.txt" "$MVTRACK" view "$IN/reference.jsonl" --sheet "$OUT/no/such/dir/x.png"
expect_grep "no/such/dir/x.png" "$OUT/e_write.txt"
echo "view_cli: ok"
