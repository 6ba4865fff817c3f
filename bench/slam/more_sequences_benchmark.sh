#!/usr/bin/env bash
# Camera tracking with the project's own detector (--detector learned) on pf2_synth sequences
# beyond the headline's seed-1 set: other seeds, four and five people (close people who fill half
# the view, nearer than the sensor's range), blur, misalignment, people close on rpy and halfsphere
# paths. ATE against the sequences' ground truth and the frames' status. Repeatable runs (the back
# end in the front end's thread), map off, bodies off.
#
# Usage: bench/slam/more_sequences_benchmark.sh [BUILD_DIR] [WORK_DIR]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${1:-$root/build}"
work="${2:-/tmp/pf2_more_sequences}"
mkdir -p "$work"
source "$root/bench/bench_lib.sh"

# name: pf2_synth options (commas for spaces)
sequences=(
  "p5_xyz_s7:--people,5,--camera,xyz,--seed,7"
  "p5_halfsphere_s8:--people,5,--camera,halfsphere,--seed,8"
  "p5_static_s14:--people,5,--camera,static,--seed,14"
  "close_rpy_s9:--close,--camera,rpy,--seed,9"
  "close_blur_halfsphere_s13:--close,--blur,--camera,halfsphere,--seed,13"
  "blur_halfsphere_s10:--blur,--camera,halfsphere,--seed,10"
  "misalign2_rpy_s11:--misalign,2,--camera,rpy,--seed,11"
  "loop_s12:--camera,loop,--seed,12,--frames,450"
  "p5_xyz_s21:--people,5,--camera,xyz,--seed,21"
  "p5_halfsphere_s22:--people,5,--camera,halfsphere,--seed,22"
  "p5_rpy_s23:--people,5,--camera,rpy,--seed,23"
  "p5_static_s24:--people,5,--camera,static,--seed,24"
  "p5_close_xyz_s25:--people,5,--camera,xyz,--close,--seed,25"
  "p4_loop_s26:--people,4,--camera,loop,--seed,26,--frames,450"
)

echo "machine: $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)"
echo
echo "| sequence | frames | ATE RMSE (mm) | ATE max (mm) | posed | bridged | relocalised | lost |"
echo "| --- | --- | --- | --- | --- | --- | --- | --- |"
for entry in "${sequences[@]}"; do
  name="${entry%%:*}" options="${entry#*:}"
  sequence="$work/$name"
  # shellcheck disable=SC2086
  [ -f "$sequence/groundtruth.txt" ] || "$build/apps/pf2_synth" "$sequence" ${options//,/ } --quiet >/dev/null
  run="$work/run_$name"
  "$build/apps/pf2_slam" "$sequence" -o "$run" --detector learned --no-map --no-bodies --quiet \
      --set tracker.asynchronous_backend=false >/dev/null
  "$build/apps/pf2_eval" "$sequence/groundtruth.txt" "$run/trajectory.txt" --json | tail -n 1 > "$run/ate.json"
  s="$run/stats.json"
  printf '| %s | %s | %.1f | %.1f | %s/%s | %s | %s | %s |\n' "$name" "$(json_field "$s" frames)" \
    "$(awk "BEGIN {print 1000 * $(json_field "$run/ate.json" ate_rmse)}")" \
    "$(awk "BEGIN {print 1000 * $(json_field "$run/ate.json" ate_max)}")" \
    "$(json_field "$s" tracked)" "$(json_field "$s" frames)" "$(json_field "$s" bridged)" \
    "$(json_field "$s" relocalised)" "$(json_field "$s" lost)"
done
