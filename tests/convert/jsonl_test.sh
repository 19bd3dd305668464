# mvtrack convert jsonl on a generated input (no data needed): content, ordering, determinism,
# per-camera channels, bad lines with and without --skip-bad-lines, cross-file checks.
source "$(dirname "$0")/common.sh"

# A calibration with non-dense camera ids (0, 2, 5); camera 5 has lens distortion.
cat >"$OUT/cal.yaml" <<'YAML'
format: mvtrack.calibration/1
cameras:
  - id: 5
    name: east
    image_size: [1280, 720]
    fx: 900.0
    fy: 900.0
    cx: 640.0
    cy: 360.0
    distortion: [-0.1, 0.02, 0.0, 0.0, 0.0]
    rvec: [1.2091995761561452, 1.2091995761561452, -1.2091995761561452]
    t: [0.0, 1.5, 4.0]
  - id: 0
    image_size: [1920, 1080]
    K: [[1000, 0, 960], [0, 1000, 540], [0, 0, 1]]
    R: [[-1, 0, 0], [0, 0, -1], [0, -1, 0]]
    t: [0.0, 1.5, 4.0]
  - id: 2
    image_size: [1920, 1080]
    K: [[1000, 0, 960], [0, 1000, 540], [0, 0, 1]]
    R: [[1, 0, 0], [0, 0, -1], [0, 1, 0]]
    t: [0.0, 1.5, 4.0]
YAML

# gen.py SEED OUT: 40 frames; within a frame the cameras in a seeded random order; camera 5 is
# silent in every 4th frame; 0-4 detections per line, some with coco17 or body25 keypoints,
# some with embeddings; image_size on some lines.
cat >"$OUT/gen.py" <<'PY'
import json, random, sys
rng = random.Random(int(sys.argv[1]))
sizes = {0: [1920, 1080], 2: [1920, 1080], 5: [1280, 720]}
joints = {"coco17": 17, "body25": 25}
with open(sys.argv[2], "w") as out:
    for frame in range(100, 140):
        cams = [0, 2] + ([] if frame % 4 == 0 else [5])
        random.Random(frame * 7 + int(sys.argv[1])).shuffle(cams)
        for cam in cams:
            dets = []
            for _ in range(rng.randrange(5)):
                x, y = rng.uniform(0, 1200), rng.uniform(0, 600)
                d = {"box": [x, y, x + rng.uniform(5, 200), y + rng.uniform(5, 300)],
                     "score": round(rng.random(), 4)}
                if rng.random() < 0.5:
                    layout = rng.choice(sorted(joints))
                    d["layout"] = layout
                    d["keypoints"] = [[rng.uniform(0, 1200), rng.uniform(0, 600),
                                       rng.choice([0, 0.5, rng.random()])] for _ in range(joints[layout])]
                if rng.random() < 0.3:
                    d["embedding"] = [rng.uniform(-1, 1) for _ in range(16)]
                dets.append(d)
            line = {"camera": cam, "frame": frame, "utime": 1700000000000000 + frame * 33333 + cam,
                    "detections": dets}
            if rng.random() < 0.5:
                line["image_size"] = sizes[cam]
            out.write(json.dumps(line) + "\n")
PY
python3 "$OUT/gen.py" 1 "$OUT/dets.jsonl"
lines=$(wc -l <"$OUT/dets.jsonl")

timed convert_a "$MVTRACK" convert jsonl --detections "$OUT/dets.jsonl" --calibration "$OUT/cal.yaml" --out "$OUT/a"
"$CHECK" "$OUT/a" --cameras 0,2,5 --frames 40 --first-frame 100 --last-frame 139 --dump "$OUT/a.dump"
[ "$(wc -l <"$OUT/a.dump")" -eq "$lines" ] || fail "events != input lines ($lines)"
python3 "$HERE/compare_dump.py" jsonl "$OUT/dets.jsonl" "$OUT/a.dump"
[ ! -e "$OUT/a/ground_truth.jsonl" ] || fail "jsonl conversion wrote ground truth"
expect_fixed "mvtrack convert jsonl --detections $OUT/dets.jsonl --calibration $OUT/cal.yaml --out $OUT/a" "$OUT/a/README.txt"
expect_fixed "$lines lines: $lines converted, 0 bad line(s) skipped" "$OUT/a/README.txt"
# The calibration is written back in canonical form (ids ascending, names kept).
expect_grep "^format: mvtrack.calibration/1" "$OUT/a/calibration.yaml"
expect_grep 'name: "?east"?$' "$OUT/a/calibration.yaml"
[ "$(grep -c '^  - id:' "$OUT/a/calibration.yaml")" -eq 3 ] || fail "calibration cameras"

