#!/bin/sh
# CTest driver: write a sample recording with our writer, read it with @mcap/core.
# usage: run.sh WRITER OUT_DIR. Exits 77 (skip) when node or the npm packages are missing.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
writer=$1
out=$2/interop_sample.mcap
if ! command -v node >/dev/null 2>&1 || [ ! -d "$here/node_modules/@mcap/core" ]; then
  echo "skipped: needs node and 'npm install' in $here (tools/test does it)"
  exit 77
fi
"$writer" "$out"
node "$here/check_recording.mjs" "$out" "$out.expected.json"
