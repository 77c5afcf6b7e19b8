#!/usr/bin/env bash
# "Continue scan" on the device (section 9, issue 14): session 1, a 40 s house walk, replayed
# (its journal and feature map); session 2, 30 s from half way round the loop with one piece of
# furniture moved, played by the fake devices over their real transports into the real
# handscan-pipeline (`handscan hil`), which continues session 1 through the shared-memory command
# (`--continue`, start hint 1 m and 15 deg off the truth, as a tap on the screen gives it).
# Checked: the status block said locked; the daemon's trajectory in session 1's frame within 2 cm
# ATE of the ground truth (moved into that frame by session 1's alignment); the daemon's journal
# names session 1 (its copy), and `handscan merge` takes it as in session 1's frame, its points on session
# 1's surfaces (median point-to-plane at most 1 cm, no doubled walls).
# Usage: e2e_continue_hil.sh HANDSCAN_BIN HANDSCAN_PIPELINE_BIN WORK_DIR
set -euo pipefail
here=$(dirname "$0")
source "$here/../e2e_lib.sh"
e2e_begin e2e_continue_hil "$1" "$3"
daemon=$2

"$bin" -q sim --scene house --duration 40 --seed 61 --no-camera --out "$work/s1.mcap" > /dev/null
"$bin" -q sim --scene house --duration 30 --seed 62 --start-at 0.5 --scene-change 1 --no-camera \
  --out "$work/s2.mcap" > /dev/null
"$bin" -q replay "$work/s1.mcap" --out "$work/s1" --fast > /dev/null
start=$("$bin" eval --gt "$work/s2.gt.tum" --est "$work/s1/trajectory.tum" \
  --frame-gt "$work/s1.gt.tum" --frame-est "$work/s1/trajectory.tum" --start-in-frame |
  awk -F': ' '/^start in the estimate/ {print $2}')
hint=$(python3 "$here/perturb_pose.py" "$start" 1.0 15.0)

"$bin" hil "$work/s2.mcap" --out "$work/hil" --daemon "$daemon" --no-camera \
  --continue "$work/s1" --initial-pose="$hint" | tee "$work/hil.txt"
grep -q "locked .* s into the recording" "$work/hil.txt" || fail "the daemon did not lock on session 1"

"$bin" eval --gt "$work/s2.gt.tum" --est "$work/hil/trajectory.tum" --frame-gt "$work/s1.gt.tum" \
  --frame-est "$work/s1/trajectory.tum" > "$work/eval.txt"
grep -E '^(poses|ATE)' "$work/eval.txt"
ate=$(eval_rmse "$work/eval.txt" '^ATE')
at_most "$ate" 0.02 || fail "the continued scan's ATE in session 1's frame $ate m > 0.02 m"

# As on the device: the earlier scan (session 1's copy in the daemon's journal directory) and
# the one continuing it.
scan=$(ls -d "$work"/hil/journal/scan-* | tail -1)
"$bin" -q merge "$work/hil/journal/earlier-scan" "$scan" --out "$work/merged" > /dev/null ||
  fail "merge failed"
python3 - "$work/merged/sessions.json" <<'PY' || fail "the continued scan is not in session 1's frame"
import json, sys
m = json.load(open(sys.argv[1]))
s, c = m["sessions"], m.get("consistency", {})
print(f"merged {m['points']} points; the daemon's session in session 1's frame: {s[1]['in_frame']}; "
      f"against session 1 where they overlap: median {c.get('median_m', -1) * 1e3:.1f} mm over "
      f"{c.get('overlap_points', 0)} points")
sys.exit(0 if s[1]["in_frame"] and c.get("overlap_points", 0) > 1000 and c["median_m"] <= 0.01 else 1)
PY
echo "e2e_continue_hil: OK (ATE $ate m)"
