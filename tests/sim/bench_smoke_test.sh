#!/usr/bin/env bash
# mvtrack bench --suite smoke: runs every suite in miniature (paper grid corner, store scale
# inline and threaded, paced latency, soak) and writes results.json (parseable, every point with
# FPS > 0 and accuracy figures), results.md with the tables, and a PNG plot. Speeds are not
# asserted (benchmarks, not tests); that it works is.
# Usage: bench_smoke_test.sh MVTRACK WORK_DIR SOURCE_DIR
set -euo pipefail
MVTRACK=$1
OUT=$2/bench_smoke
SRC=$3
. "$SRC/tests/support/shell_asserts.sh"
PYTHON=$(python3 -c 'import sys; print(sys.executable)')
rm -rf "$OUT"
mkdir -p "$OUT"

expect_exit 0 "$OUT/bench.txt" "$MVTRACK" bench --suite smoke --out "$OUT/results"
"$PYTHON" -S - "$OUT/results/results.json" <<'PY' || fail "results.json is incomplete"
import json, math, sys
d = json.load(open(sys.argv[1]))
assert d["schema"] == "mvtrack.bench/1"
points = d["points"]
assert len(points) == 10, len(points)
for p in points:
    assert p["fps"] > 0 and p["fps_per_cpu_second"] > 0, p
    assert 0.0 <= p["coverage_two_views"] <= 1.0, p
    assert p["mota"] is not None and p["idf1"] is not None, p
    assert (p["mpjpe_m"] is not None) == (p["mode"] == "poses"), p
# The same scene tracked inline and by the threaded pipeline scores identically.
inline = [p for p in points if p["suite"] == "smoke_scale" and p["runner"] == "tracker_inline"]
threaded = [p for p in points if p["suite"] == "smoke_scale" and p["runner"] == "pipeline"]
assert len(inline) == 1 and len(threaded) == 1
assert inline[0]["mota"] == threaded[0]["mota"] and inline[0]["idf1"] == threaded[0]["idf1"]
lat = d["latency"][0]
assert lat["windows"] >= 2 and lat["p50_ms"] > 0 and lat["p99_ms"] >= lat["p50_ms"], lat
soak = d["soak"][0]
assert soak["frames"] == 900 and len(soak["rss_samples_frame_mib"]) >= 9, soak
assert len(soak["chunk_accuracy"]) == 3, soak
PY
expect_grep "### latency" "$OUT/results/results.md"
expect_grep "### soak" "$OUT/results/results.md"
# A PNG: the 8-byte signature.
[ "$(head -c 8 "$OUT/results/fps.png" | od -An -tx1 | tr -d ' \n')" = "89504e470d0a1a0a" ] ||
  fail "fps.png is not a PNG"
expect_exit 2 "$OUT/e1.txt" "$MVTRACK" bench --suite nonsense
expect_grep "unknown suite" "$OUT/e1.txt"
expect_exit 2 "$OUT/e2.txt" "$MVTRACK" bench --suite custom --cameras 2,x
expect_grep "cameras" "$OUT/e2.txt"
echo "bench_smoke_test: ok"
