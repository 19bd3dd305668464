#!/usr/bin/env bash
# mvtrack web end to end (issue 15), inside a private network namespace (never on the machine's
# network): mvtrackd plays the bundled demo recording in real time and publishes over udpm://,
# `mvtrack web` serves it, a real headless Chromium (DevTools protocol, page_probe.py) loads the
# page. Checked: /healthz, /metrics, /events (schema), the page's DOM shows the daemon's tracks
# with the right ids and positions, the page turns UNKNOWN and greys its tracks out once the
# daemon has been stopped longer than --stale-after and keeps working when a new one starts,
# says CRITICAL with greyed-out tracks when a live daemon's cameras all went silent,
# /healthz turns 503 and /metrics mvtrack_up 0 while no status arrives, and a client that never reads is
# disconnected and counted without holding anybody up. The screenshot is kept as
# OUT/page.png (docs/images/web_view.png is made from it). Skipped (77) without a namespace,
# Chromium or python3-websocket, unless CI is set (then a failure).
# Usage: web_test.sh MVTRACKD MVTRACK SOURCE_DIR OUT_DIR
set -euo pipefail
[ $# -eq 4 ] || { echo "usage: $0 MVTRACKD MVTRACK SOURCE_DIR OUT_DIR" >&2; exit 2; }
MVTRACKD=$1 MVTRACK=$2 SRC=$3 OUT=$4
# shellcheck source=../support/shell_asserts.sh
. "$SRC/tests/support/shell_asserts.sh"
skip() {
  if [ -n "${CI:-}" ]; then fail "$1 (CI is set: the browser test must run)"; fi
  echo "SKIP: $1"
  exit 77
}
PY=/usr/bin/python3
command -v chromium > /dev/null || skip "chromium is not installed (tools/dev/install_deps.sh)"
command -v curl > /dev/null || skip "curl is not installed"
command -v lcm-logplayer > /dev/null || skip "lcm-logplayer is not installed (liblcm-bin)"
"$PY" -c "import websocket" 2> /dev/null || skip "python3-websocket is not installed"
"$PY" -c "import prometheus_client.parser" 2> /dev/null ||
  skip "python3-prometheus-client is not installed (tools/dev/install_deps.sh)"
command -v ip > /dev/null || skip "the ip tool (iproute2) is not installed"
unshare -n true 2> /dev/null || skip "cannot create a private network namespace (needs root)"
rm -rf "$OUT"
mkdir -p "$OUT"
DEMO=$SRC/examples/demo
URL="udpm://239.255.76.67:7667?ttl=0"
# The site analytics (issue 41): the demo room's regions and line, in the daemon and the page.
SITE=$SRC/docs/examples/sites/demo.yaml
sed -e "s|calibration: calibration.yaml|calibration: $DEMO/calibration.yaml|" \
  -e "s|site: ../../docs/examples/sites/demo.yaml|site: $SITE|" \
  "$DEMO/mvtrackd.yaml" > "$OUT/daemon.yaml"
grep -q "site: $SITE" "$OUT/daemon.yaml" || fail "the demo configuration names no site"
# The same daemon reading udpm:// live, for the cameras that go silent.
sed -e "s|lcm_url: \"memq://\"|lcm_url: \"$URL\"|" "$OUT/daemon.yaml" > "$OUT/daemon_live.yaml"
export MVTRACKD MVTRACK SRC OUT DEMO URL PY SITE
unshare -n bash -euc '
  ip link set lo up
  ip route add 224.0.0.0/4 dev lo
  daemon() {  # daemon NAME: the demo recording in real time, tracks over udpm
    "$MVTRACKD" --config "$OUT/daemon.yaml" --input-log "$DEMO/detections.lcmlog" \
      --input-speed 1 --output-url "$URL" --tracks-jsonl "$OUT/$1.jsonl" \
      --provisional-jsonl "$OUT/$1.now.jsonl" > "$OUT/$1.log" 2>&1
  }
  "$MVTRACK" web --listen 127.0.0.1:18080 --url "$URL" --calibration "$DEMO/calibration.yaml" \
    --regions "$SITE" --stale-after 1.5 --client-queue 64 > "$OUT/web.log" 2>&1 &
  WEB=$!
  chromium --headless --no-sandbox --disable-gpu --remote-debugging-port=19222 \
    --window-size=1400,820 about:blank > "$OUT/chromium.log" 2>&1 &
  BROWSER=$!
  for _ in $(seq 100); do grep -q "serving http" "$OUT/web.log" && break; sleep 0.1; done
  curl -s -o "$OUT/healthz_before.txt" -w "%{http_code}\n" http://127.0.0.1:18080/healthz \
    > "$OUT/healthz_before.code" || true
  # The page: phase 1 after 150 tracks messages, phase 2 once the daemon has been stopped for
  # longer than --stale-after, phase 3 once 100 more came from a new daemon, phase 4 once a
  # live daemon has had its cameras silent for longer than --stale-after.
  "$PY" "$SRC/tests/web/page_probe.py" 19222 http://127.0.0.1:18080/ 30 "$OUT/page.png" \
    "$OUT/phase" 150 "@$OUT/stopped" 400 "@$OUT/silent" > "$OUT/probe.jsonl" \
    2> "$OUT/probe.err" &
  PROBE=$!
  sleep 1
  # A client that connects to /events and never reads (a stuck browser), with a tiny buffer.
  "$PY" -c "
import socket, time
s = socket.socket()
s.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 1024)
s.connect((\"127.0.0.1\", 18080))
s.sendall(b\"GET /events HTTP/1.1\r\nHost: x\r\n\r\n\")
time.sleep(14)
" &
  STUCK=$!
  daemon first &
  FIRST=$!
  for _ in $(seq 300); do [ -e "$OUT/phase.1" ] && break; sleep 0.05; done
  curl -s -o "$OUT/healthz_live.txt" -w "%{http_code}\n" http://127.0.0.1:18080/healthz \
    > "$OUT/healthz_live.code"
  curl -s http://127.0.0.1:18080/metrics > "$OUT/metrics_live.txt"
  curl -s http://127.0.0.1:18080/site.json > "$OUT/site.json"
  # A request with a body (only GET exists) is refused unread: 413, memory unchanged.
  head -c 50000000 /dev/zero > "$OUT/big.bin"
  rss_before=$(awk "/VmRSS/ {print \$2}" /proc/$WEB/status)
  curl -s -o /dev/null -w "%{http_code}\n" -X POST --data-binary @"$OUT/big.bin" \
    http://127.0.0.1:18080/healthz > "$OUT/post.code" || true
  rss_after=$(awk "/VmRSS/ {print \$2}" /proc/$WEB/status)
  echo "$rss_before $rss_after" > "$OUT/post_rss.txt"
  rm -f "$OUT/big.bin"
  curl -s -N --max-time 2 http://127.0.0.1:18080/events > "$OUT/events.txt" || true
  st=0; "$MVTRACK" status --url "$URL" --timeout 3 > "$OUT/status_live.txt" || st=$?
  echo $st > "$OUT/status_live.code"
  wait $FIRST
  st=0; "$MVTRACK" status --url "$URL" --timeout 1 > "$OUT/status_none.txt" || st=$?
  echo $st > "$OUT/status_none.code"
  sleep 2.5  # longer than --stale-after without a status
  curl -s -o "$OUT/healthz_stale.txt" -w "%{http_code}\n" http://127.0.0.1:18080/healthz \
    > "$OUT/healthz_stale.code"
  curl -s http://127.0.0.1:18080/metrics > "$OUT/metrics_stale.txt"
  touch "$OUT/stopped"
  for _ in $(seq 100); do [ -e "$OUT/phase.2" ] && break; sleep 0.05; done
  daemon second &
  SECOND=$!
  for _ in $(seq 600); do [ -e "$OUT/phase.3" ] && break; sleep 0.05; done
  wait $STUCK || true
  curl -s http://127.0.0.1:18080/metrics > "$OUT/metrics_end.txt"
  curl -s -N --max-time 1 http://127.0.0.1:18080/events > "$OUT/events_end.txt" || true
  kill -TERM $SECOND 2> /dev/null || true
  wait $SECOND || true
  # A live daemon whose cameras go silent: it keeps publishing status, no tracks.
  "$MVTRACKD" --config "$OUT/daemon_live.yaml" > "$OUT/live.log" 2>&1 &
  LIVE=$!
  for _ in $(seq 100); do grep -q "input udpm" "$OUT/live.log" && break; sleep 0.1; done
  lcm-logplayer --lcm-url="$URL" -s 2 "$DEMO/detections.lcmlog"
  sleep 4  # the cameras silent for longer than --stale-after (plus a status period)
  touch "$OUT/silent"
  wait $PROBE || echo "probe failed" > "$OUT/probe.failed"
  kill -TERM $LIVE 2> /dev/null || true
  wait $LIVE || true
  kill -TERM $WEB $BROWSER
  wait $WEB || echo "web exit $?" > "$OUT/web.failed"
  wait $BROWSER || true
' || fail "the namespace run failed (see $OUT)"
[ ! -e "$OUT/probe.failed" ] || { cat "$OUT/probe.err" "$OUT/probe.jsonl" >&2; fail "the page did not show the tracks messages (see $OUT/probe.err)"; }
[ ! -e "$OUT/web.failed" ] || fail "mvtrack web did not stop cleanly (see $OUT/web.log)"

# /healthz: 503 before any status, 200 OK while tracking, 503 when the status went stale.
expect_eq "$(cat "$OUT/healthz_before.code")" 503 "/healthz before any status"
expect_grep "^UNKNOWN: no status message received yet" "$OUT/healthz_before.txt"
expect_eq "$(cat "$OUT/healthz_live.code")" 200 "/healthz while tracking"
expect_grep "^OK" "$OUT/healthz_live.txt"
expect_eq "$(cat "$OUT/healthz_stale.code")" 503 "/healthz after the daemon stopped"
expect_grep "^UNKNOWN: the latest status is .* s old" "$OUT/healthz_stale.txt"

# A 50 MB POST (issue 39: 200 MB took mvtrack web from 12 to 506 MB): refused, RSS within 8 MB.
expect_eq "$(cat "$OUT/post.code")" 413 "a request with a body"
read -r rss_before rss_after < "$OUT/post_rss.txt"
[ $(( rss_after - rss_before )) -le 8192 ] ||
  fail "mvtrack web grew from $rss_before kB to $rss_after kB on a refused 50 MB POST"

# mvtrack status: OK (exit 0) with the cameras while tracking, UNKNOWN (exit 3) without a status.
expect_eq "$(cat "$OUT/status_live.code")" 0 "mvtrack status while tracking"
expect_grep "^mvtrack status: OK$" "$OUT/status_live.txt"
expect_grep "^cameras: 3 of 3 delivering$" "$OUT/status_live.txt"
expect_grep "^ +2 +[0-9.]+ +[0-9.]+ s " "$OUT/status_live.txt"
expect_eq "$(cat "$OUT/status_none.code")" 3 "mvtrack status without a tracker"
expect_grep "^mvtrack status: UNKNOWN: no status message on MVTRACK_STATUS within 1.0 s" \
  "$OUT/status_none.txt"

# /metrics: Prometheus text with the status counters per camera.
expect_grep "^mvtrack_up 1$" "$OUT/metrics_live.txt"
expect_grep "^mvtrack_health 0$" "$OUT/metrics_live.txt"
expect_grep '^mvtrack_camera_received_total\{camera="0"\} [1-9][0-9]*$' "$OUT/metrics_live.txt"
expect_grep '^mvtrack_camera_flag\{camera="2",flag="CLOCK_OFFSET"\} 0$' "$OUT/metrics_live.txt"
expect_grep "^# TYPE mvtrack_kernel_drops_total counter$" "$OUT/metrics_live.txt"
# ... and once the daemon stopped (issue 39): down, UNKNOWN, no stale per-camera values.
expect_grep "^mvtrack_up 0$" "$OUT/metrics_stale.txt"
expect_grep "^mvtrack_health 3$" "$OUT/metrics_stale.txt"
! grep -q "^mvtrack_camera_received_total" "$OUT/metrics_stale.txt" ||
  fail "/metrics exported a stopped daemon's camera counters"

# /events: Server-Sent Events whose data lines are the documented JSON objects.
"$PY" - "$OUT/events.txt" << 'EOF' || fail "/events did not carry tracks and status objects"
import json, sys
events = [json.loads(l[6:]) for l in open(sys.argv[1]) if l.startswith("data: ")]
kinds = {e["type"] for e in events}
assert {"tracks", "status"} <= kinds, kinds
t = next(e for e in events if e["type"] == "tracks")
assert set(t) >= {"frame", "utime", "publish_utime", "latency_us", "layer", "layout", "tracks"}, t.keys()
# Both layers (issue 44): the final tracks and the provisional ones, each frame of each.
layers = {e["layer"] for e in events if e["type"] == "tracks"}
assert layers == {"final", "provisional"}, layers
assert t["layout"] == "coco17" and t["tracks"], t
tr = t["tracks"][0]
assert set(tr) >= {"id", "state", "position", "confidence", "age_frames", "cameras", "joints"}
assert len(tr["joints"]) == 17 and len(tr["position"]) == 3
s = next(e for e in events if e["type"] == "status")
assert s["health"] == "OK" and len(s["cameras"]) == 3, s
assert set(s["cameras"][0]) >= {"camera_id", "rate_hz", "lost", "clock_offset_us", "flags"}
print(f"/events: {len(events)} events in 2 s ({', '.join(sorted(kinds))})")
EOF

# The page's DOM shows the daemon's tracks of the frame it shows: same ids, same positions
# (the table rounds to millimetres), and it kept going after the daemon was replaced.
# The page shows the provisional layer while it arrives, and says so (issue 44).
"$PY" - "$OUT/probe.jsonl" "$OUT/first.jsonl" "$OUT/events.txt" "$OUT/first.now.jsonl" << 'EOF' || fail "the page does not show the daemon's tracks"
import json, math, sys
phases = [json.loads(l) for l in open(sys.argv[1])]
first = phases[0]
assert first["layer"] == "provisional", first["layer"]
published = {}
for line in open(sys.argv[4]):
    f = json.loads(line)
    published[f["frame"]] = {t["id"]: t["position"] for t in f["tracks"]}
want = published[first["frame"]]
got = {t["id"]: (t["x"], t["y"]) for t in first["tracks"]}
assert set(got) == set(want), (first["frame"], sorted(got), sorted(want))
for i, (x, y) in got.items():
    assert abs(x - want[i][0]) <= 0.0006 and abs(y - want[i][1]) <= 0.0006, (i, (x, y), want[i])
assert first["health"] == "OK" and first["cameras"] == ["0", "1", "2"], first
assert first["latency_count"] >= 150
# Sanity only (timing belongs to benchmarks): a live page shows a frame within a second.
assert first["latency_p50_ms"] < 1000, first
# One colour per id (issue 42): the hue of `mvtrack view` (frac(id x 0.618...)), the same id the
# same colour in every phase, ids of a frame told apart, and the canvas drawing a confirmed track's
# disc in its row's colour; the scale bar is a 1-2-5 length in metres at the drawing's scale; the
# time in view is the track's age at the stream's frame period.
events = [json.loads(l[6:]) for l in open(sys.argv[3]) if l.startswith("data: ")]
tr = sorted((e for e in events if e["type"] == "tracks"), key=lambda e: e["frame"])
period = (tr[-1]["utime"] - tr[0]["utime"]) / 1e6 / (tr[-1]["frame"] - tr[0]["frame"])
first_frame = {}
for line in open(sys.argv[2]):
    f = json.loads(line)
    for t in f["tracks"]:
        first_frame.setdefault(t["id"], f["frame"])
colour_of = {}
drawn_ok = drawn_all = 0
for ph in (phases[0], phases[2]):
    for t in ph["tracks"]:
        turns = (t["id"] % 1000003) * 0.6180339887498949
        assert t["color"] == "hsl(%.1f, 85%%, 40%%)" % (360 * (turns - math.floor(turns))), t
        assert colour_of.setdefault(t["id"], t["color"]) == t["color"], (t, colour_of[t["id"]])
        if t["state"] == "confirmed" and t["drawn"] is not None:
            drawn_all += 1
            drawn_ok += all(abs(a - b) <= 12 for a, b in zip(t["drawn"], t["rgb"]))
    assert len({t["color"] for t in ph["tracks"]}) == len(ph["tracks"]), ph["tracks"]
assert drawn_all >= 4 and drawn_ok >= 0.8 * drawn_all, (drawn_ok, drawn_all)
sc = first["scale"]
assert sc["m"] > 0 and round(sc["m"] / 10 ** math.floor(math.log10(sc["m"]))) in (1, 2, 5), sc
assert abs(sc["px"] - sc["m"] * sc["px_per_m"]) < 0.2 and 40 <= sc["px"] <= 160, sc
for t in first["tracks"]:
    want = (first["frame"] - first_frame[t["id"]]) * period
    assert t["age_s"] is not None and want - 0.06 <= t["age_s"] <= want + 1.5, (t, want)
print(f"page: {len(colour_of)} ids each in its own colour, {drawn_ok} / {drawn_all} discs drawn in "
      f"it; scale bar {sc['m']:g} m = {sc['px']} px; in view {[t['age_s'] for t in first['tracks']]} s")
# The daemon stopped longer ago than --stale-after (issue 39: the page stayed green and "live"
# with its last people standing still): UNKNOWN with the reason, tracks greyed out with how long
# ago they were published.
stopped = phases[1]
assert first["stale"] == "" and first["tracks_note"] == "", first
assert stopped["health"] == "UNKNOWN" and stopped["connection"] == "stale", stopped
assert "the tracker stopped publishing" in stopped["reasons"], stopped
assert stopped["stale"] == "status tracks", stopped
assert stopped["tracks_note"].startswith("not published for "), stopped
second = phases[2]
assert second["messages"] >= 400 and second["connection"] == "live", second
assert second["stale"] == "" and second["health"] != "UNKNOWN", second
# A live daemon whose cameras all went silent: its status keeps coming and says CRITICAL (no
# camera delivers), its tracks are greyed out as not published.
silent = phases[3]
assert silent["health"] == "CRITICAL" and silent["stale"] == " tracks", silent
assert "cameras deliver" in silent["reasons"], silent
assert silent["tracks_note"].startswith("not published for "), silent
print(f"page: frame {first['frame']} with tracks {sorted(got)} as published; publish -> DOM "
      f"latency p50 {first['latency_p50_ms']} ms, max {first['latency_max_ms']} ms over "
      f"{first['latency_count']} messages; stopped: {stopped['health']}, tracks "
      f"{stopped['tracks_note']}; {second['messages']} messages after a daemon restart")
EOF

# The site analytics (issue 41): the daemon's counts reach /events, /metrics and the page, whose
# regions table shows the latest counts; /site.json is the site file's geometry.
"$PY" - "$OUT/site.json" "$OUT/events_end.txt" "$OUT/probe.jsonl" "$OUT/metrics_end.txt" << 'EOF' ||
import json, sys
site = json.load(open(sys.argv[1]))
assert [r["name"] for r in site["regions"]] == ["room", "centre", "west_strip"], site
assert site["lines"][0] == {"name": "middle", "from": [3.0, 0.0], "to": [3.0, 6.0]}, site
events = [json.loads(l[6:]) for l in open(sys.argv[2]) if l.startswith("data: ")]
counts = [e for e in events if e["type"] == "site_counts"]
assert counts, "no site_counts event on /events"
c = counts[-1]
assert [r["name"] for r in c["regions"]] == ["room", "centre", "west_strip"], c
# The demo's three people are in the room from the start: three visits of the room begun.
assert c["regions"][0]["entries"] == 3, c
page = json.loads(open(sys.argv[3]).readline())
assert [r["name"] for r in page["regions"]] == ["room", "centre", "west_strip"], page
assert page["regions"][0]["entries"] >= 1, page
metrics = open(sys.argv[4]).read()
assert 'mvtrack_region_entries_total{region="room"} 3' in metrics, metrics[-2000:]
assert 'mvtrack_line_crossings_total{line="middle",direction="left_to_right"}' in metrics
# Each analytics event reached the page: publish (the daemon, right after the tracks message
# that confirmed it) -> in the DOM. Sanity only (timing belongs to benchmarks).
assert page["analytics_events"] >= 3, page
assert 0 <= page["analytics_latency_max_ms"] < 1000, page
print(f"site analytics: counts {c['regions']}, lines {c['lines']}; page {page['regions']}; "
      f"{page['analytics_events']} events, publish -> DOM max {page['analytics_latency_max_ms']} ms")
EOF
  fail "the site analytics did not reach /events, /metrics or the page"

# /metrics is hand-written (docs/DECISIONS.md "Watching it live"): Prometheus' own Python client
# parses every exposition the test took, its histograms are cumulative with _count = +Inf, and
# mvtrack_up reads back as written (1 live, 0 once the daemon stopped, 1 again).
"$PY" - "$OUT"/metrics_live.txt "$OUT"/metrics_stale.txt "$OUT"/metrics_end.txt << 'EOF' ||
import sys
from prometheus_client.parser import text_string_to_metric_families
up = []
for path in sys.argv[1:]:
    families = {f.name: f for f in text_string_to_metric_families(open(path).read())}
    up.append(families["mvtrack_up"].samples[0].value)
    samples = sum(len(f.samples) for f in families.values())
    for f in families.values():
        if f.type != "histogram":
            continue
        by_series = {}
        for s in f.samples:
            key = tuple(sorted((k, v) for k, v in s.labels.items() if k != "le"))
            by_series.setdefault(key, {}).setdefault(s.name, []).append(s)
        for key, parts in by_series.items():
            buckets = [s.value for s in parts[f.name + "_bucket"]]
            assert buckets == sorted(buckets), (path, key, buckets)
            assert parts[f.name + "_bucket"][-1].labels["le"] == "+Inf", (path, key)
            assert parts[f.name + "_count"][0].value == buckets[-1], (path, key)
    print(f"{path.rsplit('/', 1)[-1]}: {len(families)} families, {samples} samples parsed")
assert up == [1.0, 0.0, 1.0], up
EOF
  fail "/metrics is not what Prometheus' parser reads"

# The stuck client was disconnected and counted; the page got every message meanwhile.
dropped=$(grep -E "^mvtrack_web_clients_dropped_total " "$OUT/metrics_end.txt" | awk '{print $2}')
expect_ge "$dropped" 1 "slow /events clients disconnected"
[ -s "$OUT/page.png" ] || fail "no screenshot"
echo "ok"
