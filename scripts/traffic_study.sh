#!/usr/bin/env bash
# How much does traffic cost the odometry, and how much of it does the detector win back?
# For each seed: the same simulated street without road users (traffic 0) and with heavy traffic,
# run with --detector none on both and with the geometric detector on the heavy one; and, as the
# perfect detector's reference, `none` on the heavy one with its labelled moving points deleted
# (--drop-labelled-moving).
# Usage: scripts/traffic_study.sh WORK_DIR [SCENARIO] [TRAFFIC] [FRAMES] [PRESET] [SEEDS...]
# Prints one row per seed (t_rel % over 10..50 m, per-frame translation RPE in mm, MOS IoU %) and
# the means. Deterministic: the same arguments give the same table. DETECTOR=cnn scores the CNN
# instead of the geometric detector.
set -euo pipefail
work=${1:?usage: traffic_study.sh WORK_DIR [SCENARIO] [TRAFFIC] [FRAMES] [PRESET] [SEEDS...]}
scenario=${2:-urban}
traffic=${3:-3}
frames=${4:-200}
preset=${5:-HDL-64E}
shift $(($# < 5 ? $# : 5))
seeds=${*:-11 12 13 14 15 16 17 18 19 20}
dloam=${DLOAM:-$(dirname "$0")/../build/apps/dloam}
detector=${DETECTOR:-geometric}
mkdir -p "$work"
: >"$work/runs.log"  # progress and messages of every run

# t_rel (%) and translation RPE (mm) of a run against its drive's ground truth.
score() {
  "$dloam" eval odometry "$1/poses.txt" "$2/poses.txt" --calib "$1/calib.txt" --lengths 10,20,30,40,50 |
    awk '$1 == "all" {t = $3} /RPE per frame/ {gsub("[^0-9.]", "", $6); r = $6 * 1000} END {printf "%.4f %.1f", t, r}'
}
iou() { "$dloam" eval mos "$1/labels" "$2/labels" | awk '/points +IoU/ {printf "%.1f", $3 * 100}'; }

row='%-5s %17s / %6s %17s / %6s %17s / %6s %8s %17s / %6s\n'
head='%-5s %26s %26s %26s %8s %26s\n'
printf "$head" seed "none, traffic 0" "none, traffic $traffic" "$detector, traffic $traffic" "MOS IoU" \
  "none, movers deleted"
printf "$head" "" "t_rel % / RPE mm" "t_rel % / RPE mm" "t_rel % / RPE mm" "%" "t_rel % / RPE mm"
sensor=(--preset "$preset")
rows=()
for seed in $seeds; do
  for t in 0 "$traffic"; do
    d="$work/$scenario-s$seed-t$t"
    [ -f "$d/poses.txt" ] || "$dloam" simulate --scenario "$scenario" --frames "$frames" --seed "$seed" \
      --traffic "$t" --preset "$preset" --out "$d" >/dev/null 2>>"$work/runs.log"
  done
  d="$work/$scenario-s$seed-t$traffic"  # the drive in traffic
  "$dloam" run "$work/$scenario-s$seed-t0" --overwrite --out "$work/o-s$seed-t0-none" --detector none "${sensor[@]}" \
    >/dev/null 2>>"$work/runs.log"
  for det in none "$detector"; do
    "$dloam" run "$d" --overwrite --out "$work/o-s$seed-t$traffic-$det" --detector "$det" "${sensor[@]}" \
      >/dev/null 2>>"$work/runs.log"
  done
  "$dloam" run "$d" --overwrite --out "$work/o-s$seed-t$traffic-oracle" --detector none --drop-labelled-moving \
    "${sensor[@]}" >/dev/null 2>>"$work/runs.log"
  a=$(score "$work/$scenario-s$seed-t0" "$work/o-s$seed-t0-none")
  b=$(score "$d" "$work/o-s$seed-t$traffic-none")
  c=$(score "$d" "$work/o-s$seed-t$traffic-$detector")
  m=$(iou "$d" "$work/o-s$seed-t$traffic-$detector")
  o=$(score "$d" "$work/o-s$seed-t$traffic-oracle")
  rows+=("$seed $a $b $c $m $o")
  printf "$row" $seed $a $b $c $m $o
done
printf "%s\n" "${rows[@]}" | awk -v row="$row" '{for (i = 2; i <= 10; ++i) s[i] += $i; n++}
  END {printf row, "mean", sprintf("%.4f", s[2]/n), sprintf("%.1f", s[3]/n), sprintf("%.4f", s[4]/n),
       sprintf("%.1f", s[5]/n), sprintf("%.4f", s[6]/n), sprintf("%.1f", s[7]/n), sprintf("%.1f", s[8]/n),
       sprintf("%.4f", s[9]/n), sprintf("%.1f", s[10]/n)}'
