# mvtrack convert motchallenge on hand-made det.txt files (no data needed): the log holds
# exactly the detections written by construction in expected.jsonl (box = MOT box - 1 pixel,
# score = conf, utime rule, empty events), options, and bad input (file, line, column, reason).
source "$(dirname "$0")/common.sh"

expect_exit 0 "$OUT/help.txt" "$MVTRACK" convert --help
expect_grep "^  motchallenge " "$OUT/help.txt"
expect_exit 0 "$OUT/help_motchallenge.txt" "$MVTRACK" convert motchallenge --help
expect_grep "^usage: mvtrack convert motchallenge --out DIR --detections ID=" "$OUT/help_motchallenge.txt"

cat >"$OUT/cal.yaml" <<'YAML'
format: mvtrack.calibration/1
cameras:
  - id: 0
    image_size: [1920, 1080]
    K: [[1000, 0, 960], [0, 1000, 540], [0, 0, 1]]
    R: [[-1, 0, 0], [0, 0, -1], [0, -1, 0]]
    t: [0.0, 1.5, 4.0]
  - id: 3
    image_size: [1280, 720]
    K: [[900, 0, 640], [0, 900, 360], [0, 0, 1]]
    R: [[1, 0, 0], [0, 0, -1], [0, 1, 0]]
    t: [0.0, 1.5, 4.0]
YAML
# Camera 0: frames 1 and 3 (10 columns, unsorted, CRLF line); camera 3: frame 2 (7 columns).
printf '3,-1,11,21,30,60,0.5,-1,-1,-1\r\n1,-1,101,201,50.5,120,0.75,-1,-1,-1\n1,4,1001,501,20,40,1,-1,-1,-1\n' >"$OUT/c0.txt"
printf '2,-1,501.25,301,40,80,0.125\n' >"$OUT/c3.txt"
# What the log must hold: 25 fps, --start-utime 1000000, frame f at 1000000 + (f - 1) * 40000.
cat >"$OUT/expected.jsonl" <<'JSON'
{"camera": 0, "frame": 1, "utime": 1000000, "detections": [{"box": [100, 200, 150.5, 320], "score": 0.75}, {"box": [1000, 500, 1020, 540], "score": 1}]}
{"camera": 3, "frame": 1, "utime": 1000000, "detections": []}
{"camera": 0, "frame": 2, "utime": 1040000, "detections": []}
{"camera": 3, "frame": 2, "utime": 1040000, "detections": [{"box": [500.25, 300, 540.25, 380], "score": 0.125}]}
{"camera": 0, "frame": 3, "utime": 1080000, "detections": [{"box": [10, 20, 40, 80], "score": 0.5}]}
{"camera": 3, "frame": 3, "utime": 1080000, "detections": []}
JSON

"$MVTRACK" convert motchallenge --detections "0=$OUT/c0.txt,3=$OUT/c3.txt" --calibration "$OUT/cal.yaml" \
  --fps 25 --start-utime 1000000 --out "$OUT/a" 2>"$OUT/a.log"
expect_grep "wrote .*: 6 events, 4 detections" "$OUT/a.log"
"$CHECK" "$OUT/a" --cameras 0,3 --frames 3 --first-frame 1 --last-frame 3 --every-camera-frame \
  --layout none --detections 4 --dump "$OUT/a.dump"
python3 "$HERE/compare_dump.py" jsonl "$OUT/expected.jsonl" "$OUT/a.dump"
expect_fixed "Camera 0: $OUT/c0.txt (MOTChallenge det.txt), 3 detections." "$OUT/a/README.txt"
expect_fixed "utime = 1000000 + round((frame - 1) * 1e6 / 25) µs." "$OUT/a/README.txt"

# --pixel-origin 0 keeps the coordinates; per-camera channels; determinism.
"$MVTRACK" convert motchallenge --detections "0=$OUT/c0.txt,3=$OUT/c3.txt" --calibration "$OUT/cal.yaml" \
  --fps 25 --start-utime 1000000 --pixel-origin 0 --channel per-camera --out "$OUT/b" --quiet
"$CHECK" "$OUT/b" --cameras 0,3 --frames 3 --channel per-camera --dump "$OUT/b.dump" >/dev/null
python3 - "$OUT/expected.jsonl" "$OUT/expected_origin0.jsonl" <<'PY'
import json, sys
with open(sys.argv[2], "w") as out:
    for line in open(sys.argv[1]):
        e = json.loads(line)
        for d in e["detections"]:
            d["box"] = [v + 1 for v in d["box"]]
        out.write(json.dumps(e) + "\n")
PY
python3 "$HERE/compare_dump.py" jsonl "$OUT/expected_origin0.jsonl" "$OUT/b.dump"
"$MVTRACK" convert motchallenge --detections "3=$OUT/c3.txt,0=$OUT/c0.txt" --calibration "$OUT/cal.yaml" \
  --fps 25 --start-utime 1000000 --out "$OUT/c" --quiet
same_outputs "$OUT/a" "$OUT/c" detections.lcmlog calibration.yaml

# --frames widens the range with empty events; only camera 3 listed: camera 0 is silent.
"$MVTRACK" convert motchallenge --detections "3=$OUT/c3.txt" --calibration "$OUT/cal.yaml" \
  --fps 10 --frames 1:5 --out "$OUT/d" --quiet
"$CHECK" "$OUT/d" --cameras 0,3 --frames 5 --first-frame 1 --last-frame 5 --detections 1 \
  --dump "$OUT/d.dump" >/dev/null
