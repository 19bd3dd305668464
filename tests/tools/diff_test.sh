#!/usr/bin/env bash
# mvtrack diff: identical outputs exit 0; a changed coordinate, a missing frame or different
# track ids exit 1 naming the first differing frame; the tolerance is applied; JSONL and LCM logs
# compare; formatting differences alone are not differences; unreadable inputs exit 2.
source "$(dirname "$0")/common.sh"
P=$WORK/poses
expect_exit 0 "$OUT/replay.log" "$MVTRACK" replay --quiet --calibration "$P/calibration.yaml" \
  --mode poses --out "$OUT/a.lcmlog" --jsonl "$OUT/a.jsonl" "$P/detections.lcmlog"
A=$OUT/a.jsonl

cp "$A" "$OUT/copy.jsonl"
expect_exit 0 "$OUT/same.txt" "$MVTRACK" diff "$A" "$OUT/copy.jsonl"
expect_grep "^identical \(canonical lines, byte for byte\)" "$OUT/same.txt"
expect_grep "240 in both, 0 only in A, 0 only in B; 0 differing" "$OUT/same.txt"
expect_exit 0 "$OUT/lcm.txt" "$MVTRACK" diff "$A" "$OUT/a.lcmlog" --tolerance 0.001
expect_grep "^identical \(tolerance 0.001 m\)" "$OUT/lcm.txt"

# edit FRAME PYTHON_STATEMENT OUT: A with the statement applied to frame FRAME's object `d`.
edit() {
  py - "$A" "$1" "$2" "$3" <<'PY'
import json, sys
with open(sys.argv[4], "w") as out:
    for line in open(sys.argv[1]):
        d = json.loads(line)
        if d["frame"] == int(sys.argv[2]):
            exec(sys.argv[3])
            line = json.dumps(d, sort_keys=True) + "\n"
        out.write(line)
PY
}
# One joint of frame 100 moved by 1 cm.
edit 100 'd["tracks"][1]["joints"][5][2] += 0.01' "$OUT/moved.jsonl"
id=$(py -c 'import json,sys; print([json.loads(l) for l in open(sys.argv[1])][100]["tracks"][1]["id"])' "$A")
expect_exit 1 "$OUT/moved.txt" "$MVTRACK" diff "$A" "$OUT/moved.jsonl"
expect_grep "^first difference: frame 100: track $id: joint 5 differs by 0.01 m" "$OUT/moved.txt"
expect_grep "^  A line 101: \{\"frame\": 100," "$OUT/moved.txt"
expect_grep "^  B line 101: \{\"frame\": 100," "$OUT/moved.txt"
expect_grep "1 differing \(100\)" "$OUT/moved.txt"
expect_grep "^DIFFERENT" "$OUT/moved.txt"
expect_exit 0 "$OUT/moved_tol.txt" "$MVTRACK" diff "$A" "$OUT/moved.jsonl" --tolerance 0.02
expect_exit 1 "$OUT/moved_tol2.txt" "$MVTRACK" diff "$A" "$OUT/moved.jsonl" --tolerance 0.005
expect_grep "^first difference: frame 100:" "$OUT/moved_tol2.txt"

# A track id changed in frame 7; frame 12 missing from B.
edit 7 'd["tracks"][0]["id"] = 99' "$OUT/ids.jsonl"
expect_exit 1 "$OUT/ids.txt" "$MVTRACK" diff "$A" "$OUT/ids.jsonl" --tolerance 1
expect_grep "^first difference: frame 7: track ids \[" "$OUT/ids.txt"
sed '13d' "$A" >"$OUT/missing.jsonl"
expect_exit 1 "$OUT/missing.txt" "$MVTRACK" diff "$A" "$OUT/missing.jsonl"
expect_grep "^first difference: frame 12: only in A" "$OUT/missing.txt"
expect_grep "1 only in A \(12\), 0 only in B" "$OUT/missing.txt"
expect_exit 1 "$OUT/missing_rev.txt" "$MVTRACK" diff "$OUT/missing.jsonl" "$A"
expect_grep "0 only in A, 1 only in B \(12\)" "$OUT/missing_rev.txt"

# The same content in another JSON spelling is not a difference (noted as not canonical).
py -c '
import json, sys
with open(sys.argv[2], "w") as out:
    for line in open(sys.argv[1]):
        out.write(json.dumps(json.loads(line), separators=(",", ":")) + "\n")' "$A" "$OUT/compact.jsonl"
expect_exit 0 "$OUT/compact.txt" "$MVTRACK" diff "$A" "$OUT/compact.jsonl"
expect_grep "240 line\(s\) not canonical" "$OUT/compact.txt"

# Usage and read errors: exit 2, naming the file and line.
expect_exit 2 "$OUT/e1" "$MVTRACK" diff "$A" "$OUT/none.jsonl"
expect_grep "none.jsonl: file does not exist" "$OUT/e1"
{ head -n 4 "$A"; echo '{"frame": 4, "layout": "coco17"'; } >"$OUT/broken.jsonl"
expect_exit 2 "$OUT/e2" "$MVTRACK" diff "$A" "$OUT/broken.jsonl"
expect_grep "broken.jsonl:5: " "$OUT/e2"
{ head -n 4 "$A"; sed -n 2p "$A"; } >"$OUT/repeat.jsonl"
expect_exit 2 "$OUT/e3" "$MVTRACK" diff "$A" "$OUT/repeat.jsonl"
expect_grep "repeat.jsonl:5: frame 1 repeats \(first at line 2\)" "$OUT/e3"
head -c 3000 "$OUT/a.lcmlog" >"$OUT/cut.lcmlog"
expect_exit 2 "$OUT/e4" "$MVTRACK" diff "$A" "$OUT/cut.lcmlog"
expect_grep "cut.lcmlog: truncated" "$OUT/e4"
expect_exit 2 "$OUT/e5" "$MVTRACK" diff "$A" "$A" --tolerance -1
expect_grep "\-\-tolerance must be >= 0" "$OUT/e5"
echo "ok"
