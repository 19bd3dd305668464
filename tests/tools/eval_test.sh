#!/usr/bin/env bash
# mvtrack eval: scores replayed tracks of the simulated log against its ground truth (MOTA and
# IDF1 above the floor 0.95, measured 1.000 in pose mode), writes parseable JSON, gives the exact
# values of constructed cases (GT against itself, shifted GT, no predictions), honours
# --threshold, and rejects bad command lines and inputs. PCP, layouts, --frames/--actors and box
# mode: eval_pcp_test.sh.
source "$(dirname "$0")/common.sh"
P=$WORK/poses
B=$WORK/boxes
GT=$P/gt.jsonl
gt_objects=$(py -c 'import json,sys; print(sum(len(json.loads(l)["tracks"]) for l in open(sys.argv[1])))' "$GT")
[ "$gt_objects" -gt 0 ] || fail "empty ground truth"

expect_exit 0 "$OUT/replay.log" "$MVTRACK" replay --quiet --calibration "$P/calibration.yaml" \
  --mode poses --out "$OUT/tracks.lcmlog" --jsonl "$OUT/tracks.jsonl" "$P/detections.lcmlog"

# The tracker on the simulated log: above the floor; JSON parses; the table has the protocol.
expect_exit 0 "$OUT/eval.txt" "$MVTRACK" eval --gt "$GT" --pred "$OUT/tracks.jsonl" --json "$OUT/eval.json"
expect_grep "MOTA%" "$OUT/eval.txt"
expect_grep "Protocol: CLEAR MOT" "$OUT/eval.txt"
expect_grep "joints: compared in layout coco17" "$OUT/eval.txt"
json_assert "$OUT/eval.json" \
  'd["schema"] == "mvtrack.eval/1"' "schema" \
  'd["tracking"]["clear_mot"]["mota"] >= 0.95' "MOTA below the floor 0.95" \
  'd["tracking"]["identity"]["idf1"] >= 0.95' "IDF1 below the floor 0.95" \
  "d['tracking']['clear_mot']['num_objects'] == $gt_objects" "num_objects is not the GT track-frames" \
  '"pcp" not in d' "PCP without --pcp"
mota=$(json_get "$OUT/eval.json" 'd["tracking"]["clear_mot"]["mota"], d["tracking"]["identity"]["idf1"]')
# The LCM log of the same run (given as the positional TRACKS) scores the same counts.
expect_exit 0 "$OUT/eval_lcm.txt" "$MVTRACK" eval --gt "$GT" "$OUT/tracks.lcmlog" --json "$OUT/eval_lcm.json"
counts='[d["tracking"]["clear_mot"][k] for k in ("mota", "num_matches", "num_false_positives", "num_misses", "num_switches")]'
[ "$(json_get "$OUT/eval.json" "$counts")" = "$(json_get "$OUT/eval_lcm.json" "$counts")" ] ||
  fail "the JSONL and the LCM log of one run score differently"

# Constructed cases with known results.
expect_exit 0 "$OUT/self.txt" "$MVTRACK" eval --gt "$GT" --pred "$GT" --json "$OUT/self.json"
json_assert "$OUT/self.json" \
  'd["tracking"]["clear_mot"]["mota"] == 1.0' "GT vs itself: MOTA != 1" \
  'd["tracking"]["clear_mot"]["motp_m"] == 0.0' "GT vs itself: MOTP != 0" \
  'd["tracking"]["pose"]["mpjpe_m"] == 0.0' "GT vs itself: MPJPE != 0" \
  'd["tracking"]["identity"]["idf1"] == 1.0' "GT vs itself: IDF1 != 1"
