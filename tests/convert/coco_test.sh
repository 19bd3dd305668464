# mvtrack convert coco on hand-made keypoint JSON files (no data needed): the log holds exactly
# the detections written by construction in expected.jsonl (results array and annotations
# object, image ids as integers and file names, bbox and derived boxes, visibility flags),
# and bad input names file, line, column, key path and reason.
source "$(dirname "$0")/common.sh"

expect_exit 0 "$OUT/help.txt" "$MVTRACK" convert --help
expect_grep "^  coco " "$OUT/help.txt"
expect_exit 0 "$OUT/help_coco.txt" "$MVTRACK" convert coco --help
expect_grep "^usage: mvtrack convert coco --out DIR --detections ID=" "$OUT/help_coco.txt"

cat >"$OUT/cal.yaml" <<'YAML'
format: mvtrack.calibration/1
cameras:
  - id: 1
    image_size: [1920, 1080]
    K: [[1000, 0, 960], [0, 1000, 540], [0, 0, 1]]
    R: [[-1, 0, 0], [0, 0, -1], [0, -1, 0]]
    t: [0.0, 1.5, 4.0]
  - id: 2
    image_size: [1920, 1080]
    K: [[1000, 0, 960], [0, 1000, 540], [0, 0, 1]]
    R: [[1, 0, 0], [0, 0, -1], [0, 1, 0]]
    t: [0.0, 1.5, 4.0]
YAML

# Inputs and expected output, built side by side: keypoint j of person p at
# (100 p + 10 j, 200 + 20 j), confidence 0.5 (0 for j = 1 in camera 2).
python3 - "$OUT" <<'PY'
import json, sys
out = sys.argv[1]
def kps(p, conf):
    return [[100 * p + 10 * j, 200 + 20 * j, conf(j)] for j in range(17)]
flat = lambda k: [v for t in k for v in t]
# Camera 1: a results array (mmpose style), pretty-printed, frames 10 and 12, image_id integer.
a = kps(1, lambda j: 0.5)
b = kps(2, lambda j: 0.5)
c = kps(3, lambda j: 0.5)
cam1 = [{"image_id": 10, "category_id": 1, "keypoints": flat(a), "score": 0.75, "bbox": [90, 190, 180, 340]},
        {"image_id": 10, "category_id": 1, "keypoints": flat(b), "score": 0.5, "bbox": [190, 190, 180, 340]},
        {"image_id": 12, "category_id": 1, "keypoints": flat(c), "score": 0.25, "bbox": [290, 190, 180, 340]}]
json.dump(cam1, open(f"{out}/cam1.json", "w"), indent=2)
# Camera 2: an AlphaPose-style array: image_id a file name, nested triples, no bbox (derived
# from the keypoints), no score (mean confidence), extra keys ignored.
d = kps(4, lambda j: 0.0 if j == 1 else 0.5)
cam2 = [{"image_id": "frames/000011.jpg", "keypoints": d, "idx": [3], "track_id": 7}]
json.dump(cam2, open(f"{out}/cam2.json", "w"))
# The derived box: bounds of the detected keypoints grown by 10 % of their height per side.
pts = [(x, y) for x, y, v in d if v > 0]
xs, ys = [p[0] for p in pts], [p[1] for p in pts]
pad = 0.1 * (max(ys) - min(ys))
derived = [min(xs) - pad, min(ys) - pad, max(xs) + pad, max(ys) + pad]
ut = lambda f: 5000000 + round(f * 1e6 / 30)
det = lambda k, s, box: {"box": box, "score": s, "layout": "coco17", "keypoints": k}
expected = [
    {"camera": 1, "frame": 10, "utime": ut(10), "detections": [det(a, 0.75, [90, 190, 270, 530]), det(b, 0.5, [190, 190, 370, 530])]},
    {"camera": 2, "frame": 10, "utime": ut(10), "detections": []},
    {"camera": 1, "frame": 11, "utime": ut(11), "detections": []},
    {"camera": 2, "frame": 11, "utime": ut(11), "detections": [det(d, 0.5, derived)]},
    {"camera": 1, "frame": 12, "utime": ut(12), "detections": [det(c, 0.25, [290, 190, 470, 530])]},
    {"camera": 2, "frame": 12, "utime": ut(12), "detections": []},
]
with open(f"{out}/expected.jsonl", "w") as f:
    for e in expected:
        f.write(json.dumps(e) + "\n")
# A COCO annotations file (ground-truth style) with visibility flags 0/1/2: 1 and 2 -> 1.
v = [[100 + 10 * j, 200 + 20 * j, j % 3] for j in range(17)]
json.dump({"images": [{"id": 3, "file_name": "000003.jpg"}], "categories": [{"id": 1}],
           "annotations": [{"id": 1, "image_id": 3, "category_id": 1, "num_keypoints": 11,
                            "keypoints": flat(v), "bbox": [50, 60, 200, 400], "area": 80000,
                            "iscrowd": 0}]}, open(f"{out}/gt.json", "w"))
vis = [[x, y, 1 if f > 0 else 0] for x, y, f in v]
with open(f"{out}/expected_gt.jsonl", "w") as f:
    f.write(json.dumps({"camera": 1, "frame": 3, "utime": 100000, "detections": [
        det(vis, sum(1 for t in vis if t[2] > 0) / sum(1 for t in vis if t[2] > 0), [50, 60, 250, 460])]}) + "\n")
