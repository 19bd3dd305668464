#!/usr/bin/env bash
# README command 2: install what is missing, build (warnings as errors), run every test.
# Usage: tools/dev/test.sh [preset]   (default: ci; also dev, asan, tsan)
set -euo pipefail
cd "$(dirname "$0")/../.."
preset=${1:-ci}
tools/dev/install_deps.sh test
# ccache (the presets' compiler launcher): share hits between clones of the repository.
export CCACHE_BASEDIR="$PWD" CCACHE_NOHASHDIR=true
cmake --preset "$preset" >/dev/null
cmake --build --preset "$preset"
ctest --preset "$preset" -j "$(nproc)"
