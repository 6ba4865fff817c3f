#!/usr/bin/env bash
# pf2_synth as a user runs it: usage, a small sequence in TUM layout with gt/, byte-identical output
# for the same seed, one error line and exit status 1 for bad options.
# Usage: pf2_synth_cli_test.sh PF2_SYNTH WORK_DIR
set -u
synth=$1 work=$2
rm -rf "$work" && mkdir -p "$work"
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

"$synth" -h | grep -q "Usage: pf2_synth OUT_DIR" || fail "-h does not print usage"

# Two runs with the same seed write the same bytes; another seed does not.
for run in a b; do
  "$synth" "$work/$run" --frames 3 --people 1 --camera loop --seed 7 --quiet >/dev/null || fail "run $run failed"
done
"$synth" "$work/c" --frames 3 --people 1 --camera loop --seed 8 --quiet >/dev/null || fail "run c failed"
for f in rgb.txt depth.txt groundtruth.txt camera.txt gt/README.md gt/boxes.txt gt/people.txt gt/bodies.txt \
         gt/joints.txt gt/static_scene.ply; do
  [ -s "$work/a/$f" ] || fail "missing $f"
done
[ "$(ls "$work/a/rgb" | wc -l)" -eq 3 ] || fail "expected 3 colour images"
[ "$(ls "$work/a/depth" | wc -l)" -eq 3 ] || fail "expected 3 depth images"
[ "$(ls "$work/a/gt/masks" | wc -l)" -eq 3 ] || fail "expected 3 masks"
find "$work/a" -name "*.tmp*" | grep -q . && fail "temporary files left behind"
(cd "$work/a" && find . -type f -exec md5sum {} + | sort -k2) > "$work/a.md5"
(cd "$work/b" && find . -type f -exec md5sum {} + | sort -k2) > "$work/b.md5"
cmp -s "$work/a.md5" "$work/b.md5" || fail "same seed, different bytes: $(diff "$work/a.md5" "$work/b.md5" | head -3)"
first_rgb=$(ls "$work/a/rgb" | head -1)
cmp -s "$work/a/rgb/$first_rgb" "$work/c/rgb/$first_rgb" && fail "another seed gave the same image"
# Timestamps: 6 decimals, the same in rgb.txt, depth.txt, groundtruth.txt and gt/people.txt.
stamps() { grep -v '^#' "$1" | awk '{print $1}' | sort -u; }
[ "$(stamps "$work/a/rgb.txt")" = "$(stamps "$work/a/groundtruth.txt")" ] || fail "rgb.txt and groundtruth.txt stamps differ"
[ "$(stamps "$work/a/rgb.txt")" = "$(stamps "$work/a/gt/people.txt")" ] || fail "rgb.txt and gt/people.txt stamps differ"
grep -v '^#' "$work/a/rgb.txt" | head -1 | grep -Eq '^[0-9]+\.[0-9]{6} rgb/[0-9]+\.[0-9]{6}\.png$' || fail "rgb.txt line format"

# --close: people cross close in front of the camera; gt/README.md says so, the default run does not.
"$synth" -h | grep -q -- "--close" || fail "-h does not list --close"
"$synth" "$work/close" --frames 2 --people 2 --close --quiet >/dev/null || fail "--close run failed"
grep -q "Made with close people" "$work/close/gt/README.md" || fail "gt/README.md of a --close run does not say so"
grep -q "close people" "$work/a/gt/README.md" && fail "gt/README.md of a run without --close mentions close people"

# Bad options: one error line, exit status 1.
check_error() {
  local expect=$1; shift
  local err code
  err=$("$synth" "$@" 2>&1 >/dev/null); code=$?
  [ "$code" -eq 1 ] || fail "'$*' exit code $code"
  [ "$(printf '%s\n' "$err" | wc -l)" -eq 1 ] || fail "'$*' printed more than one line: $err"
  printf '%s' "$err" | grep -q -- "$expect" || fail "'$*' error does not mention $expect: $err"
}
check_error "camera" "$work/x" --camera circle
check_error "noise" "$work/x" --noise gaussian
check_error "people" "$work/x" --people 6
check_error "frames" "$work/x" --frames 0
check_error "frames" "$work/x" --frames many
check_error "unknown option" "$work/x" --colour
check_error "OUT_DIR" --frames 2
check_error "misalign" "$work/x" --misalign 400
check_error "setting synth.frames = 0: outside its range" "$work/x" --set synth.frames=0
check_error "option --seed: setting synth.seed = -3" "$work/x" --seed -3
"$synth" --settings | grep -q "synth.camera" || fail "--settings does not list synth.camera"

if [ "$failures" -ne 0 ]; then echo "$failures check(s) failed"; exit 1; fi
echo "all pf2_synth checks passed"
