#!/usr/bin/env bash
# mvtrack analytics: visits, crossings and the hourly summary of a hand-made track file (times and
# counts worked out by hand), the comparison with a ground truth, and the errors: a site file
# mistake names its line, an unreadable track file and missing options fail.
source "$(dirname "$0")/common.sh"
cat >"$OUT/site.yaml" <<'YAML'
format: mvtrack.site/1
regions:
  - name: shelf, left
    polygon: [[0, 0], [2, 0], [2, 2], [0, 2]]
lines:
  - name: door
    from: [3, 0]
    to: [3, 2]
rules:
  hysteresis_m: 0.2
  hold_s: 0.5
  max_gap_s: 2
YAML
# Track 1 walks along y = 1 from x = -1 to x = 5 at 1 m/s (10 frames/s): it enters the region
# at t = 1.0 (x = 0), leaves it at t = 3.0 (x = 2) and crosses the door at t = 4.0 (x = 3,
# from the line's left to its right: seen from (3, 0) towards (3, 2), -x is on the left). Track 2
# appears inside the region at t = 0.0, stays still for 0.3 s (shorter than hold_s: no visit).
py - "$OUT/tracks.jsonl" <<'PY'
import json, sys
with open(sys.argv[1], "w") as out:
    for i in range(61):
        t = i / 10
        tracks = [{"id": 1, "joints": [], "position": [-1 + t, 1.0, 0.0]}]
        if i <= 3:
            tracks.append({"id": 2, "joints": [], "position": [1.0, 0.5, 0.0]})
        out.write(json.dumps({"frame": i, "layout": "none", "tracks": tracks,
                              "utime": 3600 * 1000000 + i * 100000}) + "\n")
PY
expect_exit 0 "$OUT/run.txt" "$MVTRACK" analytics --tracks "$OUT/tracks.jsonl" \
  --regions "$OUT/site.yaml" --out "$OUT/csv"
expect_grep "^  shelf, left +1 +1 +1 +2.00 +2.00$" "$OUT/run.txt"
expect_grep "^  door +1 +0$" "$OUT/run.txt"
expect_grep "mvtrack analytics: analysing 61 frames, 1 region\(s\), 1 line\(s\)" "$OUT/run.txt"
[ "$(cat "$OUT/csv/visits.csv")" = 'region,track,enter_s,exit_s,dwell_s,ended_by
"shelf, left",1,3601.000,3603.000,2.000,exit' ] || fail "visits.csv: $(cat "$OUT/csv/visits.csv")"
[ "$(cat "$OUT/csv/crossings.csv")" = 'line,track,time_s,direction
door,1,3604.000,left_to_right' ] || fail "crossings.csv: $(cat "$OUT/csv/crossings.csv")"
[ "$(cat "$OUT/csv/summary.csv")" = 'kind,name,hour_start_s,visits,mean_dwell_s,left_to_right,right_to_left
line,door,3600,,,1,0
region,"shelf, left",3600,1,2.000,,' ] || fail "summary.csv: $(cat "$OUT/csv/summary.csv")"

# Against a ground truth: itself (no error), then one without track 1's door crossing (it stops
# at x = 2.5; the region visit is the same).
expect_exit 0 "$OUT/self.txt" "$MVTRACK" analytics --tracks "$OUT/tracks.jsonl" \
  --regions "$OUT/site.yaml" --gt "$OUT/tracks.jsonl" --quiet
expect_grep "^  shelf, left +1 \(1\) +0.00 +1 \(1\) +0.00 +100.00 +0.00 +1 / 1 +0.00 +0.00$" "$OUT/self.txt"
expect_grep "^  line door: left_to_right 1 \(1\) error 0.00 %, right_to_left 0 \(0\) error 0.00 %$" \
  "$OUT/self.txt"
py - "$OUT/tracks.jsonl" "$OUT/gt.jsonl" <<'PY'
import json, sys
with open(sys.argv[2], "w") as out:
    for line in open(sys.argv[1]):
        d = json.loads(line)
        for t in d["tracks"]:
            if t["id"] == 1:
                t["position"][0] = min(t["position"][0], 2.5)
        out.write(json.dumps(d) + "\n")
PY
expect_exit 0 "$OUT/gt.txt" "$MVTRACK" analytics --tracks "$OUT/tracks.jsonl" \
  --regions "$OUT/site.yaml" --gt "$OUT/gt.jsonl" --quiet
expect_grep "^  line door: left_to_right 1 \(0\) error n/a %, right_to_left 0 \(0\) error 0.00 %$" \
  "$OUT/gt.txt"
expect_grep "^  shelf, left +1 \(1\) +0.00 +1 \(1\) +0.00 +100.00 +0.00 +1 / 1 +0.00 +0.00$" "$OUT/gt.txt"

# --plots: the pictures, drawn by the helper mvtrack-pictures (when it is built).
expect_exit 2 "$OUT/plots_usage.txt" "$MVTRACK" analytics --tracks "$OUT/tracks.jsonl" \
  --regions "$OUT/site.yaml" --plots
expect_grep "--plots needs --out DIR" "$OUT/plots_usage.txt"
if [ -x "$(dirname "$MVTRACK")/mvtrack-pictures" ]; then
  expect_exit 0 "$OUT/plots.txt" "$MVTRACK" analytics --tracks "$OUT/tracks.jsonl" \
    --regions "$OUT/site.yaml" --out "$OUT/plots" --plots
  expect_grep "wrote occupancy.png, dwell.png and heatmap.png" "$OUT/plots.txt"
  cmp "$OUT/plots/visits.csv" "$OUT/csv/visits.csv" || fail "--plots changed visits.csv"
  py - "$OUT/plots" <<'PY' || fail "the analytics pictures are not PNGs of the expected sizes"
import struct, sys
for name, width in (("occupancy.png", 900), ("dwell.png", 900), ("heatmap.png", None)):
    data = open(f"{sys.argv[1]}/{name}", "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", name
    w, h = struct.unpack(">II", data[16:24])
    assert width is None or w == width, (name, w)
    assert h > 100, (name, h)
PY
fi

# Errors: a site file mistake (file:line:column: key: reason), unreadable tracks, no --regions.
sed 's/hold_s: 0.5/hold_s: -1/' "$OUT/site.yaml" >"$OUT/bad.yaml"
expect_exit 1 "$OUT/bad.txt" "$MVTRACK" analytics --tracks "$OUT/tracks.jsonl" \
  --regions "$OUT/bad.yaml"
expect_grep "bad.yaml:11:[0-9]+: rules.hold_s: .*\[0, 3600\]" "$OUT/bad.txt"
printf '{"frame": 0, "tracks": [' >"$OUT/broken.jsonl"
expect_exit 1 "$OUT/broken.txt" "$MVTRACK" analytics --tracks "$OUT/broken.jsonl" \
  --regions "$OUT/site.yaml"
expect_grep "broken.jsonl:1" "$OUT/broken.txt"
expect_exit 2 "$OUT/usage.txt" "$MVTRACK" analytics --tracks "$OUT/tracks.jsonl"
expect_grep "--regions is required" "$OUT/usage.txt"
# check-config validates a site file and prints its canonical form.
expect_exit 0 "$OUT/check.txt" "$MVTRACK" check-config "$OUT/site.yaml"
expect_grep "^# ok: .*site.yaml: site, 1 region\(s\), 1 line\(s\)" "$OUT/check.txt"
expect_exit 1 "$OUT/check_bad.txt" "$MVTRACK" check-config "$OUT/bad.yaml"
expect_grep "rules.hold_s" "$OUT/check_bad.txt"
