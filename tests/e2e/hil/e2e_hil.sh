#!/usr/bin/env bash
# `handscan hil` end to end: a 20 s simulated office walk played by the fake Hokuyo (loopback
# TCP), the fake MTi (pty), the CAN log (candump on the host clock) and both cameras (V4L2 replay
# devices on the host clock) into the real handscan-pipeline, scanned and exported through the
# shared-memory commands. Checks the trajectory against ground truth, the exported cloud against
# the scene mesh, no sample dropped, the colour camera's colours in the journal, and the faults:
# the laser's TCP connection dropped, the daemon killed (-9) mid-scan, no IMU.
# Usage: e2e_hil.sh HANDSCAN_BIN HANDSCAN_PIPELINE_BIN WORK_DIR
set -euo pipefail
source "$(dirname "$0")/../e2e_lib.sh"
e2e_begin e2e_hil "$1" "$3"
daemon=$2

# The tracking camera at 10 frames/s instead of 50 keeps the recording small (its frames are
# played but not used yet); the recording's device.yaml is the one hil gives the daemon.
sed '/^tracking_camera:/,/^[a-z]/ s/^  fps: .*/  fps: 10/' "$(dirname "$0")/../../../config/device.yaml" > "$work/device.yaml"
grep -A6 '^tracking_camera:' "$work/device.yaml" | grep -q 'fps: 10' || fail "could not set the tracking camera's rate"
"$bin" -q sim --scene office --duration 20 --seed 4 --device "$work/device.yaml" --out "$work/office.mcap"
"$bin" -q sim --scene office --export-mesh "$work/office.ply"

# json_number FILE KEY: the first number after "KEY": in a JSON file.
json_number() { grep -o "\"$2\": [0-9.eE+-]*" "$1" | head -1 | awk '{print $2}'; }

# 1. The recording as recorded: trajectory and map against the truth, nothing dropped.
"$bin" -q hil "$work/office.mcap" --out "$work/run" --daemon "$daemon" --device "$work/device.yaml" \
  --viz "$work/run/scan.viz.mcap"
for f in trajectory.tum trajectory.host.tum stats.json map.ply daemon.log device.yaml; do
  [ -s "$work/run/$f" ] || fail "hil wrote no $f"
done
ls "$work"/run/journal/scan-*/journal.hsj > /dev/null || fail "no journal"
"$bin" eval --gt "$work/office.gt.tum" --est "$work/run/trajectory.tum" > "$work/eval.txt"
cat "$work/eval.txt"
ate=$(eval_rmse "$work/eval.txt" '^ATE')
[ -n "$ate" ] || fail "eval printed no ATE rmse"
at_most "$ate" "${HANDSCAN_E2E_HIL_MAX_ATE:-0.03}" || fail "ATE rmse $ate m above ${HANDSCAN_E2E_HIL_MAX_ATE:-0.03} m"
"$bin" eval --map "$work/run/map.ply" --mesh "$work/office.ply" --gt "$work/office.gt.tum" \
  --est "$work/run/trajectory.tum" > "$work/eval_map.txt"
