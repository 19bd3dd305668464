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

python3 - "$SCENE" "$SRC/tests/regression/sim_floors.txt" "$OUT/eval.json" <<'PY'
import json, sys

scene, floors_path, eval_path = sys.argv[1:]
report = json.load(open(eval_path, encoding="utf-8"))
clear = report["tracking"]["clear_mot"]
metrics = {
    "mota": clear["mota"],
    "idf1": report["tracking"]["identity"]["idf1"],
    "false_positives": clear["num_false_positives"],
    "misses": clear["num_misses"],
    "id_switches": clear["num_switches"],
}
checked, failures = 0, []
for number, raw in enumerate(open(floors_path, encoding="utf-8"), 1):
    line = raw.split("#", 1)[0].split()
    if not line:
        continue
    where = f"{floors_path}:{number}"
    if len(line) != 4 or line[2] not in (">=", "<="):
        sys.exit(f"{where}: expected 'SCENE METRIC >=|<= BOUND', got {raw.strip()!r}")
    name, op, bound = line[1], line[2], float(line[3])
    if line[0] != scene:
        continue
    if name not in metrics:
        sys.exit(f"{where}: unknown metric {name!r} (known: {', '.join(sorted(metrics))})")
    value = metrics[name]
    ok = value is not None and (value >= bound if op == ">=" else value <= bound)
    print(f"{scene} {name} = {value} (bound {op} {bound}): {'ok' if ok else 'REGRESSION'}")
    checked += 1
    if not ok:
        failures.append(f"{name} = {value}, bound {op} {bound} ({where})")
if checked == 0:
    sys.exit(f"{floors_path}: no bound for scene {scene}")
if failures:
    sys.exit("FAIL: " + scene + " regressed: " + "; ".join(failures))
print(f"PASS: {scene}: {checked} bounds hold, replays byte-identical")
PY
