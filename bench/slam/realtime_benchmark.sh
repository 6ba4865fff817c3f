#!/usr/bin/env bash
# End-to-end speed of pf2_slam on this machine, everything a user's run does (decoding, detection,
# filter, tracking, map, humans, bodies, writing the outputs): the median fps of 3 runs of each
# configuration, interleaved so that a change in the machine's load hits every configuration
# alike, with the load written down before and after. Configurations: the learned detector with
# bodies off and on, and --detector none as the reference of the ratio. Sequences: the real Bonn
# crowd frames (when present) and a pf2_synth sequence with three people (xyz, 300 frames).
#
# Usage: bench/slam/realtime_benchmark.sh [BUILD_DIR] [WORK_DIR] [DATA_DIR] [RUNS]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${1:-$root/build}"
work="${2:-/tmp/pf2_realtime}"
data="${3:-$root/../shared/data}"
runs="${4:-3}"
mkdir -p "$work"
source "$root/bench/bench_lib.sh"

synth="$work/xyz_p3_n300"
[ -f "$synth/groundtruth.txt" ] || "$build/apps/pf2_synth" "$synth" --frames 300 --people 3 --camera xyz \
    --seed 1 --quiet >/dev/null
sequences=("$synth")
[ -f "$data/bonn_crowd_250_150/rgb.txt" ] && sequences=("$data/bonn_crowd_250_150" "${sequences[@]}")
configs=("learned|--no-bodies" "learned|" "none|")

echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//')"
echo "load before: $(cut -d' ' -f1-3 /proc/loadavg)"
declare -A fps
for ((r = 1; r <= runs; ++r)); do
  for sequence in "${sequences[@]}"; do
    for config in "${configs[@]}"; do
      detector="${config%%|*}" extra="${config#*|}"
      out="$work/run"
      rm -rf "$out"
      # shellcheck disable=SC2086
      "$build/apps/pf2_slam" "$sequence" -o "$out" --detector "$detector" --quiet $extra >/dev/null
      key="$(basename "$sequence")|$config"
      fps[$key]="${fps[$key]:-} $(json_field "$out/stats.json" fps)"
    done
  done
done
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"
echo
echo "| sequence | detector | bodies | fps (median of $runs) | runs | ratio to none |"
echo "| --- | --- | --- | --- | --- | --- |"
median() { tr ' ' '\n' | grep -v '^$' | sort -g | awk '{a[NR] = $1} END {print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2}'; }
for sequence in "${sequences[@]}"; do
  name="$(basename "$sequence")"
  reference="$(echo "${fps[$name|none|]}" | median)"
  for config in "${configs[@]}"; do
    detector="${config%%|*}" extra="${config#*|}"
    bodies=on
    [ "$extra" = "--no-bodies" ] && bodies=off
    [ "$detector" = none ] && bodies="—"
    value="$(echo "${fps[$name|$config]}" | median)"
    printf '| %s | %s | %s | %.1f | %s | %.2f |\n' "$name" "$detector" "$bodies" "$value" "${fps[$name|$config]# }" \
      "$(echo "$value / $reference" | bc -l)"
  done
done
