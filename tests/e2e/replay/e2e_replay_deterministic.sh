#!/usr/bin/env bash
# `handscan replay --fast` is deterministic: the same recording gives the same trajectory and map
# bytes, run after run (the journal's chunks are cut on the wall clock, every 0.5 s, so its bytes
# are not compared). And replay at the recording's pace runs the same worker on the
# same source clock (the recording's log times, not the wall clock), so it gives the same
# trajectory too - only slower.
# Usage: e2e_replay_deterministic.sh HANDSCAN_BIN WORK_DIR
set -euo pipefail
source "$(dirname "$0")/../e2e_lib.sh"
e2e_begin e2e_replay_deterministic "$1" "$2"

"$bin" -q sim --scene office --duration 12 --seed 4 --out "$work/office.mcap"
"$bin" -q replay "$work/office.mcap" --out "$work/a" --fast
"$bin" -q replay "$work/office.mcap" --out "$work/b" --fast
for f in trajectory.tum map.ply; do
  [ -s "$work/a/$f" ] || fail "replay wrote no $f"
  cmp "$work/a/$f" "$work/b/$f" || fail "two replays --fast of one recording differ in $f"
done
sweeps=$(/usr/bin/python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["sweeps"])' "$work/a/stats.json")
[ "$sweeps" -ge 5 ] || fail "only $sweeps sweeps registered in 12 s"
"$bin" -q replay "$work/office.mcap" --out "$work/paced" --speed 3
cmp "$work/a/trajectory.tum" "$work/paced/trajectory.tum" ||
  fail "replay at the recording's pace (x3) gives another trajectory than --fast"
echo "e2e_replay_deterministic: $sweeps sweeps; --fast twice and paced x3 give the same bytes"
