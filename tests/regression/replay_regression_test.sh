#!/usr/bin/env bash
# Regression test on real data (labels data + regression): converts DATASET (shelf, campus or
# wildtrack) from ../shared/data (or $MVTRACK_DATA), replays it twice -- window jobs inline
# (--threads 0) and on a 2-worker pool (--threads 2) -- requires byte-identical JSONL, scores it
# with the standard protocol (the same commands as tools/dev/results.sh and docs/RESULTS.md:
# poses against the ground truth; WILDTRACK's footprints against its ground-truth positions with
# `eval --points --area`: MODA, MODP, precision, recall) and requires every metric of tests/regression/floors.txt for
# DATASET to stay within its bound.
# A missing dataset fails when CI is set, and is skipped otherwise.
# Usage: replay_regression_test.sh DATASET MVTRACK WORK_DIR SOURCE_DIR
set -euo pipefail
if [ $# -ne 4 ]; then
  echo "usage: $0 DATASET MVTRACK WORK_DIR SOURCE_DIR" >&2
  exit 2
fi
DATASET=$1
MVTRACK=$2
WORK=$3
SRC=$4
# shellcheck source=../support/shell_asserts.sh
. "$SRC/tests/support/shell_asserts.sh"
DATA_ROOT=${MVTRACK_DATA:-$SRC/../shared/data}
gt=ground_truth.jsonl
source=$DATASET   # the dataset converted
convert_args=()
case $DATASET in
  shelf)
    replay_args=(--mode poses --layout body25)
    eval_args=(--frames 300-600 --distance joints --pcp --actors 0,1,2 --head-rule shelf-4da) ;;
  campus)
    replay_args=(--mode poses --layout shelf14)
    eval_args=(--frames 350-470,650-750 --distance joints --pcp --actors 0,1,2) ;;
  shelf_fit)  # the skeleton fit (issue 40): bone-length stability as well as PCP
    source=shelf
    replay_args=(--mode poses --layout body25
                 --config "$SRC/docs/examples/ablations/refinement_fit_skeleton.yaml")
    eval_args=(--frames 300-600 --distance joints --pcp --actors 0,1,2 --head-rule shelf-4da) ;;
  campus_fit)
    source=campus
    replay_args=(--mode poses --layout shelf14
                 --config "$SRC/docs/examples/ablations/refinement_fit_skeleton.yaml")
    eval_args=(--frames 350-470,650-750 --distance joints --pcp --actors 0,1,2) ;;
  campus_hard)
    # The hard corruption level (docs/ACCURACY.md "Campus at the hard corruption level").
    source=campus
    convert_args=(--corruption hard)
    replay_args=(--mode poses --layout shelf14)
    eval_args=(--frames 350-470,650-750 --distance joints --pcp --actors 0,1,2) ;;
  wildtrack)
    # Defaults, no tuned file: the 2 fps stream scales the frame counts (reference_fps).
    # Detection metrics (footprints against the positions, 0.5 m).
    replay_args=(--mode boxes --layout none)
    eval_args=(--points --area -3,9,-9,27) ;;
  wildtrack_tracking)
    # Tracking with person ids (opentraj/): MVDeTr's boxes, test frames, 1 m.
    source=wildtrack
    replay_args=(--mode boxes --layout none)
    eval_args=(--threshold 1.0) ;;
  wildtrack_annotated)
    # The annotated per-view boxes as they are, test frames 360-399, 1 m.
    source=wildtrack
    convert_args=(--detections annotated --corruption clean)
    replay_args=(--mode boxes --layout none)
    eval_args=(--threshold 1.0) ;;
  wildtrack_annotated_all_default)
    # The annotated boxes of all 400 frames through the default detector model, 1 m.
    source=wildtrack
    convert_args=(--detections annotated --frames 0-399 --corruption default)
    replay_args=(--mode boxes --layout none)
    eval_args=(--threshold 1.0) ;;
  epfl)
    # EPFL Terrace, the annotated boxes as they are; cameras from the floor homographies; 0.5 m.
    convert_args=(--corruption clean)
    replay_args=(--mode boxes --layout none)
    eval_args=() ;;
  epfl_default)
    # EPFL Terrace through the default detector model; 0.5 m.
    source=epfl
    convert_args=(--corruption default)
    replay_args=(--mode boxes --layout none)
    eval_args=() ;;
  *) echo "unknown dataset '$DATASET' (shelf, shelf_fit, campus, campus_fit, campus_hard," \
       "wildtrack," \
       "wildtrack_tracking, wildtrack_annotated, wildtrack_annotated_all_default, epfl," \
       "epfl_default)" >&2; exit 2 ;;
esac
if [ ! -d "$DATA_ROOT/$source" ]; then
  message="dataset '$source' not found under $DATA_ROOT (set MVTRACK_DATA to the data root)"
  [ -n "${CI:-}" ] && fail "CI is set and $message"
  echo "SKIPPED: $message"
  exit 0
fi
OUT=$WORK/$DATASET
rm -rf "$OUT"
mkdir -p "$OUT"

expect_exit 0 "$OUT/convert.log" \
  "$MVTRACK" convert "$source" "${convert_args[@]}" --data "$DATA_ROOT" --out "$OUT/data" --quiet
for threads in 0 2; do
  expect_exit 0 "$OUT/replay$threads.log" \
    "$MVTRACK" replay --calibration "$OUT/data/calibration.yaml" "${replay_args[@]}" \
    --threads "$threads" --jsonl "$OUT/tracks$threads.jsonl" --quiet "$OUT/data/detections.lcmlog"
done
cmp "$OUT/tracks0.jsonl" "$OUT/tracks2.jsonl" ||
  fail "two replays of $DATASET (--threads 0 and 2) wrote different JSONL"
[ -s "$OUT/tracks0.jsonl" ] || fail "the replay of $DATASET wrote no tracks"
expect_exit 0 "$OUT/eval.txt" \
  "$MVTRACK" eval --gt "$OUT/data/$gt" "$OUT/tracks0.jsonl" "${eval_args[@]}" \
  --json "$OUT/eval.json"
cat "$OUT/eval.txt"

python3 "$SRC/tests/regression/check_floors.py" "$DATASET" "$SRC/tests/regression/floors.txt" "$OUT/eval.json"
