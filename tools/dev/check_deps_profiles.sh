#!/usr/bin/env bash
# Checks tools/dev/install_deps.sh's profiles (CTest deps/profiles):
#   1. every profile's packages are real Debian packages of this release (no virtual names: a
#      virtual one is never "installed", so install_deps.sh would install it on every run);
#   2. README command 1's profile (`build`) holds none of the packages the later profiles add;
#   3. nothing that `build` pulls in, dependencies of dependencies included (apt-cache depends
#      --recurse, Recommends and Suggests left out as install_deps.sh installs), is a JDK or
#      Java runtime, a browser, an X server, a linter or another package only the tests need.
# Needs apt's package lists (apt-get update); without them it skips (exit 77), and fails when
# the CI variable is set.
# Usage: tools/dev/check_deps_profiles.sh [SOURCE_DIR]
set -euo pipefail
src=${1:-$(cd "$(dirname "$0")/../.." && pwd)}
deps="$src/tools/dev/install_deps.sh"
fail() { echo "check_deps_profiles: FAIL: $*" >&2; exit 1; }
list() { bash "$deps" --list "$1" | sort -u; }
# own PROFILE: the packages of PROFILE's own rows (--list prints the rows in order, the earlier
# profiles' first).
own() {
  local prev="" n=0
  case $1 in build) prev=run ;; pictures) prev=build ;; package) prev=pictures ;; test) prev=package ;; *) prev="" ;; esac
  [ -z "$prev" ] || n=$(bash "$deps" --list "$prev" | wc -l)
  bash "$deps" --list "$1" | tail -n +$((n + 1)) | sort -u
}

if ! apt-cache show --no-all-versions build-essential 2>/dev/null | grep -x 'Package: build-essential' >/dev/null; then
  msg="apt has no package lists (run apt-get update)"
  if [ -n "${CI:-}" ]; then fail "$msg"; fi
  echo "check_deps_profiles: skipped: $msg"
  exit 77
fi

# 1. Real packages.
real=$(apt-cache show --no-all-versions $(list test) 2>/dev/null | sed -n 's/^Package: //p' | sort -u)
not_real=$(comm -23 <(list test) <(echo "$real"))
[ -z "$not_real" ] ||
  fail "not Debian packages here (virtual or misspelt), in install_deps.sh: $(echo $not_real)"
echo "all $(list test | wc -l) packages of the profiles are Debian packages"

# 2. Each package is listed once, and so the demo's list holds none of the later profiles'.
twice=$(bash "$deps" --list test | sort | uniq -d)
[ -z "$twice" ] || fail "listed in more than one row of install_deps.sh: $(echo $twice)"

# 3. The closure of the demo's list.
closure=$(apt-cache depends --recurse --no-recommends --no-suggests --no-conflicts --no-breaks \
            --no-replaces --no-enhances $(list build) | grep -v '^ ' | sort -u)
heavy=$(echo "$closure" | grep -E '(^|-)(openjdk|jdk|jre)(-|$)|^default-j|^java|chromium|firefox|^xserver|^xvfb$|^xorg|clang-tidy|clang-format|^shellcheck|^pylint' || true)
[ -z "$heavy" ] || fail "README command 1's packages (profile build) pull in $(echo $heavy)"
# catch2 is the one exception: Debian 12's libspdlog-dev depends on it (a header-only test
# framework, 600 kB).
test_only=$(comm -12 <(echo "$closure") <(own test) | grep -vx catch2 || true)
[ -z "$test_only" ] || fail "profile build pulls in test-only packages: $(echo $test_only)"
echo "profile build: $(list build | wc -l) packages, $(echo "$closure" | wc -l) names with their" \
     "dependencies (alternatives and virtual names counted), none of them a JDK, browser, X server," \
     "linter or test-only package"
