#!/usr/bin/env bash
# The bundled demo recording (examples/demo, README command 1): the committed files are exactly
# what `mvtrack sim` writes with the documented command (regenerate.sh), and the daemon tracks it
# accurately. Arguments: MVTRACK WORK_DIR SOURCE_DIR MVTRACKD.
MVTRACKD=$4
set -- "$1" "$2" "$3"
. "$(dirname "$0")/common.sh"
DEMO=$SRC/examples/demo

# 1. Provenance: regenerating gives byte-identical files.
expect_exit 0 "$OUT/regenerate.txt" bash "$DEMO/regenerate.sh" "$MVTRACK" "$OUT/regenerated"
for f in detections.lcmlog calibration.yaml gt.jsonl; do
  cmp "$DEMO/$f" "$OUT/regenerated/$f" ||
    fail "examples/demo/$f differs from what examples/demo/regenerate.sh writes: run it and commit"
done

# 2. The daemon on the bundle (what tools/dev/demo.sh runs) publishes every frame, and the tracks
#    match the simulation's ground truth.
expect_exit 0 "$OUT/daemon.txt" "$MVTRACKD" --config "$DEMO/mvtrackd.yaml" \
  --input-log "$DEMO/detections.lcmlog" --tracks-jsonl "$OUT/tracks.jsonl" --workers 2
expect_grep 'published_frames=300 ' "$OUT/daemon.txt"
expect_grep 'decode_errors=0 ' "$OUT/daemon.txt"
expect_exit 0 "$OUT/eval.txt" "$MVTRACK" eval --gt "$DEMO/gt.jsonl" --pred "$OUT/tracks.jsonl" \
  --json "$OUT/eval.json"
# Floors: the measured MOTA 99.2 %, IDF1 99.6 %, MPJPE 7.7 mm (2026-12-02, gap bridging), with margin.
py -c '
import json, sys
d = json.load(open(sys.argv[1]))
mota = d["tracking"]["clear_mot"]["mota"]; idf1 = d["tracking"]["identity"]["idf1"]
mpjpe = d["tracking"]["pose"]["mpjpe_m"]
print("MOTA", mota, "IDF1", idf1, "MPJPE", mpjpe)
assert mota >= 0.95, mota
assert idf1 >= 0.90, idf1
assert mpjpe <= 0.02, mpjpe
' "$OUT/eval.json" || fail "demo accuracy below its floor (see $OUT/eval.txt)"
# The recording as a smoke test (`mvtrack demo --recording DIR`; packages: `--installed`): it
# passes as shipped, fails (exit 1, saying why) when damaged, and the two options exclude each
# other.
expect_exit 0 "$OUT/smoke.txt" "$MVTRACK" demo --recording "$SRC/examples/demo"
expect_grep "^mvtrack demo: smoke test passed: MOTA 9[0-9.]+ %, IDF1 9[0-9.]+ % \(pass mark 95 %\)" "$OUT/smoke.txt"
mkdir -p "$OUT/damaged"
cp "$SRC/examples/demo/calibration.yaml" "$SRC/examples/demo/gt.jsonl" "$OUT/damaged/"
head -c 100000 "$SRC/examples/demo/detections.lcmlog" > "$OUT/damaged/detections.lcmlog"
expect_exit 1 "$OUT/smoke_damaged.txt" "$MVTRACK" demo --recording "$OUT/damaged"
expect_grep "smoke test FAILED" "$OUT/smoke_damaged.txt"
expect_exit 1 "$OUT/smoke_missing.txt" "$MVTRACK" demo --recording "$OUT/nowhere"
expect_grep "nowhere/calibration.yaml" "$OUT/smoke_missing.txt"
expect_exit 2 "$OUT/smoke_both.txt" "$MVTRACK" demo --installed --recording "$SRC/examples/demo"
echo "PASS demo_bundle"
