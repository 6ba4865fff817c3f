#!/usr/bin/env bash
# pf2_detect as a user runs it: help, errors (one line, non-zero exit), outputs, metrics.
# Arguments: PF2_DETECT MAKE_FIXTURE WORK_DIR
set -u
detect="$1"; fixture="$2"; work="$3"
rm -rf "$work"; mkdir -p "$work"
fail() { echo "FAIL: $*"; exit 1; }

"$detect" -h | grep -q "Usage: pf2_detect" || fail "-h prints no usage"

"$fixture" "$work/seq" || fail "fixture"

# Missing sequence: exit 1, one error line naming the folder.
if "$detect" "$work/nope" "$work/out0" 2> "$work/err"; then fail "missing sequence accepted"; fi
[ "$(wc -l < "$work/err")" -eq 1 ] || fail "more than one error line: $(cat "$work/err")"
grep -q "$work/nope" "$work/err" || fail "error does not name the folder: $(cat "$work/err")"

# Unknown detector.
if "$detect" "$work/seq" "$work/out0" --detector nope 2> "$work/err"; then fail "unknown detector accepted"; fi
grep -q "unknown detector 'nope'" "$work/err" || fail "unknown detector message: $(cat "$work/err")"

# Filter settings are the filter.* keys (as pf2_slam's): a value out of range is one error line
# naming the key and range, and nothing is written; --settings lists the keys with their defaults.
if "$detect" "$work/seq" "$work/out_bad" --set filter.box_scale=9 2> "$work/err"; then fail "box_scale 9 accepted"; fi
[ "$(wc -l < "$work/err")" -eq 1 ] || fail "more than one error line: $(cat "$work/err")"
grep -qF "filter.box_scale = 9: outside its range [1, 3]" "$work/err" || fail "range message: $(cat "$work/err")"
[ ! -e "$work/out_bad" ] || fail "output written for a refused setting"
"$detect" --settings | grep -qF '| `filter.box_scale` | 1.2 |' || fail "--settings does not list filter.box_scale"

# Ground-truth boxes on clean depth: every person pixel removed, every static one kept.
"$detect" "$work/seq" "$work/out" --json > "$work/log" || fail "gt run failed: $(cat "$work/log")"
for f in "$work"/seq/depth/*.png; do
  name=$(basename "$f")
  [ -s "$work/out/static_depth/$name" ] || fail "no static depth $name"
  [ -s "$work/out/masks/$name" ] || fail "no mask $name"
done
[ "$(grep -vc '^#' "$work/out/boxes.txt")" -eq 3 ] || fail "boxes.txt should have 3 boxes"
grep -q '"recall":1.000000' "$work/log" || fail "recall is not 1: $(cat "$work/log")"
grep -q '"precision":1.000000' "$work/log" || fail "precision is not 1: $(cat "$work/log")"
ls "$work/out/static_depth" | grep -q tmp && fail "temporary files left behind"

# The written boxes fed back through the file backend give the same masks.
"$detect" "$work/seq" "$work/out2" --detector file --boxes "$work/out/boxes.txt" > "$work/log2" ||
  fail "file run failed: $(cat "$work/log2")"
for f in "$work"/out/masks/*.png; do cmp -s "$f" "$work/out2/masks/$(basename "$f")" || fail "file backend differs"; done

# Boxes only (no filter) and a degraded, shrunken box: recall drops below 1.
"$detect" "$work/seq" "$work/out3" --no-filter --shrink 0.5 --json > "$work/log3" || fail "degraded run failed"
grep -q '"recall":1.000000' "$work/log3" && fail "shrunken boxes without filter still remove everything"

# A malformed boxes file: one error line naming file and line.
printf '# boxes\n100.0 1 2 3\n' > "$work/bad.txt"
if "$detect" "$work/seq" "$work/out4" --detector file --boxes "$work/bad.txt" 2> "$work/err"; then fail "bad file accepted"; fi
grep -q "$work/bad.txt:2:" "$work/err" || fail "error does not name file:line: $(cat "$work/err")"
# Malformed plug-in backend options.
if "$detect" "$work/seq" "$work/out5" --backend-options "novalue" 2> "$work/err"; then fail "bad backend options accepted"; fi
grep -q "backend-options" "$work/err" || fail "backend options message: $(cat "$work/err")"
echo "pf2_detect CLI: all checks passed"
