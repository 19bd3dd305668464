# mvtrack convert wildtrack on the real data (label data): boxes against MVDeTr_test.json, the
# ground points file, no ground truth, determinism.
source "$(dirname "$0")/common.sh"
require_dataset wildtrack

timed convert "$MVTRACK" convert wildtrack --data "$DATA_ROOT" --out "$OUT/a"
"$CHECK" "$OUT/a" --cameras 0,1,2,3,4,5,6 --frames 40 --first-frame 360 --last-frame 399 \
  --every-camera-frame --fps 2 --layout none --ground-points-lines 40 --dump "$OUT/a.dump"
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
"$MVTRACK" convert wildtrack --data "$DATA_ROOT" --out "$OUT/b" --quiet
same_outputs "$OUT/a" "$OUT/b" detections.lcmlog calibration.yaml ground_points.jsonl
echo "wildtrack: ok"
