#!/usr/bin/env bash
# The UI's "calibrate" through the real daemon: a 25 s simulated house walk recorded with the true
# calibration is scanned by handscan-pipeline (fake devices on real transports, `handscan hil`)
# started with a wrong START calibration (laser 0.4 deg roll and 0.4 deg pitch off on its shaft,
# encoder zero 0.2 deg off). The daemon records the scan's raw streams beside its journal; the
# calibrate command (sent as the UI does, after the export) runs `handscan calibrate` on that
# recording on an idle-priority thread and writes the field calibration (--field-calibration, as
# the installed unit: /var/lib/handscan/calibration), the factory file staying untouched
# (/etc/handscan is read-only under the unit's ProtectSystem=strict). Checked: the scan has its
# raw.mcap, the field file is new and nearer the truth than START (laser rotation, encoder
# zero), START is unchanged, there is no .prev yet (the factory file is the previous one), and
# the new scan the operator starts next runs with the new file (no restart of the daemon).
# Usage: e2e_hil_calibrate.sh HANDSCAN_BIN HANDSCAN_PIPELINE_BIN WORK_DIR
set -euo pipefail
source "$(dirname "$0")/../e2e_lib.sh"
e2e_begin e2e_hil_calibrate "$1" "$3"
daemon=$2
config=$(dirname "$0")/../../../config

"$bin" -q sim --scene house --duration 25 --seed 41 --no-camera --out "$work/walk.mcap" > /dev/null
mkdir -p "$work/cal"
cp "$config/camchain.yaml" "$work/cal/"
cat > "$work/cal/calibration.yaml" <<YAML
T_shaft_laser:
  translation: [0.0, 0.0, 0.05]
  rpy_deg: [0.4, -89.6, 0.0]
T_camera_shaftbase:
  translation: [0.0, 0.08, 0.0]
  rpy_deg: [0.0, 0.0, 0.0]
encoder_zero_offset_deg: 0.2
camchain: camchain.yaml
YAML
cp "$work/cal/calibration.yaml" "$work/start.yaml"
field="$work/state/calibration/calibration.yaml"

"$bin" -q hil "$work/walk.mcap" --out "$work/hil" --daemon "$daemon" --no-camera \
  --calibration "$work/cal/calibration.yaml" --field-calibration "$field" --calibrate 2 |
  tee "$work/hil.txt"
grep -q "^calibrate: calibrated.*factory calibration kept" "$work/hil.txt" || fail "the daemon did not answer calibrated"
grep -q "calibration: $work/cal/calibration.yaml" "$work/hil/daemon.log" ||
  fail "the daemon did not start from the factory calibration (no field calibration yet)"
# The new scan after it runs with the new calibration, without a restart of the daemon.
grep -q "calibration: $field in use from this scan" "$work/hil/daemon.log" ||
  fail "the scan after the calibration did not take the new calibration"
ls "$work"/hil/journal/scan-*/raw.mcap > /dev/null || fail "the daemon recorded no raw.mcap beside the journal"
cmp -s "$work/start.yaml" "$work/cal/calibration.yaml" || fail "the factory calibration was changed"
[ -f "$field" ] || fail "no field calibration written at $field"
[ -e "$field.prev" ] && fail "$field.prev exists after the first calibration"
grep -q "Written by \`handscan calibrate\`" "$field" || fail "the field calibration is not calibrate's"

python3 - "$config/calibration.yaml" "$work/start.yaml" "$field" <<'PY' || fail "the new calibration is not nearer the truth"
import math, re, sys

def mul(A, B):
    return [[sum(A[i][k] * B[k][j] for k in range(3)) for j in range(3)] for i in range(3)]

def rot(axis, deg):
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    i, j = [(1, 2), (2, 0), (0, 1)][axis]
    R = [[1.0 if a == b else 0.0 for b in range(3)] for a in range(3)]
    R[i][i] = c; R[j][j] = c; R[i][j] = -s; R[j][i] = s
    return R

def load(path):
    text = open(path).read()
    block = re.search(r"T_shaft_laser:[^\n]*\n\s*translation: \[([^\]]*)\][^\n]*\n\s*rpy_deg: \[([^\]]*)\]", text)
    r, p, y = [float(v) for v in block.group(2).split(",")]
    zero = float(re.search(r"encoder_zero_offset_deg:\s*([-0-9.e]+)", text).group(1))
    # What the pipeline applies: the laser's rotation on the shaft turned by minus the zero.
    return mul(rot(2, -zero), mul(rot(2, y), mul(rot(1, p), rot(0, r))))

def angle_deg(A, B):
    D = mul(A, [[B[j][i] for j in range(3)] for i in range(3)])
    return math.degrees(math.acos(max(-1.0, min(1.0, (D[0][0] + D[1][1] + D[2][2] - 1) / 2))))

truth, start, found = (load(p) for p in sys.argv[1:4])
before, after = angle_deg(start, truth), angle_deg(found, truth)
print(f"laser on the shaft incl. encoder zero: START {before:.3f} deg off the truth, "
      f"calibrated {after:.3f} deg")
assert after < 0.5 * before, f"{after:.3f} deg is not nearer than half of START's {before:.3f} deg"
PY
echo "e2e_hil_calibrate: ok"
