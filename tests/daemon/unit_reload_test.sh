#!/usr/bin/env bash
# The systemd unit's reload works on a minimal system: ExecReload= of systemd/mvtrackd.service
# names only a program of an Essential package (not /bin/kill, which is procps), and run as
# systemd runs it (argv split as systemd does, MAINPID in the environment, no PATH, so no
# program outside the command line is found) against an idle mvtrackd, it reloads the daemon.
source "$(dirname "$0")/common.sh"
UNIT=$SRC/systemd/mvtrackd.service
CFG=$OUT/daemon.yaml
LOG=$OUT/daemon.log
PID=
trap '[ -n "$PID" ] && kill -KILL $PID 2>/dev/null || true' EXIT

line=$(sed -n 's/^ExecReload=//p' "$UNIT")
[ -n "$line" ] || fail "$UNIT has no ExecReload="
[ "$(grep -c '^ExecReload=' "$UNIT")" -eq 1 ] || fail "$UNIT has more than one ExecReload="
# systemd's quoting, for this command line, is the shell's: single quotes keep \$MAINPID for sh.
mapfile -t argv < <(python3 -c 'import shlex, sys; print("\n".join(shlex.split(sys.argv[1])))' "$line")
program=${argv[0]}
case "$program" in
  /*) ;;
  *) fail "ExecReload= runs '$program', not an absolute path" ;;
esac
[ "$program" != /bin/kill ] && [ "$program" != /usr/bin/kill ] ||
  fail "ExecReload= runs $program (procps, not on a minimal system)"
# The program's package is Essential (dpkg knows /bin/sh under its unmerged name).
owner=$(dpkg -S "$program" 2>/dev/null | grep -v '^diversion' | head -1 | cut -d: -f1) || true
[ -n "$owner" ] || owner=$(dpkg -S "${program#/usr}" 2>/dev/null | grep -v '^diversion' | head -1 | cut -d: -f1) || true
[ -n "$owner" ] || fail "no Debian package owns $program (ExecReload=)"
[ "$(dpkg-query -W -f='${Essential}' "$owner")" = yes ] ||
  fail "ExecReload= runs $program of package $owner, which is not Essential"
echo "ExecReload=$line: $program from the Essential package $owner"

write_config "$CFG"
"$MVTRACKD" --config "$CFG" > "$LOG" 2>&1 &
PID=$!
for _ in $(seq 1200); do
  grep -q "input memq://" "$LOG" && break
  kill -0 $PID 2>/dev/null || { cat "$LOG" >&2; fail "mvtrackd died"; }
  sleep 0.1
done
grep -q "input memq://" "$LOG" || { cat "$LOG" >&2; fail "mvtrackd did not start"; }
expect_exit 0 "$OUT/reload.log" env -i MAINPID=$PID "${argv[@]}"
for _ in $(seq 1200); do
  grep -q "configuration reloaded" "$LOG" && break
  sleep 0.1
done
expect_grep "configuration reloaded" "$LOG"
# Without $MAINPID the command fails instead of signalling something else.
if env -i "${argv[@]}" > "$OUT/nopid.log" 2>&1; then
  fail "ExecReload= without MAINPID exited 0"
fi
kill -TERM $PID
rc=0
wait $PID || rc=$?
PID=
expect_eq "$rc" 0 "mvtrackd exit status after SIGTERM"
echo "ok: the unit's reload command reloaded mvtrackd with no PATH"
