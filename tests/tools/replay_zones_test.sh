#!/usr/bin/env bash
# mvtrack replay --zones (issue 43): a simulated site whose cameras see local floor (a 32 x 8 m
# floor under a ceiling grid of 16 cameras) split into two zones by `mvtrack calib zones`;
# each zone tracked with its own and border cameras, the zones' tracks stitched into global ids.
# The output is byte-identical at any --threads, and the site's identity is close to one tracker
# over all cameras on the same log.
source "$(dirname "$0")/common.sh"
S=$OUT/site
expect_exit 0 "$OUT/sim.txt" "$MVTRACK" sim --out "$S" --cameras 16 --people 16 --layout grid \
  --room 32x8 --frames 300 --mode boxes --seed 5 --quiet
expect_exit 0 "$OUT/zones.txt" "$MVTRACK" calib zones "$S/calibration.yaml" --max-cameras 8 \
  --out "$S/zones"
expect_grep "^zones of .*: 16 camera\(s\), 2 zone\(s\)" "$OUT/zones.txt"
for n in 0 2; do
  expect_exit 0 "$OUT/z$n.txt" "$MVTRACK" replay --quiet --threads "$n" --mode boxes \
    --calibration "$S/calibration.yaml" --zones "$S/zones/zones.yaml" \
    --jsonl "$OUT/z$n.jsonl" --out "$OUT/z$n.lcmlog" --zones-jsonl "$OUT/zj" "$S/detections.lcmlog"
done
cat "$OUT/z0.txt"
cmp "$OUT/z0.jsonl" "$OUT/z2.jsonl" || fail "--zones: --threads 2 JSONL differs from --threads 0"
cmp "$OUT/z0.lcmlog" "$OUT/z2.lcmlog" || fail "--zones: --threads 2 LCM log differs"
expect_grep "^  zones: 2 " "$OUT/z0.txt"
expect_grep "^    zone1: cameras [0-9,]+ \+ border [0-9,]+; [0-9]+ frame\(s\)" "$OUT/z0.txt"
expect_grep "^  stitched: 300 site frame\(s\), [0-9]+ global id\(s\); zone tracks joined in an overlap [1-9]" \
  "$OUT/z0.txt"
expect_grep "track-frames seen by two or more zones [1-9]" "$OUT/z0.txt"
expect_grep "output: 300 frame\(s\)" "$OUT/z0.txt"

# The site against one tracker over every camera, both against the ground truth.
expect_exit 0 "$OUT/one.txt" "$MVTRACK" replay --quiet --mode boxes \
  --calibration "$S/calibration.yaml" --jsonl "$OUT/one.jsonl" "$S/detections.lcmlog"
for r in z0 one; do
  expect_exit 0 "$OUT/$r.eval.txt" "$MVTRACK" eval --gt "$S/gt.jsonl" --pred "$OUT/$r.jsonl" \
    --json "$OUT/$r.eval.json"
done
py - "$OUT/z0.eval.json" "$OUT/one.eval.json" <<'PY' || fail "the stitched site lost identity"
import json, sys
def scores(path):
    t = json.load(open(path))["tracking"]
    return t["identity"]["idf1"], t["clear_mot"]["mota"]
(zi, zm), (oi, om) = scores(sys.argv[1]), scores(sys.argv[2])
print("zones: IDF1 %.4f MOTA %.4f; one tracker: IDF1 %.4f MOTA %.4f" % (zi, zm, oi, om))
assert zi >= oi - 0.02, "IDF1 more than 2 points below one tracker"
assert zm >= om - 0.02, "MOTA more than 2 points below one tracker"
PY

# A zone daemon that dies 3 s in and comes back at 6 s (a fresh tracker, ids above its first's):
# deterministic, the zone's ids after the return are new, and the site goes on.
for n in 0 2; do
  expect_exit 0 "$OUT/o$n.txt" "$MVTRACK" replay --quiet --threads "$n" --mode boxes \
    --calibration "$S/calibration.yaml" --zones "$S/zones/zones.yaml" --zone-outage zone2:3:6 \
    --zones-jsonl "$OUT/oz$n" --jsonl "$OUT/o$n.jsonl" "$S/detections.lcmlog"
