# mvtrack convert shelf on the real data (label data; skipped without ../shared/data/shelf unless
# CI is set): structure, content against the source files, ground truth, peer, determinism.
source "$(dirname "$0")/common.sh"
require_dataset shelf

timed convert "$MVTRACK" convert shelf --data "$DATA_ROOT" --out "$OUT/a"
"$CHECK" "$OUT/a" --cameras 0,1,2,3,4 --frames 301 --first-frame 300 --last-frame 600 \
  --every-camera-frame --fps 25 --layout body25 --gt-lines 301 --gt-layout shelf14 \
  --peer-lines 301 --dump "$OUT/a.dump"
# Every person of shelf/derived is one detection of its camera-frame, keypoints as in the file
# (scores clamped to 1), box and score by the documented rule.
python3 "$HERE/compare_dump.py" shelf "$DATA_ROOT" "$OUT/a.dump"
expect_fixed "mvtrack convert shelf --data $DATA_ROOT --out $OUT/a" "$OUT/a/README.txt"
expect_fixed "scored frames [300, 600], scored actors 0, 1, 2" "$OUT/a/README.txt"
expect_fixed "Actors (frames present): 0 (279) 1 (37) 2 (161) 3 (33)" "$OUT/a/README.txt"
expect_fixed "4d_association" "$OUT/a/README.txt"
# The ground truth holds the 4 actors with all 14 joints.
python3 - "$OUT/a/ground_truth.jsonl" <<'PY'
import json, sys, collections
ids = collections.Counter()
for line in open(sys.argv[1]):
    d = json.loads(line)
    for t in d["tracks"]:
        ids[t["id"]] += 1
        assert len(t["joints"]) == 14 and all(j is not None for j in t["joints"]), line[:80]
assert dict(ids) == {0: 279, 1: 37, 2: 161, 3: 33}, ids
PY

# Determinism: a second conversion is byte-identical.
"$MVTRACK" convert shelf --data "$DATA_ROOT" --out "$OUT/b" --quiet
same_outputs "$OUT/a" "$OUT/b" detections.lcmlog calibration.yaml ground_truth.jsonl peer.jsonl
# Per-camera channels: same events on other channels.
"$MVTRACK" convert shelf --data "$DATA_ROOT" --out "$OUT/p" --channel per-camera --quiet
"$CHECK" "$OUT/p" --cameras 0,1,2,3,4 --frames 301 --every-camera-frame --channel per-camera \
  --layout body25 --gt-lines 301 --peer-lines 301 >/dev/null
cmp -s "$OUT/a/detections.lcmlog" "$OUT/p/detections.lcmlog" && fail "per-camera log equals the shared one"
# The older linux-branch run of 4D Association as the peer: same detections and ground truth,
# another peer file, named in the README.
"$MVTRACK" convert shelf --data "$DATA_ROOT" --out "$OUT/l" --peer 4d_association_linux --quiet
same_outputs "$OUT/a" "$OUT/l" detections.lcmlog calibration.yaml ground_truth.jsonl
cmp -s "$OUT/a/peer.jsonl" "$OUT/l/peer.jsonl" && fail "the linux-branch peer equals the windows one"
expect_fixed "4d_association_linux/skel.txt" "$OUT/l/README.txt"
echo "shelf: ok, $(stat -c %s "$OUT/a/detections.lcmlog") bytes of log"
