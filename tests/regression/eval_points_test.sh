#!/usr/bin/env bash
# `mvtrack eval --points` (the WILDTRACK footprint comparison of docs/RESULTS.md) end to end on
# hand-made files whose result is computed by hand below (label unit; no data needed).
# Usage: eval_points_test.sh MVTRACK SOURCE_DIR
set -euo pipefail
if [ $# -ne 2 ]; then
  echo "usage: $0 MVTRACK SOURCE_DIR" >&2
  exit 2
fi
MVTRACK=$1
SRC=$2
# shellcheck source=../support/shell_asserts.sh
. "$SRC/tests/support/shell_asserts.sh"
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT

# Reference points (ids meaningless): frame 0 at (0, 0) and (2, 0); frame 1 at (0, 0).
cat >"$WORK/ref.jsonl" <<'J'
{"frame": 0, "layout": "none", "tracks": [{"id": 0, "joints": [], "position": [0.0000, 0.0000, 0.0000]}, {"id": 1, "joints": [], "position": [2.0000, 0.0000, 0.0000]}], "utime": 0}
{"frame": 1, "layout": "none", "tracks": [{"id": 0, "joints": [], "position": [0.0000, 0.0000, 0.0000]}], "utime": 500000}
J
# Footprints: frame 0 at (0.1, 0) -> 0.1 m, (2, 0.3) -> 0.3 m, and (5, 5), farther than the
# 0.5 m gate from both points; frame 1: nobody.
cat >"$WORK/pred.jsonl" <<'J'
{"frame": 0, "layout": "none", "tracks": [{"id": 4, "joints": [], "position": [0.1000, 0.0000, 0.0000]}, {"id": 5, "joints": [], "position": [2.0000, 0.3000, 0.0000]}, {"id": 6, "joints": [], "position": [5.0000, 5.0000, 0.0000]}], "utime": 0}
{"frame": 1, "layout": "none", "tracks": [], "utime": 500000}
J
expect_exit 0 "$WORK/out.txt" "$MVTRACK" eval --gt "$WORK/ref.jsonl" "$WORK/pred.jsonl" --points \
  --json "$WORK/out.json"
expect_grep '^Footprints vs reference points \(gate 0\.500 m' "$WORK/out.txt"
expect_grep 'ids ignored on both sides' "$WORK/out.txt"
# By hand: 2 frames, 3 reference points, 3 footprints, 2 pairs (0.1 and 0.3 m): median 0.2,
# mean 0.2, p90 (nearest rank ceil(1.8) = 2nd) 0.3; precision 2/3, recall 2/3; count
# differences +1 (frame 0) and -1 (frame 1): mean 0, mean |.| 1, no frame with equal counts.
python3 - "$WORK/out.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
assert "tracking" not in r and "pcp" not in r, sorted(r)
p = r["points"]
assert p["valid"] and p["num_frames"] == 2, p
assert (p["num_reference"], p["num_predicted"], p["num_matched"]) == (3, 3, 2), p
assert abs(p["median_distance_m"] - 0.2) < 1e-6 and abs(p["mean_distance_m"] - 0.2) < 1e-6, p
assert abs(p["p90_distance_m"] - 0.3) < 1e-6 and abs(p["max_distance_m"] - 0.3) < 1e-6, p
assert abs(p["precision"] - 2 / 3) < 1e-6 and abs(p["recall"] - 2 / 3) < 1e-6, p
assert p["mean_count_difference"] == 0 and p["mean_abs_count_difference"] == 1, p
assert p["frames_with_equal_count"] == 0 and p["max_abs_count_difference"] == 1, p
assert [(f["frame"], f["num_reference"], f["num_predicted"], f["num_matched"])
        for f in p["frames"]] == [(0, 2, 3, 2), (1, 1, 0, 0)], p["frames"]
PY
# A tighter gate drops the 0.3 m pair (JSON on stdout, the table on stderr).
"$MVTRACK" eval --gt "$WORK/ref.jsonl" "$WORK/pred.jsonl" --points --threshold 0.2 --json - \
  >"$WORK/out2.json" 2>"$WORK/out2.txt"
expect_grep '^Footprints vs reference points \(gate 0\.200 m' "$WORK/out2.txt"
python3 - "$WORK/out2.json" <<'PY'
import json, sys
p = json.load(open(sys.argv[1]))["points"]
assert p["num_matched"] == 1 and abs(p["median_distance_m"] - 0.1) < 1e-6, p
PY
# Usage errors (exit 2): --points excludes --pcp and joint matching.
expect_exit 2 "$WORK/e1.txt" "$MVTRACK" eval --gt "$WORK/ref.jsonl" "$WORK/pred.jsonl" --points --pcp
expect_grep 'points and --pcp' "$WORK/e1.txt"
expect_exit 2 "$WORK/e2.txt" "$MVTRACK" eval --gt "$WORK/ref.jsonl" "$WORK/pred.jsonl" --points \
  --distance joints
expect_grep 'distance must be footprint' "$WORK/e2.txt"
# MODA / MODP in the table and the JSON; --area drops points outside on both sides.
expect_grep 'MODA%' "$WORK/out2.txt"
"$MVTRACK" eval --gt "$WORK/ref.jsonl" "$WORK/pred.jsonl" --points --area -100,100,-100,100 \
  --json "$WORK/out3.json" >"$WORK/out3.txt"
expect_grep 'outside area' "$WORK/out3.txt"
python3 - "$WORK/out3.json" <<'PY'
import json, sys
b = json.load(open(sys.argv[1]))["points"]
# Every point lies inside the area: TP 2, FP 1, FN 1 of GT 3; MODA = 1 - (FP + FN) / GT.
assert (b["num_matched"], b["false_positives"], b["misses"]) == (2, 1, 1), b
assert abs(b["moda"] - (1 - 2 / 3)) < 1e-5, b  # JSON keeps 6 digits
assert b["area"] == {"min_x": -100, "max_x": 100, "min_y": -100, "max_y": 100}, b["area"]
assert b["num_reference_outside"] == 0 and b["num_predicted_outside"] == 0, b
PY
expect_exit 2 "$WORK/e3.txt" "$MVTRACK" eval --gt "$WORK/ref.jsonl" "$WORK/pred.jsonl" --area 0,1,0,1
expect_grep 'area needs --points' "$WORK/e3.txt"
expect_exit 2 "$WORK/e4.txt" "$MVTRACK" eval --gt "$WORK/ref.jsonl" "$WORK/pred.jsonl" --points \
  --area 1,0,0,1
expect_grep 'MIN_X,MAX_X,MIN_Y,MAX_Y' "$WORK/e4.txt"
echo "PASS: eval --points"
