#!/usr/bin/env bash
# Quick start (a): install the dependencies, build, and run the main job, printing its figures.
# Until pf2_slam exists the main job is the evaluator on a generated example: a ground-truth
# trajectory and an estimate made from it with a known misalignment and 1 cm noise.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${PF2_BUILD_DIR:-$root/build}"
out="${PF2_OUT_DIR:-$root/out}"

if [ "${PF2_SKIP_INSTALL:-0}" != "1" ]; then bash "$root/scripts/install_deps.sh"; fi
bash "$root/scripts/build.sh"
mkdir -p "$out"
python3 "$root/scripts/make_example_trajectories.py" "$out/example"
"$build/apps/pf2_eval" "$out/example/groundtruth.txt" "$out/example/estimate.txt" \
  --rpe --plot "$out/example/ate.png"
echo "plot: $out/example/ate.png"
