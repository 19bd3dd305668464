#!/usr/bin/env bash
# mvtrack sim + replay + eval on its output, end to end: the recording is complete and
# deterministic (same options -> byte-identical files, another seed -> different), `mvtrack
# replay` tracks it and `mvtrack eval` scores it above a floor in both modes, enter/leave
# creates more ground-truth ids than people, and bad command lines exit 2 with a message.
# Usage: sim_cli_test.sh MVTRACK WORK_DIR SOURCE_DIR
set -euo pipefail
MVTRACK=$1
OUT=$2/sim_cli
SRC=$3
. "$SRC/tests/support/shell_asserts.sh"
PYTHON=$(python3 -c 'import sys; print(sys.executable)')
rm -rf "$OUT"
mkdir -p "$OUT"

for mode in boxes poses; do
  D=$OUT/$mode
  expect_exit 0 "$OUT/sim_$mode.txt" "$MVTRACK" sim --quiet --out "$D" --cameras 4 --people 5 \
    --frames 150 --mode $mode --seed 3
  for f in detections.lcmlog calibration.yaml gt.jsonl; do
    [ -s "$D/$f" ] || fail "mvtrack sim did not write $f"
  done
  lines=$(wc -l < "$D/gt.jsonl")
  [ "$lines" -eq 150 ] || fail "gt.jsonl has $lines lines, expected 150"
  expect_exit 0 "$OUT/replay_$mode.txt" "$MVTRACK" replay --quiet --calibration "$D/calibration.yaml" \
    --mode $mode --jsonl "$D/tracks.jsonl" "$D/detections.lcmlog"
  expect_exit 0 "$OUT/eval_$mode.txt" "$MVTRACK" eval --gt "$D/gt.jsonl" --pred "$D/tracks.jsonl" \
    --json "$D/eval.json"
  "$PYTHON" -S - "$D/eval.json" "$mode" <<'PY' || fail "eval of the simulated $mode recording below the floor"
import json, sys
d = json.load(open(sys.argv[1]))["tracking"]
mota, idf1 = d["clear_mot"]["mota"], d["identity"]["idf1"]
print("mode %s: MOTA %.3f IDF1 %.3f" % (sys.argv[2], mota, idf1))
assert mota >= 0.8 and idf1 >= 0.8, (mota, idf1)
if sys.argv[2] == "poses":
    assert d["pose"]["mpjpe_m"] < 0.05, d["pose"]["mpjpe_m"]
PY
done

# Deterministic: the same options give byte-identical files; another seed does not.
expect_exit 0 "$OUT/again.txt" "$MVTRACK" sim --quiet --out "$OUT/again" --cameras 4 --people 5 \
  --frames 150 --mode boxes --seed 3
for f in detections.lcmlog calibration.yaml gt.jsonl; do
  cmp -s "$OUT/boxes/$f" "$OUT/again/$f" || fail "$f differs between two identical runs"
done
expect_exit 0 "$OUT/seed4.txt" "$MVTRACK" sim --quiet --out "$OUT/seed4" --cameras 4 --people 5 \
  --frames 150 --mode boxes --seed 4
cmp -s "$OUT/boxes/gt.jsonl" "$OUT/seed4/gt.jsonl" && fail "another seed gave the same ground truth"

# Entering and leaving: more distinct ids than simultaneous people.
expect_exit 0 "$OUT/el.txt" "$MVTRACK" sim --quiet --out "$OUT/el" --cameras 3 --people 4 \
  --frames 900 --mode boxes --enter-leave --mean-stay 4
ids=$("$PYTHON" -S -c 'import json,sys; print(len({t["id"] for l in open(sys.argv[1]) for t in json.loads(l)["tracks"]}))' "$OUT/el/gt.jsonl")
[ "$ids" -gt 4 ] || fail "--enter-leave: only $ids ground-truth ids over 30 s"

# A store floor on a ceiling grid with per-camera channels.
expect_exit 0 "$OUT/grid.txt" "$MVTRACK" sim --quiet --out "$OUT/grid" --cameras 12 --people 20 \
  --frames 30 --mode boxes --layout grid --per-camera-channels
expect_grep "ceiling grid" "$OUT/grid.txt"

# Usage errors: exit 2 with a message naming the option.
expect_exit 2 "$OUT/e1.txt" "$MVTRACK" sim --cameras 4
expect_grep "out DIR is required" "$OUT/e1.txt"
expect_exit 2 "$OUT/e2.txt" "$MVTRACK" sim --out "$OUT/x" --room 5by5
expect_grep "room" "$OUT/e2.txt"
expect_exit 2 "$OUT/e3.txt" "$MVTRACK" sim --out "$OUT/x" --people 500 --room 6x6
expect_grep "do not fit" "$OUT/e3.txt"
expect_exit 2 "$OUT/e4.txt" "$MVTRACK" sim --out "$OUT/x" --layout dome
expect_grep "layout" "$OUT/e4.txt"
expect_exit 2 "$OUT/e5.txt" "$MVTRACK" sim --out "$OUT/x" --linger-at "2,3;4"
expect_grep "linger-at: expected X,Y" "$OUT/e5.txt"
expect_exit 2 "$OUT/e6.txt" "$MVTRACK" sim --out "$OUT/x" --linger-at "0.1,3"
expect_grep "linger_spots must be at least 0.2 m inside" "$OUT/e6.txt"
# Lingering: someone stands at the spot (the description names it).
expect_exit 0 "$OUT/linger.txt" "$MVTRACK" sim --out "$OUT/linger" --cameras 3 --people 4 \
  --frames 600 --mode boxes --linger-at "3,3" --linger-s 30
expect_grep "1 linger spots, 30 s mean" "$OUT/linger.txt"
"$PYTHON" -S - "$OUT/linger/gt.jsonl" <<'PY' || fail "--linger-at 3,3: nobody stood there"
import json, math, sys
near = 0
for line in open(sys.argv[1]):
    frame = json.loads(line)
    near += any(math.hypot(t["position"][0] - 3, t["position"][1] - 3) < 0.4 for t in frame["tracks"])
print("frames with someone within 0.4 m of (3, 3):", near)
sys.exit(0 if near >= 300 else 1)
PY
expect_exit 0 "$OUT/help.txt" "$MVTRACK" sim --help
expect_grep "gt.jsonl" "$OUT/help.txt"
echo "sim_cli_test: ok"
