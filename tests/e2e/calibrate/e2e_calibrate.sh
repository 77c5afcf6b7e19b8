#!/usr/bin/env bash
# `handscan calibrate` end to end. A 40 s house walk recorded with the true calibration
# (config/calibration.yaml, device.yaml's latencies: IMU 1.0 ms, encoder 0.12 ms) is calibrated
# from a START with every error of issue 13's table at once: the laser 1 deg roll, 1 deg pitch,
# 0.5 deg yaw and 1 cm off on its shaft, the encoder zero 0.3 deg off, the IMU latency 2.5 ms and
# the encoder latency 1.5 ms off (replayed as it is, tracking is lost after 5 s). Checked:
#  - each recovered value against the truth, within 3 reported standard deviations and the issue's
#    accuracy (0.05 deg, 2 mm, 0.05 deg, 0.3 ms). The encoder's latency is not separable from its
#    zero at a constant shaft speed, so the zero is checked as the effective one: the rotation the
#    pipeline applies, Rz(w * (latency - true latency) - zero) * R_shaft_laser, against the truth's;
#  - `replay --calibration` with the written file: ATE and mean drift within 1.5x of the true
#    calibration's.
# Measured (house 40 s seed 31): see the commit message.
# Usage: e2e_calibrate.sh HANDSCAN_BIN WORK_DIR
set -euo pipefail
source "$(dirname "$0")/../e2e_lib.sh"
e2e_begin e2e_calibrate "$1" "$2"
config=$(dirname "$0")/../../../config

"$bin" -q sim --scene house --duration 40 --seed 31 --no-camera --out "$work/walk.mcap" > /dev/null
cp "$config/camchain.yaml" "$work/"
cat > "$work/start.yaml" <<YAML
T_shaft_laser:
  translation: [0.01, 0.0, 0.05]
  rpy_deg: [1.0, -89.0, 0.5]
T_camera_shaftbase:
  translation: [0.0, 0.08, 0.0]
  rpy_deg: [0.0, 0.0, 0.0]
encoder_zero_offset_deg: 0.3
time_offsets:
  xsens_frame_latency_ms: 3.5
  motor_tpdo_latency_ms: 1.62
camchain: camchain.yaml
YAML

"$bin" -q calibrate "$work/walk.mcap" --calibration "$work/start.yaml" --out "$work/found.yaml" \
  > "$work/calibrate.txt" || { cat "$work/calibrate.txt"; fail "calibrate failed"; }
cat "$work/calibrate.txt"

python3 - "$config/calibration.yaml" "$work/found.yaml" <<'PY' || fail "recovered calibration off the truth"
import math, re, sys

def mul(A, B):
    if isinstance(B[0], list):
        return [[sum(A[i][k] * B[k][j] for k in range(3)) for j in range(3)] for i in range(3)]
    return [sum(A[i][k] * B[k] for k in range(3)) for i in range(3)]

def transpose(A):
    return [[A[j][i] for j in range(3)] for i in range(3)]

def rot(axis, deg):
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    i, j = [(1, 2), (2, 0), (0, 1)][axis]
    R = [[1.0 if a == b else 0.0 for b in range(3)] for a in range(3)]
    R[i][i] = c; R[j][j] = c; R[i][j] = -s; R[j][i] = s
    return R

def load(path):
    text = open(path).read()
    block = re.search(r"T_shaft_laser:[^\n]*\n\s*translation: \[([^\]]*)\][^\n]*\n\s*rpy_deg: \[([^\]]*)\]", text)
    t = [float(v) for v in block.group(1).split(",")]
    r, p, y = [float(v) for v in block.group(2).split(",")]
    zero = float(re.search(r"encoder_zero_offset_deg:\s*([-0-9.e]+)", text).group(1))
    def opt(key, default):
        m = re.search(key + r":\s*([-0-9.e]+)", text)
        return float(m.group(1)) if m else default
    std = {m.group(1): float(m.group(2)) for m in re.finditer(r"# (.*?): [-0-9.]+ \w+ \(std ([0-9.e]+)\)", text)}
    return dict(R=mul(rot(2, y), mul(rot(1, p), rot(0, r))), t=t, zero=zero,
                imu=opt("xsens_frame_latency_ms", 1.0), enc=opt("motor_tpdo_latency_ms", 0.12), std=std)

truth, found = load(sys.argv[1]), load(sys.argv[2])
w_deg_per_ms = 360.0 / 1000.0  # the simulated shaft: 1 rev/s
def effective(c):  # what the pipeline applies: Rz(w * latency error - zero) * R_shaft_laser
    turn = w_deg_per_ms * (c["enc"] - truth["enc"]) - c["zero"]
    return mul(rot(2, turn), c["R"]), mul(rot(2, turn), c["t"])
Rt, tt = effective(truth)
Rf, tf = effective(found)
D = mul(Rf, transpose(Rt))
err_deg = [math.degrees(v / 2.0) for v in (D[2][1] - D[1][2], D[0][2] - D[2][0], D[1][0] - D[0][1])]
dt_mm = [(a - b) * 1e3 for a, b in zip(tf, tt)]
s = found["std"]
checks = [
    ("rotation about shaft x", err_deg[0], s["laser roll about shaft x"], 0.05, "deg"),
    ("rotation about shaft y", err_deg[1], s["laser pitch about shaft y"], 0.05, "deg"),
    ("effective encoder zero", err_deg[2], s["encoder zero"], 0.05, "deg"),
    ("shift along shaft x", dt_mm[0], s["laser shift along shaft x"], 2.0, "mm"),
    ("shift along shaft y", dt_mm[1], s["laser shift along shaft y"], 2.0, "mm"),
    ("IMU latency", found["imu"] - truth["imu"], s["IMU time offset"], 0.3, "ms"),
]
ok = True
for name, e, sd, target, unit in checks:
    good = abs(e) <= 3.0 * sd and abs(e) <= target
    ok &= good
    print(f"{name}: error {e:+.4f} {unit}, reported std {sd:.4f}, target {target} -> {'ok' if good else 'FAIL'}")
sys.exit(0 if ok else 1)
PY

"$bin" -q replay "$work/walk.mcap" --out "$work/true" --fast --no-colour > /dev/null
"$bin" -q replay "$work/walk.mcap" --out "$work/found" --fast --no-colour --calibration "$work/found.yaml" > /dev/null
"$bin" eval --gt "$work/walk.gt.tum" --est "$work/true/trajectory.tum" > "$work/eval_true.txt"
"$bin" eval --gt "$work/walk.gt.tum" --est "$work/found/trajectory.tum" > "$work/eval_found.txt"
ate_true=$(eval_rmse "$work/eval_true.txt" '^ATE')
ate_found=$(eval_rmse "$work/eval_found.txt" '^ATE')
drift_true=$(awk '/^drift mean:/ {print $3; exit}' "$work/eval_true.txt")
drift_found=$(awk '/^drift mean:/ {print $3; exit}' "$work/eval_found.txt")
echo "true calibration: ATE $ate_true m, drift $drift_true %; calibrated: ATE $ate_found m, drift $drift_found %"
at_most "$ate_found" "$(awk -v a="$ate_true" 'BEGIN {print 1.5 * a}')" || fail "ATE $ate_found m > 1.5x the true calibration's $ate_true m"
at_most "$drift_found" "$(awk -v a="$drift_true" 'BEGIN {print 1.5 * a}')" || fail "drift $drift_found % > 1.5x the true calibration's $drift_true %"
echo "e2e_calibrate: ok"
