#!/usr/bin/env bash
# The main job on an embedded default: simulate a short dynamic urban drive with exact ground
# truth, run the SLAM on it, and evaluate it (and the real KITTI drive when ../shared is there).
#   bash scripts/demo.sh [BUILD_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${1:-build}
DLOAM="$BUILD_DIR/apps/dloam"
OUT=${DLOAM_DEMO_OUT:-out/demo}

"$DLOAM" simulate --scenario urban --frames 100 --seed 7 --out "$OUT/sim-urban" --overwrite
"$DLOAM" run "$OUT/sim-urban" --out "$OUT/run-urban" --overwrite

KITTI=../shared/data/kitti-raw-0005
if [[ -d "$KITTI" ]]; then
  "$DLOAM" run "$KITTI" --out "$OUT/run-kitti-0005" --config config/kitti-raw.yaml --overwrite
fi
echo "demo outputs in $OUT"
