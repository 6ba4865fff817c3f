#!/usr/bin/env bash
# pf2_view as a user runs it: usage, error lines for bad run folders, and (with xvfb-run) a
# screenshot of a tiny run folder whose pixels show the map, the first camera and the tracks.
# Usage: pf2_view_cli_test.sh PF2_VIEW IMAGE_STATS WORK_DIR
set -u
view=$1 stats=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
source "$(dirname "${BASH_SOURCE[0]}")/cli_test_lib.sh"

# -h prints usage with the keys and exits 0.
help=$("$view" -h) || fail "-h exit code"
printf '%s' "$help" | grep -q "Usage: pf2_view RUN_DIR" || fail "-h does not print usage"
printf '%s' "$help" | grep -q "r reset" || fail "-h does not list the keys"

# A tiny run folder: a red 2 m x 2 m floor 1 m below the camera, a 3-pose trajectory, two people.
run="$work/run"
mkdir -p "$run"
cat > "$run/map.ply" <<'PLY'
ply
format ascii 1.0
element vertex 4
property float x
property float y
property float z
property uchar red
property uchar green
property uchar blue
element face 2
property list uchar int vertex_indices
end_header
-1 1 1 220 30 30
1 1 1 220 30 30
1 1 3 220 30 30
-1 1 3 220 30 30
3 0 1 2
3 0 2 3
PLY
printf '# t tx ty tz qx qy qz qw\n0.0 0 0 0 0 0 0 1\n0.1 0.2 0 0 0 0 0 1\n0.2 0.4 0 0.1 0 0 0 1\n' > "$run/trajectory.txt"
printf '# t id x y z\n0.0 1 -0.5 0.2 2\n0.1 1 -0.4 0.2 2.1\n0.2 1 -0.3 0.2 2.2\n0.0 2 0.5 0.2 2.5\n0.2 2 0.6 0.2 2.3\n' > "$run/humans.txt"

# Bad input: one line naming the folder or file, exit 1, no window needed (checked before one opens).
expect_error "no_such_run" "$view" "$work/no_such_run"
mkdir -p "$work/empty"
expect_error "trajectory.txt" "$view" "$work/empty"
broken="$work/broken_map"
cp -r "$run" "$broken"
printf 'ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nend_header\n0.5\n' > "$broken/map.ply"
expect_error "map.ply" "$view" "$broken"
broken="$work/broken_humans"
cp -r "$run" "$broken"
printf '0.0 1 0.5 zero 2\n' > "$broken/humans.txt"
expect_error "humans.txt:1:" "$view" "$broken"
expect_error "--size" "$view" "$run" --size 12
expect_error "DISPLAY" env -u DISPLAY "$view" "$run" --screenshot "$work/x.png"
expect_error "no_such_folder/x.png" "$view" "$run" --screenshot "$work/no_such_folder/x.png"

# Missing optional files are notes, not errors (checked up to the display, which is absent here).
sparse="$work/sparse"
mkdir -p "$sparse" && cp "$run/trajectory.txt" "$sparse/"
out=$(env -u DISPLAY "$view" "$sparse" 2>/dev/null)
printf '%s' "$out" | grep -q "map.ply not found" || fail "no note for the missing map.ply: $out"
printf '%s' "$out" | grep -q "humans.txt not found" || fail "no note for the missing humans.txt: $out"

if ! command -v xvfb-run >/dev/null 2>&1; then
  if [ "$failures" -ne 0 ]; then echo "$failures check(s) failed"; exit 1; fi
  echo "SKIPPED: no xvfb-run for the screenshot checks"; exit 77
fi

# stat KEY FILE: one value of image_stats.
stat() { "$stats" "$2" | awk -v k="$1" '$1 == k { print $2 }'; }
# at_least VALUE MIN: VALUE >= MIN as numbers.
at_least() { awk -v v="$1" -v m="$2" 'BEGIN { exit !(v >= m) }'; }

shot="$work/run.png"
xvfb-run -a "$view" "$run" --screenshot "$shot" --size 640x400 >/dev/null || fail "screenshot run failed"
if [ -s "$shot" ]; then
  [ "$(stat width "$shot")x$(stat height "$shot")" = "640x400" ] || fail "screenshot size"
  at_least "$(stat distinct "$shot")" 20 || fail "screenshot nearly uniform: $(stat distinct "$shot") colours"
  # The red floor covers a good part of the view (30 % when written), the first camera's frustum
  # is green (0.18 %, 0.1 % without the map) and person 1's track and label are blue (0.03 %); the background is none.
  at_least "$(stat red "$shot")" 0.15 || fail "map not visible: red fraction $(stat red "$shot")"
  at_least "$(stat green "$shot")" 0.0005 || fail "first camera not visible: green $(stat green "$shot")"
  at_least "$(stat blue "$shot")" 0.0001 || fail "person 1 not visible: blue $(stat blue "$shot")"
else
  fail "no screenshot written"
fi

# --no-map: the floor is gone, the rest stays.
shot="$work/no_map.png"
xvfb-run -a "$view" "$run" --no-map --screenshot "$shot" --size 640x400 >/dev/null || fail "--no-map run failed"
if [ -s "$shot" ]; then
  at_least 0.001 "$(stat red "$shot")" || fail "--no-map still shows the map: red $(stat red "$shot")"
  at_least "$(stat green "$shot")" 0.0005 || fail "--no-map: first camera not visible"
else
  fail "--no-map: no screenshot written"
fi

# humans.json: person 1's body (blue) standing at the end of their track, upright in this world
# (y down: the root turned 180 degrees about x), covers far more of the view than their track.
zeros() { local n=$1 out=""; for ((i = 0; i < n; ++i)); do out+="${out:+,}0"; done; printf '%s' "$out"; }
pose="3.141593,0,0,$(zeros 69)"
joints=$(for ((j = 0; j < 24; ++j)); do printf '%s[-0.3,0.2,2.2]' "$([ $j -gt 0 ] && echo ,)"; done)
printf '{"tracks":[{"id":1,"frames":[{"timestamp":0.2,"T_w_h":[1,0,0,-0.3,0,-1,0,0.2,0,0,-1,2.2,0,0,0,1],"pose":[%s],"shape":[%s],"translation":[-0.3,1.1,2.2],"joints_w":[%s],"pelvis_w":[-0.3,0.2,2.2],"fitted":true}]}]}\n' \
  "$pose" "$(zeros 10)" "$joints" > "$run/humans.json"
shot="$work/bodies.png"
xvfb-run -a "$view" "$run" --no-map --screenshot "$shot" --size 640x400 >/dev/null || fail "bodies run failed"
if [ -s "$shot" ]; then
  at_least "$(stat blue "$shot")" 0.01 || fail "person 1's body not visible: blue $(stat blue "$shot")"
else
  fail "bodies: no screenshot written"
fi
printf '{"tracks": [{"id": 1}]}' > "$run/humans.json"
expect_error "humans.json" xvfb-run -a "$view" "$run" --screenshot "$work/x.png"

if [ "$failures" -ne 0 ]; then echo "$failures check(s) failed"; exit 1; fi
echo "all pf2_view checks passed"
