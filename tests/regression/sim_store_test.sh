#!/usr/bin/env bash
# Accuracy regression on a simulated store floor (labels regression + sim, no data needed):
# `mvtrack sim` writes a seeded mid-size ceiling-grid scene (16 cameras, 32 people, 300 frames,
# boxes; the scene where association over-segments people seen by many cameras), `mvtrack
# replay` tracks it twice -- window jobs inline (--threads 0) and on a 2-worker pool
# (--threads 2) -- which must write byte-identical JSONL, and `mvtrack eval` (footprints, 0.5 m
# gate) must keep every metric of tests/regression/sim_floors.txt for the scene within its
# bound. The scene is generated at test time (same options and seed: byte-identical files).
# Usage: sim_store_test.sh MVTRACK WORK_DIR SOURCE_DIR
set -euo pipefail
if [ $# -ne 3 ]; then
  echo "usage: $0 MVTRACK WORK_DIR SOURCE_DIR" >&2
  exit 2
fi
MVTRACK=$1
WORK=$2
SRC=$3
# shellcheck source=../support/shell_asserts.sh
. "$SRC/tests/support/shell_asserts.sh"
SCENE=store16x32
OUT=$WORK/$SCENE
rm -rf "$OUT"
mkdir -p "$OUT"

expect_exit 0 "$OUT/sim.log" \
  "$MVTRACK" sim --cameras 16 --people 32 --frames 300 --mode boxes --seed 1 \
  --out "$OUT/scene" --quiet
for threads in 0 2; do
  expect_exit 0 "$OUT/replay$threads.log" \
    "$MVTRACK" replay --calibration "$OUT/scene/calibration.yaml" --mode boxes \
    --threads "$threads" --jsonl "$OUT/tracks$threads.jsonl" --quiet "$OUT/scene/detections.lcmlog"
done
cmp "$OUT/tracks0.jsonl" "$OUT/tracks2.jsonl" ||
  fail "two replays of $SCENE (--threads 0 and 2) wrote different JSONL"
[ -s "$OUT/tracks0.jsonl" ] || fail "the replay of $SCENE wrote no tracks"
expect_exit 0 "$OUT/eval.txt" \
  "$MVTRACK" eval --gt "$OUT/scene/gt.jsonl" "$OUT/tracks0.jsonl" --json "$OUT/eval.json"
cat "$OUT/eval.txt"

python3 "$SRC/tests/regression/check_floors.py" "$SCENE" "$SRC/tests/regression/sim_floors.txt" "$OUT/eval.json"
