#!/usr/bin/env bash
# Regenerates docs/images/lcm-spy.png: lcm-spy (through the mvtrack-spy launcher's class path)
# watching a live mvtrack system, with the MVTRACK_TRACKS message view open.
#
# usage: tools/dev/screenshot_lcm_spy.sh [BUILD_DIR] [OUT.png]
#        (defaults: build/dev, docs/images/lcm-spy.png; the build needs the targets mvtrackd,
#        mvtrack_make_sim_log (tests/tools) and mvtrack_lcmtypes_java)
#
# Inside a private network namespace (root: `unshare -n`; nothing leaves the machine, see
# ../shared/TOOLCHAIN.md) and a virtual X server (xvfb-run), on udpm://239.255.76.67:7667?ttl=0:
# lcm-logplayer plays a simulated 3-camera recording (tests/tools/make_sim_log, box mode, even
# cameras on MVTRACK_DETECTIONS, odd ones on MVTRACK_DETECTIONS_<id>) in real time, mvtrackd
# (docs/examples/mvtrackd.yaml, status every 0.5 s) tracks it and publishes MVTRACK_TRACKS and
# MVTRACK_STATUS, and tools/lcm-spy/SpyScreenshot.java runs lcm.spy.Spy, opens the tracks view
# and captures both windows, scaled to 1000 px wide.
set -euo pipefail
src=$(cd "$(dirname "$0")/../.." && pwd)
build=$(cd "${1:-$src/build/dev}" && pwd)
out=$(readlink -f "${2:-$src/docs/images/lcm-spy.png}")

die() { echo "screenshot_lcm_spy: $*" >&2; exit 1; }
mvtrackd=$build/daemon/mvtrackd
make_sim_log=$build/tests/tools/mvtrack_make_sim_log
spy=$build/bin/mvtrack-spy
for f in "$mvtrackd" "$make_sim_log" "$spy"; do
  [ -x "$f" ] || die "$f not found: build mvtrackd, mvtrack_make_sim_log and mvtrack_lcmtypes_java in $build"
done
for t in xvfb-run javac java lcm-logplayer unshare ip; do
  command -v "$t" >/dev/null || die "$t not found (tools/dev/install_deps.sh installs xvfb, the JDK and liblcm-bin)"
done
[ "$(id -u)" -eq 0 ] || die "needs root for the private network namespace (unshare -n)"

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$make_sim_log" "$work/sim" --mode boxes --frames 600 >"$work/sim.log"
sed -E 's/^( *status_period_s:) *[0-9.]+/\1 0.5/; s/^( *level:) *info/\1 warn/' \
  "$src/docs/examples/mvtrackd.yaml" >"$work/mvtrackd.yaml"
javac --release 8 -cp "$("$spy" --print-classpath)" -d "$work/classes" "$src/tools/lcm-spy/SpyScreenshot.java"
classpath="$("$spy" --print-classpath):$work/classes"
mkdir -p "$(dirname "$out")"

export mvtrackd work classpath out
unshare -n bash -c '
  set -euo pipefail
  ip link set lo up
  ip route add 224.0.0.0/4 dev lo
  url="udpm://239.255.76.67:7667?ttl=0"
  "$mvtrackd" --config "$work/mvtrackd.yaml" --calibration "$work/sim/calibration.yaml" \
    >"$work/daemon.log" 2>&1 &
  daemon=$!
  lcm-logplayer -s 1 -l "$url" "$work/sim/detections.lcmlog" >"$work/player.log" 2>&1 &
  player=$!
  status=0
  xvfb-run -a -s "-screen 0 1600x900x24" java -Djava.net.preferIPv4Stack=true -cp "$classpath" \
    SpyScreenshot "$url" "$out" 7000 MVTRACK_TRACKS 1000 || status=$?
  kill "$player" "$daemon" 2>/dev/null || true
  wait "$daemon" 2>/dev/null || true
  exit "$status"
' || { cat "$work/daemon.log" >&2; die "capture failed"; }
echo "screenshot_lcm_spy: wrote $out ($(stat -c %s "$out") bytes)"