done
cmp "$OUT/o0.jsonl" "$OUT/o2.jsonl" || fail "--zone-outage: --threads 2 differs from --threads 0"
expect_grep "output: 300 frame\(s\)" "$OUT/o0.txt"
py - "$OUT/oz0/zone2.jsonl" "$OUT/zj/zone2.jsonl" <<'PY' || fail "the zone's outage is not as asked"
import json, sys
def frames(path):
    return [json.loads(l) for l in open(path)]
out, base = frames(sys.argv[1]), frames(sys.argv[2])
t0 = base[0]["utime"]
sec = lambda f: (f["utime"] - t0) / 1e6
assert not [f for f in out if 3.0 <= sec(f) < 6.0], "zone2 has frames during its outage"
before = {t["id"] for f in out if sec(f) < 3.0 for t in f["tracks"]}
after = {t["id"] for f in out if sec(f) >= 6.0 for t in f["tracks"]}
assert after and min(after) > max(before), "ids after the return must be new: %s %s" % (before, after)
PY
expect_exit 2 "$OUT/o_bad.txt" "$MVTRACK" replay --quiet --mode boxes \
  --calibration "$S/calibration.yaml" --zones "$S/zones/zones.yaml" --zone-outage zone2:6:3 \
  --jsonl "$OUT/x.jsonl" "$S/detections.lcmlog"
expect_grep "is not ZONE:FROM:TO" "$OUT/o_bad.txt"
expect_exit 2 "$OUT/o_none.txt" "$MVTRACK" replay --quiet --mode boxes \
  --calibration "$S/calibration.yaml" --zones "$S/zones/zones.yaml" --zone-outage zone9:1:2 \
  --jsonl "$OUT/x.jsonl" "$S/detections.lcmlog"
expect_grep "no zone is named 'zone9'" "$OUT/o_none.txt"

# Errors: a zone camera the calibration lacks; a zone of one camera; --provisional-jsonl.
sed 's/cameras: \[0,/cameras: [99, 0,/' "$S/zones/zones.yaml" > "$OUT/bad_camera.yaml"
expect_exit 1 "$OUT/bad_camera.txt" "$MVTRACK" replay --quiet --mode boxes \
  --calibration "$S/calibration.yaml" --zones "$OUT/bad_camera.yaml" --jsonl "$OUT/x.jsonl" \
  "$S/detections.lcmlog"
expect_grep "zone zone1: camera 99 is not in" "$OUT/bad_camera.txt"
printf 'format: mvtrack.zones/1\nzones:\n  - name: a\n    cameras: [0]\n  - name: b\n    cameras: [1, 2]\n' \
  > "$OUT/small.yaml"
expect_exit 1 "$OUT/small.txt" "$MVTRACK" replay --quiet --mode boxes \
  --calibration "$S/calibration.yaml" --zones "$OUT/small.yaml" --jsonl "$OUT/x.jsonl" \
  "$S/detections.lcmlog"
expect_grep "zone a has fewer than 2 cameras" "$OUT/small.txt"
printf 'format: mvtrack.zones/1\nzones:\n  - name: a\n    cameras: [0, 1]\n  - name: b\n    cameras: [1, 2]\n' \
  > "$OUT/twice.yaml"
expect_exit 1 "$OUT/twice.txt" "$MVTRACK" replay --quiet --mode boxes \
  --calibration "$S/calibration.yaml" --zones "$OUT/twice.yaml" --jsonl "$OUT/x.jsonl" \
  "$S/detections.lcmlog"
expect_grep "twice.yaml:6:[0-9]+: .*camera 1 is zone 'a''s already" "$OUT/twice.txt"
expect_exit 2 "$OUT/prov.txt" "$MVTRACK" replay --quiet --mode boxes \
  --calibration "$S/calibration.yaml" --zones "$S/zones/zones.yaml" --jsonl "$OUT/x.jsonl" \
  --provisional-jsonl "$OUT/now.jsonl" "$S/detections.lcmlog"
expect_grep "no provisional layer yet" "$OUT/prov.txt"
echo "ok"
