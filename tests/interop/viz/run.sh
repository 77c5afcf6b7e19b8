#!/bin/sh
# CTest driver: a short simulated recording, `handscan replay --viz`, and the viz file read back by
# @mcap/core + protobufjs from its embedded descriptors (check_viz.mjs); then the replay's journal
# exported with `--format mcap` and that file checked the same way against the export.
# usage: run.sh HANDSCAN OUT_DIR. Exits 77 (skip) when node or the npm packages are missing.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
bin=$1
work=$2/viz
if ! command -v node >/dev/null 2>&1 || [ ! -d "$here/node_modules/protobufjs" ]; then
  echo "skipped: needs node and 'npm install' in $here (tools/test does it)"
  exit 77
fi
rm -rf "$work"
mkdir -p "$work"
# 6 s of the office walk: a dozen sweeps, both cameras, ground truth.
"$bin" -q sim --scene office --duration 6 --seed 4 --out "$work/office.mcap"
"$bin" -q replay "$work/office.mcap" --fast --out "$work/replay" --viz "$work/office.viz.mcap"
# The camchain's sizes (config/camchain.yaml): the tracking camera 640x512, the colour 1600x1200.
node "$here/check_viz.mjs" "$work/office.viz.mcap" "$work/replay" 640x512 1600x1200 \
  "$here/../../../tools/foxglove/handscan-layout.json"
rec=$(stat -c %s "$work/office.mcap")
viz=$(stat -c %s "$work/office.viz.mcap")
echo "recording $rec bytes, viz $viz bytes"
[ "$viz" -le $((2 * rec)) ] || { echo "viz file $viz bytes > 2x the recording's $rec"; exit 1; }

# The journal's viz (export --format mcap): the same writer, poses and points from the journal.
mkdir -p "$work/stick"
"$bin" -q export "$work/replay" --to "$work/stick" --format mcap --name scan > "$work/export.txt"
points=$(node -e "console.log(JSON.parse(require('fs').readFileSync('$work/stick/scan/scan.json')).journal.points)")
node "$here/check_viz.mjs" "$work/stick/scan/scan.viz.mcap" "$work/stick/scan" 640x512 1600x1200 \
  "$here/../../../tools/foxglove/handscan-layout.json" --journal "$points"
journal=$(stat -c %s "$work/replay/journal.hsj")
jviz=$(stat -c %s "$work/stick/scan/scan.viz.mcap")
echo "journal $journal bytes, its viz $jviz bytes"
