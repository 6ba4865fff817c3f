#!/usr/bin/env bash
# pf2_batch as a user runs it: 3 short pf2_synth sequences x 2 detectors on a local Dask cluster of
# 2 workers on the loopback address. The table holds what the same pf2_slam runs give when run
# singly; run again, the batch skips all 6; a run that fails is retried once and reported, one
# whose pf2_slam or worker is killed once succeeds on its retry; bad input gives one error line.
# Usage: pf2_batch_test.sh PYTHON SCRIPTS_DIR PF2_SLAM PF2_SYNTH PF2_EVAL PF2_HUMANS_EVAL WORK_DIR
set -u
python=$1 scripts=$2 slam=$3 synth=$4 eval_bin=$5 humans=$6 work=$7
rm -rf "$work" && mkdir -p "$work"
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

if ! "$python" -c "import distributed, yaml" 2>/dev/null; then
  echo "SKIP: $python cannot import distributed and yaml (Debian: python3-distributed python3-yaml)"
  exit 77
fi
batch() { "$python" "$scripts/pf2_batch" --pf2-slam "$slam" --pf2-eval "$eval_bin" \
            --pf2-humans-eval "$humans" "$@"; }

# Three sequences of 40 frames (over 1 s, so the RPE's 1 s pairs exist), two people each.
seed=0
for camera in xyz static halfsphere; do
  seed=$((seed + 1))
  "$synth" "$work/seqs/s_$camera" --frames 40 --people 2 --camera "$camera" --seed "$seed" --quiet \
    > /dev/null || fail "pf2_synth $camera"
done

# The batch: with and without person removal. Fusion is off (not measured here) and the pose graph
# runs in the front end's thread, so a run's figures do not depend on what else the machine runs.
fixed=(--set map.build=false --set tracker.asynchronous_backend=false)
batch "$work/seqs/*" -o "$work/batch" --set detector.name=gt,none "${fixed[@]}" --workers 2 \
  > "$work/batch.out" 2> "$work/batch.err" || fail "batch exit code: $(tail -n 3 "$work/batch.err")"
grep -q "6 runs (0 skipped as complete, 0 failed)" "$work/batch.out" || fail "batch summary: $(cat "$work/batch.out")"
grep -q "runs: 6/6 done (0 skipped, 0 failed)" "$work/batch.err" || fail "no final progress line"
grep -q "ETA" "$work/batch.err" || fail "no ETA on the terminal"

# The same runs singly, with their evaluations.
mkdir -p "$work/single"
for camera in xyz static halfsphere; do
  for detector in gt none; do
    seq="$work/seqs/s_$camera" out="$work/single/s_${camera}_$detector"
    "$slam" "$seq" -o "$out" --quiet --set detector.name=$detector "${fixed[@]}" > /dev/null 2>&1 ||
      fail "single run $camera $detector"
    "$eval_bin" "$seq/groundtruth.txt" "$out/trajectory.txt" --rpe --json | tail -n 1 > "$out/eval.json"
    if [ -n "$humans" ] && [ -f "$out/humans.txt" ]; then
      "$humans" "$seq" "$out" --json | tail -n 1 > "$out/humans_eval.json"
    fi
  done
done

"$python" - "$work" "$humans" <<'PY' || fail "the batch table differs from the single runs"
import csv, json, os, sys
work, humans = sys.argv[1], sys.argv[2]
rows = list(csv.DictReader(open(f"{work}/batch/results.csv")))
assert len(rows) == 6, len(rows)
def close(a, b, tol):
    return abs(float(a) - float(b)) <= tol
