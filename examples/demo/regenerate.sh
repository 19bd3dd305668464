#!/usr/bin/env bash
# Regenerates the bundled demo recording with the project's own simulator. The same command
# always writes byte-identical files (CTest tools/demo_bundle checks that the committed files
# are exactly what it writes).  Usage: examples/demo/regenerate.sh [MVTRACK_BINARY [OUT_DIR]]
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
m="${1:-$here/../../build/release/tools/mvtrack}"
"$m" sim --out "${2:-$here}" --cameras 3 --people 3 --frames 300 --mode poses --seed 1 --quiet
