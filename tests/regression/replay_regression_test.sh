#!/usr/bin/env bash
# Regression test on real data (labels data + regression): converts DATASET (shelf, campus or
# wildtrack) from ../shared/data (or $MVTRACK_DATA), replays it twice -- window jobs inline
# (--threads 0) and on a 2-worker pool (--threads 2) -- requires byte-identical JSONL, scores it
# with the standard protocol (the same commands as tools/dev/results.sh and docs/RESULTS.md:
# poses against the ground truth; WILDTRACK's bottom-centre footprints against MVDeTr's ground
# points with `eval --points`) and requires every metric of tests/regression/floors.txt for
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
case $DATASET in
  shelf)
    replay_args=(--mode poses --layout body25)
    eval_args=(--frames 300-600 --distance joints --pcp --actors 0,1,2 --head-rule shelf-4da) ;;
  campus)
    replay_args=(--mode poses --layout shelf14)
    eval_args=(--frames 350-470,650-750 --distance joints --pcp --actors 0,1,2) ;;
  wildtrack)
    replay_args=(--mode boxes --layout none
                 --config "$SRC/docs/examples/ablations/box_point_bottom_center.yaml")
    gt=ground_points.jsonl
    eval_args=(--points) ;;
  *) echo "unknown dataset '$DATASET' (shelf, campus, wildtrack)" >&2; exit 2 ;;
esac
if [ ! -d "$DATA_ROOT/$DATASET" ]; then
  message="dataset '$DATASET' not found under $DATA_ROOT (set MVTRACK_DATA to the data root)"
  [ -n "${CI:-}" ] && fail "CI is set and $message"
  echo "SKIPPED: $message"
  exit 0
fi
OUT=$WORK/$DATASET
rm -rf "$OUT"
mkdir -p "$OUT"

expect_exit 0 "$OUT/convert.log" \
  "$MVTRACK" convert "$DATASET" --data "$DATA_ROOT" --out "$OUT/data" --quiet
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

python3 - "$DATASET" "$SRC/tests/regression/floors.txt" "$OUT/eval.json" <<'PY'
import json, sys

dataset, floors_path, eval_path = sys.argv[1:]
report = json.load(open(eval_path, encoding="utf-8"))
metrics = {}
if "tracking" in report:
    clear = report["tracking"]["clear_mot"]
    metrics.update({
        "mota": clear["mota"],
        "idf1": report["tracking"]["identity"]["idf1"],
        "mpjpe_m": report["tracking"]["pose"]["mpjpe_m"],
        "false_positives": clear["num_false_positives"],
        "misses": clear["num_misses"],
        "id_switches": clear["num_switches"],
    })
if "pcp" in report:
    metrics["pcp_average"] = report["pcp"]["average_pcp"]
    for actor in report["pcp"]["actors"]:
        metrics[f"pcp_actor{actor['actor_id']}"] = actor["pcp"]
if "points" in report:
    for key in ("median_distance_m", "p90_distance_m", "precision", "recall",
                "mean_abs_count_difference"):
        metrics[key] = report["points"][key]

checked, failures = 0, []
for number, raw in enumerate(open(floors_path, encoding="utf-8"), 1):
    line = raw.split("#", 1)[0].split()
    if not line:
        continue
    where = f"{floors_path}:{number}"
    if len(line) != 4 or line[2] not in (">=", "<="):
        sys.exit(f"{where}: expected 'DATASET METRIC >=|<= BOUND', got {raw.strip()!r}")
    ds, name, op, bound = line[0], line[1], line[2], float(line[3])
    if ds != dataset:
        continue
    if name not in metrics:
        sys.exit(f"{where}: unknown metric {name!r} (known: {', '.join(sorted(metrics))})")
    value = metrics[name]
    ok = value is not None and (value >= bound if op == ">=" else value <= bound)
    print(f"{dataset} {name} = {value} (bound {op} {bound}): {'ok' if ok else 'REGRESSION'}")
    checked += 1
    if not ok:
        failures.append(f"{name} = {value}, bound {op} {bound} ({where})")
if checked == 0:
    sys.exit(f"{floors_path}: no bound for dataset {dataset}")
if failures:
    sys.exit("FAIL: " + dataset + " regressed: " + "; ".join(failures))
print(f"PASS: {dataset}: {checked} bounds hold, replays byte-identical")
PY
