// The live floor view served at / by mvtrack web (docs/OPERATING.md). One self-contained page:
// no script, style or font from elsewhere (a store network may have no internet access). It
// reads /floor.json and /layouts.json once, then the /events stream (EventSource reconnects by
// itself when the server restarts), and keeps a DOM table of the latest tracks (ids and
// positions, read by the browser test) next to the canvas drawing. It ages what it shows with
// the server's staleness rule (`stale_after_s` of /floor.json, --stale-after): no status within
// it turns the badge UNKNOWN with the reason, tracks not published within it are greyed out
// with how long ago they were (issue 39: a stopped daemon looked healthy, "live", forever).

#include <string>

#include "web/web_server.h"

namespace mvtrack::web {

const std::string& IndexPage() {
  static const std::string page = R"HTML(<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>mvtrack live</title>
<style>
  body { font: 14px system-ui, sans-serif; margin: 0; background: #f4f4f4; color: #222; }
  header { display: flex; gap: 1.5em; align-items: baseline; padding: 0.5em 1em; background: #223; color: #eee; flex-wrap: wrap; }
  header h1 { font-size: 1.1em; margin: 0; }
  #health { font-weight: bold; padding: 0.1em 0.5em; border-radius: 3px; }
  .OK { background: #2a7; color: #fff; } .WARNING { background: #e90; color: #000; }
  .CRITICAL, .UNKNOWN { background: #c33; color: #fff; }
  main { display: flex; gap: 1em; padding: 1em; flex-wrap: wrap; }
  #floor { background: #fff; border: 1px solid #ccc; }
  table { border-collapse: collapse; background: #fff; font-size: 12px; }
  th, td { border: 1px solid #ddd; padding: 2px 6px; text-align: right; }
  th { background: #eee; } td.flags { text-align: left; color: #a30; } td.ok { color: #2a7; }
  section h2 { font-size: 1em; margin: 0 0 0.3em 0; }
  #reasons { color: #fdd; }
  #tracks.stale td { color: #999; } #tracks-note { color: #a30; }
  .swatch { display: inline-block; width: 0.8em; height: 0.8em; border-radius: 50%; margin-right: 0.3em; }
</style>
</head>
<body>
<header>
  <h1>mvtrack live</h1>
  <span id="health" class="UNKNOWN">UNKNOWN</span>
  <span>frame <b id="frame">-</b></span>
  <span><b id="track-count">0</b> tracks</span>
  <span><b id="fps">-</b> fps</span>
  <span>tracker latency p99 <b id="latency-p99-ms">-</b> ms</span>
  <span>page latency p50 <b id="web-latency-p50-ms">-</b> / max <b id="web-latency-max-ms">-</b> ms
    over <b id="web-latency-count">0</b></span>
  <span>messages <b id="tracks-messages">0</b></span>
  <label>layer <select id="layer-choice">
    <option value="auto">auto</option><option value="provisional">now (provisional)</option>
    <option value="final">final</option></select></label>
  <span id="layer" data-layer="final">showing the final layer</span>
  <span id="connection">connecting</span>
  <span id="reasons"></span>
</header>
<main>
  <canvas id="floor" width="640" height="560"></canvas>
  <div>
    <section id="zones-section" hidden>
      <h2>Zones</h2>
      <table id="zones"><thead><tr><th>zone</th><th>state</th><th>frames</th><th>late</th>
        <th>latency ms</th><th>last msg s</th><th>tracks</th><th>daemon</th><th>flags</th></tr></thead>
        <tbody></tbody></table>
    </section>
    <section id="cameras-section">
      <h2>Cameras</h2>
      <table id="cameras"><thead><tr><th>camera</th><th>rate Hz</th><th>last msg s</th>
        <th>latency ms</th><th>clock offset ms</th><th>late</th><th>dropped</th><th>lost</th><th>rejected</th>
        <th>flags</th></tr></thead><tbody></tbody></table>
    </section>
    <section id="site-section" hidden>
      <h2>Regions and lines</h2>
      <table id="regions"><thead><tr><th>region</th><th>inside</th><th>entries</th><th>exits</th>
        </tr></thead><tbody></tbody></table>
      <table id="lines"><thead><tr><th>line</th><th>left to right</th><th>right to left</th>
        </tr></thead><tbody></tbody></table>
      <ol id="analytics-events" reversed></ol>
    </section>
    <section>
      <h2>Tracks <span id="tracks-note"></span></h2>
      <table id="tracks"><thead><tr><th>id</th><th>state</th><th>x m</th><th>y m</th>
        <th>in view s</th><th>cameras</th><th>zones</th></tr></thead><tbody></tbody></table>
    </section>
  </div>
</main>
<script>
"use strict";
const canvas = document.getElementById("floor");
const ctx = canvas.getContext("2d");
let floor = { cameras: [], bounds: null };
let layouts = {};
let site = { regions: [], lines: [] };  // /site.json: the geometry (mvtrack web --regions)
let counts = null;                      // the latest site_counts event
const MAX_EVENTS = 20;                  // analytics events listed
let latest = null;            // the latest tracks event
const trails = new Map();     // id -> [[x, y, t_ms], ...]
const TRAIL_MS = 5000;
const latencies = [];         // page latency samples, ms (publish -> shown)
let messages = 0;
const arrivals = [];          // [t_ms, frame] of the last tracks messages
let drawPending = false;
let staleAfterMs = 5000;      // /floor.json's stale_after_s (the server's --stale-after)
let lastStatusMs = null;      // performance.now() of the latest status / tracks event
let lastTracksMs = null;
let statusStale = false, tracksStale = false;
// Which tracks layer is drawn: the provisional one ("now": every frame as soon as it is closed)
// or the final one (windowed, about a window behind). auto: the provisional layer while it
// arrives (a message within PROVISIONAL_FRESH_MS), else the final one.
const PROVISIONAL_FRESH_MS = 2000;
let layerChoice = "auto";
let lastProvisionalMs = null;
function shownLayer() {
  if (layerChoice !== "auto") return layerChoice;
  const fresh = lastProvisionalMs !== null && performance.now() - lastProvisionalMs <= PROVISIONAL_FRESH_MS;
  return fresh ? "provisional" : "final";
}
function showLayer() {
  const layer = shownLayer();
  const el = document.getElementById("layer");
  if (el.dataset.layer === layer) return;
  el.dataset.layer = layer;
  el.textContent = layer === "provisional" ? "showing the provisional layer (now)"
                                           : "showing the final layer (windowed, about a window behind)";
}

function text(id, v) { document.getElementById(id).textContent = v; }

// A track's colour: its id alone decides it, so it is the same in every frame and the same hue
// as in `mvtrack view` (viz::TrackColor: hue = frac(id x 0.618...), ids modulo 1000003), darker
// for this light page.
function trackHue(id) {
  const turns = (((id % 1000003) + 1000003) % 1000003) * 0.6180339887498949;
  return 360 * (turns - Math.floor(turns));
}
function trackColor(id, alpha) {
  const h = trackHue(id).toFixed(1);
  return alpha === undefined ? "hsl(" + h + ", 85%, 40%)" : "hsla(" + h + ", 85%, 40%, " + alpha.toFixed(3) + ")";
}
// The stream's frame period (s), from consecutive tracks messages (capture utime per frame).
let framePeriodS = null;
let previousTracks = null;

function bounds() {
  let b = floor.bounds ? floor.bounds.slice() : null;
  const grow = (x, y) => {
    if (!b) { b = [x, y, x, y]; return; }
    b[0] = Math.min(b[0], x); b[1] = Math.min(b[1], y);
    b[2] = Math.max(b[2], x); b[3] = Math.max(b[3], y);
  };
  if (latest) for (const t of latest.tracks) if (t.position[0] !== null) grow(t.position[0], t.position[1]);
  for (const r of site.regions) for (const p of r.polygon) grow(p[0], p[1]);
  for (const l of site.lines) { grow(l.from[0], l.from[1]); grow(l.to[0], l.to[1]); }
  if (!b) b = [-5, -5, 5, 5];
  const pad = 0.5;
  return [b[0] - pad, b[1] - pad, b[2] + pad, b[3] + pad];
}

function draw() {
  drawPending = false;
  const [x0, y0, x1, y1] = bounds();
  const s = Math.min(canvas.width / (x1 - x0), canvas.height / (y1 - y0));
  const px = (x) => (x - x0) * s;
  const py = (y) => canvas.height - (y - y0) * s;   // +y up
  window.floorToCanvas = (x, y) => [px(x), py(y)];  // for tests: where a floor point is drawn
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  // metre grid
  ctx.strokeStyle = "#eee"; ctx.lineWidth = 1;
  for (let x = Math.ceil(x0); x <= x1; x++) { ctx.beginPath(); ctx.moveTo(px(x), 0); ctx.lineTo(px(x), canvas.height); ctx.stroke(); }
  for (let y = Math.ceil(y0); y <= y1; y++) { ctx.beginPath(); ctx.moveTo(0, py(y)); ctx.lineTo(canvas.width, py(y)); ctx.stroke(); }
  // cameras and their fields of view on the floor
  for (const c of floor.cameras) {
    if (c.fov.length > 2) {
      ctx.fillStyle = "rgba(80, 120, 200, 0.06)"; ctx.strokeStyle = "rgba(80, 120, 200, 0.35)";
      ctx.beginPath(); ctx.moveTo(px(c.fov[0][0]), py(c.fov[0][1]));
      for (const p of c.fov) ctx.lineTo(px(p[0]), py(p[1]));
      ctx.closePath(); ctx.fill(); ctx.stroke();
    }
    ctx.fillStyle = "#35a"; ctx.fillRect(px(c.position[0]) - 5, py(c.position[1]) - 5, 10, 10);
    ctx.fillText("cam " + c.id, px(c.position[0]) + 7, py(c.position[1]) - 7);
  }
  // regions (with the people inside now) and lines (with their crossings)
  const countOf = (list, name) => (counts ? counts[list].find((c) => c.name === name) : null);
  for (const r of site.regions) {
    const c = countOf("regions", r.name);
    ctx.fillStyle = c && c.occupancy > 0 ? "rgba(60, 160, 90, 0.16)" : "rgba(60, 160, 90, 0.05)";
    ctx.strokeStyle = "rgba(40, 130, 70, 0.8)"; ctx.lineWidth = 1.5;
    ctx.beginPath(); ctx.moveTo(px(r.polygon[0][0]), py(r.polygon[0][1]));
    for (const p of r.polygon) ctx.lineTo(px(p[0]), py(p[1]));
    ctx.closePath(); ctx.fill(); ctx.stroke();
    ctx.fillStyle = "#1a5"; ctx.fillText(r.name + (c ? ": " + c.occupancy : ""), px(r.polygon[0][0]) + 4, py(r.polygon[0][1]) - 4);
  }
  for (const l of site.lines) {
    const c = countOf("lines", l.name);
    ctx.strokeStyle = "#a3c"; ctx.lineWidth = 3;
    ctx.beginPath(); ctx.moveTo(px(l.from[0]), py(l.from[1])); ctx.lineTo(px(l.to[0]), py(l.to[1])); ctx.stroke();
    ctx.fillStyle = "#a3c";
    ctx.fillText(l.name + (c ? " " + c.left_to_right + " / " + c.right_to_left : ""), px(l.to[0]) + 4, py(l.to[1]) - 4);
  }
  const now = performance.now();
  // trails in their track's colour, fading with age
  for (const [id, pts] of trails) {
    for (let i = 1; i < pts.length; i++) {
      const a = 1 - (now - pts[i][2]) / TRAIL_MS;
      if (a <= 0) continue;
      ctx.strokeStyle = tracksStale ? "rgba(150, 150, 150, " + (0.6 * a).toFixed(3) + ")" : trackColor(id, 0.6 * a);
      ctx.lineWidth = 2;
      ctx.beginPath(); ctx.moveTo(px(pts[i - 1][0]), py(pts[i - 1][1])); ctx.lineTo(px(pts[i][0]), py(pts[i][1])); ctx.stroke();
    }
  }
  if (!latest) return;
  const bones = (layouts[latest.layout] || { bones: [] }).bones;
  for (const t of latest.tracks) {
    if (t.position[0] === null) continue;
    // skeleton seen from above
    ctx.strokeStyle = "#777"; ctx.lineWidth = 1;
    for (const [a, b] of bones) {
      const ja = t.joints[a], jb = t.joints[b];
      if (!ja || !jb || ja[0] === null || jb[0] === null) continue;
      ctx.beginPath(); ctx.moveTo(px(ja[0]), py(ja[1])); ctx.lineTo(px(jb[0]), py(jb[1])); ctx.stroke();
    }
    // confirmed: a filled disc in the track's colour; tentative or lost: a ring
    const colour = tracksStale ? "#999" : trackColor(t.id);
    ctx.beginPath(); ctx.arc(px(t.position[0]), py(t.position[1]), 6, 0, 2 * Math.PI);
    if (t.state === "confirmed") { ctx.fillStyle = colour; ctx.fill(); }
    else { ctx.strokeStyle = colour; ctx.lineWidth = 2.5; ctx.stroke(); }
    ctx.fillStyle = "#000"; ctx.fillText(String(t.id), px(t.position[0]) + 8, py(t.position[1]) + 4);
  }
  drawScale(s);
}

// A scale bar in the bottom-left corner: the longest of 1-2-5 x 10^k metres up to 160 px.
function drawScale(pxPerM) {
  let m = Math.pow(10, Math.floor(Math.log10(160 / pxPerM)));
  for (const f of [5, 2]) if (f * m * pxPerM <= 160) { m *= f; break; }
  const len = m * pxPerM, x = 12, y = canvas.height - 12;
  ctx.strokeStyle = "#222"; ctx.lineWidth = 2;
  ctx.beginPath(); ctx.moveTo(x, y - 5); ctx.lineTo(x, y); ctx.lineTo(x + len, y); ctx.lineTo(x + len, y - 5); ctx.stroke();
  ctx.fillStyle = "#222"; ctx.fillText((m >= 1 ? m.toFixed(0) : m.toPrecision(1)) + " m", x + len / 2 - 8, y - 7);
  canvas.dataset.scaleM = m; canvas.dataset.scalePx = len.toFixed(1); canvas.dataset.pxPerM = pxPerM.toFixed(4);
}

function scheduleDraw() { if (!drawPending) { drawPending = true; requestAnimationFrame(draw); } }

// Ages the page's state (every 250 ms and on every event): the server's staleness rule.
function checkStale() {
  const now = performance.now();
  const seconds = (t) => ((now - t) / 1000).toFixed(1);
  statusStale = lastStatusMs !== null && now - lastStatusMs > staleAfterMs;
  tracksStale = lastTracksMs !== null && now - lastTracksMs > staleAfterMs;
  if (statusStale) {
    const h = document.getElementById("health");
    h.textContent = "UNKNOWN"; h.className = "UNKNOWN";
    text("reasons", "no status message for " + seconds(lastStatusMs) + " s: the tracker stopped publishing");
    text("connection", "stale");
  }
  document.getElementById("tracks").classList.toggle("stale", tracksStale);
  text("tracks-note", tracksStale ? "not published for " + seconds(lastTracksMs) + " s (frame " +
       (latest ? latest.frame : "-") + ")" : "");
  document.body.dataset.stale = (statusStale ? "status" : "") + (tracksStale ? " tracks" : "");
}

function onTracks(e) {
  if (previousTracks && e.frame > previousTracks.frame && e.utime > previousTracks.utime) {
    framePeriodS = (e.utime - previousTracks.utime) / 1e6 / (e.frame - previousTracks.frame);
  }
  previousTracks = e;
  latest = e;
  messages++;
  const now = performance.now();
  lastTracksMs = now;
  const seen = new Set();
  for (const t of e.tracks) {
    seen.add(t.id);
    if (t.position[0] === null) continue;
    let pts = trails.get(t.id);
    if (!pts) { pts = []; trails.set(t.id, pts); }
    pts.push([t.position[0], t.position[1], now]);
    while (pts.length && now - pts[0][2] > TRAIL_MS) pts.shift();
  }
  for (const [id, pts] of trails) {
    while (pts.length && now - pts[0][2] > TRAIL_MS) pts.shift();
    if (!pts.length) trails.delete(id);
  }
  const rows = [];
  for (const t of e.tracks) {
    const x = t.position[0] === null ? "" : t.position[0].toFixed(3);
    const y = t.position[1] === null ? "" : t.position[1].toFixed(3);
    // time in view: the track's age (frames since its first) at the stream's frame period
    const age = framePeriodS === null ? "" : (t.age_frames * framePeriodS).toFixed(1);
    // a site's stitched output: the zones that see the person (names from the network: escaped)
    const zones = escapeHtml((t.zones || []).join(" "));
    rows.push('<tr data-id="' + t.id + '" data-x="' + x + '" data-y="' + y + '" data-color="' + trackColor(t.id) +
              '" data-age-s="' + age + '" data-zones="' + zones + '"><td><span class="swatch" style="background:' +
              trackColor(t.id) + '"></span>' + t.id + "</td><td>" + t.state + "</td><td>" + x + "</td><td>" + y +
              "</td><td>" + age + "</td><td>" + t.cameras.join(" ") + "</td><td>" + zones + "</td></tr>");
  }
  document.querySelector("#tracks tbody").innerHTML = rows.join("");
  text("frame", e.frame);
  text("track-count", e.tracks.length);
  text("tracks-messages", messages);
  document.body.dataset.frame = e.frame;
  // output frames per second over the last 3 s (the output comes in bursts of a window step)
  if (arrivals.length && arrivals[arrivals.length - 1][1] > e.frame) arrivals.length = 0;  // a new daemon
  arrivals.push([now, e.frame]);
  while (arrivals.length > 2 && now - arrivals[0][0] > 3000) arrivals.shift();
  const span = now - arrivals[0][0];
  if (span >= 1000) text("fps", ((e.frame - arrivals[0][1]) * 1000 / span).toFixed(1));
  // publish (daemon host clock) -> in the DOM (this host's clock): one host in the tests
  const ms = Date.now() - e.publish_utime / 1000;
  latencies.push(ms);
  if (latencies.length > 5000) latencies.shift();
  const sorted = latencies.slice().sort((a, b) => a - b);
  text("web-latency-p50-ms", sorted[Math.floor((sorted.length - 1) / 2)].toFixed(1));
  text("web-latency-max-ms", sorted[sorted.length - 1].toFixed(1));
  text("web-latency-count", latencies.length);
  checkStale();
  scheduleDraw();
}

// A status arrived (a tracker's or a site's): the page is live, with its verdict.
function showHealth(s) {
  lastStatusMs = performance.now();
  if (statusStale) text("connection", "live");
  checkStale();
  const h = document.getElementById("health");
  h.textContent = s.health; h.className = s.health;
  text("reasons", s.reasons.join("; "));
}

function onStatus(s) {
  showHealth(s);
  document.getElementById("zones-section").hidden = true;
  document.getElementById("cameras-section").hidden = false;
  text("latency-p99-ms", (s.latency_p99_us / 1000).toFixed(1));
  const rows = [];
  for (const c of s.cameras) {
    const age = c.last_receive_utime > 0 ? ((s.utime - c.last_receive_utime) / 1e6).toFixed(1) : "never";
    // capture (camera clock) to receive (tracker clock); beyond an hour the clocks are not comparable
    const lat_us = c.last_receive_utime - c.last_utime;
    const latency = c.last_receive_utime <= 0 ? "-" : Math.abs(lat_us) > 3.6e9 ? "n/a" : (lat_us / 1000).toFixed(1);
    rows.push('<tr data-camera="' + c.camera_id + '"><td>' + c.camera_id + "</td><td>" + c.rate_hz.toFixed(1) +
              "</td><td>" + age + "</td><td>" + latency + "</td><td>" + (c.clock_offset_us / 1000).toFixed(1) + "</td><td>" + c.late +
              "</td><td>" + c.dropped + "</td><td>" + c.lost + "</td><td>" + c.rejected +
              '</td><td class="flags' + (c.flags.length ? '">' + c.flags.join(" ") : ' ok">ok') + "</td></tr>");
  }
  document.querySelector("#cameras tbody").innerHTML = rows.join("");
}

// A site's stitcher status (issue 43): the site's health, and a row per zone instead of the
// cameras (each zone daemon's cameras are on its own status channel).
function onSiteStatus(s) {
  showHealth(s);
  document.getElementById("zones-section").hidden = false;
  document.getElementById("cameras-section").hidden = true;
  document.querySelector("#zones tbody").innerHTML = s.zones.map((z) => {
    const state = z.flags.includes("NO_DATA") || z.flags.includes("STALE") ? "stale" : "live";
    const age = z.last_receive_utime > 0 ? ((s.utime - z.last_receive_utime) / 1e6).toFixed(1) : "never";
    const daemon = escapeHtml(z.daemon_health) + (z.daemon_reasons ? ": " + escapeHtml(z.daemon_reasons) : "");
    return '<tr data-zone="' + escapeHtml(z.name) + '" data-state="' + state + '" data-daemon="' +
      escapeHtml(z.daemon_health) + '"><td>' + escapeHtml(z.name) + "</td><td>" + state + "</td><td>" + z.frames +
      "</td><td>" + z.late + "</td><td>" + (z.latency_us / 1000).toFixed(1) + "</td><td>" + age + "</td><td>" +
      z.tracks + "</td><td>" + daemon + '</td><td class="flags' +
      (z.flags.length ? '">' + z.flags.join(" ") : ' ok">ok') + "</td></tr>";
  }).join("");
}

// Names come from the daemon's messages: written as text, never as HTML.
function escapeHtml(v) {
  return String(v).replace(/[&<>"']/g, (c) => ({ "&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;", "'": "&#39;" })[c]);
}

function onSiteCounts(c) {
  counts = c;
  document.getElementById("site-section").hidden = false;
  document.querySelector("#regions tbody").innerHTML = c.regions.map((r) =>
    '<tr data-region="' + escapeHtml(r.name) + '"><td>' + escapeHtml(r.name) + "</td><td>" + r.occupancy +
    "</td><td>" + r.entries + "</td><td>" + r.exits + "</td></tr>").join("");
  document.querySelector("#lines tbody").innerHTML = c.lines.map((l) =>
    '<tr data-line="' + escapeHtml(l.name) + '"><td>' + escapeHtml(l.name) + "</td><td>" + l.left_to_right +
    "</td><td>" + l.right_to_left + "</td></tr>").join("");
  scheduleDraw();
}

const analyticsLatencies = [];  // publish -> shown, ms, of the analytics events
function onAnalytics(e) {
  document.getElementById("site-section").hidden = false;
  analyticsLatencies.push(Date.now() - e.publish_utime / 1000);
  if (analyticsLatencies.length > 5000) analyticsLatencies.shift();
  document.body.dataset.analyticsLatencyMaxMs = Math.max(...analyticsLatencies).toFixed(1);
  document.body.dataset.analyticsEvents = analyticsLatencies.length;
  const list = document.getElementById("analytics-events");
  const item = document.createElement("li");
  const what = e.kind === "crossing" ? "crossed " + e.name + " " + e.direction.replace(/_/g, " ")
             : e.kind === "enter" ? "entered " + e.name
             : "left " + e.name + " after " + e.dwell_s.toFixed(1) + " s" + (e.track_ended ? " (track ended)" : "");
  item.textContent = "track " + e.track_id + " " + what;
  item.dataset.kind = e.kind;
  list.insertBefore(item, list.firstChild);
  while (list.children.length > MAX_EVENTS) list.removeChild(list.lastChild);
}

function connect() {
  const es = new EventSource("/events");
  es.onopen = () => text("connection", "live");
  es.onerror = () => text("connection", "reconnecting");
  es.onmessage = (m) => {
    const e = JSON.parse(m.data);
    if (e.type === "tracks") {
      const layer = e.layer === "provisional" ? "provisional" : "final";
      if (layer === "provisional") lastProvisionalMs = performance.now();
      showLayer();
      if (layer === shownLayer()) onTracks(e);
    } else if (e.type === "status") onStatus(e);
    else if (e.type === "site_status") onSiteStatus(e);
    else if (e.type === "site_counts") onSiteCounts(e); else if (e.type === "analytics") onAnalytics(e);
  };
}

Promise.all([fetch("/floor.json").then((r) => r.json()), fetch("/layouts.json").then((r) => r.json()),
             fetch("/site.json").then((r) => r.json())])
  .then(([f, l, g]) => {
    floor = f; layouts = l; site = g;
    if (site.regions.length || site.lines.length) document.getElementById("site-section").hidden = false;
    if (f.stale_after_s > 0) staleAfterMs = 1000 * f.stale_after_s;
    scheduleDraw();
  })
  .catch(() => {})
  .finally(connect);
document.getElementById("layer-choice").addEventListener("change", (ev) => {
  layerChoice = ev.target.value;
  showLayer();
});
setInterval(() => { showLayer(); checkStale(); scheduleDraw(); }, 250);  // trails fade, state ages, without messages
</script>
</body>
</html>
)HTML";
  return page;
}

}  // namespace mvtrack::web
