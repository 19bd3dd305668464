# examples/python/print_site.py decodes the site analytics mvtrackd publishes: the daemon runs a
# simulated room with people walking in and out of a region and across a line, with a site file,
# and publishes into a file://...?mode=w log; print_site.py reads that log. Every event and
# counts message of the log is printed, and the events agree with the counts the daemon
# published last (entries, exits and crossings are the events' totals; occupancy = entries -
# exits).
source "$(dirname "$0")/common.sh"
[ -n "$MVTRACKD" ] || fail "print_site: mvtrackd not given"
expect_exit 0 "$OUT/sim.log" "$MVTRACK" sim --quiet --out "$OUT/sim" --cameras 4 --people 6 \
  --enter-leave --mean-stay 6 --frames 900 --mode boxes --seed 5
cat >"$OUT/site.yaml" <<'YAML'
format: mvtrack.site/1
regions:
  - name: west
    polygon: [[0, 0], [3, 0], [3, 6], [0, 6]]
lines:
  - name: middle
    from: [3, 0]
    to: [3, 6]
YAML
cat >"$OUT/daemon.yaml" <<YAML
format: mvtrack.daemon/1
cameras:
  calibration: $OUT/sim/calibration.yaml
input:
  lcm_url: "memq://"
output:
  status_period_s: 0.5
analytics:
  site: $OUT/site.yaml
tracker:
  mode: boxes
YAML
expect_exit 0 "$OUT/daemon.log" "$MVTRACKD" --config "$OUT/daemon.yaml" \
  --input-log "$OUT/sim/detections.lcmlog" --output-url "file://$OUT/out.lcmlog?mode=w"
expect_exit 0 "$OUT/print.log" "$VPY" "$EXAMPLES/print_site.py" --counts --json \
  --url "file://$OUT/out.lcmlog?speed=0"
mv "$OUT/print.log" "$OUT/print.jsonl"
"$VPY" - "$OUT/print.jsonl" "$OUT/out.lcmlog" <<'PY' || fail "print_site.py's output disagrees with the log"
import json, sys
import lcm
events, counts = [], []
for line in open(sys.argv[1]):
    if line.startswith("print_site.py:"):
        continue  # the "listening" line (stderr, captured with stdout by expect_exit)
    m = json.loads(line)
    (events if "event" in m else counts).append(m.get("event") or m.get("counts"))
on_log = {"MVTRACK_ANALYTICS_EVENTS": 0, "MVTRACK_SITE_COUNTS": 0}
for e in lcm.EventLog(sys.argv[2], "r"):
    if e.channel in on_log:
        on_log[e.channel] += 1
print(f"{len(events)} events, {len(counts)} counts messages printed; on the log: {on_log}")
assert len(events) == on_log["MVTRACK_ANALYTICS_EVENTS"] >= 4, "not every event was printed"
assert len(counts) == on_log["MVTRACK_SITE_COUNTS"] >= 1, "not every counts message was printed"
last = counts[-1]
def total(kind, name, direction=None):
    return sum(1 for e in events if e["kind"] == kind and e["name"] == name
               and (direction is None or e["direction"] == direction))
west = last["regions"]["west"]
assert west["entries"] == total("enter", "west") > 0, (west, total("enter", "west"))
assert west["exits"] == total("exit", "west") > 0, (west, total("exit", "west"))
assert west["occupancy"] == west["entries"] - west["exits"], west
middle = last["lines"]["middle"]
for d in ("left_to_right", "right_to_left"):
    assert middle[d] == total("crossing", "middle", d) > 0, (d, middle)
for e in events:
    if e["kind"] == "exit":
        assert e["dwell_s"] > 0 and e["enter_utime"] < e["utime"], e
PY
# Human-readable lines, --count, --timeout without a publisher, usage errors.
expect_exit 0 "$OUT/human.txt" "$VPY" "$EXAMPLES/print_site.py" --count 3 \
  --url "file://$OUT/out.lcmlog?speed=0"
[ "$(grep -c '^[0-9.]* track [0-9]*: \(enter\|exit\|crossing\) ' "$OUT/human.txt")" -eq 3 ] ||
  fail "--count 3 printed another number of events"
expect_exit 1 "$OUT/timeout.txt" "$VPY" "$EXAMPLES/print_site.py" --url "memq://" --timeout 0.3
expect_grep "no message for 0.3 s \(0 events received\)" "$OUT/timeout.txt"
expect_exit 2 "$OUT/usage.txt" "$VPY" "$EXAMPLES/print_site.py" --timeout -1
echo "print_site: ok"
