#!/usr/bin/env bash
# Accuracy regression on a seeded simulated scene (labels regression + sim, no data needed):
# `mvtrack sim` writes SCENE's recording, `mvtrack replay` tracks it twice -- window jobs inline
# (--threads 0) and on a 2-worker pool (--threads 2) -- which must write byte-identical JSONL,
# and `mvtrack eval` (footprints, 0.5 m gate) must keep every metric of
# tests/regression/sim_floors.txt for SCENE within its bound. The scene is generated at test
# time (same options and seed: byte-identical files). Scenes:
#   store16x32         16 cameras, 32 people, 300 frames, boxes: the ceiling grid where
#                      association over-segments people seen by many cameras
#   identity4x12boxes  4 cameras, 12 people entering and leaving, 3000 frames, boxes: ids that
#                      must not pass from a person who leaves to the next who enters
#   identity4x12poses  the same scene in pose mode
# The box scene store16x32 and the pose scene identity4x12poses are also replayed with
# linking.fragment_births_wait and merge_linked_duplicates off: the pose tracks must not
# change, the box tracks must.
# Usage: sim_regression_test.sh SCENE MVTRACK WORK_DIR SOURCE_DIR
set -euo pipefail
if [ $# -ne 4 ]; then
  echo "usage: $0 SCENE MVTRACK WORK_DIR SOURCE_DIR" >&2
  exit 2
fi
SCENE=$1
MVTRACK=$2
WORK=$3
SRC=$4
# shellcheck source=../support/shell_asserts.sh
. "$SRC/tests/support/shell_asserts.sh"
config=()  # extra replay options of the scene
case $SCENE in
  store16x32)
    mode=boxes
    sim_args=(--cameras 16 --people 32 --frames 300 --seed 1) ;;
  identity4x12boxes)
    mode=boxes
    sim_args=(--cameras 4 --people 12 --enter-leave --frames 3000 --seed 11) ;;
  identity4x12poses)
    mode=poses
    sim_args=(--cameras 4 --people 12 --enter-leave --frames 3000 --seed 11) ;;
  store32x100app)
    mode=boxes
    sim_args=(--cameras 32 --people 100 --frames 600 --seed 1 --embedding-dim 128)
    config=(--config "$SRC/docs/examples/appearance.yaml") ;;
  *) echo "unknown scene '$SCENE' (store16x32, identity4x12boxes, identity4x12poses," \
       "store32x100app)" >&2; exit 2 ;;
esac
OUT=$WORK/$SCENE
rm -rf "$OUT"
mkdir -p "$OUT"

expect_exit 0 "$OUT/sim.log" \
  "$MVTRACK" sim "${sim_args[@]}" --mode "$mode" --out "$OUT/scene" --quiet
for threads in 0 2; do
  expect_exit 0 "$OUT/replay$threads.log" \
    "$MVTRACK" replay --calibration "$OUT/scene/calibration.yaml" --mode "$mode" "${config[@]}" \
    --threads "$threads" --jsonl "$OUT/tracks$threads.jsonl" --quiet "$OUT/scene/detections.lcmlog"
done
cmp "$OUT/tracks0.jsonl" "$OUT/tracks2.jsonl" ||
  fail "two replays of $SCENE (--threads 0 and 2) wrote different JSONL"
[ -s "$OUT/tracks0.jsonl" ] || fail "the replay of $SCENE wrote no tracks"
# LinkerOptions::fragment_births_wait and merge_linked_duplicates are box-mode rules: off,
# pose mode writes the same tracks, and the 16-camera store other tracks.
if [ "$SCENE" = identity4x12poses ] || [ "$SCENE" = store16x32 ]; then
  printf 'tracker:\n  linking:\n    fragment_births_wait: false\n    merge_linked_duplicates: false\n' \
    > "$OUT/no_fragment_wait.yaml"
  expect_exit 0 "$OUT/replay_no_fragment_wait.log" \
    "$MVTRACK" replay --calibration "$OUT/scene/calibration.yaml" --mode "$mode" \
    --config "$OUT/no_fragment_wait.yaml" --jsonl "$OUT/tracks_no_fragment_wait.jsonl" --quiet \
    "$OUT/scene/detections.lcmlog"
  if [ "$mode" = poses ]; then
    cmp "$OUT/tracks0.jsonl" "$OUT/tracks_no_fragment_wait.jsonl" ||
      fail "pose mode: linking.fragment_births_wait or merge_linked_duplicates changed the tracks of $SCENE"
  elif cmp -s "$OUT/tracks0.jsonl" "$OUT/tracks_no_fragment_wait.jsonl"; then
    fail "box mode: linking.fragment_births_wait and merge_linked_duplicates off left the tracks of $SCENE unchanged"
  fi
fi
expect_exit 0 "$OUT/eval.txt" \
  "$MVTRACK" eval --gt "$OUT/scene/gt.jsonl" "$OUT/tracks0.jsonl" --json "$OUT/eval.json"
cat "$OUT/eval.txt"

python3 "$SRC/tests/regression/check_floors.py" "$SCENE" "$SRC/tests/regression/sim_floors.txt" "$OUT/eval.json"
