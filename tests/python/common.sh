# Sourced by tests/python/*_test.sh: arguments, helpers, the venv, and a small tracks log made by
# `mvtrack replay` from a simulated recording (tests/tools/make_sim_log).
set -euo pipefail
if [ $# -ne 7 ] && [ $# -ne 8 ]; then
  echo "usage: $0 PYTHON VENV_DIR WHEEL MVTRACK MAKE_SIM_LOG WORK_DIR SOURCE_DIR [MVTRACKD]" >&2
  exit 2
fi
PYTHON=$1 VENV=$2 WHEEL=$3 MVTRACK=$4 MAKE_SIM_LOG=$5 WORK=$6 SRC=$7 MVTRACKD=${8:-}
# shellcheck source=../support/shell_asserts.sh
. "$SRC/tests/support/shell_asserts.sh"
# shellcheck source=venv.sh
. "$SRC/tests/python/venv.sh"
HERE=$SRC/tests/python
EXAMPLES=$SRC/examples/python
OUT=$WORK/$(basename "$0" _test.sh)
rm -rf "$OUT"
mkdir -p "$OUT"
ensure_venv "$VENV" "$PYTHON" "$WHEEL"
VPY=$VENV/bin/python

# make_tracks_log: $OUT/sim (detections log, calibration) and $OUT/tracks.lcmlog + tracks.jsonl.
make_tracks_log() {
  "$MAKE_SIM_LOG" "$OUT/sim" --mode poses --frames 60 >"$OUT/sim.log" 2>&1 ||
    { cat "$OUT/sim.log" >&2; fail "make_sim_log failed"; }
  expect_exit 0 "$OUT/replay.log" "$MVTRACK" replay --quiet --calibration "$OUT/sim/calibration.yaml" \
    --mode poses --out "$OUT/tracks.lcmlog" --jsonl "$OUT/tracks.jsonl" "$OUT/sim/detections.lcmlog"
  [ -s "$OUT/tracks.jsonl" ] || fail "replay wrote no tracks"
}
