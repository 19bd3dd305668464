#!/usr/bin/env bash
# README command 1: install what is missing, build, and run the main job on data the project
# generates itself: a simulated 3-camera scene of 3 walking people, tracked, with accuracy.
set -euo pipefail
cd "$(dirname "$0")/../.."
tools/dev/install_deps.sh
export CCACHE_BASEDIR="$PWD" CCACHE_NOHASHDIR=true
cmake --preset release >/dev/null
cmake --build --preset release --target mvtrack
exec build/release/tools/mvtrack demo "$@"
