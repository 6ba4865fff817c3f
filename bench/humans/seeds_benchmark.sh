#!/usr/bin/env bash
# How general the person tracks and bodies are: the three track targets of docs/BENCHMARKS.md
# (track RMSE <= 5 cm against the true pelvis, 0 identity switches, as many tracks as people)
# on pf2_synth sequences of many seeds, not only seed 1 (bodies_benchmark.sh). For each seed and
# camera (static, xyz, halfsphere; 3 people, made here when missing) pf2_slam runs with the
# learned detector in its repeatable mode (back end and bodies in the front end's thread, so a
# run gives the same figures every time) and pf2_humans_eval scores it. Prints one row per run and
# then per group of five seeds the sums the headline quotes: track RMSE, MPJPE mean, identity
# switches, tracks, and the runs meeting all three targets.
#
# Usage: bench/humans/seeds_benchmark.sh [BUILD_DIR] [WORK_DIR] [FIRST_SEED] [LAST_SEED] [FRAMES]
# Defaults: build, /tmp/pf2_seeds, seeds 1-10, 300 frames. About 20 s per run on two cores.
# Extra pf2_slam settings: PF2_BENCH_CONFIG=FILE (a --config file used by every run, e.g. the line
# `detector.segmenter rvm`).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${1:-$root/build}"
work="${2:-/tmp/pf2_seeds}"
first="${3:-1}"
last="${4:-10}"
frames="${5:-300}"
[[ "$first" =~ ^[0-9]+$ && "$last" =~ ^[0-9]+$ && "$frames" =~ ^[0-9]+$ ]] ||
  { echo "seeds_benchmark.sh: FIRST_SEED, LAST_SEED and FRAMES must be whole numbers" >&2; exit 1; }
(( first >= 1 && first <= last )) || { echo "seeds_benchmark.sh: need 1 <= FIRST_SEED <= LAST_SEED" >&2; exit 1; }
for tool in apps/pf2_synth apps/pf2_slam bench/humans/pf2_humans_eval; do
  [ -x "$build/$tool" ] || { echo "seeds_benchmark.sh: $build/$tool not built" >&2; exit 1; }
done
mkdir -p "$work"
source "$root/bench/bench_lib.sh"
config_args=()
[ -n "${PF2_BENCH_CONFIG:-}" ] && config_args=(--config "$PF2_BENCH_CONFIG")
rows="$(mktemp "$work/rows.XXXXXX")"  # one line per run, for the sums; gone however the script ends
trap 'rm -f "$rows"' EXIT

echo "machine: $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)"
echo
echo "| seed | camera | track RMSE (cm) | id switches | tracks (3 people) | MPJPE mean (mm) | all three met |"
echo "| --- | --- | --- | --- | --- | --- | --- |"
for seed in $(seq "$first" "$last"); do
  for camera in static xyz halfsphere; do
    sequence="$work/${camera}_s${seed}_n${frames}"
    [ -f "$sequence/groundtruth.txt" ] || "$build/apps/pf2_synth" "$sequence" --frames "$frames" --people 3 \
        --camera "$camera" --seed "$seed" --quiet >/dev/null
    "$build/apps/pf2_slam" "$sequence" -o "$work/run_${camera}_s${seed}" --detector learned --no-map --quiet \
        --set tracker.asynchronous_backend=false --set bodies.asynchronous=false "${config_args[@]}" >/dev/null
    j="$work/${camera}_s${seed}.json"
    "$build/bench/humans/pf2_humans_eval" "$sequence" "$work/run_${camera}_s${seed}" --json | tail -n 1 > "$j"
    rmse=$(json_field "$j" rmse) switches=$(json_field "$j" id_switches) tracks=$(json_field "$j" tracks)
    met=$(awk -v r="$rmse" -v s="$switches" -v t="$tracks" 'BEGIN { print (r <= 0.05 && s == 0 && t == 3) ? "yes" : "no" }')
    printf '| %s | %s | %.1f | %s | %s | %.0f | %s |\n' "$seed" "$camera" "$(awk -v r="$rmse" 'BEGIN { print 100 * r }')" \
      "$switches" "$tracks" "$(json_field "$j" mpjpe_mean_mm)" "$met"
    echo "$seed $rmse $switches $tracks $(json_field "$j" mpjpe_mean_mm) $met" >> "$rows"
  done
done
echo
echo "| seeds | runs | track RMSE sum (cm) | MPJPE sum (mm) | id switches | tracks (people) | all three met |"
echo "| --- | --- | --- | --- | --- | --- | --- |"
awk '{ g = int(($1 - 1) / 5); n[g]++; r[g] += $2; s[g] += $3; t[g] += $4; m[g] += $5; ok[g] += ($6 == "yes") }
     END { for (g in n) printf "| %d-%d | %d | %.1f | %.0f | %d | %d (%d) | %d of %d |\n", 5 * g + 1, 5 * g + 5, n[g],
           100 * r[g], m[g], s[g], t[g], 3 * n[g], ok[g], n[g] }' "$rows" | sort -t'|' -k2,2n
