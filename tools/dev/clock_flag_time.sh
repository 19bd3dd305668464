#!/usr/bin/env bash
# Measures how soon the clock model flags a broken camera live (issue 14's target: within 2 s):
# a simulated 30 fps recording of 3 cameras with camera 0's clock skewed (+2 s, +250 ms) or its
# frame counter running ten times fast from frame 10 on (tests/daemon/make_clock_log.cc) is
# played in real time over udpm inside a private network namespace (needs root); the time from
# the fault's start to the daemon's CLOCK_OFFSET warning is printed.
#
# Usage: tools/dev/clock_flag_time.sh [--build-dir DIR]   (default build/ci)
set -euo pipefail
cd "$(dirname "$0")/../.."
build=build/ci
case ${1:-} in
  --build-dir) build=$2 ;;
  -h|--help) sed -n '2,8p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
  "") ;;
  *) echo "clock_flag_time: unknown argument $1 (see --help)" >&2; exit 2 ;;
esac
for p in daemon/mvtrackd tools/mvtrack tests/daemon/mvtrack_make_clock_log; do
  [ -x "$build/$p" ] || { echo "clock_flag_time: $build/$p not found (build first)" >&2; exit 2; }
done
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$build/tools/mvtrack" sim --out "$work/sim" --cameras 3 --people 3 --frames 150 --mode poses \
  --seed 5 2> /dev/null
URL="udpm://239.255.76.67:7667?ttl=0"
printf 'format: mvtrack.daemon/1\ncameras:\n  calibration: %s\ninput:\n  lcm_url: "%s"\ntracker:\n  mode: poses\n' \
  "$work/sim/calibration.yaml" "$URL" > "$work/daemon.yaml"
daemon=$(realpath "$build/daemon/mvtrackd")
export daemon work URL
for kind in skew:2000000 skew:250000 fast_counter; do
  "$build/tests/daemon/mvtrack_make_clock_log" "$work/sim/detections.lcmlog" "$work/fault.lcmlog" "$kind"
  unshare -n bash -euc '
    ip link set lo up
    ip route add 224.0.0.0/4 dev lo
    "$daemon" --config "$work/daemon.yaml" > "$work/daemon.log" 2>&1 &
    pid=$!
    for _ in $(seq 100); do grep -q "input udpm" "$work/daemon.log" && break; sleep 0.1; done
    date +%s.%N > "$work/start"
    lcm-logplayer --lcm-url="$URL" -s 1 "$work/fault.lcmlog" > /dev/null
    kill -TERM $pid
    wait $pid
  '
  python3 - "$work/daemon.log" "$work/start" "$kind" << 'EOF'
import datetime, sys
start = float(open(sys.argv[2]).read())
for line in open(sys.argv[1]):
    if "off the other cameras" in line:
        t = datetime.datetime.strptime(line[1:24], "%Y-%m-%dT%H:%M:%S.%f").replace(
            tzinfo=datetime.timezone.utc).timestamp()
        # the fault starts at frame 10 of the 30 fps recording
        print(f"{sys.argv[3]}: flagged {t - start - 10 / 30:.2f} s after the fault began")
        break
else:
    print(f"{sys.argv[3]}: never flagged")
EOF
done
