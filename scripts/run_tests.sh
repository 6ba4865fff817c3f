#!/usr/bin/env bash
# Quick start (b): install the dependencies, build, and run the whole test suite with ctest.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${PF2_BUILD_DIR:-$root/build}"

if [ "${PF2_SKIP_INSTALL:-0}" != "1" ]; then bash "$root/scripts/install_deps.sh"; fi
bash "$root/scripts/build.sh"
cd "$build"
ctest --output-on-failure -j "${PF2_JOBS:-$(nproc)}"
