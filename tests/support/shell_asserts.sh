# Shell assertion helpers shared by the CTest scripts (sourced by tests/*/common.sh).

fail() {
  echo "FAIL: $*" >&2
  exit 1
}

# expect_exit CODE LOG CMD...: runs CMD with stdout and stderr into LOG and requires exit CODE.
expect_exit() {
  local want=$1 log=$2
  shift 2
  local got=0
  "$@" >"$log" 2>&1 || got=$?
  if [ "$got" -ne "$want" ]; then
    echo "--- output of: $*" >&2
    cat "$log" >&2
    fail "exit status $got, expected $want: $*"
  fi
}

# expect_grep REGEX FILE: FILE must contain a line matching the extended REGEX.
expect_grep() {
  if ! grep -qE -- "$1" "$2"; then
    echo "--- $2:" >&2
    cat "$2" >&2
    fail "no line matching '$1' in $2"
  fi
}

# expect_eq ACTUAL EXPECTED MESSAGE
expect_eq() {
  [ "$1" = "$2" ] || fail "$3: got '$1', expected '$2'"
}

# expect_ge ACTUAL MIN MESSAGE
expect_ge() {
  [ "$1" -ge "$2" ] || fail "$3: got $1, expected >= $2"
}
