# mvtrack convert panoptic on the real data (label data): camera selection (--cameras,
# --num-cameras and its documented order), sequences, clean and corrupted, determinism.
source "$(dirname "$0")/common.sh"
require_dataset panoptic

timed convert_default "$MVTRACK" convert panoptic --data "$DATA_ROOT" --sequence 160906_band2 --out "$OUT/a"
"$CHECK" "$OUT/a" --cameras 2,6,7,12,13,28 --frames 20 --first-frame 139 --last-frame 158 \
  --every-camera-frame --fps 29.97 --layout panoptic19 --gt-lines 20 --gt-layout panoptic19
expect_fixed "keypoint noise sigma 6 px" "$OUT/a/README.txt"
expect_grep 'name: "?00_28"?$' "$OUT/a/calibration.yaml"
"$MVTRACK" convert panoptic --data "$DATA_ROOT" --sequence 160906_band2 --out "$OUT/b" --quiet
same_outputs "$OUT/a" "$OUT/b" detections.lcmlog calibration.yaml ground_truth.jsonl
# --num-cameras 6 is the default subset.
"$MVTRACK" convert panoptic --data "$DATA_ROOT" --sequence 160906_band2 --num-cameras 6 --out "$OUT/n6" --quiet
same_outputs "$OUT/a" "$OUT/n6" detections.lcmlog calibration.yaml

# --num-cameras 9: the six defaults, then 00_00, 00_01, 00_03 (the others by name).
timed convert_n9 "$MVTRACK" convert panoptic --data "$DATA_ROOT" --sequence 160906_band1 --num-cameras 9 --clean --out "$OUT/n9"
"$CHECK" "$OUT/n9" --cameras 0,1,2,3,6,7,12,13,28 --frames 20 --first-frame 168 --last-frame 187 \
  --every-camera-frame --layout panoptic19 --gt-lines 20 --gt-layout panoptic19 --dump "$OUT/n9.dump"
# Clean: at most one detection per person (3 people) in each camera-frame, all with confidence-1
# keypoints or none.
python3 - "$OUT/n9.dump" <<'PY'
import json, sys
for line in open(sys.argv[1]):
    e = json.loads(line)
    assert len(e["detections"]) <= 3, line[:80]
    for d in e["detections"]:
        assert all(c in (0, 1) for _, _, c in d["keypoints"]), line[:80]
        assert d["score"] == 1
PY
# All 31 HD cameras; --cameras by name and by index, in any order.
timed convert_31 "$MVTRACK" convert panoptic --data "$DATA_ROOT" --sequence 160906_band2 --num-cameras 31 --out "$OUT/n31"
"$CHECK" "$OUT/n31" --cameras "$(seq -s, 0 30)" --frames 20 --every-camera-frame --layout panoptic19 --gt-lines 20 >/dev/null
"$MVTRACK" convert panoptic --data "$DATA_ROOT" --sequence 160906_band2 --cameras 00_28,3,00_05 --clean --out "$OUT/sel" --quiet
"$CHECK" "$OUT/sel" --cameras 3,5,28 --frames 20 --every-camera-frame --gt-lines 20 >/dev/null
expect_fixed "HD cameras 00_28, 00_03, 00_05" "$OUT/sel/README.txt"
echo "panoptic: ok"
