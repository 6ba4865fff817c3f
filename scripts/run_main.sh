#!/usr/bin/env bash
# Quick start (a): install the dependencies and the learned detector's models, build, and run the
# main job: pf2_slam with the learned person detector on the built-in synthetic sequence (people
# walking through a textured room), printing its figures (frames, lost frames, fps per stage, ATE
# against the ground truth). Outputs land in out/slam/.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${PF2_BUILD_DIR:-$root/build}"
out="${PF2_OUT_DIR:-$root/out}"

if [ "${PF2_SKIP_INSTALL:-0}" != "1" ]; then bash "$root/scripts/install_deps.sh"; fi
# The main job runs the project's own (learned) person detector: its models, pinned and
# checksummed, are fetched once (a no-op when present).
bash "$root/scripts/fetch_models.sh"
bash "$root/scripts/build.sh"
mkdir -p "$out"
"$build/apps/pf2_slam" -o "$out/slam" "$@"
echo "report: $out/slam/report.html (open it in a browser; it needs no network)"