cat "$work/eval_map.txt"
median=$(awk '/median/ {for (i = 1; i <= NF; ++i) if ($i == "median") {print $(i + 1); exit}}' "$work/eval_map.txt")
[ -n "$median" ] || fail "eval printed no map median"
at_most "$median" 0.03 || fail "exported points median $median m from the true surfaces"
dropped=$(json_number "$work/run/stats.json" samples_dropped)
[ "$dropped" = 0 ] || fail "$dropped samples dropped"
sent=$(json_number "$work/run/stats.json" hokuyo_scans_sent)
recorded=$(json_number "$work/run/stats.json" hokuyo_scans_recorded)
[ "$sent" = "$recorded" ] || fail "the fake laser sent $sent of $recorded scans"
rss=$(json_number "$work/run/stats.json" peak_rss_mib)
at_most 1 "$rss" || fail "no peak RSS measured"
# Every recorded frame reached the daemon's cameras' files, and the colour camera coloured the
# points it saw (`handscan replay` colours 22 % of this walk's points; the rest keep the laser's
# grey).
colour_frames=$(json_number "$work/run/stats.json" colour_camera_frames)
at_most 50 "$colour_frames" || fail "only $colour_frames colour frames played"
grep -q "colour-cam: connected" "$work/run/daemon.log" || fail "the daemon's colour camera did not start"
coloured=$(json_number "$work/run/stats.json" coloured_points)
journal_points=$(json_number "$work/run/stats.json" points)
share=$(awk -v c="$coloured" -v n="$journal_points" 'BEGIN {print c / n}')
at_most 0.10 "$share" || fail "only $coloured of $journal_points points coloured by the camera"
# --viz: the daemon's journal with the recording's frames and ground truth, read by @mcap/core and
# protobufjs (tests/interop/viz): /pose = trajectory.tum (the recording's clock), every journal
# point on /sweep, camera sizes as the camchain's, the ground truth aligned at the first pose.
viz_check=$(cd "$(dirname "$0")/../../interop/viz" && pwd)
if command -v node > /dev/null && [ -d "$viz_check/node_modules/protobufjs" ]; then
  node "$viz_check/check_viz.mjs" "$work/run/scan.viz.mcap" "$work/run" 640x512 1600x1200 \
    "$viz_check/../../../tools/foxglove/handscan-layout.json" --journal "$journal_points" \
    || fail "hil's viz file does not read back as the daemon's scan"
  echo "hil --viz: $(stat -c %s "$work/run/scan.viz.mcap") bytes for a $(stat -c %s "$work/office.mcap") byte recording"
fi

# 2. The laser's TCP connection dropped at 8 s: the driver reconnects, the scan goes on.
"$bin" -q hil "$work/office.mcap" --out "$work/disconnect" --daemon "$daemon" --device "$work/device.yaml" --no-camera --fault-hokuyo-disconnect 8
connections=$(json_number "$work/disconnect/stats.json" hokuyo_connections)
at_most 2 "$connections" || fail "the laser was not reconnected ($connections connections)"
"$bin" eval --gt "$work/office.gt.tum" --est "$work/disconnect/trajectory.tum" > "$work/eval_disconnect.txt"
ate_d=$(eval_rmse "$work/eval_disconnect.txt" '^ATE')
at_most "$ate_d" 0.10 || fail "ATE rmse $ate_d m after the reconnect"

# 3. kill -9 at 10 s: the restarted daemon recovers the journal and exports the scan, and its
# devices come back (the encoder's CANopen start-up answered again, the cameras restarted).
"$bin" -q hil "$work/office.mcap" --out "$work/kill" --daemon "$daemon" --device "$work/device.yaml" --kill-at 10
grep -q '"recovered_after_kill": true' "$work/kill/stats.json" || fail "journal not recovered after kill -9"
points=$(grep -A3 '"recovered"' "$work/kill/stats.json" | grep -o '"points": [0-9]*' | awk '{print $2}')
exported=$(json_number "$work/kill/stats.json" export_points)
at_most 10000 "$exported" || fail "the export after kill -9 holds $exported points"
[ "$exported" = "$points" ] || fail "exported $exported of the recovered journal's $points points"
for device in encoder colour-cam hokuyo; do
  lives=$(grep -c "\] $device: connected" "$work/kill/daemon.log" || true)
  [ "$lives" -ge 2 ] || fail "$device did not come back for the restarted daemon"
done

# 4. No IMU: the daemon runs on, says the IMU is missing, and journals no made-up motion.
if "$bin" -q hil "$work/office.mcap" --out "$work/noimu" --daemon "$daemon" --device "$work/device.yaml" --no-camera --no-xsens > "$work/noimu.txt" 2>&1; then
  poses=$(json_number "$work/noimu/stats.json" poses)
  [ "$poses" = 0 ] || fail "$poses poses without an IMU"
fi
grep -q "xsens" "$work/noimu/daemon.log" || fail "the daemon log does not mention the missing IMU"
echo "e2e_hil: ok (ATE rmse $ate m, map median $median m, $coloured of $journal_points points coloured, after reconnect $ate_d m, $exported points exported after kill -9)"
