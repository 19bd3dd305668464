#!/usr/bin/env bash
# mvtrack calib: --help; import (4D Association JSON, EasyMocap text files) writes a valid
# calibration; check prints the cameras, the overlap graph and a short-baseline warning for two
# cameras 10 cm apart, writes the picture, and --strict turns warnings into exit 3; floor
# homographies import to the cameras that made them, with the checks printed; bad input fails
# with exit 1 naming the file, usage errors exit 2.
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

# Floor homographies (EPFL's Homography.txt format): three cameras of known pose, f = 430 px,
# 360x288, the floor in metres for camera 0 and 1 and the same written mirrored-free; the import
# gives the cameras back, prints the checks, and refuses bad input.
py - "$OUT" <<'PY'
import math, sys
out = sys.argv[1]
def sub(a, b): return [x - y for x, y in zip(a, b)]
def cross(a, b): return [a[1]*b[2]-a[2]*b[1], a[2]*b[0]-a[0]*b[2], a[0]*b[1]-a[1]*b[0]]
def unit(a):
    n = math.sqrt(sum(x * x for x in a))
    return [x / n for x in a]
def inverse(m):
    (a, b, c), (d, e, f), (g, h, i) = m
    det = a*(e*i-f*h) - b*(d*i-f*g) + c*(d*h-e*g)
    adj = [[e*i-f*h, c*h-b*i, b*f-c*e], [f*g-d*i, a*i-c*g, c*d-a*f], [d*h-e*g, b*g-a*h, a*e-b*d]]
    return [[x / det for x in row] for row in adj]
for k, (centre, target) in enumerate([([-3, -4, 2], [1, 1, 0]), ([8, -2, 2.5], [2, 2, 0]),
                                      ([2, 9, 3], [1, 1, 0])]):
    z = unit(sub(target, centre))
    x = unit(cross(z, [0, 0, 1]))
    y = cross(z, x)
    R = [x, y, z]  # rows: cam_from_world
    t = [-sum(R[r][c] * centre[c] for c in range(3)) for r in range(3)]
    K = [[430, 0, 180], [0, 430, 144], [0, 0, 1]]
    P = [[R[r][0], R[r][1], t[r]] for r in range(3)]
    G = [[sum(K[r][j] * P[j][c] for j in range(3)) for c in range(3)] for r in range(3)]
    H = inverse(G)
    with open(f"{out}/H{k}.txt", "w") as f:
        for row in H:
            f.write("\t".join(f"{v:.17g}" for v in row) + "\n")
PY
expect_grep "homography H0.txt \[H1.txt ...\]" "$OUT/help_import.txt"
expect_exit 0 "$OUT/hom.txt" "$MVTRACK" calib import homography "$OUT/H0.txt" "$OUT/H1.txt" "$OUT/H2.txt" \
  --image-size 360x288 --floor-unit 1 --out "$OUT/hom.yaml"
expect_grep "^calib import homography: 3 camera\(s\), image 360x288, floor unit 1.000000 m, floor y kept" "$OUT/hom.txt"
expect_grep "^ +0 +430.0 \(est.\) +2.000 +45.4 +37.0 .*H0.txt$" "$OUT/hom.txt"
expect_grep "^ +2 +430.0 \(est.\) +3.000 .*H2.txt$" "$OUT/hom.txt"
expect_grep "note: .*square pixels" "$OUT/hom.txt"
expect_grep "note: focal length from each homography.*0: 430.0 px \(closed form 430.0\), 1: 430.0 px" "$OUT/hom.txt"
expect_grep "wrote 3 camera\(s\) to .*hom.yaml" "$OUT/hom.txt"
expect_exit 0 "$OUT/hom_check.txt" "$MVTRACK" calib check "$OUT/hom.yaml"
expect_grep "^ +0  360x288 +430.0 +430.0 +180.0 +144.0 .* -3.00 +-4.00 +2.00 " "$OUT/hom_check.txt"
# No --floor-unit: the metre, said in a note; --focal given.
expect_exit 0 "$OUT/hom_focal.txt" "$MVTRACK" calib import homography "$OUT/H0.txt" \
  --image-size 360x288 --focal 500 --out "$OUT/hom_focal.yaml"
expect_grep "floor unit 1 m \(assumed\)" "$OUT/hom_focal.txt"
expect_grep "note: floor unit taken as 1 m" "$OUT/hom_focal.txt"
expect_grep "^ +0 +500.0 \(given\)" "$OUT/hom_focal.txt"
# Usage errors and bad input.
expect_exit 2 "$OUT/h1.txt" "$MVTRACK" calib import homography "$OUT/H0.txt" --out "$OUT/y.yaml"
expect_grep "--image-size" "$OUT/h1.txt"
expect_exit 2 "$OUT/h2.txt" "$MVTRACK" calib import homography "$OUT/H0.txt" --image-size 360x288 \
  --floor-unit 0 --out "$OUT/y.yaml"
expect_grep "--floor-unit must be > 0" "$OUT/h2.txt"
expect_exit 2 "$OUT/h3.txt" "$MVTRACK" calib import 4da "$OUT/close.json" --focal 400 --out "$OUT/y.yaml"
expect_grep "--focal is for homography only" "$OUT/h3.txt"
expect_exit 2 "$OUT/h4.txt" "$MVTRACK" calib import 4da "$OUT/close.json" "$OUT/H0.txt" "$OUT/H1.txt" --out "$OUT/y.yaml"
expect_grep "takes at most one input" "$OUT/h4.txt"
printf '1 2 3\n2 4 6\n0 0 1\n' >"$OUT/Hsingular.txt"
expect_exit 1 "$OUT/h5.txt" "$MVTRACK" calib import homography "$OUT/H0.txt" "$OUT/Hsingular.txt" \
  --image-size 360x288 --out "$OUT/y.yaml"
expect_grep "Hsingular.txt: camera 1: the homography is singular" "$OUT/h5.txt"
printf '1 2 3\n2 4\n0 0 1\n' >"$OUT/Hshort.txt"
expect_exit 1 "$OUT/h6.txt" "$MVTRACK" calib import homography "$OUT/Hshort.txt" --image-size 360x288 --out "$OUT/y.yaml"
expect_grep "Hshort.txt: line 2: expected a row of 3 numbers" "$OUT/h6.txt"
expect_exit 1 "$OUT/h7.txt" "$MVTRACK" calib import homography "$OUT/nope.txt" --image-size 360x288 --out "$OUT/y.yaml"
expect_grep "nope.txt: not found" "$OUT/h7.txt"
[ ! -e "$OUT/y.yaml" ] || fail "a failed homography import left an output file"
echo "calib_cli: ok"
