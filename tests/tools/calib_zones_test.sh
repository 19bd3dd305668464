#!/usr/bin/env bash
# mvtrack calib zones (issue 43): splits a site calibration into zones, prints them, and with
# --out writes one daemon configuration per zone that `mvtrack check-config` accepts, with the
# zone's own and border cameras and channels namespaced by the zone; --png draws them; bad
# arguments are usage errors.
source "$(dirname "$0")/common.sh"
CAL=$WORK/boxes/calibration.yaml
expect_exit 0 "$OUT/one.txt" "$MVTRACK" calib zones "$CAL"
expect_grep "^zones of .*: [0-9]+ camera\(s\), 1 zone\(s\) of at most 16 own camera\(s\)$" "$OUT/one.txt"
expect_grep "^  zone1: cameras .*; border cameras none; neighbours none$" "$OUT/one.txt"
expect_exit 0 "$OUT/two.txt" "$MVTRACK" calib zones "$CAL" --max-cameras 2 --out "$OUT/site"
cat "$OUT/two.txt"
expect_grep "^  zone2: cameras " "$OUT/two.txt"
for z in zone1 zone2; do
  [ -f "$OUT/site/$z.yaml" ] || fail "no $OUT/site/$z.yaml"
  expect_exit 0 "$OUT/$z.check.txt" "$MVTRACK" check-config "$OUT/site/$z.yaml"
  Z=$(echo "$z" | tr a-z A-Z)
  expect_grep "^  tracks_channel: \"?MVTRACK_TRACKS_$Z\"?$" "$OUT/$z.check.txt"
  expect_grep "^  status_channel: \"?MVTRACK_STATUS_$Z\"?$" "$OUT/$z.check.txt"
  expect_grep "^  provisional_channel: \"?MVTRACK_TRACKS_NOW_$Z\"?$" "$OUT/$z.check.txt"
  expect_grep "^  channels: per_camera$" "$OUT/$z.check.txt"
done
expect_grep "^  - name: zone1$" "$OUT/site/zones.yaml"
# --png draws the zones (the picture's colours: tests/viz/zones_map_test.cc).
expect_exit 0 "$OUT/png.txt" "$MVTRACK" calib zones "$CAL" --max-cameras 2 --png "$OUT/zones.png"
expect_grep "^wrote .*zones.png$" "$OUT/png.txt"
[ -s "$OUT/zones.png" ] || fail "no zones picture"
[ "$(head -c 8 "$OUT/zones.png" | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ] ||
  fail "$OUT/zones.png is not a PNG"
expect_grep "^    daemon: \"zone2.yaml\"$" "$OUT/site/zones.yaml"
# --mode and --lcm-url go into the zone daemons' configurations, which stay valid.
expect_exit 0 "$OUT/modes.txt" "$MVTRACK" calib zones "$CAL" --max-cameras 2 --out "$OUT/site2" \
  --mode boxes --lcm-url "udpm://239.255.76.67:7667?ttl=1"
expect_grep "^  mode: boxes$" "$OUT/site2/zone1.yaml"
expect_grep "^  lcm_url: \"udpm://239.255.76.67:7667\?ttl=1\"$" "$OUT/site2/zone1.yaml"
expect_exit 0 "$OUT/modes_check.txt" "$MVTRACK" check-config "$OUT/site2/zone1.yaml"
expect_grep "^  mode: boxes$" "$OUT/modes_check.txt"
expect_exit 2 "$OUT/badmode.txt" "$MVTRACK" calib zones "$CAL" --out "$OUT/x" --mode cars
expect_grep "--mode must be 'boxes' or 'poses'" "$OUT/badmode.txt"
expect_exit 2 "$OUT/bad.txt" "$MVTRACK" calib zones "$CAL" --max-cameras 1
expect_grep "max-cameras must be in" "$OUT/bad.txt"
expect_exit 1 "$OUT/missing.txt" "$MVTRACK" calib zones "$OUT/nothing.yaml"
echo "ok"
