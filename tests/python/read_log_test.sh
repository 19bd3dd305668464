# examples/python/read_log.py with PyPI's lcm on a `mvtrack replay` output: every tracks message
# decodes to the values replay wrote as JSONL; the summary counts frames, track ids and
# detections correctly; bad input exits 1 with a message.
source "$(dirname "$0")/common.sh"
make_tracks_log

# Every message, as JSON, equals replay's JSONL (independent writer, 4 decimals).
"$VPY" "$EXAMPLES/read_log.py" --json "$OUT/tracks.lcmlog" >"$OUT/got.jsonl" 2>"$OUT/summary.txt" ||
  { cat "$OUT/summary.txt" >&2; fail "read_log.py --json failed"; }
"$PYTHON" "$HERE/compare_tracks.py" "$OUT/got.jsonl" "$OUT/tracks.jsonl"

# The summary: frames and track ids as counted in the JSONL.
read -r frames ids < <("$PYTHON" -c '
import json, sys
lines = [json.loads(l) for l in open(sys.argv[1])]
print(len(lines), len({t["id"] for l in lines for t in l["tracks"]}))' "$OUT/tracks.jsonl")
[ "$ids" -gt 0 ] || fail "the replay has no tracks"
expect_grep "^tracks: $frames frame\(s\), $ids track id\(s\)$" "$OUT/summary.txt"
expect_grep "^  MVTRACK_TRACKS: $frames$" "$OUT/summary.txt"
"$VPY" "$EXAMPLES/read_log.py" --print "$OUT/tracks.lcmlog" >"$OUT/print.txt"
[ "$(grep -c '^frame ' "$OUT/print.txt")" -eq "$frames" ] || fail "--print: expected $frames frames"
expect_grep "^  id +[0-9]+ (tentative|confirmed|lost|ended) +\(" "$OUT/print.txt"

# The detections log: 3 cameras x 60 frames (make_sim_log writes every camera-frame).
"$VPY" "$EXAMPLES/read_log.py" "$OUT/sim/detections.lcmlog" >"$OUT/dets.txt"
expect_grep "^detections: 3 camera\(s\)$" "$OUT/dets.txt"
for cam in 0 1 2; do expect_grep "^  camera $cam: 60 camera-frame\(s\), [0-9]+ detection\(s\)$" "$OUT/dets.txt"; done

# Bad input: a missing file and a log with a corrupt message.
expect_exit 1 "$OUT/missing.txt" "$VPY" "$EXAMPLES/read_log.py" "$OUT/nosuch.lcmlog"
expect_grep "cannot open .*nosuch.lcmlog" "$OUT/missing.txt"
"$VPY" - "$OUT/tracks.lcmlog" "$OUT/corrupt.lcmlog" <<'PY'
import sys, lcm
src, dst = lcm.EventLog(sys.argv[1], "r"), lcm.EventLog(sys.argv[2], "w", overwrite=True)
for i, e in enumerate(src):
    data = e.data if i != 2 else e.data[:12]  # the third message cut after its fingerprint
    dst.write_event(e.timestamp, e.channel, data)
dst.close()
PY
expect_exit 1 "$OUT/corrupt.txt" "$VPY" "$EXAMPLES/read_log.py" "$OUT/corrupt.lcmlog"
expect_grep "event 2 on MVTRACK_TRACKS: tracks3d_t: " "$OUT/corrupt.txt"
echo "read_log: ok ($frames frames, $ids track ids)"
