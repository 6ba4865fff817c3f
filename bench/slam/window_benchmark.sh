#!/usr/bin/env bash
# Robustness on real people beyond one fixed stretch: pf2_slam with its own detector (learned) on
# windows of a recorded sequence (each window a TUM folder of its own, so every run starts where
# the window starts, in the crowd or not), each run REPEATS times (the back end's and the
# detector's threads make runs differ slightly). Prints per window the median and the largest ATE
# RMSE and the fewest frames posed over the repeats, then the same over all windows.
#
# Usage: bench/slam/window_benchmark.sh [BUILD_DIR] [WORK_DIR] [SEQUENCE_DIR] [REPEATS] [WINDOWS]
# WINDOWS: space-separated FIRST:END frame ranges (default "0:100 25:125 50:150 0:75 75:150 0:150").
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${1:-$root/build}"
work="${2:-/tmp/pf2_windows}"
sequence="$(cd "${3:-$root/../shared/data/bonn_crowd_250_150}" && pwd)"
repeats="${4:-3}"
windows="${5:-0:100 25:125 50:150 0:75 75:150 0:150}"
mkdir -p "$work"
source "$root/bench/bench_lib.sh"

# window FIRST END: a TUM folder holding frames [FIRST, END) of the sequence (lists cut, images
# and the rest linked); prints its path.
window() {
  local dir="$work/window_$1_$2"
  mkdir -p "$dir"
  for entry in "$sequence"/*; do
    case "$(basename "$entry")" in rgb.txt | depth.txt) ;; *) ln -sfn "$entry" "$dir/" ;; esac
  done
  for list in rgb.txt depth.txt; do
    { grep '^#' "$sequence/$list" || true; grep -v '^#' "$sequence/$list" | sed -n "$(($1 + 1)),$2p"; } > "$dir/$list"
  done
  echo "$dir"
}

# median / largest of the ATE values given as arguments (metres), in centimetres.
median_cm() { printf '%s\n' "$@" | sort -g | awk '{a[NR] = $1} END {print 100 * a[int((NR + 1) / 2)]}'; }
largest_cm() { printf '%s\n' "$@" | sort -g | tail -n 1 | awk '{print 100 * $1}'; }

echo "machine: $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg); $repeats runs per window, learned detector"
echo
echo "| frames | ATE RMSE median (cm) | ATE RMSE largest (cm) | fewest frames posed |"
echo "| --- | --- | --- | --- |"
all=()
for spec in $windows; do
  first="${spec%%:*}" end="${spec#*:}"
  dir="$(window "$first" "$end")"
  ates=() fewest=""
  for ((r = 1; r <= repeats; ++r)); do
    out="$work/run_${first}_${end}_$r"
    "$build/apps/pf2_slam" "$dir" -o "$out" --detector learned --no-map --no-bodies --quiet >/dev/null
    "$build/apps/pf2_eval" "$sequence/groundtruth.txt" "$out/trajectory.txt" --json | tail -n 1 > "$out/ate.json"
    ates+=("$(json_field "$out/ate.json" ate_rmse)")
    posed="$(json_field "$out/stats.json" tracked)/$(json_field "$out/stats.json" frames)"
    if [ -z "$fewest" ] || [ "${posed%/*}" -lt "${fewest%/*}" ]; then fewest="$posed"; fi
  done
  all+=("${ates[@]}")
  printf '| %s-%s | %.2f | %.2f | %s |\n' "$first" "$((end - 1))" "$(median_cm "${ates[@]}")" \
    "$(largest_cm "${ates[@]}")" "$fewest"
done
printf '| all windows | %.2f | %.2f | |\n' "$(median_cm "${all[@]}")" "$(largest_cm "${all[@]}")"
