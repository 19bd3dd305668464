# examples/python/publish_detections.py with PyPI's lcm: JSON-lines detections with embeddings
# published to a file:// LCM log reach `mvtrack replay` with appearance on (every embedding used,
# the bad ones dropped and counted, tracks identical to `mvtrack convert jsonl` of the same
# file); a broken line exits 1 naming it.
source "$(dirname "$0")/common.sh"
# A small scene with 16-d embeddings, as JSON lines (written from the simulator's log).
expect_exit 0 "$OUT/sim.txt" "$MVTRACK" sim --quiet --out "$OUT/sim" --cameras 3 --people 3 \
  --frames 90 --mode boxes --seed 4 --embedding-dim 16
"$VPY" - "$OUT/sim/detections.lcmlog" "$OUT/dets.jsonl" <<'PY'
import json, sys, lcm, mvtrack
out = open(sys.argv[2], "w")
for e in lcm.EventLog(sys.argv[1], "r"):
    m = mvtrack.camera_detections_t.decode(e.data)
    out.write(json.dumps({"camera": m.camera_id, "frame": m.frame, "utime": m.utime,
        "image_size": [m.image_width, m.image_height],
        "detections": [{"box": [d.x_min, d.y_min, d.x_max, d.y_max], "score": d.score,
                        "embedding": list(d.embedding), "embedding_model": d.embedding_model}
                       for d in m.detections]}) + "\n")
PY
"$VPY" "$EXAMPLES/publish_detections.py" "$OUT/dets.jsonl" \
  --lcm-url "file://$OUT/published.lcmlog?mode=w" 2>"$OUT/publish.txt" ||
  { cat "$OUT/publish.txt" >&2; fail "publish_detections.py failed"; }
expect_grep "^published 270 camera-frame\(s\), [0-9]+ detection\(s\) with an embedding$" \
  "$OUT/publish.txt"
ON=$SRC/docs/examples/appearance.yaml
expect_exit 0 "$OUT/replay.txt" "$MVTRACK" replay --calibration "$OUT/sim/calibration.yaml" \
  --mode boxes --config "$ON" --jsonl "$OUT/published.jsonl" "$OUT/published.lcmlog"
expect_grep "appearance: [1-9][0-9]* embeddings used, 0 dropped" "$OUT/replay.txt"
expect_exit 0 "$OUT/convert.txt" "$MVTRACK" convert jsonl --detections "$OUT/dets.jsonl" \
  --calibration "$OUT/sim/calibration.yaml" --out "$OUT/converted" --quiet
expect_exit 0 "$OUT/replay2.txt" "$MVTRACK" replay --calibration "$OUT/sim/calibration.yaml" \
  --mode boxes --config "$ON" --jsonl "$OUT/converted.jsonl" "$OUT/converted/detections.lcmlog"
cmp -s "$OUT/published.jsonl" "$OUT/converted.jsonl" ||
  fail "published and converted detections gave different tracks"
# A broken line: exit 1, the line named.
printf '{"camera": 0, "frame": 0, "utime": 1, "detections": [{"score": 1}]}\n' >"$OUT/bad.jsonl"
expect_exit 1 "$OUT/bad.txt" "$VPY" "$EXAMPLES/publish_detections.py" "$OUT/bad.jsonl" \
  --lcm-url "file://$OUT/bad.lcmlog?mode=w"
expect_grep "bad.jsonl:1: " "$OUT/bad.txt"
# docs/PYTHON.md's minimal publisher, as printed there, through LCM's default URL set to a
# file:// log: one camera-frame of camera 0 with one box that read_log.py decodes.
"$PYTHON" - "$SRC/docs/PYTHON.md" >"$OUT/snippet.py" <<'PY'
import sys
doc = open(sys.argv[1]).read()
start = doc.index("```python", doc.index("A minimal publisher")) + len("```python")
print(doc[start:doc.index("```", start)])
PY
LCM_DEFAULT_URL="file://$OUT/snippet.lcmlog?mode=w" PYTHONPATH="$EXAMPLES" \
  expect_exit 0 "$OUT/snippet.txt" "$VPY" "$OUT/snippet.py"
expect_exit 0 "$OUT/snippet_read.txt" "$VPY" "$EXAMPLES/read_log.py" "$OUT/snippet.lcmlog"
expect_grep "camera 0: 1 camera-frame\(s\), 1 detection\(s\)" "$OUT/snippet_read.txt"
echo "publish_detections: ok"
