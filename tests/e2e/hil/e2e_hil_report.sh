#!/usr/bin/env bash
# The report of a scan the daemon journaled has the module timeline and the devices' rates, from
# the journal's per-sweep records, and it agrees with the report of a replay of the same
# recording: a 16 s simulated office walk through `handscan hil` (fake devices, the real
# handscan-pipeline, exported through the shared-memory command) and through `handscan replay`
# + `handscan export`. The timeline's data (data-lane / data-from / data-to of every span, the
# devices' table) is compared, not just looked for.
# Usage: e2e_hil_report.sh HANDSCAN_BIN HANDSCAN_PIPELINE_BIN WORK_DIR
set -euo pipefail
source "$(dirname "$0")/../e2e_lib.sh"
e2e_begin e2e_hil_report "$1" "$3"
daemon=$2

"$bin" -q sim --scene office --duration 16 --seed 6 --no-camera --out "$work/office.mcap"
"$bin" -q hil "$work/office.mcap" --out "$work/hil" --daemon "$daemon" --no-camera
"$bin" -q replay "$work/office.mcap" --out "$work/replay" --fast
mkdir -p "$work/replay-export"
"$bin" -q export "$work/replay" --to "$work/replay-export" --format ply --name replay
daemon_report=$(find "$work/hil/export" -name report.html | head -1)
replay_report="$work/replay-export/replay/report.html"
[ -s "$daemon_report" ] || fail "the daemon's export has no report.html"
[ -s "$replay_report" ] || fail "the replay's export has no report.html"

python3 - "$daemon_report" "$replay_report" <<'PY' || fail "the reports' timelines do not agree"
import re, sys

def facts(path):
    html = open(path).read()
    m = re.search(r"From the (\S+) \((\d+) sweeps\)", html)
    assert m, f"{path}: no module timeline"
    assert "timeline unavailable" not in html, f"{path}: says the timeline is unavailable"
    lanes = {}
    for colour, lane, a, b in re.findall(
            r'fill="(#[0-9a-f]+)" data-lane="([^"]+)" data-from="([0-9.]+)" data-to="([0-9.]+)"', html):
        lanes.setdefault(lane, {}).setdefault(colour, 0.0)
        lanes[lane][colour] += float(b) - float(a)
    devices = {d: (float(mean), float(low), int(drop)) for d, mean, low, drop in re.findall(
        r'<tr data-device="([^"]+)"><td>[^<]+</td><td>([0-9.]+) [^<]+</td><td>([0-9.]+) [^<]+</td>'
        r'<td>(\d+)</td></tr>', html)}
    return m.group(1), int(m.group(2)), lanes, devices

scan, imu = "#3c78eb", "#f59628"
d_src, d_n, d_lanes, d_dev = facts(sys.argv[1])
r_src, r_n, r_lanes, r_dev = facts(sys.argv[2])
print(f"daemon: {d_n} sweeps from the {d_src}, devices {d_dev}")
print(f"replay: {r_n} sweeps from the {r_src}, devices {r_dev}")
assert d_src == "journal" and r_src == "journal", (d_src, r_src)
assert d_n >= 10, f"the daemon journaled only {d_n} sweeps of a 16 s walk"
assert abs(d_n - r_n) <= 2, f"{d_n} sweeps against replay's {r_n}"
for lane in ["rx", "ry", "rz", "tx", "ty", "tz"]:
    d, r = d_lanes.get(lane, {}), r_lanes.get(lane, {})
    d_total, r_total = sum(d.values()), sum(r.values())
    assert d_total > 10 and r_total > 10, f"{lane}: {d_total:.1f} s / {r_total:.1f} s drawn"
    d_share, r_share = d.get(scan, 0) / d_total, r.get(scan, 0) / r_total
    print(f"{lane}: scan matching {100 * d_share:.0f} % (daemon) / {100 * r_share:.0f} % (replay)")
    assert abs(d_share - r_share) <= 0.15, f"{lane}: {d_share:.2f} against {r_share:.2f}"
for dev, nominal in [("laser", 40.0), ("IMU", 100.0), ("encoder", 50.0)]:
    assert dev in d_dev and dev in r_dev, f"{dev} missing from a report's devices table"
    (dm, dl, dd), (rm, rl, rd) = d_dev[dev], r_dev[dev]
    assert dm >= 0.5 * nominal, f"{dev}: daemon {dm}/s"
    assert abs(dm - rm) <= 0.1 * rm, f"{dev}: daemon {dm}/s, replay {rm}/s"
    assert dd == 0 and rd == 0, f"{dev}: dropouts daemon {dd}, replay {rd}"
PY
echo "e2e_hil_report: ok"
