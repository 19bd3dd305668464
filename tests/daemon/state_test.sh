#!/usr/bin/env bash
# Track ids never repeat across restarts (issue 14): with a state directory, a second run's ids
# are all above the first run's, also after kill -9 of a run in progress; a malformed state file
# stops the daemon with a clear message instead of starting ids at 1 again.
source "$(dirname "$0")/common.sh"
ids() {  # min max of the track ids of a tracks JSONL
  python3 -c '
import json, sys
ids = [t["id"] for line in open(sys.argv[1]) if line.strip() for t in json.loads(line)["tracks"]]
print(min(ids), max(ids))' "$1"
}
STATE=$OUT/state
mkdir -p "$STATE"
write_config "$OUT/daemon.yaml" "state:" "  directory: $STATE" "  id_block: 1000"
expect_exit 0 "$OUT/run1.log" "$MVTRACKD" --config "$OUT/daemon.yaml" \
  --input-log "$P/detections.lcmlog" --tracks-jsonl "$OUT/run1.jsonl"
expect_grep "track ids start at 1 " "$OUT/run1.log"
read -r min1 max1 < <(ids "$OUT/run1.jsonl")
expect_exit 0 "$OUT/run2.log" "$MVTRACKD" --config "$OUT/daemon.yaml" \
  --input-log "$P/detections.lcmlog" --tracks-jsonl "$OUT/run2.jsonl"
read -r min2 max2 < <(ids "$OUT/run2.jsonl")
[ "$min2" -gt "$max1" ] || fail "run 2's ids ($min2..$max2) repeat run 1's ($min1..$max1)"
# The same tracks otherwise: ids shifted by the reservation.
[ "$(( max2 - min2 ))" -eq "$(( max1 - min1 ))" ] || fail "run 2 tracked differently"

# kill -9 in the middle of a real-time run, then a restart: still no id repeats.
write_config "$OUT/live.yaml" "state:" "  directory: $STATE" "  id_block: 1000"
sed -i "s|lcm_url: \"memq://\"|lcm_url: \"file://$P/detections.lcmlog?speed=1\"|" "$OUT/live.yaml"
"$MVTRACKD" --config "$OUT/live.yaml" --tracks-jsonl "$OUT/killed.jsonl" > "$OUT/killed.log" 2>&1 &
pid=$!
for _ in $(seq 1 100); do
  [ -s "$OUT/killed.jsonl" ] && [ "$(grep -c '"id"' "$OUT/killed.jsonl")" -gt 0 ] && break
  sleep 0.1
done
sleep 1
kill -9 "$pid"
wait "$pid" 2>/dev/null || true
[ -s "$OUT/killed.jsonl" ] || fail "the killed run published nothing"
read -r mink maxk < <(ids "$OUT/killed.jsonl")
[ "$mink" -gt "$max2" ] || fail "the killed run's ids ($mink..$maxk) repeat run 2's"
expect_exit 0 "$OUT/run3.log" "$MVTRACKD" --config "$OUT/daemon.yaml" \
  --input-log "$P/detections.lcmlog" --tracks-jsonl "$OUT/run3.jsonl"
read -r min3 max3 < <(ids "$OUT/run3.jsonl")
[ "$min3" -gt "$maxk" ] || fail "after kill -9 the ids ($min3..$max3) repeat the killed run's ($mink..$maxk)"

# A malformed state file: exit 1 with the reason.
echo "garbage" > "$STATE/track_ids"
expect_exit 1 "$OUT/bad.log" "$MVTRACKD" --config "$OUT/daemon.yaml" \
  --input-log "$P/detections.lcmlog" --tracks-jsonl "$OUT/bad.jsonl"
expect_grep "track_ids: not a mvtrack.track_ids/1 file" "$OUT/bad.log"
echo "ok"
