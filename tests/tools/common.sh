# Sourced by the tests/tools/*_test.sh scripts: strict mode, the arguments every script gets
# (MVTRACK binary, WORK dir holding the fixture recordings, SRC = repository root), a fresh
# output directory per script, and small assertion helpers.
set -euo pipefail
if [ $# -ne 3 ]; then
  echo "usage: $0 MVTRACK WORK_DIR SOURCE_DIR" >&2
  exit 2
fi
MVTRACK=$1
WORK=$2
SRC=$3
# shellcheck source=../support/shell_asserts.sh
. "$SRC/tests/support/shell_asserts.sh"
OUT=$WORK/out/$(basename "$0" _test.sh)
rm -rf "$OUT"
mkdir -p "$OUT"

# py ARGS...: python3 started fast: the interpreter itself (python3 may be a version-manager
# shim) without site packages (the scripts use the standard library only).
PYTHON=$(python3 -c 'import sys; print(sys.executable)')
py() {
  "$PYTHON" -S "$@"
}




# json_get FILE PYTHON_EXPR: parses FILE as JSON (fails if it does not parse) and prints the
# expression evaluated with the document bound to `d`.
json_get() {
  py -c 'import json, sys; d = json.load(open(sys.argv[1])); print(eval(sys.argv[2]))' "$1" "$2"
}

# json_assert FILE EXPR MESSAGE [EXPR MESSAGE ...]: parses FILE as JSON (fails if it does not
# parse) and fails with MESSAGE for the first Python EXPR (document bound to `d`) that is false.
json_assert() {
  py - "$@" <<'PY' || fail "$1: see above"
import json, sys
d = json.load(open(sys.argv[1]))
args = sys.argv[2:]
for expr, message in zip(args[0::2], args[1::2]):
    if not eval(expr):
        print("FAIL: %s: %s (%s)" % (sys.argv[1], message, expr), file=sys.stderr)
        sys.exit(1)
PY
}

# float_ge A B: true when the real A >= B.
float_ge() {
  py -c 'import sys; sys.exit(0 if float(sys.argv[1]) >= float(sys.argv[2]) else 1)' "$1" "$2"
}
