# mvtrack convert campus on the real data (label data): the clean variant equals the 2D ground
# truth, the corrupted one is seeded and deterministic, and the seed and rates matter.
source "$(dirname "$0")/common.sh"
require_dataset campus

# The peer's frames: the distinct round(timestamp / 0.04) of result_3d.json.
peer_frames=$(python3 -c "
import json, sys
r = json.load(open(sys.argv[1]))
print(len({round(e['timestamp'] / 0.04) for e in r}))" "$DATA_ROOT/campus/crossview_longcw/result_3d.json")
common=(--cameras 0,1,2 --frames 2000 --first-frame 0 --last-frame 1999 --every-camera-frame --fps 25
        --layout shelf14 --gt-lines 2000 --gt-layout shelf14 --peer-lines "$peer_frames")

timed convert_clean "$MVTRACK" convert campus --data "$DATA_ROOT" --clean --out "$OUT/clean"
"$CHECK" "$OUT/clean" "${common[@]}" --dump "$OUT/clean.dump"
python3 "$HERE/compare_dump.py" campus-clean "$DATA_ROOT" "$OUT/clean.dump"
expect_fixed "clean" "$OUT/clean/README.txt"

timed convert_default "$MVTRACK" convert campus --data "$DATA_ROOT" --out "$OUT/a"
"$CHECK" "$OUT/a" "${common[@]}"
expect_fixed "seed 1, keypoint noise sigma 2 px, joint dropout 0.05, miss rate 0.05, false positives 0.1 per camera-frame" "$OUT/a/README.txt"
expect_fixed "scored frames [350, 470] + [650, 750]" "$OUT/a/README.txt"
# The defaults are datasets::CorruptionOptions' defaults: spelling them out changes nothing.
"$MVTRACK" convert campus --data "$DATA_ROOT" --out "$OUT/b" --seed 1 --noise-px 2 --dropout 0.05 \
  --miss-rate 0.05 --false-positives 0.1 --quiet
same_outputs "$OUT/a" "$OUT/b" detections.lcmlog calibration.yaml ground_truth.jsonl peer.jsonl
# Corruption changes the detections but not the ground truth, peer or calibration.
cmp -s "$OUT/a/detections.lcmlog" "$OUT/clean/detections.lcmlog" && fail "corrupted log equals the clean one"
same_outputs "$OUT/a" "$OUT/clean" calibration.yaml ground_truth.jsonl peer.jsonl
# Another seed, or another rate, gives another log.
"$MVTRACK" convert campus --data "$DATA_ROOT" --out "$OUT/s2" --seed 2 --quiet
cmp -s "$OUT/a/detections.lcmlog" "$OUT/s2/detections.lcmlog" && fail "--seed 2 gave the seed-1 log"
expect_fixed "seed 2," "$OUT/s2/README.txt"
"$MVTRACK" convert campus --data "$DATA_ROOT" --out "$OUT/fp" --false-positives 0 --miss-rate 0 \
  --dropout 0 --noise-px 0 --quiet
# With every rate 0 the model only drops the keypoints outside the image (and people left with
# fewer than 2), and shuffles each camera-frame.
"$CHECK" "$OUT/fp" "${common[@]}" --dump "$OUT/fp.dump" >/dev/null
python3 "$HERE/compare_dump.py" campus-zero-rates "$DATA_ROOT" "$OUT/fp.dump"
# ... which the clean variant does not do (the comparison above can fail).
if python3 "$HERE/compare_dump.py" campus-clean "$DATA_ROOT" "$OUT/fp.dump" >/dev/null 2>&1; then
  fail "the zero-rate corruption equals the clean variant although keypoints leave the image"
fi
# The hard level: seeded, deterministic, its blackout named and inside the scored frames, and
# --corruption default is the default.
"$MVTRACK" convert campus --data "$DATA_ROOT" --out "$OUT/h1" --corruption hard --quiet
"$MVTRACK" convert campus --data "$DATA_ROOT" --out "$OUT/h2" --corruption hard --quiet
same_outputs "$OUT/h1" "$OUT/h2" detections.lcmlog calibration.yaml ground_truth.jsonl
cmp -s "$OUT/h1/detections.lcmlog" "$OUT/a/detections.lcmlog" && fail "the hard level equals the default"
expect_fixed "Student-t noise tails (3 dof), partial false positives next to real people 0.3 per camera-frame, camera" "$OUT/h1/README.txt"
blackout=$(grep -o "blacked out in frames [0-9]*-[0-9]*" "$OUT/h1/README.txt" | head -1)
[ -n "$blackout" ] || fail "the hard level's README names no blackout"
first=${blackout#blacked out in frames }; last=${first#*-}; first=${first%-*}
[ $((last - first + 1)) -eq 25 ] || fail "blackout $first-$last is not 1 s at 25 fps"
if ! { [ "$first" -ge 350 ] && [ "$last" -le 470 ]; } && ! { [ "$first" -ge 650 ] && [ "$last" -le 750 ]; }; then
  fail "blackout $first-$last is not inside the scored frames"
fi
"$MVTRACK" convert campus --data "$DATA_ROOT" --out "$OUT/d" --corruption default --quiet
same_outputs "$OUT/a" "$OUT/d" detections.lcmlog
echo "campus: ok"
