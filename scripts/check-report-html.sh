#!/usr/bin/env bash
# Renders a sweep's report.html in headless Chromium (Debian's `chromium`), checks the
# screenshot is not blank (not all pixels one colour), the page logged no console errors,
# and the DOM has the provenance, tables and inline SVG charts, with no external resource.
# Usage: scripts/check-report-html.sh [results-dir]  (default: runs configs/movingai.toml).
set -euo pipefail
cd "$(dirname "$0")/.."
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
results=${1:-}
if [ -z "$results" ]; then
  results="$work/results"
  cargo run -q -p xtask --release -- experiment configs/movingai.toml --output "$results"
fi
page="$(cd "$results" && pwd)/report.html"
browser=$(command -v chromium || command -v chromium-browser)
flags=(--headless --no-sandbox --disable-gpu --no-first-run --disable-background-networking
       --disable-component-update --disable-sync --window-size=1200,2000)
"$browser" "${flags[@]}" --user-data-dir="$work/profile-shot" --enable-logging=stderr --v=0 \
  --screenshot="$work/shot.png" "file://$page" 2>"$work/log.txt" >/dev/null || true
"$browser" "${flags[@]}" --user-data-dir="$work/profile-dom" --dump-dom "file://$page" \
  >"$work/dom.html" 2>/dev/null
if grep -iE "CONSOLE.*(error|uncaught)|Uncaught" "$work/log.txt"; then
  echo "report.html logged console errors" >&2
  exit 1
fi
${KEEP_SCREENSHOT:+cp "$work/shot.png" "$KEEP_SCREENSHOT"}
python3 - "$work/shot.png" "$work/dom.html" <<'PY'
import struct, sys, zlib
png, dom = sys.argv[1], open(sys.argv[2], encoding="utf-8").read()
data = open(png, "rb").read()
assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
pos, idat, width, height = 8, b"", 0, 0
while pos < len(data):
    length, kind = struct.unpack(">I4s", data[pos:pos + 8])
    body = data[pos + 8:pos + 8 + length]
    if kind == b"IHDR":
        width, height, depth, colour = struct.unpack(">IIBB", body[:10])
        assert depth == 8 and colour in (2, 6), f"unexpected PNG format {depth} {colour}"
        channels = 3 if colour == 2 else 4
    elif kind == b"IDAT":
        idat += body
    pos += 12 + length
raw = zlib.decompress(idat)
stride = width * channels + 1
# Scanline filters change bytes, but a one-colour image has all-equal filtered rows
# after the first; count distinct raw rows and distinct bytes as a blankness test.
rows = {raw[i * stride + 1:(i + 1) * stride] for i in range(height)}
distinct = len(set(raw[1:stride])) + len(rows)
assert (width, height) == (1200, 2000), f"screenshot is {width}x{height}"
assert len(rows) > 10 and distinct > 12, "screenshot is blank (one colour)"
for needle in ("Provenance", "<table", "<svg", "Aggregates", "Charts"):
    assert needle in dom, f"report.html DOM lacks {needle}"
for bad in ("<script", "http://", "https://"):
    body = dom.replace('xmlns="http://www.w3.org/2000/svg"', "")
    assert bad not in body, f"report.html has an external reference or script: {bad}"
print(f"report.html check: {width}x{height} screenshot, {len(rows)} distinct rows: 1 passed, 0 failed")
PY
