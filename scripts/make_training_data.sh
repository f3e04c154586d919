#!/usr/bin/env bash
# Simulated SemanticKITTI-layout drives for training the moving-object CNN (see models/MODEL.md).
# Usage: scripts/make_training_data.sh OUT_DIR [DLOAM_BINARY]
# Seeds 101-108 / 201-202 are training seeds: evaluate on other seeds (e.g. urban --seed 1).
set -euo pipefail
out=${1:?usage: make_training_data.sh OUT_DIR [DLOAM_BINARY]}
dloam=${2:-$(dirname "$0")/../build/apps/dloam}
mkdir -p "$out"
sim() {  # name, then simulate options
  local name=$1; shift
  [ -f "$out/$name/poses.txt" ] && return 0
  "$dloam" simulate --out "$out/$name" --overwrite "$@"
}
sim urban-101 --scenario urban --frames 150 --seed 101
sim urban-102 --scenario urban --frames 150 --seed 102 --traffic 2
sim urban-103 --scenario urban --frames 150 --seed 103 --traffic 3 --speed 4
sim urban-104 --scenario urban --frames 150 --seed 104 --traffic 2 --speed 10 --density 2
sim urban-105 --scenario urban --frames 150 --seed 105 --traffic 3 --density 0.5
sim urban-106 --scenario urban --frames 150 --seed 106 --traffic 1.5 --speed 0.5
sim highway-201 --scenario highway --frames 120 --seed 201
sim highway-202 --scenario highway --frames 120 --seed 202 --traffic 2 --speed 18
