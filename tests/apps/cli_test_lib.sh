# Shared by the command-line tests of the apps (sourced): failure counting and the check that a
# refused command exits 1 with one error line naming what was wrong.
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# expect_error NAME ARGS...: running ARGS exits 1 and prints exactly one stderr line containing NAME.
expect_error() {
  local name=$1; shift
  local err code
  err=$("$@" 2>&1 >/dev/null); code=$?
  [ "$code" -eq 1 ] || fail "$name: exit code $code (want 1)"
  [ "$(printf '%s\n' "$err" | wc -l)" -eq 1 ] || fail "$name: not one error line: $err"
  printf "%s" "$err" | grep -qF -- "$name" || fail "$name not named in: $err"
}
