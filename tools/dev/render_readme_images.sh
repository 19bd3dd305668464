#!/usr/bin/env bash
# Regenerates the README pictures in docs/images/ (each must stay under 300 KB):
#   shelf_view.png       Shelf frame 450: `mvtrack convert shelf`, tracked by `mvtrack replay`
#                        (BODY25 poses), drawn by `mvtrack view` with the detections
#   store_view.png       a simulated store (`mvtrack sim`: 6 ceiling cameras, 10 people entering
#                        and leaving, boxes), tracked and drawn the same way, frame 300
#   shelf_coverage.png   `mvtrack calib check` of the Shelf calibration: cameras per floor cell
#                        and the overlap graph
# Usage: tools/dev/render_readme_images.sh [BUILD_DIR]   (default build/release; the mvtrack
# target is built there first). Needs the Shelf data (../shared/data or $MVTRACK_DATA).
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BUILD=${1:-$ROOT/build/release}
cd "$ROOT"
if [ ! -f "$BUILD/CMakeCache.txt" ]; then
  cmake --preset release >/dev/null
  BUILD=$ROOT/build/release
fi
export CCACHE_BASEDIR="$ROOT" CCACHE_NOHASHDIR=true
cmake --build "$BUILD" --target mvtrack >/dev/null
[ -x "$BUILD/tools/mvtrack-pictures" ] || {
  echo "render_readme_images: $BUILD has no mvtrack-pictures (it draws): run" \
       "tools/dev/install_deps.sh pictures, configure again (cmake --preset release), then this" >&2
  exit 1
}
M=$BUILD/tools/mvtrack
OUT=$ROOT/docs/images
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
mkdir -p "$OUT"

# Shelf.
"$M" convert shelf --out "$WORK/shelf" >/dev/null
"$M" replay --calibration "$WORK/shelf/calibration.yaml" --mode poses --layout body25 \
  --jsonl "$WORK/shelf/tracks.jsonl" --quiet "$WORK/shelf/detections.lcmlog" >/dev/null
"$M" view "$WORK/shelf/tracks.jsonl" --calibration "$WORK/shelf/calibration.yaml" \
  --detections "$WORK/shelf/detections.lcmlog" --frame 450 --png "$OUT/shelf_view.png" \
  --title "Shelf: mvtrack replay, BODY25 poses" >/dev/null
"$M" calib check "$WORK/shelf/calibration.yaml" --png "$OUT/shelf_coverage.png" >/dev/null

# Simulated store.
"$M" sim --out "$WORK/store" --cameras 6 --people 10 --frames 450 --mode boxes --layout grid \
  --room 14x8 --enter-leave --quiet >/dev/null
"$M" replay --calibration "$WORK/store/calibration.yaml" --mode boxes \
  --jsonl "$WORK/store/tracks.jsonl" --quiet "$WORK/store/detections.lcmlog" >/dev/null
"$M" view "$WORK/store/tracks.jsonl" --calibration "$WORK/store/calibration.yaml" \
  --detections "$WORK/store/detections.lcmlog" --frame 300 --png "$OUT/store_view.png" \
  --title "Simulated store: mvtrack sim, 6 ceiling cameras, boxes" >/dev/null

for f in shelf_view store_view shelf_coverage; do
  size=$(stat -c %s "$OUT/$f.png")
  echo "render_readme_images: $OUT/$f.png ($size bytes)"
  if [ "$size" -gt 307200 ]; then
    echo "render_readme_images: $f.png is larger than 300 KB" >&2
    exit 1
  fi
done