PY

"$MVTRACK" convert coco --detections "1=$OUT/cam1.json,2=$OUT/cam2.json" --calibration "$OUT/cal.yaml" \
  --fps 30 --start-utime 5000000 --out "$OUT/a" 2>"$OUT/a.log"
expect_grep "wrote .*: 6 events, 4 detections" "$OUT/a.log"
"$CHECK" "$OUT/a" --cameras 1,2 --frames 3 --first-frame 10 --last-frame 12 --every-camera-frame \
  --layout coco17 --detections 4 --dump "$OUT/a.dump"
python3 "$HERE/compare_dump.py" jsonl "$OUT/expected.jsonl" "$OUT/a.dump"
expect_fixed "Camera 2: $OUT/cam2.json (COCO-style keypoint JSON), 1 detections." "$OUT/a/README.txt"
expect_fixed "utime = 5000000 + round((frame - 0) * 1e6 / 30) µs." "$OUT/a/README.txt"

# The annotations object with visibility flags (no score: mean confidence = 1).
"$MVTRACK" convert coco --detections "1=$OUT/gt.json" --calibration "$OUT/cal.yaml" --fps 30 \
  --keypoint-score visibility --out "$OUT/g" --quiet
"$CHECK" "$OUT/g" --cameras 1,2 --frames 1 --dump "$OUT/g.dump" >/dev/null
python3 "$HERE/compare_dump.py" jsonl "$OUT/expected_gt.jsonl" "$OUT/g.dump"
# Read as confidences, the flag 2 is out of range: a clear error.
expect_exit 1 "$OUT/e0.txt" "$MVTRACK" convert coco --detections "1=$OUT/gt.json" \
  --calibration "$OUT/cal.yaml" --fps 30 --out "$OUT/e0"
expect_grep "gt.json:1:[0-9]+: annotations\[0\]\.keypoints\[8\]: confidence 2 of keypoint 2 is outside \[0, 1\] \(use --keypoint-score visibility" "$OUT/e0.txt"

# Bad input on a known line and column of a pretty-printed file.
python3 - "$OUT/cam1.json" "$OUT/bad.json" <<'PY'
import sys
text = open(sys.argv[1]).read().replace('"score": 0.25', '"score": "high"')
open(sys.argv[2], "w").write(text)
PY
line=$(grep -n '"score": "high"' "$OUT/bad.json" | cut -d: -f1)
col=$(( $(grep '"score": "high"' "$OUT/bad.json" | awk '{print index($0, "\"high\"")}') ))
expect_exit 1 "$OUT/e1.txt" "$MVTRACK" convert coco --detections "1=$OUT/bad.json" \
  --calibration "$OUT/cal.yaml" --fps 30 --out "$OUT/e1"
expect_fixed "$OUT/bad.json:$line:$col: [2].score: expected a number, found a string" "$OUT/e1.txt"
[ ! -e "$OUT/e1/detections.lcmlog" ] || fail "a failed conversion left a log"
printf '[{"image_id": 1, "keypoints": [1, 2, 3]}' >"$OUT/trunc.json"
expect_exit 1 "$OUT/e2.txt" "$MVTRACK" convert coco --detections "1=$OUT/trunc.json" \
  --calibration "$OUT/cal.yaml" --fps 30 --out "$OUT/e2"
# The error is just after the last byte.
expect_fixed "$OUT/trunc.json:1:$(( $(wc -c <"$OUT/trunc.json") + 1 )): syntax error while parsing array - unexpected end of input; expected ']'" "$OUT/e2.txt"
printf '[]' >"$OUT/empty.json"
expect_exit 1 "$OUT/e3.txt" "$MVTRACK" convert coco --detections "1=$OUT/empty.json" \
  --calibration "$OUT/cal.yaml" --fps 30 --out "$OUT/e3"
expect_fixed "no detections in any file; give --frames FIRST:LAST" "$OUT/e3.txt"
# ... unless a frame range is given: empty events.
"$MVTRACK" convert coco --detections "1=$OUT/empty.json" --calibration "$OUT/cal.yaml" --fps 30 \
  --frames 0:2 --out "$OUT/e3f" --quiet
"$CHECK" "$OUT/e3f" --cameras 1,2 --frames 3 --first-frame 0 --last-frame 2 --detections 0 >/dev/null

# Usage errors: exit 2.
expect_exit 2 "$OUT/u1.txt" "$MVTRACK" convert coco --detections "1=$OUT/cam1.json" \
  --calibration "$OUT/cal.yaml" --fps 30 --keypoint-score flags --out "$OUT/u"
expect_grep "--keypoint-score must be 'confidence' or 'visibility'" "$OUT/u1.txt"
expect_exit 2 "$OUT/u2.txt" "$MVTRACK" convert coco --calibration "$OUT/cal.yaml" --fps 30 --out "$OUT/u"
expect_grep "--detections CAMERA_ID=FILE,... is required" "$OUT/u2.txt"
expect_exit 2 "$OUT/u3.txt" "$MVTRACK" convert coco --detections "x=$OUT/cam1.json" \
  --calibration "$OUT/cal.yaml" --fps 30 --out "$OUT/u"
expect_grep "camera id 'x'" "$OUT/u3.txt"
[ ! -e "$OUT/u" ] || fail "a usage error created the output directory"
echo "coco: ok"