# Determinism: the same input twice, and the same lines with every frame's cameras in another
# order, give byte-identical logs.
"$MVTRACK" convert jsonl --detections "$OUT/dets.jsonl" --calibration "$OUT/cal.yaml" --out "$OUT/b" --quiet
same_outputs "$OUT/a" "$OUT/b" detections.lcmlog calibration.yaml
python3 - "$OUT/dets.jsonl" "$OUT/dets_reordered.jsonl" <<'PY'
import json, sys, itertools
lines = [l for l in open(sys.argv[1])]
with open(sys.argv[2], "w") as out:
    for _, group in itertools.groupby(lines, key=lambda l: json.loads(l)["frame"]):
        out.writelines(reversed(list(group)))
PY
cmp -s "$OUT/dets.jsonl" "$OUT/dets_reordered.jsonl" && fail "the reordered input is not reordered"
"$MVTRACK" convert jsonl --detections "$OUT/dets_reordered.jsonl" --calibration "$OUT/cal.yaml" --out "$OUT/c" --quiet
same_outputs "$OUT/a" "$OUT/c" detections.lcmlog
# Another input gives another log (the comparison above can fail).
python3 "$OUT/gen.py" 2 "$OUT/dets2.jsonl"
"$MVTRACK" convert jsonl --detections "$OUT/dets2.jsonl" --calibration "$OUT/cal.yaml" --out "$OUT/d" --quiet
cmp -s "$OUT/a/detections.lcmlog" "$OUT/d/detections.lcmlog" && fail "different inputs gave the same log"

# Per-camera channels.
"$MVTRACK" convert jsonl --detections "$OUT/dets.jsonl" --calibration "$OUT/cal.yaml" --out "$OUT/p" \
  --channel per-camera --quiet
"$CHECK" "$OUT/p" --cameras 0,2,5 --frames 40 --channel per-camera >/dev/null
expect_fixed "per-camera channels MVTRACK_DETECTIONS_<camera id>" "$OUT/p/README.txt"

# The output directory must be empty unless --overwrite (which replaces the earlier files).
expect_exit 1 "$OUT/nonempty.txt" "$MVTRACK" convert jsonl --detections "$OUT/dets2.jsonl" \
  --calibration "$OUT/cal.yaml" --out "$OUT/a"
expect_grep "is not empty" "$OUT/nonempty.txt"
same_outputs "$OUT/a" "$OUT/b" detections.lcmlog
touch "$OUT/d/notes.txt"
"$MVTRACK" convert jsonl --detections "$OUT/dets.jsonl" --calibration "$OUT/cal.yaml" --out "$OUT/d" \
  --overwrite --quiet
same_outputs "$OUT/a" "$OUT/d" detections.lcmlog
[ -e "$OUT/d/notes.txt" ] || fail "--overwrite removed a file it does not own"

# A bad line (line 3: keypoint confidence 1.5) stops the conversion with the line, column and
# key path; no log is left behind.
python3 - "$OUT/dets.jsonl" "$OUT/bad.jsonl" <<'PY'
import sys
lines = open(sys.argv[1]).readlines()
lines.insert(2, '{"camera": 0, "frame": 100, "utime": 1, "detections": [{"box": [0, 0, 5, 5], '
                '"score": 0.5, "layout": "coco17", "keypoints": [' +
                ", ".join(["[1, 2, 1.5]"] * 17) + "]}]}\n")
