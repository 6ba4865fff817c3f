#!/usr/bin/env bash
# End-to-end benchmark: pf2_slam on pf2_synth sequences with people, for every camera motion,
# with the project's learned detector, with the human filter fed by ground-truth masks and boxes
# (oracle), by ground-truth boxes only (oracle, the paper's input), and without person removal
# (--detector none). Prints one markdown row per run: ATE RMSE, lost frames, end-to-end fps and the
# median per stage.
#
# Usage: bench/slam_benchmark.sh [BUILD_DIR] [WORK_DIR] [FRAMES] [PEOPLE]
# PF2_BENCH_MODES: the inputs to run (default "learned gt-masks gt-boxes none").
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-$root/build}"
work="${2:-/tmp/pf2_slam_benchmark}"
frames="${3:-300}"
people="${4:-3}"
mkdir -p "$work"

source "$root/bench/bench_lib.sh"
stage_median() {  # stage_median STATS_JSON STAGE
  grep -o "\"$2\":{\"count\":[0-9]*,\"median_ms\":[0-9.]*" "$1" | head -n 1 | sed 's/.*median_ms"://'
}

echo "| camera | people | frames | detector | ATE RMSE (m) | ATE max (m) | lost | fps end-to-end | track median (ms) | filter median (ms) |"
echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
for camera in static xyz halfsphere rpy loop; do
  n=$frames
  [ "$camera" = loop ] && n=$((frames * 3))
  sequence="$work/${camera}_p${people}_n${n}"
  [ -f "$sequence/groundtruth.txt" ] || "$build/apps/pf2_synth" "$sequence" --frames "$n" \
      --people "$people" --camera "$camera" --seed 1 >/dev/null
  printf 'detector.gt_masks false\n' > "$work/boxes_only.cfg"
  for mode in ${PF2_BENCH_MODES:-learned gt-masks gt-boxes none}; do
    out="$work/run_${camera}_${mode}"
    case "$mode" in
      gt-masks) args=(--detector gt) ;;
      gt-boxes) args=(--detector gt --config "$work/boxes_only.cfg") ;;
      none) args=(--detector none) ;;
      learned) args=(--detector learned) ;;
    esac
    "$build/apps/pf2_slam" "$sequence" -o "$out" "${args[@]}" --no-map --quiet >/dev/null
    "$build/apps/pf2_eval" "$sequence/groundtruth.txt" "$out/trajectory.txt" --json | tail -n 1 > "$out/ate.json"
    printf '| %s | %s | %s | %s | %.4f | %.4f | %s | %.1f | %.1f | %s |\n' "$camera" "$people" "$n" \
      "$mode$(case "$mode" in gt-*) echo " (oracle)" ;; esac)" "$(json_field "$out/ate.json" ate_rmse)" "$(json_field "$out/ate.json" ate_max)" \
      "$(json_field "$out/stats.json" lost)" "$(json_field "$out/stats.json" fps)" \
      "$(stage_median "$out/stats.json" track)" "$(stage_median "$out/stats.json" filter || echo -)"
  done
done
