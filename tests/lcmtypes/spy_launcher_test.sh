#!/usr/bin/env bash
# Tests tools/lcm-spy/mvtrack-spy without a display: help, --print-classpath (every entry
# exists), the exact java command line it execs (through a fake java), and its errors.
# Usage: spy_launcher_test.sh <path to the launcher in the build tree's bin/>
set -euo pipefail
launcher=${1:?usage: spy_launcher_test.sh LAUNCHER}
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
pass() { echo "ok: $*"; }

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# --help
if out=$("$launcher" --help) && grep -q -- "--print-classpath" <<<"$out"; then
  pass "--help exits 0 and documents --print-classpath"
else
  fail "--help"
fi

# --print-classpath: three existing jars, in the order lcm.jar, jchart2d.jar, types jar.
classpath=$("$launcher" --print-classpath) || fail "--print-classpath exited non-zero"
IFS=: read -r -a entries <<<"$classpath"
if [ "${#entries[@]}" -ne 3 ]; then
  fail "class path has ${#entries[@]} entries, want 3: $classpath"
fi
for entry in "${entries[@]}"; do
  if [ -f "$entry" ]; then pass "class path entry exists: $entry"; else fail "missing: $entry"; fi
done
[[ "${entries[0]:-}" == */lcm.jar ]] || fail "first entry is not lcm.jar: ${entries[0]:-}"
[[ "${entries[1]:-}" == */jchart2d.jar ]] || fail "second entry is not jchart2d.jar: ${entries[1]:-}"
[[ "${entries[2]:-}" == */mvtrack_lcmtypes.jar ]] || fail "third entry is not the types jar: ${entries[2]:-}"
types_jar=${entries[2]:-}

# Through a symlink elsewhere the build-tree jar is still found (the script resolves itself).
ln -s "$(readlink -f "$launcher")" "$tmp/spy-link"
if [ "$("$tmp/spy-link" --print-classpath)" = "$classpath" ]; then
  pass "a symlinked launcher finds the same jars"
else
  fail "a symlinked launcher finds different jars"
fi

# --jar / --jar= / MVTRACK_TYPES_JAR select another jar.
cp "$types_jar" "$tmp/other types.jar"
if "$launcher" --jar "$tmp/other types.jar" --print-classpath | grep -q ":$tmp/other types.jar\$" &&
   "$launcher" "--jar=$tmp/other types.jar" --print-classpath | grep -q ":$tmp/other types.jar\$" &&
   MVTRACK_TYPES_JAR="$tmp/other types.jar" "$launcher" --print-classpath |
     grep -q ":$tmp/other types.jar\$"; then
  pass "--jar, --jar= and MVTRACK_TYPES_JAR select the types jar"
else
  fail "--jar / MVTRACK_TYPES_JAR not honoured"
fi

# The command it execs, through a fake java that prints its arguments one per line.
printf '#!/bin/sh\nprintf "%%s\\n" "$@"\n' >"$tmp/fake-java"
chmod +x "$tmp/fake-java"
expected=$(printf '%s\n' -Djava.net.preferIPv4Stack=true -cp "$classpath" lcm.spy.Spy \
  -l 'memq://' --print-classpath)
actual=$(JAVA="$tmp/fake-java" "$launcher" -l 'memq://' -- --print-classpath)
if [ "$actual" = "$expected" ]; then
  pass "execs java -Djava.net.preferIPv4Stack=true -cp <class path> lcm.spy.Spy <args>"
else
  fail "unexpected java command line:"$'\n'"$actual"$'\n'"want:"$'\n'"$expected"
fi

# Errors: non-zero exit and a message naming the problem.
expect_error() {  # expect_error <description> <regex> <command...>
  local what=$1 regex=$2
  shift 2
  local err rc=0
  err=$("$@" 2>&1 >/dev/null) || rc=$?
  if [ "$rc" -ne 0 ] && grep -qE "$regex" <<<"$err"; then
    pass "$what (exit $rc)"
  else
    fail "$what: exit $rc, stderr: $err"
  fi
}
expect_error "--jar to a missing file" "does not exist" \
  "$launcher" --jar "$tmp/nope.jar" --print-classpath
expect_error "--jar without a path" "needs a path" "$launcher" --jar
expect_error "MVTRACK_TYPES_JAR to a missing file" "MVTRACK_TYPES_JAR" \
  env MVTRACK_TYPES_JAR="$tmp/nope.jar" "$launcher" --print-classpath
expect_error "missing lcm.jar" "lcm.jar.*liblcm-java" \
  env MVTRACK_LCM_JAR="$tmp/nope.jar" "$launcher" --print-classpath
expect_error "missing jchart2d.jar" "jchart2d.jar.*libjchart2d-java" \
  env MVTRACK_JCHART2D_JAR="$tmp/nope.jar" "$launcher" --print-classpath
expect_error "missing java" "not found" env JAVA="$tmp/no-java" "$launcher"
# A copy of the launcher far from any build or install tree finds no jar.
mkdir -p "$tmp/a/b"
cp "$launcher" "$tmp/a/b/lonely-spy"
if [ ! -f /usr/share/java/mvtrack_lcmtypes.jar ] &&
   [ ! -f /usr/local/share/java/mvtrack_lcmtypes.jar ]; then
  expect_error "no types jar anywhere" "mvtrack_lcmtypes.jar not found" \
    "$tmp/a/b/lonely-spy" --print-classpath
fi

if [ "$failures" -ne 0 ]; then
  echo "$failures check(s) failed"
  exit 1
fi
echo "all launcher checks passed"
