#!/usr/bin/env bash
# Trains the shipped moving-object CNN and the models of the m sweep (paper Fig. 6), exactly as
# recorded in models/MODEL.md.
# Usage: scripts/train_models.sh [main|sweep|sweep-real|all] [DATA_DIR] [DLOAM_BINARY]
# DATA_DIR holds the simulated training drives (scripts/make_training_data.sh makes them there).
# main: models/mos_m3.pt from the simulated drives and the real drive REAL (default
#   ../shared/data/kitti-raw-0005), labelled without annotation by `dloam run --clean` (its
#   labels/ are never read for training).
# sweep: the simulated drives alone, m = 0, 1, 2 (models/sweep/) and 6 (models/mos_m6.pt).
# sweep-real: main's recipe for m = 0, 1, 2, 6 (models/sweep/mos_mM_real.pt; m = 3 is main).
set -euo pipefail
what=${1:-all}
data=${2:-$(dirname "$0")/../train/sim}
dloam=${3:-$(dirname "$0")/../build/apps/dloam}
real=${REAL:-$(dirname "$0")/../../shared/data/kitti-raw-0005}
models=$(dirname "$0")/../models
[ -d "$data" ] || "$(dirname "$0")/make_training_data.sh" "$data" "$dloam"
mkdir -p "$models/sweep"
labelled=$(dirname "$data")/real/$(basename "$real")
main_recipe() {  # m, model file
  [ -f "$labelled/clean/metrics.json" ] ||
    "$dloam" run "$real" --config kitti-raw --detector geometric --clean --out "$labelled" --overwrite
  "$dloam" train "$data"/* "$real,run=$labelled,weight=4,config=kitti-raw" --out "$2" \
    --m "$1" --width 8 --epochs 12 --seed 1 --threads 1
}
if [ "$what" = main ] || [ "$what" = all ]; then
  main_recipe 3 "$models/mos_m3.pt"
fi
if [ "$what" = sweep-real ] || [ "$what" = all ]; then
  for m in ${SWEEP_M:-0 1 2 6}; do main_recipe "$m" "$models/sweep/mos_m${m}_real.pt"; done
fi
if [ "$what" = sweep ] || [ "$what" = all ]; then
  # Same data, seed and schedule for every m, so the sweep compares like with like.
  for m in ${SWEEP_M:-0 1 2 6}; do
    out="$models/sweep/mos_m${m}_e8.pt"
    [ "$m" = 6 ] && out="$models/mos_m6.pt"
    "$dloam" train "$data"/* --out "$out" --m "$m" --width 8 --epochs 8 --seed 1 --threads 1
  done
fi
