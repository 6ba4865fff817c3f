#!/usr/bin/env bash
# The run report as a browser shows it. Headless Chromium loads the sample report and
#   1. its DOM holds every <svg class="plot"> of the file, each with a drawn series (path data);
#   2. a copy of the page with a probe script finds each plot laid out (non-zero size) and each
#      series with geometry (bounding box, length): the plots rendered, not just parsed;
#   3. a screenshot is written and is not blank (size, and colours when OpenCV's Python is there).
# The report itself has no script; the probe is added to a copy here only.
#
# usage: report_chromium_test.sh FIXTURE WORK_DIR PYTHON
# Exit 77 (skipped) when Chromium is not installed (Debian: apt-get install chromium).
set -euo pipefail
fixture=$1
work=$2
python=$3

# PF2_CHROMIUM names the browser to use instead (e.g. another build); only it is tried then.
if [ -n "${PF2_CHROMIUM:-}" ]; then
  candidates=("$PF2_CHROMIUM")
else
  candidates=(/usr/bin/chromium "$(command -v chromium 2>/dev/null || true)")
fi
browser=""
for candidate in "${candidates[@]}"; do
  if [ -n "$candidate" ] && [ -x "$candidate" ]; then
    browser=$candidate
    break
  fi
done
if [ -z "$browser" ]; then
  echo "SKIP: chromium is not installed (Debian package chromium)"
  exit 77
fi

rm -rf "$work"
mkdir -p "$work"
"$fixture" "$work/report.html"

# A container has no sandbox support and a small /dev/shm; a private profile keeps parallel runs apart.
chromium_run() {
  timeout 60 "$browser" --headless --no-sandbox --disable-gpu --disable-dev-shm-usage --no-first-run \
    --user-data-dir="$work/profile" "$@" 2>>"$work/chromium.log"
}

# 1. The DOM after loading.
chromium_run --dump-dom "file://$work/report.html" >"$work/dom.html"
"$python" - "$work/report.html" "$work/dom.html" <<'PY'
import re, sys
source = open(sys.argv[1], encoding="utf-8").read()
dom = open(sys.argv[2], encoding="utf-8").read()
ids = re.findall(r'<svg class="plot" id="([^"]+)"', source)
assert len(ids) >= 6, f"expected at least 6 plots in the report, found {ids}"
dom_ids = re.findall(r'<svg class="plot" id="([^"]+)"', dom)
assert dom_ids == ids, f"plots in the DOM {dom_ids} differ from the file's {ids}"
for plot_id in ids:
    start = dom.index(f'<svg class="plot" id="{plot_id}"')
    svg = dom[start:dom.index("</svg>", start)]
    paths = re.findall(r'<path class="series"[^>]*\sd="([^"]*)"', svg)
    assert any(re.match(r"M-?[0-9.]+,-?[0-9.]+", d) for d in paths), f"{plot_id}: no series with path data"
print(f"DOM: {len(ids)} plots, each with drawn series: {' '.join(ids)}")
PY

# 2. Layout and geometry, measured by a probe script in a copy of the page.
probe='<script>
const lines = [];
for (const svg of document.querySelectorAll("svg.plot")) {
  const box = svg.getBoundingClientRect();
  let drawn = 0, length = 0;
  for (const path of svg.querySelectorAll(".series")) {
    const b = path.getBBox();
    if (b.width + b.height > 0) drawn++;
    length += path.getTotalLength();
  }
  lines.push([svg.id, Math.round(box.width), Math.round(box.height), drawn, Math.round(length)].join(" "));
}
const pre = document.createElement("pre");
pre.id = "render-check";
pre.textContent = lines.join("\n");
document.body.appendChild(pre);
</script>'
"$python" - "$work/report.html" "$work/probe.html" "$probe" <<'PY'
import sys
page = open(sys.argv[1], encoding="utf-8").read()
open(sys.argv[2], "w", encoding="utf-8").write(page.replace("</body>", sys.argv[3] + "\n</body>"))
PY
chromium_run --window-size=1100,900 --dump-dom "file://$work/probe.html" >"$work/probe_dom.html"
"$python" - "$work/report.html" "$work/probe_dom.html" <<'PY'
import re, sys
ids = re.findall(r'<svg class="plot" id="([^"]+)"', open(sys.argv[1], encoding="utf-8").read())
found = re.search(r'<pre id="render-check">(.*?)</pre>', open(sys.argv[2], encoding="utf-8").read(), re.S)
assert found, "the probe script did not run"
rows = [line.split() for line in found.group(1).strip().splitlines()]
assert [row[0] for row in rows] == ids, f"probe saw {[row[0] for row in rows]}, the file has {ids}"
for plot_id, width, height, drawn, length in rows:
    assert int(width) > 100 and int(height) > 50, f"{plot_id}: laid out {width}x{height}"
    assert int(drawn) >= 1 and int(length) > 0, f"{plot_id}: {drawn} series drawn, total length {length}"
    print(f"rendered: {plot_id} {width}x{height} px, {drawn} series, {length} px of lines")
PY

# 3. A screenshot of the top of the page.
chromium_run --hide-scrollbars --window-size=1100,2400 --screenshot="$work/report.png" "file://$work/report.html" \
  >/dev/null
"$python" - "$work/report.png" <<'PY'
import os, sys
path = sys.argv[1]
size = os.path.getsize(path)
assert size > 10_000, f"{path}: {size} bytes, expected a picture of the page"
try:
    import cv2, numpy
except ImportError:
    print(f"screenshot: {size} bytes (no cv2: colours not counted)")
    sys.exit(0)
image = cv2.imread(path)
assert image is not None, f"{path}: not a readable PNG"
colours = len(numpy.unique(image.reshape(-1, 3), axis=0))
assert colours > 50, f"{path}: only {colours} colours, looks blank"
print(f"screenshot: {image.shape[1]}x{image.shape[0]}, {size} bytes, {colours} colours")
PY
echo "pf2_report_chromium: passed"
