#!/usr/bin/env bash
# `handscan replay --modules` and `--skip-every-other` on short simulated office walks (8 s):
# - a dark recording (`sim --dark`) with `--modules all`: the tracking camera solves nothing, the
#   visual-inertial odometry is bypassed from its second frame on (stats.json "vio"), and the
#   result is byte for byte that of `--modules imu,laser` (a bypassed camera changes nothing);
# - a lit one: the VIO solves directions on most frames, its solved directions reach every
#   sweep's stats ("vio_solved_dof_mask"), and `--modules imu,vision` replays without the laser;
# - `--skip-every-other` halves every stream; `--modules imu,vision` without /camera/track is
#   refused with a message naming the channel.
# Measured (seed 5): dark bypass from frame 2 (20 ms), trajectory identical; lit 8 s: VIO
# used on most frames.
# Usage: e2e_replay_modules.sh HANDSCAN_BIN WORK_DIR
set -euo pipefail
source "$(dirname "$0")/../e2e_lib.sh"
e2e_begin e2e_replay_modules "$1" "$2"

"$bin" -q sim --scene office --duration 8 --seed 5 --dark --no-colour --out "$work/dark.mcap"
"$bin" -q replay "$work/dark.mcap" --out "$work/dark_il" --fast --modules imu,laser
"$bin" -q replay "$work/dark.mcap" --out "$work/dark_all" --fast --modules all
cmp "$work/dark_il/trajectory.tum" "$work/dark_all/trajectory.tum" ||
  fail "dark camera: --modules all differs from imu,laser (the bypassed VIO changed the result)"
/usr/bin/python3 - "$work/dark_all/stats.json" <<'PY' || fail "dark camera not bypassed within 1 s"
import json, sys
v = json.load(open(sys.argv[1]))["vio"]
b = v["bypassed"]
print(f"dark: {v['processed']} frames processed, {v['used']} used, bypassed {b}")
assert v["processed"] > 100 and v["used"] == 0, "a dark frame was used"
assert b and b[0]["begin_s"] - v["first_frame_s"] <= 1.0, "bypass later than 1 s"
assert b[0]["end_s"] is None and b[0]["frames"] >= v["processed"] - 1, "bypass did not hold"
PY

"$bin" -q sim --scene office --duration 8 --seed 5 --no-colour --out "$work/lit.mcap"
"$bin" -q replay "$work/lit.mcap" --out "$work/lit_all" --fast --modules all
"$bin" -q replay "$work/lit.mcap" --out "$work/lit_vis" --fast --modules imu,vision
"$bin" -q replay "$work/lit.mcap" --out "$work/lit_il" --fast
"$bin" -q replay "$work/lit.mcap" --out "$work/lit_skip" --fast --skip-every-other
/usr/bin/python3 - "$work" <<'PY' || fail "modules or skip-every-other wrong on the lit walk"
import json, sys
w = sys.argv[1]
a = json.load(open(f"{w}/lit_all/stats.json"))
v = a["vio"]
print(f"lit all: {v['processed']} frames, {v['used']} used, {v['all_solved']} all solved, "
      f"{v['mean_features']:.0f} features, {v['mean_with_laser_depth']:.0f} with laser depth")
assert v["used"] >= 0.8 * v["processed"], "the lit camera solved too few frames"
assert v["mean_with_laser_depth"] > 3, "no laser depth reached the VIO"
matched = [s for s in a["per_sweep"][1:] if s["associations"] > 0]
with_vio = sum(1 for s in matched if s["vio_solved_dof_mask"] != 0)
print(f"lit all: {with_vio} of {len(matched)} matched sweeps carry VIO-solved directions")
assert matched and with_vio >= 0.5 * len(matched), "VIO directions missing from per_sweep"
vis = json.load(open(f"{w}/lit_vis/stats.json"))
assert vis["sweeps"] == 0 and vis["vio"]["used"] > 0 and vis["poses"] > 1000, "imu,vision"
il = json.load(open(f"{w}/lit_il/stats.json"))
sk = json.load(open(f"{w}/lit_skip/stats.json"))
assert "vio" not in il, "imu,laser ran the VIO"
for key in ("samples",):
    r = sk["imu"][key] / il["imu"][key]
    assert abs(r - 0.5) < 0.01, f"--skip-every-other kept {r:.3f} of the IMU samples"
r = sk["sweep_assembly"]["scans"] / il["sweep_assembly"]["scans"]
assert abs(r - 0.5) < 0.01, f"--skip-every-other kept {r:.3f} of the scans"
print(f"skip-every-other: IMU {sk['imu']['samples']} of {il['imu']['samples']}, scans "
      f"{sk['sweep_assembly']['scans']} of {il['sweep_assembly']['scans']}")
PY

"$bin" -q sim --scene office --duration 3 --seed 5 --no-camera --out "$work/nocam.mcap"
if "$bin" -q replay "$work/nocam.mcap" --out "$work/nocam" --fast --modules imu,vision \
     2> "$work/nocam.err"; then
  fail "--modules imu,vision on a recording without /camera/track did not fail"
fi
grep -q "/camera/track" "$work/nocam.err" || fail "the refusal does not name /camera/track"
echo "e2e_replay_modules: ok"