[ "$(grep -c '"camera": 3' "$OUT/d.dump")" -eq 5 ] && [ "$(wc -l <"$OUT/d.dump")" -eq 5 ] ||
  fail "expected 5 events, all of camera 3"
expect_grep '"frame": 5, "utime": 400000' "$OUT/d.dump"
expect_fixed "Calibrated cameras without a file (no events): 0." "$OUT/d/README.txt"


# Bad input: exit 1, the message names the file, line, column and reason; no output left.
printf '1,-1,1,1,10,10,1\n2,-1,1,1,10,-4,1\n' >"$OUT/bad.txt"
expect_exit 1 "$OUT/e1.txt" "$MVTRACK" convert motchallenge --detections "0=$OUT/bad.txt" \
  --calibration "$OUT/cal.yaml" --fps 25 --out "$OUT/e1"
expect_fixed "$OUT/bad.txt:2: column 6 (height): '-4' is not > 0" "$OUT/e1.txt"
[ ! -e "$OUT/e1/detections.lcmlog" ] || fail "a failed conversion left a log"
printf '1,-1,1,1,10,10\n' >"$OUT/short.txt"
expect_exit 1 "$OUT/e2.txt" "$MVTRACK" convert motchallenge --detections "0=$OUT/short.txt" \
  --calibration "$OUT/cal.yaml" --fps 25 --out "$OUT/e2"
expect_fixed "$OUT/short.txt:1: 6 comma-separated values, expected 7" "$OUT/e2.txt"
printf '1,-1,1,1,10,10,3.5\n' >"$OUT/score.txt"
expect_exit 1 "$OUT/e3.txt" "$MVTRACK" convert motchallenge --detections "0=$OUT/score.txt" \
  --calibration "$OUT/cal.yaml" --fps 25 --out "$OUT/e3"
expect_fixed "$OUT/score.txt:1: column 7 (conf): '3.5' is outside [0, 1] (--clamp-scores clamps it)" "$OUT/e3.txt"
"$MVTRACK" convert motchallenge --detections "0=$OUT/score.txt" --calibration "$OUT/cal.yaml" \
  --fps 25 --clamp-scores --out "$OUT/e3c" --quiet
expect_fixed "--clamp-scores: 1 score(s) or confidence(s) clamped into [0, 1]." "$OUT/e3c/README.txt"
expect_exit 1 "$OUT/e4.txt" "$MVTRACK" convert motchallenge --detections "5=$OUT/c0.txt" \
  --calibration "$OUT/cal.yaml" --fps 25 --out "$OUT/e4"
expect_fixed "camera 5 ($OUT/c0.txt) is not in the calibration" "$OUT/e4.txt"
expect_exit 1 "$OUT/e5.txt" "$MVTRACK" convert motchallenge --detections "0=$OUT/c0.txt" \
  --calibration "$OUT/cal.yaml" --fps 25 --frames 1:2 --out "$OUT/e5"
expect_fixed "$OUT/c0.txt:1: frame 3 is outside --frames 1:2" "$OUT/e5.txt"
expect_exit 1 "$OUT/e6.txt" "$MVTRACK" convert motchallenge --detections "0=$OUT/nosuch.txt" \
  --calibration "$OUT/cal.yaml" --fps 25 --out "$OUT/e6"
expect_fixed "$OUT/nosuch.txt: cannot open the detections file" "$OUT/e6.txt"

# Usage errors: exit 2.
expect_exit 2 "$OUT/u1.txt" "$MVTRACK" convert motchallenge --detections "0=$OUT/c0.txt" \
  --calibration "$OUT/cal.yaml" --out "$OUT/u"
expect_grep "--fps F is required" "$OUT/u1.txt"
expect_exit 2 "$OUT/u2.txt" "$MVTRACK" convert motchallenge --detections "$OUT/c0.txt" \
  --calibration "$OUT/cal.yaml" --fps 25 --out "$OUT/u"
expect_grep "is not CAMERA_ID=FILE" "$OUT/u2.txt"
expect_exit 2 "$OUT/u3.txt" "$MVTRACK" convert motchallenge --detections "0=$OUT/c0.txt,0=$OUT/c3.txt" \
  --calibration "$OUT/cal.yaml" --fps 25 --out "$OUT/u"
expect_grep "camera 0 is given twice" "$OUT/u3.txt"
expect_exit 2 "$OUT/u4.txt" "$MVTRACK" convert motchallenge --detections "0=$OUT/c0.txt" \
  --calibration "$OUT/cal.yaml" --fps 25 --pixel-origin 2 --out "$OUT/u"
expect_grep "--pixel-origin must be 1 or 0" "$OUT/u4.txt"
expect_exit 2 "$OUT/u5.txt" "$MVTRACK" convert motchallenge --detections "0=$OUT/c0.txt" \
  --calibration "$OUT/cal.yaml" --fps 25 --frames 0:3 --out "$OUT/u"
expect_grep "--frames: '0:3' needs 1 <= FIRST <= LAST" "$OUT/u5.txt"
expect_exit 2 "$OUT/u6.txt" "$MVTRACK" convert motchallenge --detections "0=$OUT/c0.txt" \
  --calibration "$OUT/cal.yaml" --fps 0 --out "$OUT/u"
expect_grep "--fps must be in" "$OUT/u6.txt"
[ ! -e "$OUT/u" ] || fail "a usage error created the output directory"
echo "motchallenge: ok"
