# Sourced by the tests/daemon/*_test.sh scripts: strict mode, the arguments every script gets
# (MVTRACKD and MVTRACK binaries, WORK dir holding the fixture recordings, SRC = repository
# root, and the clock-fault log writer), a fresh output directory per script, a daemon config
# writer and small helpers.
set -euo pipefail
if [ $# -lt 4 ] || [ $# -gt 5 ]; then
  echo "usage: $0 MVTRACKD MVTRACK WORK_DIR SOURCE_DIR [MAKE_CLOCK_LOG]" >&2
  exit 2
fi
MVTRACKD=$1
MVTRACK=$2
WORK=$3
SRC=$4
MAKE_CLOCK_LOG=${5:-}
# shellcheck source=../support/shell_asserts.sh
. "$SRC/tests/support/shell_asserts.sh"
OUT=$WORK/out/$(basename "$0" _test.sh)
rm -rf "$OUT"
mkdir -p "$OUT"
P=$WORK/poses

# write_config FILE [EXTRA YAML LINES...]: a daemon config for the simulated pose recording
# (input memq:// unless --input-log overrides it); extra top-level sections are appended.
write_config() {
  local file=$1
  shift
  {
    echo "format: mvtrack.daemon/1"
    echo "cameras:"
    echo "  calibration: $P/calibration.yaml"
    echo "input:"
    echo "  lcm_url: \"memq://\""
    echo "output:"
    echo "  status_period_s: 0.2"
    echo "tracker:"
    echo "  mode: poses"
    echo "  layout: coco17"
    for line in "$@"; do echo "$line"; done
  } > "$file"
}

# summary_value LOG KEY: the integer after "KEY=" in the daemon's summary lines.
summary_value() {
  local v
  v=$(grep -o "summary: .*" "$1" | grep -o "[ :]$2=[0-9]*" | head -1 | sed 's/.*=//')
  [ -n "$v" ] || fail "$1: no '$2=' in the summary"
  echo "$v"
}

# count_value FILE KEY: the value of "KEY=N" in a key=value file.
count_value() {
  grep "^$2=" "$1" | sed 's/.*=//'
}


# require_netns: exit 77 (skipped, with a message) where separate processes cannot talk over
# udpm:// inside a private network namespace (no lcm-logplayer, no ip tool, no unshare).
require_netns() {
  if ! command -v lcm-logplayer > /dev/null || ! command -v lcm-logger > /dev/null; then
    echo "SKIP: lcm-logplayer/lcm-logger not installed (liblcm-bin)"
    exit 77
  fi
  if ! command -v ip > /dev/null; then
    echo "SKIP: the ip tool (iproute2) is not installed"
    exit 77
  fi
  if ! unshare -n true 2> /dev/null; then
    echo "SKIP: cannot create a private network namespace (needs root and unshare)"
    exit 77
  fi
}

# write_udpm_config FILE URL: a daemon config for the simulated pose recording reading URL
# live, blocking (not dropping) when a camera queue is full.
write_udpm_config() {
  {
    echo "format: mvtrack.daemon/1"
    echo "cameras:"
    echo "  calibration: $P/calibration.yaml"
    echo "input:"
    echo "  lcm_url: \"$2\""
    echo "queues:"
    echo "  camera_overflow: block"
    echo "tracker:"
    echo "  mode: poses"
    echo "  layout: coco17"
  } > "$1"
}
