#!/usr/bin/env bash
# Test names must not contain ';': catch_discover_tests hands each name to CTest as a CMake
# list, a ';' cuts it, the cut name matches no test case, and the test binary then reports "no
# tests ran" with exit 0, which CTest counts as passed: the test never runs.
# Usage: tools/dev/check_test_names.sh [SOURCE_DIR]
set -euo pipefail
root=${1:-$(cd "$(dirname "$0")/../.." && pwd)}
if grep -rnE 'TEST_CASE\("[^"]*;' "$root/tests"; then
  echo "check_test_names: the TEST_CASE names above contain ';' (use ',' instead)" >&2
  exit 1
fi
echo "check_test_names: ok"
