#!/usr/bin/env bash
# End to end on degenerate scenes: 50 s walks (3 s still, then walking) in the simulator's
# smooth tunnel and open field, replayed with laser + IMU. Checks that every sweep flags the
# directions the scan matcher cannot solve (stats.json) and that the trajectory stays bounded.
# Measured (seed 2): tunnel ATE 0.76 m, field 3.3 m; before the motion prior in unsolved
# directions 44 m and 14 m (and km-scale over 90 s).
# Then a 60 s walk in the corridor (seed 6), whose axis a few door recesses hold only weakly:
# the matcher must confirm it by re-association (scan::ScanMatcherConfig::
# degeneracy_probe_max_std_m) rather than leave it to the walker's motion prior. Measured: ATE
# 0.02 m; with the axis held at the prior (the hard threshold of eq. 21 alone) 3.7 m.
# Usage: e2e_degenerate.sh HANDSCAN_BIN WORK_DIR
set -euo pipefail
source "$(dirname "$0")/../e2e_lib.sh"
e2e_begin e2e_degenerate "$1" "$2"

# scene, max ATE rmse (m), minimum degenerate directions expected on most sweeps[, duration, seed]
check() {
  local scene=$1 max_ate=$2 min_deg=$3 duration=${4:-50} seed=${5:-2}
  "$bin" -q sim --scene "$scene" --duration "$duration" --seed "$seed" --no-camera --out "$work/$scene.mcap"
  "$bin" -q replay "$work/$scene.mcap" --out "$work/$scene" --fast
  "$bin" eval --gt "$work/$scene.gt.tum" --est "$work/$scene/trajectory.tum" > "$work/$scene.eval.txt"
  cat "$work/$scene.eval.txt"
  local ate
  ate=$(eval_rmse "$work/$scene.eval.txt" '^ATE')
  [ -n "$ate" ] || fail "$scene: eval printed no ATE rmse"
  at_most "$ate" "$max_ate" || fail "$scene: ATE rmse $ate m above $max_ate m"
  # The degenerate directions of every matched sweep are in stats.json: most sweeps must flag
  # at least min_deg of them (the tunnel: its axis; the field: x, y and yaw).
  /usr/bin/python3 - "$work/$scene/stats.json" "$min_deg" "$scene" <<'PY' || fail "$scene: degenerate directions not flagged"
import json, sys
d = json.load(open(sys.argv[1]))
need, scene = int(sys.argv[2]), sys.argv[3]
sweeps = [s for s in d["per_sweep"] if s["associations"] > 0]
flagged = sum(1 for s in sweeps if s["degenerate_directions"] >= need)
print(f"{scene}: {flagged} of {len(sweeps)} matched sweeps flag >= {need} degenerate directions; "
      f"histogram {d['degenerate_directions_histogram']}")
sys.exit(0 if sweeps and flagged >= 0.8 * len(sweeps) else 1)
PY
  echo "$scene: ATE rmse $ate m (bound $max_ate m)"
}

check tunnel 5.0 1
check field 8.0 2
check corridor 0.5 0 60 6
echo "e2e_degenerate: ok"
