#!/usr/bin/env bash
# Appearance on and off, end to end on a seeded simulated re-entry scene (4 cameras, 8 people
# who leave and come back after 10-60 s with the same look, 128-d embeddings):
#  - on is the default (issue 42): the defaults and docs/examples/appearance.yaml track alike;
#  - off = exactly the output of the same scene without embeddings (byte-identical JSONL), and
#    appearance on over a stream without embeddings changes nothing either;
#  - on: at least 90 % of the returns get their old id back, none gets another person's id,
#    IDF1 >= 0.9 (off: about 0.4, every return is a new id);
#  - unusable embeddings (NaN, zero, another length or model) are dropped with a count, the
#    detections are still used.
# Usage: appearance_test.sh MVTRACK WORK_DIR SOURCE_DIR
set -euo pipefail
MVTRACK=$1
OUT=$2/appearance
SRC=$3
. "$SRC/tests/support/shell_asserts.sh"
PYTHON=$(python3 -c 'import sys; print(sys.executable)')
rm -rf "$OUT"
mkdir -p "$OUT"
ON=$SRC/docs/examples/appearance.yaml
OFF=$SRC/docs/examples/appearance_off.yaml
SCENE=(--cameras 4 --people 8 --enter-leave --frames 9000 --mode boxes --seed 21 --reentry 0.7)

expect_exit 0 "$OUT/sim_plain.txt" "$MVTRACK" sim --quiet --out "$OUT/plain" "${SCENE[@]}"
expect_exit 0 "$OUT/sim_emb.txt" "$MVTRACK" sim --quiet --out "$OUT/emb" "${SCENE[@]}" \
  --embedding-dim 128
replay() {  # replay DIR OUT.jsonl [config]
  local cfg=()
  [ $# -ge 3 ] && cfg=(--config "$3")
  expect_exit 0 "$2.txt" "$MVTRACK" replay --calibration "$1/calibration.yaml" --mode boxes \
    "${cfg[@]}" --jsonl "$2" "$1/detections.lcmlog"
}
replay "$OUT/plain" "$OUT/plain_off.jsonl" "$OFF"
replay "$OUT/emb" "$OUT/emb_off.jsonl" "$OFF"
replay "$OUT/plain" "$OUT/plain_on.jsonl" "$ON"
replay "$OUT/emb" "$OUT/emb_on.jsonl" "$ON"
replay "$OUT/emb" "$OUT/emb_default.jsonl"
cmp -s "$OUT/emb_on.jsonl" "$OUT/emb_default.jsonl" ||
  fail "the defaults do not use the embeddings (appearance is on by default)"
cmp -s "$OUT/plain_off.jsonl" "$OUT/emb_off.jsonl" ||
  fail "appearance off: tracks differ between the scene with and without embeddings"
cmp -s "$OUT/plain_off.jsonl" "$OUT/plain_on.jsonl" ||
  fail "appearance on over a stream without embeddings changed the tracks"
cmp -s "$OUT/emb_off.jsonl" "$OUT/emb_on.jsonl" && fail "appearance on changed nothing"
expect_grep "appearance: [0-9]+ embeddings used, 0 dropped" "$OUT/emb_on.jsonl.txt"

for run in emb_off emb_on; do
  expect_exit 0 "$OUT/eval_$run.txt" "$MVTRACK" eval --gt "$OUT/emb/gt.jsonl" \
    --pred "$OUT/$run.jsonl" --json "$OUT/eval_$run.json"
done
"$PYTHON" -S - "$OUT/eval_emb_off.json" "$OUT/eval_emb_on.json" <<'PY' || fail "appearance targets"
import json, sys
off, on = (json.load(open(p))["tracking"] for p in sys.argv[1:3])
r = on["returns"]
print("off: IDF1 %.3f, returns kept %d / %d" % (off["identity"]["idf1"], off["returns"]["kept"],
                                                off["returns"]["num_returns"]))
print("on:  IDF1 %.3f, returns kept %d / %d, another person's id %d" % (
    on["identity"]["idf1"], r["kept"], r["num_returns"], r["other_person_id"]))
assert r["num_returns"] >= 50, r["num_returns"]
assert r["kept"] >= 0.9 * r["num_returns"], r
assert r["other_person_id"] == 0, r
assert on["identity"]["idf1"] >= 0.9, on["identity"]["idf1"]
assert off["returns"]["kept"] == 0
PY

# Untrusted embeddings through the JSONL input: a NaN, a zero vector, another length, another
# model: each dropped with a count, every detection still used.
cat > "$OUT/bad.jsonl" <<'JSONL'
{"camera": 0, "frame": 0, "utime": 1000000, "detections": [{"box": [100, 100, 200, 400], "score": 0.9, "embedding": [0.6, 0.8], "embedding_model": "m"}, {"box": [400, 100, 500, 400], "score": 0.9, "embedding": [0, 0], "embedding_model": "m"}]}
{"camera": 0, "frame": 1, "utime": 1033333, "detections": [{"box": [101, 100, 201, 400], "score": 0.9, "embedding": [1, 0, 0], "embedding_model": "m"}, {"box": [401, 100, 501, 400], "score": 0.9, "embedding": [0, 1], "embedding_model": "other"}]}
JSONL
expect_exit 0 "$OUT/convert_bad.txt" "$MVTRACK" convert jsonl --detections "$OUT/bad.jsonl" \
  --calibration "$OUT/emb/calibration.yaml" --out "$OUT/bad" --quiet
replay_bad=("$MVTRACK" replay --calibration "$OUT/bad/calibration.yaml" --mode boxes --config "$ON"
  --jsonl "$OUT/bad_tracks.jsonl" "$OUT/bad/detections.lcmlog")
expect_exit 0 "$OUT/replay_bad.txt" "${replay_bad[@]}"
expect_grep "detections: 4 used, 0 rejected" "$OUT/replay_bad.txt"
expect_grep "appearance: 1 embeddings used, 3 dropped as unusable" "$OUT/replay_bad.txt"
echo "appearance: OK"
