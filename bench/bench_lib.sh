# Helpers shared by the end-to-end benchmark scripts; `source` it.

# json_field FILE KEY: the number after "KEY": in a one-line JSON file (stats.json, pf2_eval --json).
json_field() {
  grep -o "\"$2\":[-0-9.e]*" "$1" | head -n 1 | cut -d: -f2
}

# removal_row LABEL1 LABEL2 JSON: a markdown row of pf2_detect --json's removal figures:
# | LABEL1 | LABEL2 | recall % | precision % | retention % | filter median ms |
removal_row() {
  python3 - "$1" "$2" "$3" <<'PY'
import json, sys
r = json.loads(sys.argv[3])
print(f"| {sys.argv[1]} | {sys.argv[2]} | {100 * r['recall']:.2f} | {100 * r['precision']:.2f} | "
      f"{100 * r['retention']:.2f} | {r['filter_median_ms']:.2f} |")
PY
}
