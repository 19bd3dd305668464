# mvtrack convert wildtrack on the real data (label data): boxes against MVDeTr_test.json, the
# ground points file, the ground-truth positions (no ids; --gt-frames), determinism.
source "$(dirname "$0")/common.sh"
require_dataset wildtrack

timed convert "$MVTRACK" convert wildtrack --data "$DATA_ROOT" --out "$OUT/a"
"$CHECK" "$OUT/a" --cameras 0,1,2,3,4,5,6 --frames 40 --first-frame 360 --last-frame 399 \
  --every-camera-frame --fps 2 --layout none --ground-points-lines 40 --gt-lines 40 \
  --gt-layout none \
  --dump "$OUT/a.dump"
python3 "$HERE/compare_dump.py" wildtrack "$DATA_ROOT" "$OUT/a.dump"
expect_fixed "MEANINGLESS" "$OUT/a/README.txt"
expect_grep 'name: "?C7"?$' "$OUT/a/calibration.yaml"
# Ground points: ids 0..n-1 within each frame, on the ground, sorted by x then y.
python3 - "$OUT/a/ground_points.jsonl" <<'PY'
import json, sys
total = 0
for line in open(sys.argv[1]):
    d = json.loads(line)
    ids = [t["id"] for t in d["tracks"]]
    assert ids == list(range(len(ids))), line[:80]
    pts = [tuple(t["position"]) for t in d["tracks"]]
    assert all(p[2] == 0 for p in pts) and pts == sorted(pts), line[:80]
    assert all(t["joints"] == [] for t in d["tracks"])
    total += len(pts)
assert total > 0
print(f"ground points: {total}")
PY
# Ground truth: the 40 detection frames, 952 positions of 41 people (SOURCE.md), with the
# person ids and positions of opentraj/annotations_positions.
expect_fixed "WITH person ids" "$OUT/a/README.txt"
expect_fixed "--threshold 1.0" "$OUT/a/README.txt"
python3 - "$OUT/a/ground_truth.jsonl" "$DATA_ROOT/wildtrack/opentraj/annotations_positions" \
  360 399 952 41 <<'PY'
