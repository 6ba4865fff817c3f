#!/usr/bin/env bash
# Tracking with the project's own detector: pf2_slam with --detector learned on real sequences
# (../shared/data when present: the Bonn crowd frames, TUM fr1/rpy) and on pf2_synth sequences with
# three people made hard on purpose (every camera motion, depth misaligned 3 px with motion blur,
# people close to the camera and cut by the border), next to the ground-truth oracle
# (--detector gt, synthetic only). Prints one markdown row per run: ATE RMSE and max, frames posed
# (tracked, bridged, relocalised) and lost, end-to-end fps.
#
# Usage: bench/slam/no_oracle_benchmark.sh [BUILD_DIR] [WORK_DIR] [FRAMES] [DATA_DIR]
# Extra pf2_slam settings: PF2_BENCH_CONFIG=FILE (a --config file used by every run).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${1:-$root/build}"
work="${2:-/tmp/pf2_no_oracle}"
frames="${3:-300}"
data="${4:-$root/../shared/data}"
mkdir -p "$work"

source "$root/bench/bench_lib.sh"

config_args=()
[ -n "${PF2_BENCH_CONFIG:-}" ] && config_args=(--config "$PF2_BENCH_CONFIG")

# run NAME SEQUENCE DETECTOR [GT_FORMAT]: one pf2_slam run and its row.
run() {
  local name="$1" sequence="$2" detector="$3" format="${4:-tum}"
  local out="$work/run_${name}_${detector}"
  "$build/apps/pf2_slam" "$sequence" -o "$out" --detector "$detector" --no-map --quiet \
      "${config_args[@]}" >/dev/null
  "$build/apps/pf2_eval" "$sequence/groundtruth.txt" "$out/trajectory.txt" --gt-format "$format" \
      --json | tail -n 1 > "$out/ate.json"
  local label="$detector"
  [ "$detector" = gt ] && label="gt (oracle)"
  local total posed
  total="$(json_field "$out/stats.json" frames)"
  posed="$(json_field "$out/stats.json" tracked)"
  printf '| %s | %s | %s | %.4f | %.4f | %s/%s (%.1f %%) | %s | %s | %s | %.1f |\n' "$name" "$total" "$label" \
    "$(json_field "$out/ate.json" ate_rmse)" "$(json_field "$out/ate.json" ate_max)" "$posed" "$total" \
    "$(echo "100 * $posed / $total" | bc -l)" "$(json_field "$out/stats.json" bridged)" \
    "$(json_field "$out/stats.json" relocalised)" "$(json_field "$out/stats.json" lost)" \
    "$(json_field "$out/stats.json" fps)"
}

synth() {  # synth NAME FRAMES ARGS...: generates the sequence once
  local name="$1" n="$2"
  shift 2
  local sequence="$work/$name"
  [ -f "$sequence/groundtruth.txt" ] || "$build/apps/pf2_synth" "$sequence" --frames "$n" --people 3 \
      --seed 1 --quiet "$@" >/dev/null
  echo "$sequence"
}

echo "| sequence | frames | detector | ATE RMSE (m) | ATE max (m) | posed | bridged | relocalised | lost | fps |"
echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
if [ -d "$data/bonn_crowd_250_150" ]; then
  run bonn_crowd_250_150 "$data/bonn_crowd_250_150" learned
fi
if [ -d "$data/tum_fr1_rpy_120" ]; then
  run tum_fr1_rpy_120 "$data/tum_fr1_rpy_120" learned
fi
cases=(static xyz halfsphere rpy loop misalign3_blur)
"$build/apps/pf2_synth" -h | grep -q -- '--close' && cases+=(close_xyz)
for case in "${cases[@]}"; do
  case "$case" in
    loop) sequence="$(synth loop $((frames * 2)) --camera loop)" ;;
    misalign3_blur) sequence="$(synth xyz_misalign3_blur "$frames" --camera xyz --misalign 3 --blur)" ;;
    close_xyz) sequence="$(synth close_xyz "$frames" --camera xyz --close)" ;;
    *) sequence="$(synth "$case" "$frames" --camera "$case")" ;;
  esac
  run "$(basename "$sequence")" "$sequence" learned
  run "$(basename "$sequence")" "$sequence" gt
done