for row in rows:
    detector = row["settings"].split()[0].split("=")[1]
    single = f"{work}/single/{row['sequence']}_{detector}"
    stats, ate = json.load(open(f"{single}/stats.json")), json.load(open(f"{single}/eval.json"))
    where = f"{row['sequence']} {detector}"
    assert row["status"] == "ok" and row["attempts"] == "1", (where, row["status"], row["attempts"])
    assert row["detector"] == detector == stats["detector"], (where, row["detector"])
    assert int(row["frames"]) == stats["frames"] == 40, (where, row["frames"], stats["frames"])
    assert int(row["lost"]) == stats["lost"] and int(row["tracked"]) == stats["tracked"], where
    # 10 micrometres: the pose solver's floating-point sums, not a different result.
    for col, key in (("ate_rmse_m", "ate_rmse"), ("rpe_trans_rmse_m", "rpe_trans_rmse")):
        assert close(row[col], ate[key], 1e-5), (where, col, row[col], ate[key])
    assert close(row["rpe_rot_rmse_deg"], ate["rpe_rot_rmse_deg"], 1e-3), (where, row["rpe_rot_rmse_deg"])
    assert float(row["ate_rmse_m"]) > 0, where
    if humans and detector == "gt":
        h = json.load(open(f"{single}/humans_eval.json"))
        assert close(row["humans_recall"], h["recall"], 1e-3), (where, row["humans_recall"], h["recall"])
        assert int(row["humans_id_switches"]) == h["id_switches"], where
        assert close(row["humans_rmse_m"], h["rmse"], 1e-3), (where, row["humans_rmse_m"], h["rmse"])
    if detector == "none":
        assert row["humans_recall"] == "" and "no humans.txt" in row["note"], (where, row["note"])
    report = os.path.join(f"{work}/batch", row["report"])
    assert os.path.isfile(os.path.join(report, "stats.json")) or report.endswith("report.html"), report
    manifest = json.load(open(os.path.join(f"{work}/batch", row["report"].split("/")[0], "batch_run.json")))
    assert manifest["sequence"] == row["sequence_path"] and manifest["version"]["pf2_slam_sha256"], manifest
md = open(f"{work}/batch/results.md").read()
assert sum(line.startswith("| s_") for line in md.splitlines()) == 6, md
assert "Settings of every run: `map.build=false tracker.asynchronous_backend=false`" in md, md
PY

# Run again: all 6 skipped, nothing rerun, the same table.
stamps=$(stat -c %Y "$work"/batch/*/stats.json)
cp "$work/batch/results.csv" "$work/first.csv"
batch "$work/seqs/s_xyz" "$work/seqs/s_static" "$work/seqs/s_halfsphere" -o "$work/batch" \
  --set detector.name=gt,none "${fixed[@]}" > "$work/again.out" 2> "$work/again.err" ||
  fail "rerun exit code: $(tail -n 3 "$work/again.err")"
grep -q "6 runs (6 skipped as complete, 0 failed)" "$work/again.out" || fail "rerun: $(cat "$work/again.out")"
[ "$stamps" = "$(stat -c %Y "$work"/batch/*/stats.json)" ] || fail "rerun: a complete run was run again"
"$python" - "$work/first.csv" "$work/batch/results.csv" <<'PY' || fail "rerun: the table changed"
import csv, sys
first, again = (list(csv.DictReader(open(f))) for f in sys.argv[1:3])
assert [r["status"] for r in again] == ["skipped"] * 6, [r["status"] for r in again]
keep = [c for c in first[0] if c not in ("status", "sequence", "sequence_path")]
key = lambda r: (r["sequence"], r["settings"])
assert sorted((key(r), [r[c] for c in keep]) for r in first) == \
       sorted((key(r), [r[c] for c in keep]) for r in again)
PY

# The same grid from a YAML file names the same runs: all complete.
printf 'detector:\n  name: [gt, none]\nmap.build: false\ntracker.asynchronous_backend: false\n' \
  > "$work/grid.yaml"
batch "$work/seqs/*" -o "$work/batch" --grid "$work/grid.yaml" --dry-run > "$work/dry.out" 2>&1 ||
  fail "--grid --dry-run exit code: $(cat "$work/dry.out")"
[ "$(grep -c '^skip ' "$work/dry.out")" -eq 6 ] || fail "--grid does not name the 6 complete runs: $(cat "$work/dry.out")"

# A preset is one more grid key: "none" names the complete runs, "offline" new ones.
batch "$work/seqs/*" -o "$work/batch" --preset none,offline --set detector.name=gt,none \
  --set map.build=false --set tracker.asynchronous_backend=false --dry-run > "$work/preset.out" 2>&1 ||
  fail "--preset --dry-run exit code: $(cat "$work/preset.out")"
[ "$(grep -c '^run .*preset=offline' "$work/preset.out")" -eq 6 ] || fail "--preset offline runs: $(cat "$work/preset.out")"
[ "$(grep -c '^skip ' "$work/preset.out")" -eq 6 ] || fail "--preset none runs: $(cat "$work/preset.out")"

# Failures: a sequence whose images are missing fails twice and is reported; a run whose pf2_slam
# is killed once, and one whose worker is killed once, succeed on their retry.
mkdir -p "$work/seqs_bad/broken"
printf '1700000000.0 rgb/none.png\n' > "$work/seqs_bad/broken/rgb.txt"
printf '1700000000.0 depth/none.png\n' > "$work/seqs_bad/broken/depth.txt"
cat > "$work/flaky_slam" <<EOF
#!/usr/bin/env bash
# pf2_slam, except that its first run of s_xyz is killed and its first run of s_static kills the
# worker that started it.
case "\$1" in
  */s_xyz) mkdir "$work/killed_slam" 2>/dev/null && kill -KILL \$\$ ;;
  */s_static) mkdir "$work/killed_worker" 2>/dev/null && kill -KILL \$PPID && sleep 30 ;;
