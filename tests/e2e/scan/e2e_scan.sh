#!/usr/bin/env bash
# End to end on the digital twin: simulate a scan -> info -> replay (twice, byte-identical) ->
# accuracy against ground truth -> export -> replay of a recording cut short by a power cut.
# Usage: e2e_scan.sh HANDSCAN_BIN WORK_DIR
set -euo pipefail
source "$(dirname "$0")/../e2e_lib.sh"
e2e_begin e2e_scan "$1" "$2"

# 14 s: 3 s standing still, then walking through the first room. This test guards the tool
# chain and the accuracy reached so far (ATE 1.3 cm with IMU feedback; 60 s walks in the issue
# notes).
"$bin" -q sim --scene office --duration 14 --seed 3 --no-camera --out "$work/office.mcap"
[ -s "$work/office.gt.tum" ] || fail "no ground truth written"

"$bin" info "$work/office.mcap" > "$work/info.txt"
for topic in /hokuyo/raw /xsens/raw /motor/can /groundtruth/pose; do
  grep -q -- "$topic" "$work/info.txt" || fail "info does not list $topic"
done

"$bin" -q replay "$work/office.mcap" --out "$work/r1" --fast
"$bin" -q replay "$work/office.mcap" --out "$work/r2" --fast
for f in trajectory.tum map.ply; do
  [ -s "$work/r1/$f" ] || fail "replay wrote no $f"
  cmp -s "$work/r1/$f" "$work/r2/$f" || fail "$f differs between two --fast replays (not deterministic)"
done
grep -q '"realtime_factor"' "$work/r1/stats.json" || fail "stats.json without realtime_factor"
# The map within a 1 MiB budget (tiles flushed to a scratch file and merged back at the end): the
# same map.ply, and no scratch file left behind.
"$bin" -q replay "$work/office.mcap" --out "$work/r3" --fast --map-memory 1 --map-tile 2
cmp -s "$work/r1/map.ply" "$work/r3/map.ply" || fail "map.ply differs when built out of core (--map-memory 1)"
grep -q '"fragments_flushed": [1-9]' "$work/r3/stats.json" || fail "a 1 MiB map budget flushed no tiles"
if ls -A "$work/r3" | grep -q spill; then fail "the map's scratch file was left behind"; fi

"$bin" eval --gt "$work/office.gt.tum" --est "$work/r1/trajectory.tum" > "$work/eval.txt"
cat "$work/eval.txt"
ate=$(eval_rmse "$work/eval.txt" '^ATE')
[ -n "$ate" ] || fail "eval printed no ATE rmse"
at_most "$ate" "${HANDSCAN_E2E_MAX_ATE:-0.05}" || fail "ATE rmse $ate m above ${HANDSCAN_E2E_MAX_ATE:-0.05} m"
# The 200 Hz trajectory the scan keeps is as good as the scan matches it lies between (issue 12:
# within 1.2x of the matched sweep poses' ATE; before fusion::TrajectorySmoother it was 1.5x).
/usr/bin/python3 - "$work/r1/stats.json" "$work/sweeps.tum" <<'PY'
import json, sys
with open(sys.argv[2], "w") as out:
    for s in json.load(open(sys.argv[1]))["per_sweep"]:
        if s["in_map"]:
            out.write("%.9f %s\n" % (s["t_start_s"], " ".join("%.9f" % v for v in s["pose_xyz_qxyzw"])))
PY
"$bin" eval --gt "$work/office.gt.tum" --est "$work/sweeps.tum" > "$work/eval_sweeps.txt"
sweep_ate=$(eval_rmse "$work/eval_sweeps.txt" '^ATE')
at_most "$ate" "$(awk -v s="$sweep_ate" 'BEGIN { print 1.2 * s + 0.0005 }')" ||
  fail "200 Hz trajectory ATE $ate m against the matched sweeps' $sweep_ate m (more than 1.2x)"

mkdir -p "$work/stick"
"$bin" -q export "$work/r1" --to "$work/stick" --format ply,las,e57 --name scan > "$work/export.txt"
for f in cloud.ply cloud.las cloud.e57 trajectory.tum trajectory.csv scan.json report.html; do
  [ -s "$work/stick/scan/$f" ] || fail "export wrote no $f"
done
if command -v weasyprint > /dev/null; then
  [ "$(head -c 5 "$work/stick/scan/report.pdf" 2>/dev/null)" = "%PDF-" ] \
    || fail "weasyprint is installed but the export wrote no report.pdf"
fi
"$bin" info "$work/stick/scan/cloud.e57" > "$work/e57info.txt" || fail "handscan info cannot read cloud.e57"
# The independent E57 reader (npm web-e57, installed by tools/test) on the replay's export.
interop=$(cd "$(dirname "$0")/../../interop/export" && pwd)
if command -v node > /dev/null && [ -d "$interop/node_modules/web-e57" ]; then
  node --experimental-wasm-modules "$interop/check_e57.mjs" "$work/stick/scan" 2>/dev/null \
    || fail "web-e57 does not read the export's cloud.e57 as its cloud.ply"
fi

# A power cut while recording: the file ends mid-chunk; replay uses every intact chunk.
size=$(stat -c %s "$work/office.mcap")
head -c $((size * 2 / 3)) "$work/office.mcap" > "$work/cut.mcap"
"$bin" -q replay "$work/cut.mcap" --out "$work/rcut" --fast
[ -s "$work/rcut/trajectory.tum" ] || fail "replay of a truncated recording wrote no trajectory"
grep -q '"truncated": true' "$work/rcut/stats.json" || fail "stats.json does not report the truncation"
# With the colour camera: map points the camera saw carry its colours, the rest intensity grey.
"$bin" -q sim --scene office --duration 8 --seed 4 --out "$work/colour.mcap"
"$bin" -q replay "$work/colour.mcap" --out "$work/rcol" --fast
grep -q '"colourisation"' "$work/rcol/stats.json" || fail "replay did not colourise"
coloured=$(/usr/bin/python3 - "$work/rcol/map.ply" <<'PY'
import sys
import numpy as np
f = open(sys.argv[1], "rb")
h = b""
while not h.endswith(b"end_header\n"):
    h += f.read(1)
n = int([l for l in h.decode().split("\n") if l.startswith("element vertex")][0].split()[-1])
a = np.frombuffer(f.read(), dtype=np.dtype([("x", "<f4"), ("y", "<f4"), ("z", "<f4"), ("r", "u1"), ("g", "u1"),
                                            ("b", "u1"), ("i", "<u2"), ("t", "<f8")]), count=n)
print(f"{((a['r'] != a['g']) | (a['g'] != a['b'])).mean():.3f}")
PY
)
awk -v c="$coloured" 'BEGIN { exit !(c >= 0.10) }' || fail "only a fraction $coloured of the map took camera colour"
echo "e2e_scan: ok (ATE rmse $ate m, sweeps $sweep_ate m, coloured fraction $coloured)"
