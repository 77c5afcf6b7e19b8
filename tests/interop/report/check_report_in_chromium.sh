#!/usr/bin/env bash
# Opens the fixture's report.html in headless Chromium under Xvfb, offline, with a fresh profile,
# screenshots it and checks the picture shows the top-down map (check_screenshot.py).
set -euo pipefail
out=$1
here=$(cd "$(dirname "$0")" && pwd)
html=$out/target/walk/report.html
[ -f "$html" ] || { echo "no $html (did the fixture run?)"; exit 1; }
command -v chromium >/dev/null || { echo "chromium is not installed (tools/install-deps)"; exit 77; }
command -v xvfb-run >/dev/null || { echo "xvfb-run is not installed (tools/install-deps)"; exit 77; }
# Self-contained: nothing the page would fetch (the SVG namespace is a name, not a fetch).
if grep -Eo '(src|href)="[a-z]+:' "$html" | grep -v 'src="data:' ; then
  echo "report.html refers to something outside itself"; exit 1
fi
profile=$(mktemp -d)
trap 'rm -rf "$profile"' EXIT
rm -f "$out/screenshot.png"
timeout 120 xvfb-run -a chromium --headless --no-sandbox --disable-gpu \
  --disable-background-networking --no-first-run --disable-component-update --disable-sync \
  --user-data-dir="$profile" --window-size=1300,1500 --hide-scrollbars \
  --screenshot="$out/screenshot.png" "file://$html" 2>"$out/chromium.log" || {
  echo "chromium failed:"; tail -20 "$out/chromium.log"; exit 1; }
/usr/bin/python3 "$here/check_screenshot.py" "$out/screenshot.png"
