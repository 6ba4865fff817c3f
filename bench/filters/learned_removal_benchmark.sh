#!/usr/bin/env bash
# Person removal with the project's own detector (learned), per hard case: pf2_synth sequences with
# three people (a seated person and people cut by the border in the static view, every camera
# motion, depth misaligned 3 px with motion blur, people close to the camera), the filter as
# pf2_slam runs it (backend masks, box rule within 20 px of a mask, temporal guard) without and
# with the geometric addition (depth in front of the farthest static depth seen so far, pf2_detect's
# stand-in for the keyframe prediction pf2_slam uses; it moves its model with groundtruth.txt).
# Prints recall (person depth removed), precision and retention (static depth kept).
#
# Usage: bench/filters/learned_removal_benchmark.sh [BUILD_DIR] [WORK_DIR] [FRAMES]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${1:-$root/build}"
work="${2:-/tmp/pf2_no_oracle}"
frames="${3:-300}"
mkdir -p "$work"
source "$root/bench/bench_lib.sh"

synth() {  # synth NAME ARGS...: generates the sequence once, prints its folder
  local name="$1"
  shift
  [ -f "$work/$name/groundtruth.txt" ] || "$build/apps/pf2_synth" "$work/$name" --frames "$frames" \
      --people 3 --seed 1 --quiet "$@" >/dev/null
  echo "$work/$name"
}

row() {  # row CASE SEQUENCE LABEL OPTIONS...
  local case="$1" sequence="$2" label="$3"
  shift 3
  removal_row "$case" "$label" \
    "$("$build/apps/pf2_detect" "$sequence" "$work/removal_${case}" --detector learned --json "$@" | tail -n 1)"
}

echo "| case | filter | person depth removed (recall %) | precision % | static depth kept (retention %) | filter ms |"
echo "| --- | --- | --- | --- | --- | --- |"
cases=("static:--camera static" "xyz:--camera xyz" "halfsphere:--camera halfsphere" "rpy:--camera rpy"
       "xyz_misalign3_blur:--camera xyz --misalign 3 --blur")
"$build/apps/pf2_synth" -h | grep -q -- '--close' && cases+=("close_xyz:--camera xyz --close")
slam_filter=(--use-mask --mask-reach 20 --temporal)
for spec in "${cases[@]}"; do
  name="${spec%%:*}"
  read -r -a args <<< "${spec#*:}"
  sequence="$(synth "$name" "${args[@]}")"
  row "$name" "$sequence" "paper's filter" 
  row "$name" "$sequence" "pf2_slam's, no geometric" "${slam_filter[@]}"
  row "$name" "$sequence" "pf2_slam's + geometric" "${slam_filter[@]}" --geometric
done
