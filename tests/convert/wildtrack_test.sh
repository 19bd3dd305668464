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
# Ground truth: the 40 detection frames, 952 positions (SOURCE.md), ids 0..n-1 per frame.
expect_fixed "There are NO person ids" "$OUT/a/README.txt"
expect_fixed "--points --area -3,9,-9,27" "$OUT/a/README.txt"
python3 - "$OUT/a/ground_truth.jsonl" 40 952 <<'PY'
import json, sys
frames, total = 0, 0
for line in open(sys.argv[1]):
    d = json.loads(line)
    assert [t["id"] for t in d["tracks"]] == list(range(len(d["tracks"]))), line[:80]
    assert all(-3 <= t["position"][0] < 9 and -9 <= t["position"][1] < 27 for t in d["tracks"])
    frames += 1
    total += len(d["tracks"])
assert (frames, total) == (int(sys.argv[2]), int(sys.argv[3])), (frames, total)
print(f"ground truth: {frames} frames, {total} positions")
PY
# Any annotated range; a bad one is a usage error, one outside the file a failure.
"$MVTRACK" convert wildtrack --data "$DATA_ROOT" --out "$OUT/all" --gt-frames 0-399 --quiet
[ "$(wc -l < "$OUT/all/ground_truth.jsonl")" -eq 400 ] || fail "--gt-frames 0-399: not 400 lines"
expect_exit 2 "$OUT/bad_range.txt" \
  "$MVTRACK" convert wildtrack --data "$DATA_ROOT" --out "$OUT/bad" --gt-frames 5-1 --quiet
expect_exit 1 "$OUT/out_of_file.txt" \
  "$MVTRACK" convert wildtrack --data "$DATA_ROOT" --out "$OUT/bad2" --gt-frames 390-450 --quiet
expect_fixed "not within the file's annotated frames" "$OUT/out_of_file.txt"
"$MVTRACK" convert wildtrack --data "$DATA_ROOT" --out "$OUT/b" --quiet
same_outputs "$OUT/a" "$OUT/b" detections.lcmlog calibration.yaml ground_points.jsonl \
  ground_truth.jsonl
echo "wildtrack: ok"