esac
exec "$slam" "\$@"
EOF
chmod +x "$work/flaky_slam"
"$python" "$scripts/pf2_batch" --pf2-slam "$work/flaky_slam" --pf2-eval "$eval_bin" \
  --pf2-humans-eval "$humans" "$work/seqs/s_xyz" "$work/seqs/s_static" "$work/seqs_bad/broken" \
  -o "$work/failing" --detector none --frames 10 --workers 2 > "$work/failing.out" 2> "$work/failing.err"
code=$?
[ "$code" -eq 1 ] || fail "a batch with a failed run exits $code (want 1)"
grep -q "3 runs (0 skipped as complete, 1 failed)" "$work/failing.out" || fail "failing: $(cat "$work/failing.out")"
grep -q "^FAILED broken .*after 2 attempts.*missing or unreadable colour image" "$work/failing.err" ||
  fail "the failed run is not reported on the terminal: $(cat "$work/failing.err")"
"$python" - "$work/failing/results.csv" <<'PY' || fail "failing: table"
import csv, sys
rows = {r["sequence"]: r for r in csv.DictReader(open(sys.argv[1]))}
assert sorted(rows) == ["broken", "s_static", "s_xyz"], sorted(rows)
broken, xyz, static = rows["broken"], rows["s_xyz"], rows["s_static"]
assert broken["status"] == "failed" and broken["attempts"] == "2", broken
assert broken["note"].count("missing or unreadable colour image") == 2, broken["note"]
assert xyz["status"] == "ok" and xyz["attempts"] == "2" and xyz["frames"] == "10", xyz
assert "killed by signal SIGKILL" in xyz["note"], xyz["note"]
assert static["status"] == "ok" and static["attempts"] == "2" and static["frames"] == "10", static
assert "worker" in static["note"] and "died" in static["note"], static["note"]
PY
grep -q "the attempt above ended with its worker" "$work"/failing/s_static-*/pf2_slam.log ||
  fail "the killed worker's attempt is not in the run's log"
# Run again: the two complete runs are skipped, the failed one is tried again.
"$python" "$scripts/pf2_batch" --pf2-slam "$work/flaky_slam" --pf2-eval "$eval_bin" \
  --pf2-humans-eval "$humans" "$work/seqs/s_xyz" "$work/seqs/s_static" "$work/seqs_bad/broken" \
  -o "$work/failing" --detector none --frames 10 --workers 1 > "$work/failing2.out" 2>&1
grep -q "3 runs (2 skipped as complete, 1 failed)" "$work/failing2.out" || fail "failing rerun: $(tail -n 2 "$work/failing2.out")"

# Bad input: one error line naming it, exit 1, no batch folder.
refused() {
  local name=$1; shift
  local err code
  err=$(batch "$@" -o "$work/refused" 2>&1 >/dev/null); code=$?
  [ "$code" -eq 1 ] || fail "$name: exit code $code (want 1)"
  [ "$(printf '%s\n' "$err" | wc -l)" -eq 1 ] || fail "$name: not one error line: $err"
  printf "%s" "$err" | grep -qF -- "$name" || fail "$name not named in: $err"
  [ ! -e "$work/refused" ] || fail "$name: a batch folder was created"
}
refused "unknown setting 'map.voxels'" "$work/seqs/s_xyz" --set map.voxels=0.01,0.02
refused "map.voxel_size = 100: outside its range" "$work/seqs/s_xyz" --set map.voxel_size=0.02,100
refused "not a sequence folder (no rgb.txt)" "$work/seqs/s_xyz" "$work/seqs"
refused "no folder matches" "$work/nowhere/*"
printf 'map.build: [true\n' > "$work/bad.yaml"
refused "bad.yaml:2: not valid YAML/JSON" "$work/seqs/s_xyz" --grid "$work/bad.yaml"
refused "expected KEY=VALUE" "$work/seqs/s_xyz" --set map.build
refused "settings preset=fast: no preset 'fast' (presets: offline)" "$work/seqs/s_xyz" --preset fast
refused "pf2_slam not found" "$work/seqs/s_xyz" --pf2-slam "$work/nowhere/pf2_slam"

[ "$failures" -eq 0 ] && echo "pf2_batch: all checks passed"
exit $((failures > 0))
