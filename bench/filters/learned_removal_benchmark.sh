#!/usr/bin/env bash
# Person removal with the project's own detector (learned), per hard case: pf2_synth sequences with
# three people (a seated person and people cut by the border in the static view, every camera
# motion, depth misaligned 3 px with motion blur, people close to the camera, people seen from a
# camera 2.4 m high). Rows: pf2_slam
# itself (its --masks, scored by pf2_removal_score) with and without the geometric addition (the
# keyframes' prediction, candidates, keep_static); and pf2_detect's filter runs: the paper's
# filter, pf2_slam's filter settings without and with pf2_detect's stand-in for the prediction
# (the farthest static depth seen so far, moved with groundtruth.txt).
# Prints recall (person depth removed), precision and retention (static depth kept). pf2_slam also
# runs with the learned detector's crop masks (detector.crop_masks), with video matting as its mask
# (detector.segmenter rvm), and with both and what the rules beside the masks take given to the
# map alone (--preset offline), that also without the geometric addition; and without the
# geometric addition with the detector's second look at its candidates (detector.candidate_poses).
#
# Usage: bench/filters/learned_removal_benchmark.sh [BUILD_DIR] [WORK_DIR] [FRAMES] [SEED]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${1:-$root/build}"
work="${2:-/tmp/pf2_no_oracle}"
frames="${3:-300}"
seed="${4:-1}"
mkdir -p "$work"
source "$root/bench/bench_lib.sh"

synth() {  # synth NAME ARGS...: generates the sequence once, prints its folder
  local name="$1"
  shift
  [ -f "$work/$name/groundtruth.txt" ] || "$build/apps/pf2_synth" "$work/$name" --frames "$frames" \
      --people 3 --seed "$seed" --quiet "$@" >/dev/null
  echo "$work/$name"
}

row() {  # row CASE SEQUENCE LABEL OPTIONS...
  local case="$1" sequence="$2" label="$3"
  shift 3
  removal_row "$case" "$label" \
    "$("$build/apps/pf2_detect" "$sequence" "$work/removal_${case}" --detector learned --json "$@" | tail -n 1)"
}

# slam_row CASE SEQUENCE LABEL MISALIGN PF2_SLAM_OPTIONS...: pf2_slam with --masks, scored.
slam_row() {
  local case="$1" sequence="$2" label="$3" misalign="$4"
  shift 4
  local out="$work/slam_${case}_$(echo "$label" | tr -c 'a-z0-9' '_')"
  "$build/apps/pf2_slam" "$sequence" -o "$out" --detector learned --no-map --quiet --masks "$@" >/dev/null
  local score filter_ms
  score="$("$build/bench/filters/pf2_removal_score" "$sequence" "$out/masks" --misalign "$misalign" --json)"
  filter_ms="$(grep -o '"filter":{[^}]*}' "$out/stats.json" | grep -o '"median_ms":[0-9.e-]*' | cut -d: -f2)"
  removal_row "$case" "$label" "${score%\}},\"filter_median_ms\":$filter_ms}"
}

echo "| case | filter | person depth removed (recall %) | precision % | static depth kept (retention %) | filter ms |"
echo "| --- | --- | --- | --- | --- | --- |"
cases=("static:--camera static" "xyz:--camera xyz" "halfsphere:--camera halfsphere" "rpy:--camera rpy"
       "xyz_misalign3_blur:--camera xyz --misalign 3 --blur")
"$build/apps/pf2_synth" -h | grep -q -- '--close' && cases+=("close_xyz:--camera xyz --close")
"$build/apps/pf2_synth" -h | grep -q -- '| above' && cases+=("above:--camera above")
slam_filter=(--set filter.use_mask=true --set filter.mask_reach=20 --set filter.temporal=true)
for spec in "${cases[@]}"; do
  name="${spec%%:*}"
  read -r -a args <<< "${spec#*:}"
  sequence="$(synth "${name}_s$seed" "${args[@]}")"
  misalign=0
  [[ "$name" == *misalign3* ]] && misalign=3
  slam_row "$name" "$sequence" "pf2_slam, no geometric" "$misalign" --set filter.geometric=false
  slam_row "$name" "$sequence" "pf2_slam, no geometric, candidate poses" "$misalign" --set filter.geometric=false \
    --set detector.candidate_poses=true
  slam_row "$name" "$sequence" "pf2_slam" "$misalign"
  slam_row "$name" "$sequence" "pf2_slam, crop masks" "$misalign" --set detector.crop_masks=true
  slam_row "$name" "$sequence" "pf2_slam, rvm matte" "$misalign" --set detector.segmenter=rvm
  slam_row "$name" "$sequence" "pf2_slam --preset offline (rvm matte + crop masks, map keeps beside masks)" "$misalign" --preset offline
  slam_row "$name" "$sequence" "pf2_slam --preset offline, no geometric" "$misalign" --preset offline \
    --set filter.geometric=false
  row "$name" "$sequence" "paper's filter" 
  row "$name" "$sequence" "pf2_detect, pf2_slam's settings" "${slam_filter[@]}"
  row "$name" "$sequence" "pf2_detect, + stand-in geometric" "${slam_filter[@]}" --set filter.geometric=true
done
