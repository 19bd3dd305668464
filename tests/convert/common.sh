# Sourced by the tests/convert/*_test.sh scripts: strict mode, the arguments every script gets
# (MVTRACK binary, CHECK = mvtrack_convert_check, WORK dir, SRC = repository root), a fresh
# output directory per script, the data root, and small assertion helpers.
set -euo pipefail
if [ $# -ne 4 ]; then
  echo "usage: $0 MVTRACK CHECK WORK_DIR SOURCE_DIR" >&2
  exit 2
fi
MVTRACK=$1
CHECK=$2
WORK=$3
SRC=$4
# shellcheck source=../support/shell_asserts.sh
. "$SRC/tests/support/shell_asserts.sh"
HERE=$(cd "$(dirname "$0")" && pwd)
OUT=$WORK/$(basename "$0" _test.sh)
rm -rf "$OUT"
mkdir -p "$OUT"
# The same rule as datasets::DefaultDataRoot(): $MVTRACK_DATA, else ../shared/data next to the
# repository.
DATA_ROOT=${MVTRACK_DATA:-$SRC/../shared/data}


# require_dataset FOLDER: continue when DATA_ROOT/FOLDER exists; otherwise fail when CI is set,
# else print a skip message and end the script successfully.
require_dataset() {
  if [ -d "$DATA_ROOT/$1" ]; then
    return 0
  fi
  local message="dataset '$1' not found under $DATA_ROOT (set MVTRACK_DATA to the data root)"
  if [ -n "${CI:-}" ]; then
    fail "CI is set and $message"
  fi
  echo "SKIPPED: $message"
  exit 0
}



# expect_fixed TEXT FILE: FILE must contain TEXT literally.
expect_fixed() {
  if ! grep -qF -- "$1" "$2"; then
    echo "--- $2:" >&2
    cat "$2" >&2
    fail "'$1' not found in $2"
  fi
}

# same_outputs DIR_A DIR_B FILES...: the files are byte-identical in both directories.
same_outputs() {
  local a=$1 b=$2
  shift 2
  for f in "$@"; do
    cmp "$a/$f" "$b/$f" || fail "$f differs between $a and $b"
  done
}

# timed NAME CMD...: runs CMD (which must succeed), printing its wall time.
timed() {
  local name=$1
  shift
  local start end
  start=$(date +%s.%N)
  "$@" >"$OUT/$name.log" 2>&1 || { cat "$OUT/$name.log" >&2; fail "$name failed: $*"; }
  end=$(date +%s.%N)
  echo "$name: $(python3 -c "print(f'{$end - $start:.2f}')") s"
}
