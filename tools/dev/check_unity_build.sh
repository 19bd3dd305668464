#!/usr/bin/env bash
# The release preset compiles in unity batches (CMAKE_UNITY_BUILD: README command 1
# builds in about half the time), where two .cc files of one library that each define the same
# name in their anonymous namespace no longer compile. The other presets build file by file and
# would not notice, so this check (CTest build/unity) configures the release build's sources
# as unity batches with -fsyntax-only (names are checked, no code is generated) and compiles
# every batch of every target the release preset builds, warnings as errors
# (archiving and linking are no-ops: there are no objects).
# Usage: tools/dev/check_unity_build.sh SOURCE_DIR WORK_DIR
set -euo pipefail
src=$1 work=$2
rm -rf "$work"
cmake -S "$src" -B "$work" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE=-fsyntax-only \
  -DCMAKE_UNITY_BUILD=ON -DMVTRACK_WERROR=ON -DMVTRACK_BUILD_TESTS=OFF -DMVTRACK_BUILD_JAVA=OFF \
  -DMVTRACK_MAN_PAGES=OFF -DMVTRACK_BUILD_PICTURES=ON -DCMAKE_CXX_COMPILER_LAUNCHER= \
  -DCMAKE_CXX_ARCHIVE_CREATE=true -DCMAKE_CXX_ARCHIVE_APPEND=true -DCMAKE_CXX_ARCHIVE_FINISH=true \
  -DCMAKE_CXX_LINK_EXECUTABLE=true >"$work.configure.log" 2>&1 ||
  { cat "$work.configure.log" >&2; echo "check_unity_build: configure failed" >&2; exit 1; }
mapfile -t batches < <(ninja -C "$work" -t targets all | grep -o '^[^:]*unity_[0-9]*_cxx\.cxx\.o' | sort -u)
[ ${#batches[@]} -ge 10 ] || { echo "check_unity_build: only ${#batches[@]} unity batches found" >&2; exit 1; }
if ! ninja -C "$work" "${batches[@]}" >"$work.build.log" 2>&1; then
  grep -E 'error|warning' "$work.build.log" | head -40 >&2
  echo "check_unity_build: FAIL: a unity batch does not compile (two files of one target define" \
       "the same name in their anonymous namespaces? share it in a header, or rename one)" >&2
  exit 1
fi
echo "check_unity_build: ${#batches[@]} unity batches compile (-fsyntax-only)"
