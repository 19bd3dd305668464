# examples/python/print_tracks.py receives tracks live and prints exactly what was published.
# Preferred: two processes over udpm:// inside a private network namespace (root + unshare:
# nothing leaves the machine; ../shared/TOOLCHAIN.md), lcm-logplayer publishing a `mvtrack
# replay` tracks log and print_tracks.py subscribing. Otherwise (not root, no unshare or no
# lcm-logplayer) the same subscriber code reads the log through LCM's file:// provider, and the
# test says so.
source "$(dirname "$0")/common.sh"
make_tracks_log
frames=$(wc -l <"$OUT/tracks.jsonl")

netns_ok=0
if [ "$(id -u)" -eq 0 ] && command -v unshare >/dev/null && command -v ip >/dev/null &&
   command -v lcm-logplayer >/dev/null && unshare -n true 2>/dev/null; then
  netns_ok=1
fi

if [ "$netns_ok" = 1 ]; then
  export VPY EXAMPLES OUT frames
  unshare -n bash -c '
    set -eu
    ip link set lo up
    ip route add 224.0.0.0/4 dev lo
    url="udpm://239.255.76.67:7667?ttl=0"
    "$VPY" "$EXAMPLES/print_tracks.py" --url "$url" --json --count "$frames" --timeout 30 \
      >"$OUT/got.jsonl" 2>"$OUT/sub.err" &
    sub=$!
    for _ in $(seq 300); do grep -q "listening" "$OUT/sub.err" && break; sleep 0.1; done
    grep -q "listening" "$OUT/sub.err" || { cat "$OUT/sub.err" >&2; kill "$sub"; exit 1; }
    lcm-logplayer -s 4 -l "$url" "$OUT/tracks.lcmlog" >"$OUT/player.log" 2>&1
    wait "$sub"
  ' || { cat "$OUT/sub.err" "$OUT/player.log" >&2 2>/dev/null; fail "live udpm run failed"; }
  echo "print_tracks: received $frames tracks messages live over udpm:// (private network namespace)"
else
  echo "print_tracks: no private network namespace (needs root, unshare, ip, lcm-logplayer);" \
       "testing the subscriber through LCM's file:// provider instead"
  "$VPY" "$EXAMPLES/print_tracks.py" --url "file://$OUT/tracks.lcmlog?speed=0" --json \
    >"$OUT/got.jsonl" 2>"$OUT/sub.err" || { cat "$OUT/sub.err" >&2; fail "print_tracks.py failed"; }
fi
"$PYTHON" "$HERE/compare_tracks.py" "$OUT/got.jsonl" "$OUT/tracks.jsonl"

# Human-readable output, --count, and --timeout without a publisher (exit 1 with a message).
"$VPY" "$EXAMPLES/print_tracks.py" --url "file://$OUT/tracks.lcmlog?speed=0" --count 2 \
  >"$OUT/human.txt" 2>"$OUT/human.err" || { cat "$OUT/human.err" >&2; fail "print_tracks.py (human) failed"; }
[ "$(grep -c '^frame ' "$OUT/human.txt")" -eq 2 ] || fail "--count 2 printed another number of frames"
expect_exit 1 "$OUT/timeout.txt" "$VPY" "$EXAMPLES/print_tracks.py" --url "memq://" --timeout 0.3
expect_grep "no message for 0.3 s \(0 received\)" "$OUT/timeout.txt"
expect_exit 2 "$OUT/usage.txt" "$VPY" "$EXAMPLES/print_tracks.py" --count -1
echo "print_tracks: ok"