shift_gt() {  # shift_gt DX OUT: the GT with every position and joint moved by DX metres along x
  py - "$GT" "$1" "$2" <<'PY'
import json, sys
with open(sys.argv[3], "w") as out:
    for line in open(sys.argv[1]):
        d = json.loads(line)
        for t in d["tracks"]:
            t["position"][0] += float(sys.argv[2])
            for j in t["joints"]:
                if j is not None:
                    j[0] += float(sys.argv[2])
        out.write(json.dumps(d) + "\n")
PY
}
shift_gt 0.3 "$OUT/gt_shift03.jsonl"
expect_exit 0 "$OUT/s03.txt" "$MVTRACK" eval --gt "$GT" --pred "$OUT/gt_shift03.jsonl" --json "$OUT/s03.json"
json_assert "$OUT/s03.json" \
  'd["tracking"]["clear_mot"]["mota"] == 1.0' "0.3 m shift inside the gate: MOTA != 1" \
  'abs(d["tracking"]["clear_mot"]["motp_m"] - 0.3) < 1e-4' "0.3 m shift: MOTP != 0.3"
# People are >= 0.6 m apart (the simulator's min_separation_m), so after a 0.3 m shift no
# prediction is within 0.25 m of any GT: with --threshold 0.25 nothing matches.
expect_exit 0 "$OUT/s03t.txt" "$MVTRACK" eval --gt "$GT" --pred "$OUT/gt_shift03.jsonl" --threshold 0.25 --json "$OUT/s03t.json"
json_assert "$OUT/s03t.json" 'd["tracking"]["clear_mot"]["mota"] == -1.0' "--threshold 0.25: MOTA != -1"
shift_gt 100 "$OUT/gt_shift100.jsonl"
expect_exit 0 "$OUT/s100.txt" "$MVTRACK" eval --gt "$GT" --pred "$OUT/gt_shift100.jsonl" --json "$OUT/s100.json"
json_assert "$OUT/s100.json" \
  'd["tracking"]["clear_mot"]["mota"] == -1.0' "100 m shift: MOTA != -1" \
  "d['tracking']['clear_mot']['num_false_positives'] == $gt_objects" "100 m shift: FP"
: >"$OUT/empty.jsonl"
expect_exit 0 "$OUT/empty.txt" "$MVTRACK" eval --gt "$GT" --pred "$OUT/empty.jsonl" --json "$OUT/empty.json"
json_assert "$OUT/empty.json" \
  "d['tracking']['clear_mot']['num_misses'] == $gt_objects" "no predictions: FN" \
  'd["tracking"]["clear_mot"]["mota"] == 0.0' "no predictions: MOTA != 0"

# Usage errors (2) and unreadable inputs (1).
expect_exit 2 "$OUT/u1" "$MVTRACK" eval --gt "$GT" --pred "$OUT/tracks.jsonl" --frames 9-3
expect_grep "ends before it starts" "$OUT/u1"
expect_exit 2 "$OUT/u2" "$MVTRACK" eval --gt "$GT" --pred "$OUT/tracks.jsonl" --actors 0,1
expect_grep "\-\-actors applies to PCP only" "$OUT/u2"
expect_exit 2 "$OUT/u3" "$MVTRACK" eval --gt "$GT" --pred "$OUT/tracks.jsonl" --distance iou
expect_exit 2 "$OUT/u4" "$MVTRACK" eval --gt "$GT" --pred "$OUT/tracks.jsonl" --threshold 0
expect_exit 2 "$OUT/u5" "$MVTRACK" eval --gt "$GT" --pred "$OUT/tracks.jsonl" "$OUT/tracks.jsonl"
# A detections log given as the predictions: an error saying so, not MOTA 0.
expect_exit 1 "$OUT/r0" "$MVTRACK" eval --gt "$P/gt.jsonl" --pred "$P/detections.lcmlog"
expect_grep "a detections log \([0-9]+ camera_detections_t events, no MVTRACK_TRACKS\), not tracks" "$OUT/r0"
expect_exit 1 "$OUT/r1" "$MVTRACK" eval --gt "$OUT/nope.jsonl" --pred "$OUT/tracks.jsonl"
expect_grep "nope.jsonl: file does not exist" "$OUT/r1"
{ head -n 3 "$GT"; echo '{"frame": 3, "layout": "coco17", "trakcs": [], "utime": 0}'; } >"$OUT/badgt.jsonl"
expect_exit 1 "$OUT/r2" "$MVTRACK" eval --gt "$OUT/badgt.jsonl" --pred "$OUT/tracks.jsonl"
expect_grep "badgt.jsonl:4: .*trakcs" "$OUT/r2"
echo "ok (MOTA, IDF1 $mota)"
