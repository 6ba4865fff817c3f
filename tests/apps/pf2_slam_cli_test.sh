#!/usr/bin/env bash
# pf2_slam as a user runs it: the settings table in docs/config.md is the one the program
# declares; bad settings (out of range, unknown key, bad config line) give one error line naming
# them, exit status 1 and no output folder; a short run on the built-in synthetic sequence writes
# its outputs, and --set changes what it does.
# Usage: pf2_slam_cli_test.sh PF2_SLAM DOCS_CONFIG_MD WORK_DIR
set -u
slam=$1 docs=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
source "$(dirname "${BASH_SOURCE[0]}")/cli_test_lib.sh"

# refused NAME ARGS...: expect_error, and no output folder appeared.
refused() {
  local name=$1; shift
  expect_error "$name" "$@" -o "$work/refused"
  [ ! -e "$work/refused" ] || fail "$name: an output folder was created"
}

# The documented table is the declared one, row for row.
"$slam" --settings > "$work/settings.md" || fail "--settings exit code"
[ "$(wc -l < "$work/settings.md")" -gt 50 ] || fail "--settings lists too few settings"
while IFS= read -r row; do
  grep -qxF -- "$row" "$docs" || fail "docs/config.md is not current (scripts/update_config_doc.sh): $row"
done < "$work/settings.md"

refused "map.voxel_size = 100: outside its range [0.002, 0.2] metres" "$slam" --set map.voxel_size=100
refused "map.voxel_size = 1e-6" "$slam" --set map.voxel_size=1e-6
refused "unknown setting 'map.voxels'" "$slam" --set map.voxels=0.01
refused "expected key=value" "$slam" --set map.voxel_size
refused "tracker.finest_level must lie in the range [0, tracker.pyramid_levels - 1]" "$slam" --set tracker.finest_level=3
printf 'map.build false\nfilter.mask_reach -4\n' > "$work/bad.cfg"
refused "bad.cfg:2: setting filter.mask_reach = -4" "$slam" --config "$work/bad.cfg"
printf 'map.buidl false\n' > "$work/typo.cfg"
refused "typo.cfg:1: unknown key 'map.buidl'" "$slam" --config "$work/typo.cfg"
refused "is a folder, not a config file" "$slam" --config "$work"
refused "the map of a 100 m^2 room would need about 750.0 GB" "$slam" --set map.voxel_size=0.002 --set map.truncation=1
# The dedicated options are settings too: checked against the same ranges, the option named.
refused "option --frames: setting run.max_frames = -5: outside its range" "$slam" --frames -5
refused "no preset 'fast' (presets: offline)" "$slam" --preset fast
refused "option --depth-scale: setting input.depth_scale = 0" "$slam" --depth-scale 0
refused "option --synth-people: setting synth.people = 9" "$slam" --synth-people 9

# A short run with the oracle detector (no models needed): outputs present, one pose per frame.
out="$work/run"
"$slam" -o "$out" --detector gt --synth-frames 12 --synth-people 1 --no-map --quiet > "$work/run.log" 2>&1 ||
  fail "run exit code: $(tail -n 3 "$work/run.log")"
for f in trajectory.txt stats.json humans.txt; do [ -s "$out/$f" ] || fail "run: $f missing"; done
[ "$(grep -vc '^#' "$out/trajectory.txt")" -eq 12 ] || fail "run: not 12 poses"
grep -q '"frames":12' "$out/stats.json" || fail "run: stats.json frames"
grep -q '^ate' "$work/run.log" || grep -qi 'ATE' "$work/run.log" || fail "run: no ATE printed"
# With the map (the default): mesh and OctoMap files.
"$slam" "$out/synthetic" -o "$work/mapped" --detector gt --frames 6 --quiet > /dev/null 2>&1 || fail "mapped run failed"
for f in map.ply map.bt map.ot; do [ -s "$work/mapped/$f" ] || fail "mapped run: $f missing"; done
# Without the OctoMap: the mesh, and no map.bt / map.ot.
"$slam" "$out/synthetic" -o "$work/no_octomap" --detector gt --frames 6 --quiet --set map.octomap=false \
  > "$work/no_octomap.log" 2>&1 || fail "map.octomap=false run failed: $(tail -n 2 "$work/no_octomap.log")"
[ -s "$work/no_octomap/map.ply" ] || fail "map.octomap=false: no map.ply"
[ ! -e "$work/no_octomap/map.bt" ] || fail "map.octomap=false: map.bt written"
# --set after --config wins, and run.max_frames stops early.
printf 'run.max_frames 10\n' > "$work/ten.cfg"
"$slam" "$out/synthetic" -o "$work/run8" --detector gt --no-map --quiet --config "$work/ten.cfg" \
  --set run.max_frames=8 --masks > /dev/null 2>&1 || fail "run8 exit code"
[ "$(grep -vc '^#' "$work/run8/trajectory.txt")" -eq 8 ] || fail "--set run.max_frames=8 did not give 8 poses"
# --masks: one removed-depth mask per frame, named by timestamp; no partial folder left.
[ "$(ls "$work/run8/masks" | grep -c '\.png$')" -eq 8 ] || fail "--masks did not write 8 masks"
[ ! -e "$work/run8/masks.partial" ] || fail "--masks left masks.partial"
# A second run into the same folder replaces the first run's files, those it does not write too:
# no map and no masks of the first run stay beside the second run's trajectory.
"$slam" "$out/synthetic" -o "$work/no_octomap" --detector none --frames 4 --no-map --quiet > /dev/null 2>&1 \
  || fail "second run into a folder failed"
[ ! -e "$work/no_octomap/map.ply" ] || fail "a rerun without a map left the first run's map.ply"
[ "$(grep -vc '^#' "$work/no_octomap/trajectory.txt")" -eq 4 ] || fail "the rerun's trajectory is not the rerun's"
ls -a "$work/no_octomap" | grep -q partial && fail "a rerun left a staging folder"

[ "$failures" -eq 0 ] && echo "pf2_slam_cli: all checks passed"
exit $((failures > 0))
