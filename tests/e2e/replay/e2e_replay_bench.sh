#!/usr/bin/env bash
# `handscan replay REC --bench N`: N runs of the recording --fast, each timed in wall and process
# CPU time, the medians as real-time factors, the modules' per-call costs, and DIR/bench.json with
# every figure; the outputs are those of an ordinary replay. Checked: the printed and written
# figures agree, every run is timed, and a wrong run count is refused by name.
# Usage: e2e_replay_bench.sh HANDSCAN_BIN WORK_DIR
set -euo pipefail
source "$(dirname "$0")/../e2e_lib.sh"
e2e_begin e2e_replay_bench "$1" "$2"

"$bin" -q sim --scene office --duration 8 --seed 5 --no-camera --out "$work/walk.mcap" > /dev/null
"$bin" -q replay "$work/walk.mcap" --out "$work/out" --bench 3 > "$work/bench.txt"
cat "$work/bench.txt"
grep -q '^bench: 3 runs of ' "$work/bench.txt" || fail "no summary line"
grep -q 'imu_prediction .* us x [1-9]' "$work/bench.txt" || fail "no per-call cost of the IMU prediction"
[ -s "$work/out/trajectory.tum" ] && [ -s "$work/out/stats.json" ] || fail "the replay's outputs are missing"
python3 - "$work/out/bench.json" "$work/bench.txt" <<'PY' || fail "bench.json disagrees with itself or the printout"
import json, re, statistics, sys
b = json.load(open(sys.argv[1]))
text = open(sys.argv[2]).read()
runs = b["runs"]
assert len(runs) == 3, runs
assert all(r["wall_s"] > 0 and r["cpu_s"] > 0 for r in runs), runs
assert 7.5 < b["recording_s"] < 8.5, b["recording_s"]
assert abs(b["median_cpu_s"] - statistics.median(r["cpu_s"] for r in runs)) < 1e-9
assert abs(b["realtime_factor_cpu"] - b["recording_s"] / b["median_cpu_s"]) < 1e-9
assert abs(b["realtime_factor_wall"] - b["recording_s"] / b["median_wall_s"]) < 1e-9
printed = float(re.search(r"median ([0-9.]+)x real time on one core", text).group(1))
assert abs(printed - b["realtime_factor_cpu"]) < 0.006, (printed, b["realtime_factor_cpu"])
assert b["modules_last_run"]["imu_prediction"]["calls"] > 1000
PY
status=0
"$bin" -q replay "$work/walk.mcap" --out "$work/zero" --bench 0 > "$work/zero.txt" 2>&1 || status=$?
[ "$status" -ne 0 ] || fail "--bench 0 accepted"
grep -q -- "--bench" "$work/zero.txt" || fail "--bench 0 refused without naming the option"
echo "e2e_replay_bench: ok"
