#!/usr/bin/env bash
# People and their bodies with the project's own detector (--detector learned), no oracle:
# pf2_slam on pf2_synth sequences with three people (static, xyz, halfsphere; made here when
# missing), scored by pf2_humans_eval against the sequences' ground truth: the person tracks
# (humans.txt, the fitted pelvis) against the true pelvis (RMSE, median, identity switches,
# fragmentations, tracks), and the bodies (humans.json) against the true joints (MPJPE over all body
# frames and over fitted ones). Then the real Bonn crowd frames when present (number of tracks), and
# end-to-end fps with bodies on and off on the same runs (map off, so the body stage's cost shows).
#
# Usage: bench/humans/bodies_benchmark.sh [BUILD_DIR] [WORK_DIR] [FRAMES] [DATA_DIR]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${1:-$root/build}"
work="${2:-/tmp/pf2_bodies}"
frames="${3:-300}"
data="${4:-$root/../shared/data}"
mkdir -p "$work"
source "$root/bench/bench_lib.sh"

echo "machine: $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)"
echo
echo "| sequence | track RMSE (m) | median (m) | id switches | fragmentations | tracks (people) | recall | MPJPE all mean / median (mm) | MPJPE fitted mean / median (mm) | fitted frames | fps bodies on | fps bodies off |"
echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
for camera in static xyz halfsphere; do
  sequence="$work/${camera}_p3_n${frames}"
  [ -f "$sequence/groundtruth.txt" ] || "$build/apps/pf2_synth" "$sequence" --frames "$frames" --people 3 \
      --camera "$camera" --seed 1 --quiet >/dev/null
  "$build/apps/pf2_slam" "$sequence" -o "$work/run_${camera}" --detector learned --no-map --quiet >/dev/null
  "$build/apps/pf2_slam" "$sequence" -o "$work/run_${camera}_nobodies" --detector learned --no-map --no-bodies \
      --quiet >/dev/null
  "$build/bench/humans/pf2_humans_eval" "$sequence" "$work/run_${camera}" --json | tail -n 1 > "$work/${camera}.json"
  j="$work/${camera}.json"
  printf '| %s | %.3f | %.3f | %s | %s | %s (3) | %.3f | %.0f / %.0f | %.0f / %.0f | %s | %.1f | %.1f |\n' \
    "$camera" "$(json_field "$j" rmse)" "$(json_field "$j" median)" "$(json_field "$j" id_switches)" \
    "$(json_field "$j" fragmentations)" "$(json_field "$j" tracks)" "$(json_field "$j" recall)" \
    "$(json_field "$j" mpjpe_mean_mm)" "$(json_field "$j" mpjpe_median_mm)" "$(json_field "$j" mpjpe_fitted_mean_mm)" \
    "$(json_field "$j" mpjpe_fitted_median_mm)" "$(json_field "$j" fitted_frames)" \
    "$(json_field "$work/run_${camera}/stats.json" fps)" "$(json_field "$work/run_${camera}_nobodies/stats.json" fps)"
done
for camera in static xyz halfsphere; do
  echo
  echo "$camera, per joint (median mm): $("$build/bench/humans/pf2_humans_eval" "$work/${camera}_p3_n${frames}" \
      "$work/run_${camera}" | grep '^per joint' | cut -d: -f2)"
done

bonn="$data/bonn_crowd_250_150"
if [ -f "$bonn/rgb.txt" ]; then
  "$build/apps/pf2_slam" "$bonn" -o "$work/run_bonn" --detector learned --quiet >/dev/null
  "$build/apps/pf2_slam" "$bonn" -o "$work/run_bonn_nobodies" --detector learned --no-bodies --quiet >/dev/null
  tracks=$(grep -v '^#' "$work/run_bonn/humans.txt" | awk '{print $2}' | sort -u | wc -l)
  long=$(grep -v '^#' "$work/run_bonn/humans.txt" | awk '{n[$2]++} END {k = 0; for (i in n) if (n[i] >= 30) k++; print k}')
  echo
  echo "Bonn crowd (150 frames, learned): $tracks tracks ($long seen in at least 30 frames); fps with map:" \
       "bodies on $(json_field "$work/run_bonn/stats.json" fps), off $(json_field "$work/run_bonn_nobodies/stats.json" fps);" \
       "body fits offered $(json_field "$work/run_bonn/stats.json" body_fits_offered)," \
       "skipped $(json_field "$work/run_bonn/stats.json" body_fits_skipped)"
else
  echo "note: no $bonn, the real-data row is skipped"
fi
