#!/usr/bin/env bash
# Camera tracking with the project's own detector (--detector learned) on pf2_synth sequences
# beyond the headline's seed-1 set: other seeds, four and five people (close people who fill half
# the view, nearer than the sensor's range), blur, misalignment, people close on rpy and halfsphere
# paths. ATE against the sequences' ground truth and the frames' status; the people's tracks and
# bodies scored by pf2_humans_eval (tracks against the people in view, identity switches, track
# RMSE against the true pelvis, MPJPE). Repeatable runs (the back end in the front end's thread,
# bodies fitted in the frame's thread), map off; the bodies do not change the camera's poses.
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
echo "| sequence | frames | ATE RMSE (mm) | ATE max (mm) | posed | bridged | relocalised | lost | people in view (half in view) / tracks | switches | track RMSE (cm) | MPJPE (mm) |"
echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
for entry in "${sequences[@]}"; do
  name="${entry%%:*}" options="${entry#*:}"
  sequence="$work/$name"
  # shellcheck disable=SC2086
  [ -f "$sequence/groundtruth.txt" ] || "$build/apps/pf2_synth" "$sequence" ${options//,/ } --quiet >/dev/null
  run="$work/run_$name"
  "$build/apps/pf2_slam" "$sequence" -o "$run" --detector learned --no-map --quiet \
      --set tracker.asynchronous_backend=false --set bodies.asynchronous=false >/dev/null
  "$build/apps/pf2_eval" "$sequence/groundtruth.txt" "$run/trajectory.txt" --json | tail -n 1 > "$run/ate.json"
  "$build/bench/humans/pf2_humans_eval" "$sequence" "$run" --json | tail -n 1 > "$run/humans_eval.json"
  s="$run/stats.json" h="$run/humans_eval.json"
  # People in view at some time (at least half in view at some time): gt/boxes.txt's 7th column.
  people="$(awk '!/^#/ { if ($7 > seen[$2]) seen[$2] = $7 }
                 END { for (id in seen) { n++; if (seen[id] >= 0.5) half++ }; printf "%d (%d)", n, half }' \
            "$sequence/gt/boxes.txt")"
  printf '| %s | %s | %.1f | %.1f | %s/%s | %s | %s | %s | %s / %s | %s | %.1f | %.0f |\n' "$name" \
    "$(json_field "$s" frames)" "$(awk "BEGIN {print 1000 * $(json_field "$run/ate.json" ate_rmse)}")" \
    "$(awk "BEGIN {print 1000 * $(json_field "$run/ate.json" ate_max)}")" \
    "$(json_field "$s" tracked)" "$(json_field "$s" frames)" "$(json_field "$s" bridged)" \
    "$(json_field "$s" relocalised)" "$(json_field "$s" lost)" "$people" "$(json_field "$h" tracks)" \
    "$(json_field "$h" id_switches)" "$(awk "BEGIN {print 100 * $(json_field "$h" rmse)}")" \
    "$(json_field "$h" mpjpe_mean_mm)"
done