import json, os, sys
gt, ann, first, last, want_total, want_ids = sys.argv[1], sys.argv[2], *map(int, sys.argv[3:])
lines = [json.loads(l) for l in open(gt)]
assert [d["frame"] for d in lines] == list(range(first, last + 1))
total, ids = 0, set()
for d in lines:
    people = json.load(open(os.path.join(ann, "%08d.json" % (5 * d["frame"]))))
    want = {p["personID"]: (-3 + 0.025 * (p["positionID"] % 480),
                            -9 + 0.025 * (p["positionID"] // 480)) for p in people}
    got = {t["id"]: tuple(t["position"][:2]) for t in d["tracks"]}
    assert got.keys() == want.keys(), d["frame"]
    assert all(abs(got[i][0] - want[i][0]) < 1e-6 and abs(got[i][1] - want[i][1]) < 1e-6
               for i in got), d["frame"]
    total += len(got)
    ids |= got.keys()
assert (total, len(ids)) == (want_total, want_ids), (total, len(ids))
print(f"ground truth: {len(lines)} frames, {total} positions, {len(ids)} ids")
PY
# Without opentraj/ the ground truth falls back to mvdet/gt.txt: positions without ids.
mkdir -p "$OUT/noids/wildtrack"
cp -r "$DATA_ROOT/wildtrack/derived" "$DATA_ROOT/wildtrack/rest" "$DATA_ROOT/wildtrack/mvdet" \
  "$OUT/noids/wildtrack/"
"$MVTRACK" convert wildtrack --data "$OUT/noids" --out "$OUT/n" --quiet
expect_fixed "There are NO person ids" "$OUT/n/README.txt"
expect_fixed "--points --area -3,9,-9,27" "$OUT/n/README.txt"
python3 - "$OUT/n/ground_truth.jsonl" 40 952 <<'PY'
import json, sys
frames, total = 0, 0
for line in open(sys.argv[1]):
    d = json.loads(line)
    assert [t["id"] for t in d["tracks"]] == list(range(len(d["tracks"]))), line[:80]
    assert all(-3 <= t["position"][0] < 9 and -9 <= t["position"][1] < 27 for t in d["tracks"])
    frames += 1
    total += len(d["tracks"])
assert (frames, total) == (int(sys.argv[2]), int(sys.argv[3])), (frames, total)
print(f"ground truth without ids: {frames} frames, {total} positions")
PY
expect_exit 1 "$OUT/no_annotations.txt" \
  "$MVTRACK" convert wildtrack --data "$OUT/noids" --out "$OUT/n2" --detections annotated --quiet
expect_fixed "annotations_positions not found" "$OUT/no_annotations.txt"
# Any annotated range; a bad one is a usage error.
"$MVTRACK" convert wildtrack --data "$DATA_ROOT" --out "$OUT/all" --gt-frames 0-399 --quiet
[ "$(wc -l < "$OUT/all/ground_truth.jsonl")" -eq 400 ] || fail "--gt-frames 0-399: not 400 lines"
expect_exit 2 "$OUT/bad_range.txt" \
  "$MVTRACK" convert wildtrack --data "$DATA_ROOT" --out "$OUT/bad" --gt-frames 5-1 --quiet
expect_exit 2 "$OUT/out_of_file.txt" \
  "$MVTRACK" convert wildtrack --data "$DATA_ROOT" --out "$OUT/bad2" --gt-frames 390-450 --quiet
expect_fixed "within the annotated frames 0-399" "$OUT/out_of_file.txt"
# MVDeTr's boxes are used as they are unless a corruption level is named; --frames needs the
# annotated boxes.
expect_exit 2 "$OUT/mvdetr_rate.txt" \
  "$MVTRACK" convert wildtrack --data "$DATA_ROOT" --out "$OUT/bad3" --miss-rate 0.2 --quiet
expect_fixed "needs --corruption LEVEL" "$OUT/mvdetr_rate.txt"
expect_exit 2 "$OUT/mvdetr_frames.txt" \
  "$MVTRACK" convert wildtrack --data "$DATA_ROOT" --out "$OUT/bad5" --frames 0-9 --quiet
expect_fixed "needs --detections annotated" "$OUT/mvdetr_frames.txt"
# 20 % of MVDeTr's boxes removed: fewer detections, the ground points of the kept boxes only.
"$MVTRACK" convert wildtrack --data "$DATA_ROOT" --out "$OUT/m20" --corruption default \
  --noise-px 0 --false-positives 0 --miss-rate 0.2 --quiet
"$CHECK" "$OUT/m20" --cameras 0,1,2,3,4,5,6 --frames 40 --every-camera-frame --layout none \
  --ground-points-lines 40 --gt-lines 40 --gt-layout none \
  --dump "$OUT/m20.dump"
python3 - "$OUT/a.dump" "$OUT/m20.dump" "$OUT/a/ground_points.jsonl" \
  "$OUT/m20/ground_points.jsonl" <<'PY'
import json, sys
def boxes(path):
    out = set()
    for line in open(path):
        d = json.loads(line)
        out |= {(d["frame"], d["camera"], tuple(x["box"])) for x in d["detections"]}
    return out
full, kept = boxes(sys.argv[1]), boxes(sys.argv[2])
assert kept < full, "the kept boxes are not a subset of MVDeTr's"
assert 0.7 < len(kept) / len(full) < 0.9, len(kept) / len(full)
points = [sum(len(json.loads(l)["tracks"]) for l in open(p)) for p in sys.argv[3:5]]
assert points[1] != points[0], points
print(f"20 % misses: {len(kept)} of {len(full)} boxes kept, ground points {points[0]} -> {points[1]}")
PY
expect_fixed "miss rate 0.2" "$OUT/m20/README.txt"
expect_exit 2 "$OUT/bad_source.txt" \
  "$MVTRACK" convert wildtrack --data "$DATA_ROOT" --out "$OUT/bad4" --detections yolo --quiet
"$MVTRACK" convert wildtrack --data "$DATA_ROOT" --out "$OUT/b" --quiet
same_outputs "$OUT/a" "$OUT/b" detections.lcmlog calibration.yaml ground_points.jsonl \
  ground_truth.jsonl

# The annotated per-view boxes as detections: exactly the annotations (clipped to the image).
"$MVTRACK" convert wildtrack --data "$DATA_ROOT" --out "$OUT/ann" --detections annotated \
  --corruption clean --frames 100-139 --quiet
"$CHECK" "$OUT/ann" --cameras 0,1,2,3,4,5,6 --frames 40 --first-frame 100 --last-frame 139 \
  --every-camera-frame --fps 2 --layout none --gt-lines 40 --gt-layout none \
  --dump "$OUT/ann.dump"
expect_fixed "clean (no corruption)" "$OUT/ann/README.txt"
python3 - "$OUT/ann.dump" "$DATA_ROOT/wildtrack/opentraj/annotations_positions" 100 139 <<'PY'
import collections, json, os, sys
dump, ann, first, last = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
want = collections.Counter()
for f in range(first, last + 1):
    for p in json.load(open(os.path.join(ann, "%08d.json" % (5 * f)))):
        for v in p["views"]:
            if v["xmin"] == v["ymin"] == v["xmax"] == v["ymax"] == -1:
                continue
            x0, x1 = min(max(v["xmin"], 0), 1920), min(max(v["xmax"], 0), 1920)
            y0, y1 = min(max(v["ymin"], 0), 1080), min(max(v["ymax"], 0), 1080)
            if x1 - x0 >= 2 and y1 - y0 >= 2:
                want[(f, v["viewNum"], round(x0, 3), round(y0, 3), round(x1, 3), round(y1, 3))] += 1
got = collections.Counter()
for line in open(dump):
    d = json.loads(line)
    for det in d["detections"]:
        got[(d["frame"], d["camera"], *(round(x, 3) for x in det["box"]))] += 1
assert got == want, (len(got), len(want), list((got - want).items())[:3], list((want - got).items())[:3])
print(f"annotated boxes: {sum(got.values())} detections, as annotated")
PY
# Through the detector model: seeded (the same twice, another seed differs), noisier than clean.
"$MVTRACK" convert wildtrack --data "$DATA_ROOT" --out "$OUT/c1" --detections annotated \
  --frames 100-139 --corruption hard --quiet
"$MVTRACK" convert wildtrack --data "$DATA_ROOT" --out "$OUT/c2" --detections annotated \
  --frames 100-139 --corruption hard --quiet
"$MVTRACK" convert wildtrack --data "$DATA_ROOT" --out "$OUT/c3" --detections annotated \
  --frames 100-139 --corruption hard --seed 2 --quiet
same_outputs "$OUT/c1" "$OUT/c2" detections.lcmlog ground_truth.jsonl
cmp -s "$OUT/c1/detections.lcmlog" "$OUT/c3/detections.lcmlog" && fail "--seed 2 changed nothing"
cmp -s "$OUT/c1/detections.lcmlog" "$OUT/ann/detections.lcmlog" && fail "hard == clean"
same_outputs "$OUT/c1" "$OUT/ann" ground_truth.jsonl calibration.yaml
expect_fixed "blacked out" "$OUT/c1/README.txt"
echo "wildtrack: ok"
