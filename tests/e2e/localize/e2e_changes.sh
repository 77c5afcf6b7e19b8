#!/usr/bin/env bash
# The change report of a session localized on an earlier one (section 9, issue 14), end to end on
# scenes and seeds the report was not developed on:
#  - the courtyard unchanged (two walks, the second from half way round the loop): no change
#    cell (before the report used the earlier session's visibility, surfaces the second session
#    saw for the first time were reported: 361-375 cells on courtyard walks);
#  - the office with 3 of its 20 objects moved: every cell where one of them stood or now stands
#    (precision 1), and half the moved objects both sessions saw reported (recall).
# Usage: e2e_changes.sh HANDSCAN_BIN WORK_DIR
set -euo pipefail
here=$(dirname "$0")
source "$here/../e2e_lib.sh"
e2e_begin e2e_changes "$1" "$2"

# session_pair SCENE SEED1 SEED2 CHANGES NAME: sim both sessions, replay the first, replay the
# second on it with a start hint 1 m and 15 deg off; leaves $work/NAME-frame.txt (alignment).
session_pair() {
  local scene=$1 s1=$2 s2=$3 changes=$4 name=$5
  "$bin" -q sim --scene "$scene" --duration 40 --seed "$s1" --no-camera --out "$work/$name-1.mcap" > /dev/null
  "$bin" -q sim --scene "$scene" --duration 30 --seed "$s2" --start-at 0.5 --scene-change "$changes" \
    --no-camera --out "$work/$name-2.mcap" > "$work/$name-sim2.txt"
  "$bin" -q replay "$work/$name-1.mcap" --out "$work/$name-1" --fast > /dev/null
  "$bin" eval --gt "$work/$name-2.gt.tum" --est "$work/$name-1/trajectory.tum" \
    --frame-gt "$work/$name-1.gt.tum" --frame-est "$work/$name-1/trajectory.tum" --start-in-frame \
    > "$work/$name-frame.txt"
  local start hint
  start=$(awk -F': ' '/^start in the estimate/ {print $2}' "$work/$name-frame.txt")
  hint=$(python3 "$here/perturb_pose.py" "$start" 1.0 15.0)
  "$bin" -q replay "$work/$name-2.mcap" --out "$work/$name-2" --fast --prior-map "$work/$name-1" \
    --initial-pose="$hint" > /dev/null
  python3 -c 'import json, sys; sys.exit(0 if json.load(open(sys.argv[1]))["localization"]["locked"] else 1)' \
    "$work/$name-2/stats.json" || fail "$name: session 2 did not lock on session 1"
}

alignment() { awk -F': ' '/^alignment/ {print $2}' "$work/$1-frame.txt"; }

session_pair courtyard 91 92 0 courtyard
echo "courtyard, nothing moved:"
python3 "$here/changes_where_moved.py" "$work/courtyard-2/stats.json" "$(alignment courtyard)" \
  "$work/courtyard-sim2.txt" 1.0 0 || fail "changes reported in the unchanged courtyard"

session_pair office 93 94 3 office
cat "$work/office-sim2.txt"
echo "office, 3 objects moved:"
# Precision and recall against what the simulator moved (its stdout): every cell within 1 m of a
# moved object, and at least half of the objects both sessions saw reported (here the table of
# the two objects seen by both; the chair is not: see README, the change report's limits).
python3 "$here/changes_where_moved.py" "$work/office-2/stats.json" "$(alignment office)" \
  "$work/office-sim2.txt" 1.0 --maps "$work/office-1/map.ply" "$work/office-2/map.ply" \
  --min-recall 0.5 || fail "office: a change reported where nothing moved, or too few found"
echo "e2e_changes: OK"
