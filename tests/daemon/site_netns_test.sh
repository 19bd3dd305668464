#!/usr/bin/env bash
# A site of four zones on four hosts (issue 43): six network namespaces on one bridge with
# multicast (udpm, ttl=1), no snooping: a zone mvtrackd in each of four, the stitcher and a
# logger in the fifth, lcm-logplayer publishing the 32 cameras in the sixth. Checks: ids cross
# the borders live (border crossings keep their id), a killed zone daemon is flagged stale
# within 2.3 s while the others go on, and a restarted stitcher never gives an id out again
# while the zone daemons carry on. Skipped (exit 77) where namespaces cannot be made.
source "$(dirname "$0")/common.sh"
py() { python3 -S "$@"; }
STITCHER=$(dirname "$MVTRACKD")/mvtrack-stitcher
[ -x "$STITCHER" ] || fail "no mvtrack-stitcher next to $MVTRACKD"
require_netns
if ! unshare -n -m true 2> /dev/null || ! command -v ip > /dev/null; then
  echo "SKIP: cannot create network and mount namespaces"
  exit 77
fi
S=$OUT/site
expect_exit 0 "$OUT/sim.txt" "$MVTRACK" sim --out "$S" --cameras 32 --people 16 --layout grid \
  --room 64x8 --frames 450 --mode boxes --seed 5 --per-camera-channels --quiet
expect_exit 0 "$OUT/zones.txt" "$MVTRACK" calib zones "$S/calibration.yaml" --max-cameras 8 \
  --out "$S/zones"
expect_grep "^zones of .*: 32 camera\(s\), 4 zone\(s\)" "$OUT/zones.txt"
URL="udpm://239.255.76.67:7667?ttl=1"
for z in zone1 zone2 zone3 zone4; do
  sed -e "s|^input:|input:\n  lcm_url: \"$URL\"|" \
    -e "s|calibration: ../calibration.yaml|calibration: $S/calibration.yaml|" \
    "$S/zones/$z.yaml" > "$OUT/$z.yaml"
  printf 'queues:\n  camera_overflow: block\ntracker:\n  mode: boxes\n' >> "$OUT/$z.yaml"
done
export MVTRACKD STITCHER OUT S URL
unshare -n -m bash -euc '
  cleanup() {
    kill -KILL $(jobs -p) 2> /dev/null || true
    for h in 1 2 3 4 5 6; do ip netns del h$h 2> /dev/null || true; done
  }
  trap cleanup EXIT
  mount -t tmpfs none /run
  mkdir -p /run/netns
  ip link add br0 type bridge
  ip link set br0 type bridge mcast_snooping 0
  ip link set br0 up
  for h in 1 2 3 4 5 6; do
    ip netns add h$h
    ip link add v$h type veth peer name e$h
    ip link set v$h master br0
    ip link set v$h up
    ip link set e$h netns h$h
    ip -n h$h link set lo up
    ip -n h$h addr add 10.9.0.$h/24 dev e$h
    ip -n h$h link set e$h up
    ip -n h$h route add 224.0.0.0/4 dev e$h
  done
  ip netns exec h5 lcm-logger --quiet --lcm-url="$URL" -c MVTRACK_TRACKS \
    -f "$OUT/site_tracks.lcmlog" &
  LOGGER=$!
  for z in 1 2 3 4; do
    ip netns exec h$z "$MVTRACKD" --config "$OUT/zone$z.yaml" --workers 1 > "$OUT/zone$z.log" 2>&1 &
    echo $! > "$OUT/zone$z.pid"
  done
  ip netns exec h5 "$STITCHER" --zones "$S/zones/zones.yaml" --lcm-url "$URL" \
    --state-dir "$OUT/state" --tracks-jsonl "$OUT/live1.jsonl" \
    --status-jsonl "$OUT/status1.jsonl" > "$OUT/stitcher1.log" 2>&1 &
  echo $! > "$OUT/stitcher.pid"
  for _ in $(seq 150); do
    n=0
    for z in 1 2 3 4; do grep -q "input udpm" "$OUT/zone$z.log" && n=$((n + 1)); done
    [ $n -eq 4 ] && break
    sleep 0.1
  done
  sleep 0.3
  # 5 s in: the stitcher restarts (same state directory); 9 s in: zone3 dies.
  (sleep 5
   kill -TERM "$(cat "$OUT/stitcher.pid")" || true
   while kill -0 "$(cat "$OUT/stitcher.pid")" 2> /dev/null; do sleep 0.05; done
   ip netns exec h5 "$STITCHER" --zones "$S/zones/zones.yaml" --lcm-url "$URL" \
     --state-dir "$OUT/state" --tracks-jsonl "$OUT/live2.jsonl" \
     --status-jsonl "$OUT/status2.jsonl" > "$OUT/stitcher2.log" 2>&1 &
   echo $! > "$OUT/stitcher.pid") &
  RESTART=$!
  (sleep 9; date +%s%N > "$OUT/killed_at"; kill -KILL "$(cat "$OUT/zone3.pid")" || true) &
  KILLER=$!
  ip netns exec h6 lcm-logplayer --lcm-url="$URL" -s 1 "$S/detections.lcmlog"
  wait $RESTART $KILLER
  sleep 3
  for z in 1 2 4; do kill -TERM "$(cat "$OUT/zone$z.pid")" || true; done
  for z in 1 2 4; do while kill -0 "$(cat "$OUT/zone$z.pid")" 2> /dev/null; do sleep 0.05; done; done
  sleep 0.5
  kill -TERM "$(cat "$OUT/stitcher.pid")" || true
  while kill -0 "$(cat "$OUT/stitcher.pid")" 2> /dev/null; do sleep 0.05; done
  sleep 0.3
  kill -INT $LOGGER || true
  wait $LOGGER || true
