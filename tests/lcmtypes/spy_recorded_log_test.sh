# lcm-spy's class path (the launcher's --print-classpath) decodes every channel of a log that
# mvtrackd recorded, to the values the C++ types decode and to what was written.
# Usage: spy_recorded_log_test.sh MVTRACKD MAKE_SIM_LOG DUMP_LOG JAVA LAUNCHER DECODELOG_DIR
#                                 WORK_DIR VERSION SOURCE_DIR
set -euo pipefail
[ $# -eq 9 ] || { echo "usage: $0 MVTRACKD MAKE_SIM_LOG DUMP_LOG JAVA LAUNCHER DECODELOG_DIR WORK VERSION SRC" >&2; exit 2; }
MVTRACKD=$1 MAKE_SIM_LOG=$2 DUMP_LOG=$3 JAVA=$4 LAUNCHER=$5 CLASSES=$6 WORK=$7 VERSION=$8 SRC=$9
# shellcheck source=../support/shell_asserts.sh
. "$SRC/tests/support/shell_asserts.sh"
rm -rf "$WORK"
mkdir -p "$WORK"

# A simulated recording (box mode, 3 cameras: even ones on MVTRACK_DETECTIONS, odd ones on
# MVTRACK_DETECTIONS_<id>), tracked by the daemon with its example configuration; a short
# status period so the recording holds status messages.
"$MAKE_SIM_LOG" "$WORK/sim" --mode boxes --frames 90 >"$WORK/sim.log" 2>&1 ||
  { cat "$WORK/sim.log" >&2; fail "make_sim_log failed"; }
sed -E 's/^( *status_period_s:) *[0-9.]+/\1 0.05/; s/^( *level:) *info/\1 warn/' \
  "$SRC/docs/examples/mvtrackd.yaml" >"$WORK/mvtrackd.yaml"
grep -q "status_period_s: 0.05" "$WORK/mvtrackd.yaml" || fail "status_period_s not found in the example config"
"$MVTRACKD" --config "$WORK/mvtrackd.yaml" --calibration "$WORK/sim/calibration.yaml" \
  --input-log "$WORK/sim/detections.lcmlog" --record "$WORK/recorded.lcmlog" \
  --tracks-jsonl "$WORK/tracks.jsonl" >"$WORK/daemon.log" 2>&1 ||
  { cat "$WORK/daemon.log" >&2; fail "mvtrackd failed"; }

# The C++ decode of the recording and of the input.
"$DUMP_LOG" "$WORK/recorded.lcmlog" "$WORK/recorded.dump" --channels "$WORK/channels.txt"
"$DUMP_LOG" "$WORK/sim/detections.lcmlog" "$WORK/input.dump"
cat "$WORK/channels.txt"
for want in "MVTRACK_DETECTIONS camera_detections_t" "MVTRACK_DETECTIONS_1 camera_detections_t" \
            "MVTRACK_TRACKS tracks3d_t" "MVTRACK_TRACKS_NOW tracks3d_t" \
            "MVTRACK_STATUS tracker_status_t"; do
  expect_grep "^$want [0-9]+$" "$WORK/channels.txt"
done

# Java, with exactly the launcher's class path (plus DecodeLog's directory): every event decodes
# (types found by fingerprint as lcm-spy finds them), re-encodes to the same bytes, and dumps
# identically to C++.
classpath=$("$LAUNCHER" --print-classpath)
"$JAVA" -XX:TieredStopAtLevel=1 -cp "$classpath:$CLASSES" DecodeLog --expected "$WORK/recorded.dump" \
  "$WORK/recorded.lcmlog" >"$WORK/java.dump" 2>"$WORK/java.err" ||
  { cat "$WORK/java.err" >&2; fail "DecodeLog on lcm-spy's class path failed"; }
cat "$WORK/java.err"

# The values are what was written.
python3 "$SRC/tests/lcmtypes/check_recorded_dump.py" "$WORK/recorded.dump" "$WORK/input.dump" \
  "$WORK/tracks.jsonl" "$VERSION"
echo "spy_decodes_recorded_log: ok"
