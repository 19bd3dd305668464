#!/usr/bin/env bash
# mvtrack calib: --help; import (4D Association JSON, EasyMocap text files) writes a valid
# calibration; check prints the cameras, the overlap graph and a short-baseline warning for two
# cameras 10 cm apart, writes the picture, and --strict turns warnings into exit 3; bad input
# fails with exit 1 naming the file, usage errors exit 2.
# shellcheck source=../tools/common.sh
source "$3/tests/tools/common.sh"

expect_exit 0 "$OUT/help.txt" "$MVTRACK" calib --help
expect_grep "import" "$OUT/help.txt"
expect_exit 0 "$OUT/help_import.txt" "$MVTRACK" calib import --help
expect_grep "easymocap INTRI.yml EXTRI.yml" "$OUT/help_import.txt"
expect_exit 0 "$OUT/help_check.txt" "$MVTRACK" calib check --help
expect_grep "short" "$OUT/help_check.txt"
expect_exit 0 "$OUT/top.txt" "$MVTRACK" --help
expect_grep "^  calib " "$OUT/top.txt"
expect_exit 2 "$OUT/none.txt" "$MVTRACK" calib
expect_exit 2 "$OUT/unknown.txt" "$MVTRACK" calib frobnicate
expect_grep "unknown calib command 'frobnicate'" "$OUT/unknown.txt"

# Two cameras 10 cm apart, 6 m from the scene, looking along +y (4D Association format:
# RT = [R | t] world->camera, metres).
cat >"$OUT/close.json" <<'JSON'
{"0": {"K": [1000, 0, 516, 0, 1000, 388, 0, 0, 1],
       "RT": [1, 0, 0, 0.05, 0, 0, -1, 1.5, 0, 1, 0, 6.0], "imgSize": [1032, 776]},
 "1": {"K": [1000, 0, 516, 0, 1000, 388, 0, 0, 1],
       "RT": [1, 0, 0, -0.05, 0, 0, -1, 1.5, 0, 1, 0, 6.0], "imgSize": [1032, 776]}}
JSON
expect_exit 0 "$OUT/import.txt" "$MVTRACK" calib import 4da "$OUT/close.json" --out "$OUT/close.yaml"
expect_grep "wrote 2 camera\(s\) to .*close.yaml" "$OUT/import.txt"
expect_grep "^format: \"?mvtrack.calibration/1\"?" "$OUT/close.yaml"
# The imported file is a valid calibration for the rest of the CLI.
expect_exit 0 "$OUT/cc.txt" "$MVTRACK" check-config "$SRC/docs/examples/tracker_options.yaml" --calibration "$OUT/close.yaml"

expect_exit 0 "$OUT/check.txt" "$MVTRACK" calib check "$OUT/close.yaml" --png "$OUT/coverage.png"
expect_grep "^calibration: .*close.yaml, 2 camera\(s\)" "$OUT/check.txt"
expect_grep "^ +0-1 .* SHORT BASELINE$" "$OUT/check.txt"
expect_grep "^warning: camera 0 and camera 1: short baseline: 0.10 m" "$OUT/check.txt"
expect_grep "wrote .*coverage.png" "$OUT/check.txt"
[ -s "$OUT/coverage.png" ] || fail "no coverage picture"
expect_exit 3 "$OUT/strict.txt" "$MVTRACK" calib check "$OUT/close.yaml" --strict
# A lower limit accepts the pair.
expect_exit 0 "$OUT/lenient.txt" "$MVTRACK" calib check "$OUT/close.yaml" --min-angle 0.5 --region=-3,-3,3,3
if grep -q "SHORT BASELINE" "$OUT/lenient.txt"; then fail "--min-angle 0.5 still flags the pair"; fi

# EasyMocap text files.
cat >"$OUT/intri.yml" <<'YML'
%YAML:1.0
---
names:
  - "1"
K_1: !!opencv-matrix
  rows: 3
  cols: 3
  dt: d
  data: [ 1000., 0., 640., 0., 1000., 360., 0., 0., 1. ]
dist_1: !!opencv-matrix
  rows: 1
  cols: 5
  dt: d
  data: [ 0., 0., 0., 0., 0. ]
YML
cat >"$OUT/extri.yml" <<'YML'
%YAML:1.0
---
names:
  - "1"
R_1: !!opencv-matrix
  rows: 3
  cols: 1
  dt: d
  data: [ 0., 0., 0. ]
T_1: !!opencv-matrix
  rows: 3
  cols: 1
  dt: d
  data: [ 0., 0., 2. ]
YML
expect_exit 1 "$OUT/em_nosize.txt" "$MVTRACK" calib import easymocap "$OUT/intri.yml" "$OUT/extri.yml" --out "$OUT/em.yaml"
expect_grep "intri.yml: W_1: .*--image-size" "$OUT/em_nosize.txt"
expect_exit 0 "$OUT/em.txt" "$MVTRACK" calib import easymocap "$OUT/intri.yml" "$OUT/extri.yml" --out "$OUT/em.yaml" --image-size 1280x720
expect_grep "^  - id: 1$" "$OUT/em.yaml"
expect_grep "name: \"1\"" "$OUT/em.yaml"

# Usage errors (exit 2) and bad input (exit 1).
expect_exit 2 "$OUT/u1.txt" "$MVTRACK" calib import 4da "$OUT/close.json"
expect_grep "--out" "$OUT/u1.txt"
expect_exit 2 "$OUT/u2.txt" "$MVTRACK" calib import easymocap "$OUT/intri.yml" --out "$OUT/x.yaml"
expect_grep "two files" "$OUT/u2.txt"
expect_exit 2 "$OUT/u3.txt" "$MVTRACK" calib import voxelpose "$OUT/close.json" --out "$OUT/x.yaml"
expect_grep "--image-size" "$OUT/u3.txt"
expect_exit 2 "$OUT/u4.txt" "$MVTRACK" calib import colmap "$OUT/close.json" --out "$OUT/x.yaml"
expect_grep "unknown format 'colmap'" "$OUT/u4.txt"
expect_exit 2 "$OUT/u5.txt" "$MVTRACK" calib import voxelpose "$OUT/close.json" --out "$OUT/x.yaml" --image-size 12
expect_grep "WIDTHxHEIGHT" "$OUT/u5.txt"
expect_exit 2 "$OUT/u6.txt" "$MVTRACK" calib check "$OUT/close.yaml" --region 1,2,3
expect_grep "X0,Y0,X1,Y1" "$OUT/u6.txt"
expect_exit 2 "$OUT/u7.txt" "$MVTRACK" calib check "$OUT/close.yaml" --min-angle 120
expect_grep "min_triangulation_angle_deg" "$OUT/u7.txt"
expect_exit 1 "$OUT/b1.txt" "$MVTRACK" calib import 4da "$OUT/nope.json" --out "$OUT/x.yaml"
expect_grep "nope.json" "$OUT/b1.txt"
printf '{"0": {"K": [1, 0, 0], "RT": [], "imgSize": [10, 10]}}' >"$OUT/bad.json"
expect_exit 1 "$OUT/b2.txt" "$MVTRACK" calib import 4da "$OUT/bad.json" --out "$OUT/x.yaml"
expect_grep "bad.json.*K" "$OUT/b2.txt"
[ ! -e "$OUT/x.yaml" ] || fail "a failed import left an output file"
expect_exit 1 "$OUT/b3.txt" "$MVTRACK" calib check "$OUT/close.json"
expect_grep "close.json" "$OUT/b3.txt"
echo "calib_cli: ok"