' || fail "the namespace run failed (see $OUT/*.log)"
cat "$OUT/stitcher1.log" "$OUT/stitcher2.log"
expect_grep "stopped by a signal; summary: site_frames=[1-9]" "$OUT/stitcher1.log"
expect_grep "stopped by a signal; summary: site_frames=[1-9]" "$OUT/stitcher2.log"
expect_grep "zone zone3 is stale" "$OUT/stitcher2.log"
for z in 1 2 4; do expect_grep "mvtrackd stopped \(exit 0\)" "$OUT/zone$z.log"; done
py - "$OUT" <<'PY' || fail "the four-host site"
import json, os, sys
out = sys.argv[1]
load = lambda p: [json.loads(l) for l in open(os.path.join(out, p))]
live1, live2 = load("live1.jsonl"), load("live2.jsonl")
ids1 = {t["id"] for f in live1 for t in f["tracks"]}
ids2 = {t["id"] for f in live2 for t in f["tracks"]}
print("stitcher 1: %d site frames, ids %d..%d; restarted: %d site frames, ids %d..%d"
      % (len(live1), min(ids1), max(ids1), len(live2), min(ids2), max(ids2)))
assert min(ids2) > max(ids1), "the restarted stitcher gave an id out again"
status = load("status2.jsonl")
killed_us = int(open(os.path.join(out, "killed_at")).read()) // 1000
stale = [s["utime"] for s in status
         if s["utime"] >= killed_us and s["zones"][2]["state"] == "stale"]
assert stale, "zone3 never flagged stale"
print("zone3 flagged stale %.2f s after the kill" % ((stale[0] - killed_us) / 1e6))
assert stale[0] - killed_us <= 2_300_000, "flagged too late"
others = [s for s in status if s["utime"] >= stale[0]]
assert all(s["zones"][z]["state"] == "live" for s in others[:3] for z in (0, 1, 3)), \
    "the other zones did not go on"
PY
# Ids across borders, live: the crossings of the stitched output before the restart.
py "$SRC/bench/zone_crossings.py" "$S/calibration.yaml" "$S/zones/zones.yaml" "$S/gt.jsonl" \
  "$OUT/live2.jsonl" > "$OUT/crossings.txt"
cat "$OUT/crossings.txt"
py - "$OUT/crossings.txt" <<'PY' || fail "ids did not cross the borders"
import re, sys
m = re.search(r"id kept (\d+), changed (\d+)", open(sys.argv[1]).read())
kept, changed = int(m.group(1)), int(m.group(2))
assert kept >= 1 and kept >= 2 * changed, (kept, changed)
PY
echo "ok"
