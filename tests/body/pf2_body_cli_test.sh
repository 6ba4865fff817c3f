#!/usr/bin/env bash
# pf2_body as a user runs it: usage, mesh export, info, one error line and exit 1 on bad input.
# Usage: pf2_body_cli_test.sh PF2_BODY WORK_DIR
set -u
body=$1 work=$2
rm -rf "$work" && mkdir -p "$work"
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

"$body" -h | grep -q "Usage: pf2_body COMMAND" || fail "-h does not print usage"

# OBJ and PLY of the default model, posed; no temporary files left behind.
"$body" mesh "$work/walk.obj" --pose walk --shape 1,0,0,-0.5 --translation 0,0,2 || fail "mesh .obj failed"
[ "$(grep -c '^v ' "$work/walk.obj")" = 13380 ] || fail "walk.obj does not have 13380 vertices"
[ "$(grep -c '^f ' "$work/walk.obj")" = 26756 ] || fail "walk.obj does not have 26756 faces"
"$body" mesh "$work/rest.ply" || fail "mesh .ply failed"
head -c 200 "$work/rest.ply" | grep -q "element vertex 13380" || fail "rest.ply header"
ls "$work" | grep -q tmp && fail "temporary file left in $work"

# A pose file moves the left knee: the mesh differs from the rest mesh.
printf '# bent knee\nleft_knee 1.0 0 0\n' > "$work/pose.txt"
"$body" mesh "$work/knee.obj" --pose-file "$work/pose.txt" || fail "--pose-file failed"
"$body" mesh "$work/rest.obj" || fail "mesh rest.obj failed"
cmp -s "$work/knee.obj" "$work/rest.obj" && fail "--pose-file changed nothing"

"$body" info | grep -q "^joint 15 head" || fail "info does not list the head joint"

# Bad input: exactly one error line naming the file, exit status 1.
expect_error() {  # expect_error PATTERN ARGS...
  local pattern=$1
  shift
  local err
  err=$("$body" "$@" 2>&1 >/dev/null)
  local status=$?
  [ $status -eq 1 ] || fail "'$*' exited with $status, expected 1"
  [ "$(printf '%s\n' "$err" | wc -l)" -eq 1 ] || fail "'$*' printed more than one error line: $err"
  printf '%s' "$err" | grep -q -- "$pattern" || fail "'$*' error does not mention '$pattern': $err"
}
expect_error "no_such_model.npz" mesh "$work/x.obj" --model "$work/no_such_model.npz"
printf 'not a zip' > "$work/garbage.npz"
expect_error "garbage.npz" info --model "$work/garbage.npz"
printf 'left_tail 1 2 3\n' > "$work/bad_pose.txt"
expect_error "bad_pose.txt:1:" mesh "$work/x.obj" --pose-file "$work/bad_pose.txt"
expect_error "x.stl" mesh "$work/x.stl"
expect_error "--shape" mesh "$work/x.obj" --shape 1,zwei
expect_error "option --shape: setting mesh.shape = nan: bad number" mesh "$work/x.obj" --shape nan
expect_error "outside \[-5" mesh "$work/x.obj" --shape 1e30
expect_error "mesh.shape: 12 numbers for a model with 10" mesh "$work/x.obj" --shape 0,0,0,0,0,0,0,0,0,0,1,1
expect_error "mesh.translation" mesh "$work/x.obj" --translation 1,2
expect_error "setting mesh.pose = run" mesh "$work/x.obj" --set mesh.pose=run
expect_error "base.obj" convert-mpfb2 "$work/no_mpfb2" "$work/out.npz"
expect_error "unknown command" frobnicate
[ -e "$work/x.obj" ] && fail "a failed run left x.obj"

if [ $failures -ne 0 ]; then
  echo "$failures failure(s)"
  exit 1
fi
echo "pf2_body CLI: all checks passed"
