#!/usr/bin/env bash
# mvtrack replay --threads N: the output (JSONL and LCM log) is byte-identical for the inline
# stages (0: tracker::Tracker on the main thread, no thread at all) and for the threaded
# pipeline with pools of 1, 2 and 8 workers; so is the provisional layer (--provisional-jsonl),
# whose ids are the final output's (mvtrack diff --layers, issue 44) and which leaves the final
# output as it is.
source "$(dirname "$0")/common.sh"
P=$WORK/poses
for n in 0 1 2 8; do
  expect_exit 0 "$OUT/t$n.log" "$MVTRACK" replay --quiet --threads "$n" \
    --calibration "$P/calibration.yaml" --mode poses \
    --out "$OUT/t$n.lcmlog" --jsonl "$OUT/t$n.jsonl" --provisional-jsonl "$OUT/now$n.jsonl" \
    "$P/detections.lcmlog"
  expect_grep "output: 240 frame\(s\)" "$OUT/t$n.log"
  expect_grep "wrote $OUT/now$n.jsonl \(provisional layer, JSONL, 240 line\(s\)" "$OUT/t$n.log"
done
expect_grep "inline, no threads" "$OUT/t0.log"
expect_grep "8 worker thread" "$OUT/t8.log"
for n in 1 2 8; do
  cmp "$OUT/t0.jsonl" "$OUT/t$n.jsonl" || fail "--threads $n JSONL differs from --threads 0"
  cmp "$OUT/t0.lcmlog" "$OUT/t$n.lcmlog" || fail "--threads $n LCM log differs from --threads 0"
  cmp "$OUT/now0.jsonl" "$OUT/now$n.jsonl" ||
    fail "--threads $n provisional layer differs from --threads 0"
done
expect_exit 0 "$OUT/layers.txt" "$MVTRACK" diff --layers "$OUT/t0.jsonl" "$OUT/now0.jsonl"
cat "$OUT/layers.txt"
expect_grep "^B's ids that A has at the same frame: [0-9]+ of [1-9][0-9]* \((99\.[0-9]+|100\.00) %\)$" \
  "$OUT/layers.txt"
cmp "$P/reference.jsonl" "$OUT/t0.jsonl" || fail "--threads 0 differs from tracker::Tracker"
echo "ok"