open(sys.argv[2], "w").writelines(lines)
PY
expect_exit 1 "$OUT/bad.txt" "$MVTRACK" convert jsonl --detections "$OUT/bad.jsonl" --calibration "$OUT/cal.yaml" --out "$OUT/bad"
col=$(python3 -c "import sys; print(open(sys.argv[1]).readlines()[2].index('1.5') + 1)" "$OUT/bad.jsonl")
expect_fixed "$OUT/bad.jsonl:3:$col: detections[0].keypoints[0][2]: confidence 1.5 is outside [0, 1]" "$OUT/bad.txt"
[ ! -e "$OUT/bad/detections.lcmlog" ] || fail "a failed conversion left a log"
[ -z "$(ls -A "$OUT/bad")" ] || fail "a failed conversion left files: $(ls -A "$OUT/bad")"
# With --skip-bad-lines: skipped, counted, reported; the log equals the clean conversion.
expect_exit 0 "$OUT/skip.txt" "$MVTRACK" convert jsonl --detections "$OUT/bad.jsonl" --calibration "$OUT/cal.yaml" \
  --out "$OUT/skip" --skip-bad-lines
expect_fixed "skipped 1 bad line(s) of $((lines + 1))" "$OUT/skip.txt"
expect_fixed "$OUT/bad.jsonl:3:$col: detections[0].keypoints[0][2]" "$OUT/skip.txt"
expect_fixed "1 bad line(s) skipped" "$OUT/skip/README.txt"
expect_fixed "skipped: $OUT/bad.jsonl:3:$col:" "$OUT/skip/README.txt"
same_outputs "$OUT/a" "$OUT/skip" detections.lcmlog

# Cross-line and cross-file errors name the line.
printf '%s\n' '{"camera": 0, "frame": 5, "utime": 10, "detections": []}' \
              '{"camera": 0, "frame": 4, "utime": 20, "detections": []}' >"$OUT/dec.jsonl"
expect_exit 1 "$OUT/dec.txt" "$MVTRACK" convert jsonl --detections "$OUT/dec.jsonl" --calibration "$OUT/cal.yaml" --out "$OUT/dec"
expect_fixed "dec.jsonl:2:24: frame: 4 is smaller than frame 5 of line 1 (frames must not decrease)" "$OUT/dec.txt"
printf '%s\n' '{"camera": 3, "frame": 5, "utime": 10, "detections": []}' >"$OUT/cam.jsonl"
expect_exit 1 "$OUT/cam.txt" "$MVTRACK" convert jsonl --detections "$OUT/cam.jsonl" --calibration "$OUT/cal.yaml" --out "$OUT/cam"
expect_fixed "cam.jsonl:1:12: camera: camera 3 is not in the calibration (cameras 0, 2, 5)" "$OUT/cam.txt"
printf '%s\n' '{"camera": 5, "frame": 5, "utime": 10, "image_size": [1920, 1080], "detections": []}' >"$OUT/size.jsonl"
expect_exit 1 "$OUT/size.txt" "$MVTRACK" convert jsonl --detections "$OUT/size.jsonl" --calibration "$OUT/cal.yaml" --out "$OUT/size"
expect_fixed "image_size: [1920, 1080] differs from camera 5's calibrated image size [1280, 720]" "$OUT/size.txt"
# Nothing valid at all; missing files.
: >"$OUT/empty.jsonl"
expect_exit 1 "$OUT/empty.txt" "$MVTRACK" convert jsonl --detections "$OUT/empty.jsonl" --calibration "$OUT/cal.yaml" --out "$OUT/empty"
expect_fixed "no valid line" "$OUT/empty.txt"
expect_exit 1 "$OUT/nofile.txt" "$MVTRACK" convert jsonl --detections "$OUT/none.jsonl" --calibration "$OUT/cal.yaml" --out "$OUT/nofile"
expect_fixed "$OUT/none.jsonl: cannot open" "$OUT/nofile.txt"
expect_exit 1 "$OUT/nocal.txt" "$MVTRACK" convert jsonl --detections "$OUT/dets.jsonl" --calibration "$OUT/none.yaml" --out "$OUT/nocal"
expect_fixed "$OUT/none.yaml" "$OUT/nocal.txt"
echo "jsonl: ok ($lines lines, $(stat -c %s "$OUT/a/detections.lcmlog") bytes of log)"
