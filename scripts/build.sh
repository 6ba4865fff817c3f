#!/usr/bin/env bash
# Configures and builds PoseFusion2 (Release, ccache when present) into ./build.
# Usage: scripts/build.sh [extra cmake arguments]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${PF2_BUILD_DIR:-$root/build}"
jobs="${PF2_JOBS:-$(nproc)}"

cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release "$@"
cmake --build "$build" -j "$jobs"
