#!/usr/bin/env bash
# Failures in the middle of a walk (issue 13; tools/sim incidents.hpp, lio::IncidentWatch):
#   --drop T          the scanner falls to the floor, lies 1.5 s, is picked up again;
#   --blind-laser T:5 the laser's window covered for 5 s while walking;
#   --imu-gap T:2     no IMU frame for 2 s.
# Each must be flagged (stats.json tracking.lost_intervals, with its reason) within 1 s of its
# start; no sweep of a lost interval may enter the map; after a drop or a blinded laser the walk
# recovers and the map stays as good as without the incident (no doubled walls: map error
# median within 1.3x + 1 mm of the clean walk's); after the IMU gap (heading and velocity lost)
# the scanner is found again on its own map (lio::Relocaliser) as the walk comes back into
# what was scanned, with the same map check.
# Measured (house 60 s seed 63, incidents at 25 s): clean ATE 3.2 mm, map median 5.4 mm; see
# the figures printed by each case. Held out (60 s walks, 2 s gap): house s61 and s63
# relocalised 10.5 s after the gap began, office s81 and courtyard s71 on coming back 28 s
# later, maps within 0.3 mm of clean; house s62, office s82, courtyard s72 stayed lost (no
# confirmed place), nothing of the lost walk in the map.
# Usage: e2e_incidents.sh HANDSCAN_BIN WORK_DIR
set -euo pipefail
source "$(dirname "$0")/../e2e_lib.sh"
e2e_begin e2e_incidents "$1" "$2"

"$bin" -q sim --scene house --export-mesh "$work/house.ply" > /dev/null
at=25

# run NAME [SIM ARGS]: prints "intervals reason flag_delay_s recovered leaked median_mm ate_mm".
run() {
  local name=$1
  shift
  "$bin" -q sim --scene house --duration 60 --seed 63 --no-camera --out "$work/$name.mcap" "$@" > /dev/null
  "$bin" -q replay "$work/$name.mcap" --out "$work/$name" --fast > /dev/null
  "$bin" -q eval --gt "$work/$name.gt.tum" --est "$work/$name/trajectory.tum" \
    --map "$work/$name/map.ply" --mesh "$work/house.ply" > "$work/$name.eval.txt"
  python3 - "$work/$name/stats.json" "$work/$name.eval.txt" "$at" <<'PY'
import json, re, sys
s = json.load(open(sys.argv[1]))
ev = open(sys.argv[2]).read()
at = 1000.0 + float(sys.argv[3])  # the simulator's host clock starts at 1000 s
t = s["tracking"]["lost_intervals"]
leaked = sum(1 for p in s["per_sweep"] if p["tracking"] == "lost" and p["in_map"])
median = float(re.search(r"map error .*median ([0-9.]+)", ev).group(1)) * 1000
ate = float(re.search(r"ATE .*rmse ([0-9.]+)", ev).group(1)) * 1000
if t:
    i = t[0]
    print(len(t), i["reason"], f"{i['flagged_s'] - at:.3f}", 0 if i["end_s"] is None else 1,
          leaked, f"{median:.2f}", f"{ate:.1f}")
else:
    print(0, "none", 0, 1, leaked, f"{median:.2f}", f"{ate:.1f}")
PY
}

read -r n _ _ _ leaked clean_median clean_ate < <(run clean)
[ "$n" -eq 0 ] || fail "clean walk: $n lost intervals (false alarm)"
bound=$(python3 -c "print($clean_median * 1.3 + 1.0)")

check() {  # check NAME REASON n reason delay recovered leaked median ate
  local name=$1 want=$2 n=$3 reason=$4 delay=$5 recovered=$6 leaked=$7 median=$8 ate=$9
  echo "$name: $n interval(s), $reason flagged after ${delay} s, recovered=$recovered, leaked=$leaked, map median ${median} mm (clean $clean_median), ATE ${ate} mm (clean $clean_ate)"
  [ "$n" -ge 1 ] || fail "$name: never flagged"
  [ "$reason" = "$want" ] || fail "$name: flagged as $reason, not $want"
  python3 -c "import sys; sys.exit(0 if -0.05 <= $delay <= 1.0 else 1)" || fail "$name: flagged ${delay} s after it began (at most 1 s)"
  [ "$leaked" -eq 0 ] || fail "$name: $leaked lost sweeps entered the map"
}

read -r n reason delay recovered leaked median ate < <(run drop --drop $at)
check drop dropped "$n" "$reason" "$delay" "$recovered" "$leaked" "$median" "$ate"
[ "$recovered" -eq 1 ] || fail "drop: never recovered"
python3 -c "import sys; sys.exit(0 if $median <= $bound else 1)" || fail "drop: map median $median mm > $bound mm"

read -r n reason delay recovered leaked median ate < <(run blind --blind-laser $at:5)
check blind laser_blind "$n" "$reason" "$delay" "$recovered" "$leaked" "$median" "$ate"
[ "$recovered" -eq 1 ] || fail "blind: never recovered"
python3 -c "import sys; sys.exit(0 if $median <= $bound else 1)" || fail "blind: map median $median mm > $bound mm"

read -r n reason delay recovered leaked median ate < <(run gap --imu-gap $at:2)
check gap imu_silent "$n" "$reason" "$delay" "$recovered" "$leaked" "$median" "$ate"
[ "$recovered" -eq 1 ] || fail "IMU gap: never relocalised"
grep -q relocalised "$work/gap/stats.json" || fail "IMU gap: recovered without a relocalisation"
python3 -c "import sys; sys.exit(0 if $median <= $bound else 1)" || fail "IMU gap: relocalised, but the map median is $median mm > $bound mm (a wrong place)"
echo "e2e_incidents: ok"
