#!/usr/bin/env bash
# Regenerates docs/config.md from the settings pf2_slam declares (pf2_slam --settings); the
# pf2_slam_cli test fails while the page and the program disagree.
# Usage: scripts/update_config_doc.sh [BUILD_DIR]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-$root/build}"
page="$root/docs/config.md"
tmp="$(mktemp)"
{
  cat <<'HEAD'
# Settings

Every setting of the pipeline, declared once in the code (`slamSettings()` in
modules/slam/src/slam_options.cpp) with its key, default, unit, allowed values and meaning; this
table is generated from that list (`bash scripts/update_config_doc.sh`) and a test checks that
it is current.

Set them in a file given with `pf2_slam --config FILE` (`key value` lines, `#` comments) or one by
one with `--set key=value` (repeatable, applied after the file); the dedicated options
(`--detector`, `--frames`, `--no-map`, ...) are applied last. A value outside its range, a
misspelt key or a malformed line is an error naming the key, the value, the allowed range and,
in a file, the line; nothing is run or written then. `pf2_slam --settings` prints this table.
`pf2_slam --preset NAME` sets a named group of them before the file (`offline`: video matting
and crop masks, the map keeping what the filter's rules take beside them; `pf2_slam --help` lists each preset's settings).

HEAD
  "$build/apps/pf2_slam" --settings
} > "$tmp"
mv "$tmp" "$page"
echo "wrote $page"
