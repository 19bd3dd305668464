#!/usr/bin/env bash
# Formats our C++ with the committed .clang-format, pinned to Debian 12's clang-format-14 (another
# version formats differently). Files: every tracked *.h and *.cc (git ls-files), generated code
# lives under build/ and is not tracked.
# Usage: tools/dev/format.sh          rewrite the files in place
#        tools/dev/format.sh --check  change nothing; list the files that differ, exit 1 if any
# With --check (the CTest format/clang_format), a missing clang-format-14 or a tree that is not a
# git checkout skips (exit 77) unless the environment variable CI is set, which makes it fail.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
cd "$root"
tool=clang-format-14
unavailable() {
  echo "format: $1" >&2
  if [ "$check" = 1 ] && [ -z "${CI:-}" ]; then
    echo "SKIPPED (set CI=1 to make this an error)"
    exit 77
  fi
  exit 2
}
check=0
[ "${1:-}" = "--check" ] && check=1
if ! command -v "$tool" >/dev/null; then
  unavailable "$tool not found (Debian package clang-format-14; tools/dev/install_deps.sh)"
fi
if ! git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  unavailable "$root is not a git checkout (the files to format are the tracked ones)"
fi
mapfile -t files < <(git ls-files '*.h' '*.cc')
if [ "$check" = 1 ]; then
  bad=()
  for f in "${files[@]}"; do
    if ! "$tool" --style=file "$f" | cmp -s - "$f"; then bad+=("$f"); fi
  done
  if [ ${#bad[@]} -gt 0 ]; then
    echo "format: ${#bad[@]} of ${#files[@]} files differ from .clang-format ($tool):"
    printf '  %s\n' "${bad[@]}"
    echo "format: run tools/dev/format.sh to fix them"
    exit 1
  fi
  echo "format: all ${#files[@]} files match .clang-format ($tool)"
  exit 0
fi
"$tool" --style=file -i "${files[@]}"
echo "format: formatted ${#files[@]} files with $tool"
