#!/usr/bin/python3
"""Drives a headless Chromium through the DevTools protocol (python3-websocket): opens URL once,
then for each MESSAGES_i in turn waits until the page has shown that many tracks messages (or,
for a phase written @FILE, until FILE exists, e.g. when the daemon stopped a while ago),
prints one JSON line with what the page's DOM shows (frame, tracks as id/x/y from the track
table's data attributes with each track's colour, the floor canvas's pixel where it is drawn
and its time in view, the floor's scale bar, messages, the page's latency figures, health, connection, camera rows,
the site's region rows with their counts, a site's zone rows and which zones see each track)
and creates the file PHASE_PREFIX.i (so a test can act between phases, e.g. restart the daemon
while the same page stays open). A PNG screenshot is saved after the first phase.

Usage: page_probe.py DEVTOOLS_PORT URL TIMEOUT_S SCREENSHOT.png PHASE_PREFIX MESSAGES_1|@FILE [...]
Exit status 0 when every phase was reached within TIMEOUT_S (each), 1 otherwise."""
import base64
import json
import sys
import time
import urllib.request

import websocket

port, url, timeout_s, shot, phase_prefix = sys.argv[1], sys.argv[2], float(sys.argv[3]), sys.argv[4], sys.argv[5]
phases = sys.argv[6:]

deadline = time.time() + timeout_s
targets = None
while time.time() < deadline:
    try:
        targets = json.load(urllib.request.urlopen(f"http://127.0.0.1:{port}/json/list", timeout=2))
        if any(t.get("type") == "page" for t in targets):
            break
    except OSError:
        pass
    time.sleep(0.1)
page = next(t for t in targets if t.get("type") == "page")
ws = websocket.create_connection(page["webSocketDebuggerUrl"], timeout=10, suppress_origin=True)
next_id = 0


def call(method, **params):
    global next_id
    next_id += 1
    ws.send(json.dumps({"id": next_id, "method": method, "params": params}))
    while True:
        reply = json.loads(ws.recv())
        if reply.get("id") == next_id:
            if "error" in reply:
                raise RuntimeError(f"{method}: {reply['error']}")
            return reply["result"]


PROBE = """(() => {
const floor = document.getElementById('floor');
const paint = document.createElement('canvas').getContext('2d');
// A CSS colour as [r, g, b] (painted on a scratch canvas), and the floor canvas's pixel where
// the page draws floor point (x, y).
const rgbOf = (c) => { paint.fillStyle = c; paint.fillRect(0, 0, 1, 1); return [...paint.getImageData(0, 0, 1, 1).data.slice(0, 3)]; };
const drawnAt = (x, y) => {
  if (!window.floorToCanvas) return null;
  const [u, v] = window.floorToCanvas(x, y);
  return [...floor.getContext('2d').getImageData(Math.round(u), Math.round(v), 1, 1).data.slice(0, 3)];
};
return JSON.stringify({
  frame: Number(document.body.dataset.frame === undefined ? -1 : document.body.dataset.frame),
  messages: Number(document.getElementById('tracks-messages').textContent),
  layer: document.getElementById('layer').dataset.layer,
  tracks: [...document.querySelectorAll('#tracks tbody tr')].map(r => ({
    id: Number(r.dataset.id), x: Number(r.dataset.x), y: Number(r.dataset.y),
    state: r.cells[1].textContent, color: r.dataset.color, rgb: rgbOf(r.dataset.color), drawn: drawnAt(Number(r.dataset.x), Number(r.dataset.y)),
    age_s: r.dataset.ageS === '' ? null : Number(r.dataset.ageS), zones: r.dataset.zones})),
  zones: [...document.querySelectorAll('#zones tbody tr')].map(r => ({
    name: r.dataset.zone, state: r.dataset.state, daemon: r.dataset.daemon})),
  zones_shown: !document.getElementById('zones-section').hidden,
  scale: {m: Number(floor.dataset.scaleM), px: Number(floor.dataset.scalePx), px_per_m: Number(floor.dataset.pxPerM)},
  latency_p50_ms: Number(document.getElementById('web-latency-p50-ms').textContent),
  latency_max_ms: Number(document.getElementById('web-latency-max-ms').textContent),
  latency_count: Number(document.getElementById('web-latency-count').textContent),
  health: document.getElementById('health').textContent,
  reasons: document.getElementById('reasons').textContent,
  connection: document.getElementById('connection').textContent,
  stale: document.body.dataset.stale || '',
  tracks_note: document.getElementById('tracks-note').textContent,
  cameras: [...document.querySelectorAll('#cameras tbody tr')].map(r => r.dataset.camera),
  analytics_events: Number(document.body.dataset.analyticsEvents || 0),
  analytics_latency_max_ms: Number(document.body.dataset.analyticsLatencyMaxMs || -1),
  regions: [...document.querySelectorAll('#regions tbody tr')].map(r => ({
    name: r.dataset.region, inside: Number(r.cells[1].textContent),
    entries: Number(r.cells[2].textContent), exits: Number(r.cells[3].textContent)}))
});
})()"""

call("Page.enable")
call("Page.navigate", url=url)
ok = True
import os

for i, phase in enumerate(phases, start=1):
    deadline = time.time() + timeout_s
    state = {}
    wait_file = phase[1:] if phase.startswith("@") else None
    wanted = 0 if wait_file else int(phase)
    while time.time() < deadline:
        result = call("Runtime.evaluate", expression=PROBE, returnByValue=True)["result"]
        if "value" in result:  # else the page is still loading (its elements do not exist yet)
            state = json.loads(result["value"])
            if (os.path.exists(wait_file) if wait_file else state["messages"] >= wanted):
                break
        time.sleep(0.05)
    reached = os.path.exists(wait_file) if wait_file else state.get("messages", 0) >= wanted
    ok = ok and reached
    if i == 1:
        with open(shot, "wb") as f:
            f.write(base64.b64decode(call("Page.captureScreenshot", format="png")["data"]))
    print(json.dumps(state), flush=True)
    open(f"{phase_prefix}.{i}", "w").close()
    if not reached:
        break
sys.exit(0 if ok else 1)
