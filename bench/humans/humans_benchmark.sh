#!/usr/bin/env bash
# Human tracking (paper eq. 2-3) against pf2_synth ground truth: pf2_slam's humans.txt scored by
# pf2_humans_eval, for the paper's method and ours, on the static, xyz and halfsphere sequences of
# bench/slam_benchmark.sh (made here if missing), with two detector inputs: ground-truth boxes and
# masks, and ground-truth boxes only, shrunk by 10 % with 10 % of them dropped.
# Rows: "paper" = d_m over all of D_h^t, every person, closest centre of the previous frame;
# "our centres, paper association" = d_m inside the person's depth interval (masked detections),
# no centre for slivers, the paper's association (ids re-associated offline from the "ours" run's
# centres: the ids an online run gives); "ours" = our centres, constant-velocity prediction,
# gated Hungarian, tracks kept 30 frames.
#
# Usage: bench/humans/humans_benchmark.sh [BUILD_DIR] [WORK_DIR] [FRAMES] [PEOPLE]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${1:-$root/build}"
work="${2:-/tmp/pf2_slam_benchmark}"
frames="${3:-300}"
people="${4:-3}"
mkdir -p "$work/humans"

field() {  # field JSON_LINE KEY
  echo "$1" | grep -o "\"$2\":[-0-9.e]*" | cut -d: -f2
}
row() {  # row CAMERA INPUT METHOD JSON_LINE
  printf '| %s | %s | %s | %.3f | %.3f | %.3f | %s | %s | %.3f | %s | %s |\n' "$1" "$2" "$3" \
    "$(field "$4" rmse)" "$(field "$4" median)" "$(field "$4" median_without_offset)" \
    "$(field "$4" id_switches)" "$(field "$4" fragmentations)" "$(field "$4" recall)" \
    "$(field "$4" tracks)" "$(field "$4" unmatched_estimates)"
}

printf 'humans.association paper\nhumans.depth_in_interval false\nhumans.min_area 0\n' > "$work/humans/paper.cfg"
printf 'detector.gt_masks false\ndetector.gt_shrink 0.1\ndetector.gt_drop 0.1\n' > "$work/humans/degraded.cfg"
cat "$work/humans/degraded.cfg" "$work/humans/paper.cfg" > "$work/humans/degraded_paper.cfg"

echo "| camera | detector input | method | RMSE (m) | median (m) | median without offset (m) | id switches | fragmentations | recall | tracks | unmatched centres |"
echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
for camera in static xyz halfsphere; do
  sequence="$work/${camera}_p${people}_n${frames}"
  [ -f "$sequence/groundtruth.txt" ] || "$build/apps/pf2_synth" "$sequence" --frames "$frames" \
      --people "$people" --camera "$camera" --seed 1 >/dev/null
  for input in gt-masks gt-degraded; do
    paper_args=(--config "$work/humans/paper.cfg")
    ours_args=()
    if [ "$input" = gt-degraded ]; then
      paper_args=(--config "$work/humans/degraded_paper.cfg")
      ours_args=(--config "$work/humans/degraded.cfg")
    fi
    out="$work/humans/${camera}_${input}"
    "$build/apps/pf2_slam" "$sequence" -o "$out-paper" --detector gt --no-map --quiet "${paper_args[@]}" >/dev/null
    "$build/apps/pf2_slam" "$sequence" -o "$out-ours" --detector gt --no-map --quiet ${ours_args[@]+"${ours_args[@]}"} >/dev/null
    evaluate() { "$build/bench/humans/pf2_humans_eval" "$sequence" "$@" --json | tail -n 1; }
    row "$camera" "$input" "paper" "$(evaluate "$out-paper")"
    row "$camera" "$input" "our centres, paper association" "$(evaluate "$out-ours" --reassociate paper)"
    row "$camera" "$input" "ours" "$(evaluate "$out-ours")"
  done
done
