#!/usr/bin/env bash
# Trains the shipped moving-object CNN and the models of the m sweep (paper Fig. 6), exactly as
# recorded in models/MODEL.md. Usage: scripts/train_models.sh [main|sweep|all] [DATA_DIR] [DLOAM_BINARY]
# DATA_DIR holds the simulated training drives (scripts/make_training_data.sh makes them there).
set -euo pipefail
what=${1:-all}
data=${2:-$(dirname "$0")/../train/sim}
dloam=${3:-$(dirname "$0")/../build/apps/dloam}
models=$(dirname "$0")/../models
[ -d "$data" ] || "$(dirname "$0")/make_training_data.sh" "$data" "$dloam"
mkdir -p "$models/sweep"
if [ "$what" = main ] || [ "$what" = all ]; then
  "$dloam" train "$data"/* --out "$models/mos_m6.pt" --m 6 --width 8 --epochs 8 --seed 1 --threads 1
fi
if [ "$what" = sweep ] || [ "$what" = all ]; then
  # Same data, seed and schedule as the main model (m = 6) for every other m, so the sweep
  # compares like with like; the main model is the sweep's m = 6.
  for m in ${SWEEP_M:-0 1 2}; do
    "$dloam" train "$data"/* --out "$models/sweep/mos_m${m}_e8.pt" --m "$m" --width 8 --epochs 8 --seed 1 --threads 1
  done
fi
