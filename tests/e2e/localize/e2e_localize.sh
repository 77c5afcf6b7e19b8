#!/usr/bin/env bash
# Localization on an existing map (section 9, issue 14) end to end: a 40 s house walk is session 1
# (replayed: its trajectory, journal and feature map); session 2 walks the same house from half
# way round the loop (upstairs) with one of its eight pieces of furniture moved (--scene-change
# 1), and is replayed with --prior-map on session 1 and a start hint 1 m and 15 deg off the
# truth. Checked:
#  - the localizer locked (stats.json localization.locked) and its tracking matches were used;
#  - a second replay --fast gives the same trajectory and map bytes (the matches run on the
#    localizer's own thread);
#  - session 1 without its feature map (its journal's points stand in): ATE at most 2 cm too;
#  - session 2's trajectory in session 1's frame: ATE against its ground truth moved into that
#    frame by session 1's own alignment (eval --frame-gt/--frame-est) at most 2 cm;
#  - every change reported lies within 1 m of where the moved object stood or now stands (this
#    walk sees little of it: none may be reported; e2e_changes.sh checks that changes are found);
#  - `handscan merge` of both sessions: one cloud with both session ids.
# Usage: e2e_localize.sh HANDSCAN_BIN WORK_DIR
set -euo pipefail
here=$(dirname "$0")
source "$here/../e2e_lib.sh"
e2e_begin e2e_localize "$1" "$2"

"$bin" -q sim --scene house --duration 40 --seed 61 --no-camera --out "$work/s1.mcap" > /dev/null
"$bin" -q sim --scene house --duration 30 --seed 62 --start-at 0.5 --scene-change 1 --no-camera \
  --out "$work/s2.mcap" > "$work/sim2.txt"
cat "$work/sim2.txt"
"$bin" -q replay "$work/s1.mcap" --out "$work/s1" --fast > /dev/null
[ -s "$work/s1/feature_map.hsf" ] || fail "session 1 wrote no feature_map.hsf"

"$bin" eval --gt "$work/s2.gt.tum" --est "$work/s1/trajectory.tum" --frame-gt "$work/s1.gt.tum" \
  --frame-est "$work/s1/trajectory.tum" --start-in-frame > "$work/frame.txt"
alignment=$(awk -F': ' '/^alignment/ {print $2}' "$work/frame.txt")
start=$(awk -F': ' '/^start in the estimate/ {print $2}' "$work/frame.txt")
hint=$(python3 "$here/perturb_pose.py" "$start" 1.0 15.0)
echo "session 2 starts at $start in session 1's frame; hint $hint"

"$bin" -q replay "$work/s2.mcap" --out "$work/s2" --fast --prior-map "$work/s1" \
  --initial-pose="$hint" > /dev/null
# The matches run on the localizer's thread; --fast applies each at a fixed sweep: same bytes.
"$bin" -q replay "$work/s2.mcap" --out "$work/s2again" --fast --prior-map "$work/s1" \
  --initial-pose="$hint" > /dev/null
for f in trajectory.tum map.ply; do
  cmp "$work/s2/$f" "$work/s2again/$f" || fail "two replays --fast --prior-map differ in $f"
done
python3 - "$work/s2/stats.json" <<'PY' || fail "session 2 did not lock on session 1's map"
import json, sys
l = json.load(open(sys.argv[1]))["localization"]
print(f"locked {l['locked']} at {l['lock_s']} s: on map {l['lock_on_map']:.3f} (runner-up "
      f"{l['lock_runner_up']:.3f}), {l['updates']} updates ({l['rejected_updates']} refused), "
      f"max correction {l['max_correction_m'] * 1e3:.1f} mm, {l['cpu_ms']:.0f} ms CPU "
      f"({100 * l['cpu_share_of_core']:.1f} % of a core), {len(l['changes'])} change cells")
sys.exit(0 if l["locked"] and l["updates"] >= 5 else 1)
PY

"$bin" eval --gt "$work/s2.gt.tum" --est "$work/s2/trajectory.tum" --frame-gt "$work/s1.gt.tum" \
  --frame-est "$work/s1/trajectory.tum" > "$work/eval2.txt"
cat "$work/eval2.txt"
ate=$(eval_rmse "$work/eval2.txt" '^ATE')
at_most "$ate" 0.02 || fail "session 2 ATE in session 1's frame $ate m > 0.02 m"

# A scan that left no feature map (older firmware, or the file lost) is continued on its
# journal's points: session 1 without feature_map.hsf.
mkdir -p "$work/s1journal"
cp "$work/s1/journal.hsj" "$work/s1journal/"
"$bin" -q replay "$work/s2.mcap" --out "$work/s2journal" --fast --prior-map "$work/s1journal" \
  --initial-pose="$hint" > /dev/null 2>&1
"$bin" eval --gt "$work/s2.gt.tum" --est "$work/s2journal/trajectory.tum" \
  --frame-gt "$work/s1.gt.tum" --frame-est "$work/s1/trajectory.tum" > "$work/eval2journal.txt"
ate_journal=$(eval_rmse "$work/eval2journal.txt" '^ATE')
echo "on session 1's journal alone: ATE $ate_journal m"
at_most "$ate_journal" 0.02 || fail "continued on the journal alone: ATE $ate_journal m > 0.02 m"

python3 "$here/changes_where_moved.py" "$work/s2/stats.json" "$alignment" "$work/sim2.txt" 1.0 ||
  fail "a scene change reported where nothing moved"

"$bin" -q merge "$work/s1" "$work/s2" --out "$work/merged" > "$work/merge.txt" || fail "merge failed"
cat "$work/merge.txt"
python3 - "$work/merged/sessions.json" <<'PY' || fail "merged map inconsistent"
import json, sys
m = json.load(open(sys.argv[1]))
s = m["sessions"]
ok = len(s) == 2 and all(x["points"] > 0 for x in s)
c = m.get("consistency", {})
print(f"merged {m['points']} points; session 2 against session 1 where they overlap: median "
      f"{c.get('median_m', -1) * 1e3:.1f} mm over {c.get('overlap_points', 0)} points")
sys.exit(0 if ok and c.get("overlap_points", 0) > 1000 and c["median_m"] <= 0.01 else 1)
PY
echo "e2e_localize: OK"
