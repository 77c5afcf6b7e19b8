#!/usr/bin/env python3
"""changes_where_moved.py STATS_JSON ALIGNMENT SIM_STDOUT RADIUS [MAX_CELLS]: checks replay's
change report (stats.json localization.changes, in the prior map's frame) against the objects
`handscan sim --scene-change` moved (its stdout: "moved NAME from X,Y,Z to X,Y,Z, ..."). ALIGNMENT
x,y,z,qx,qy,qz,qw (`handscan eval --start-in-frame`) moves the cells into the ground truth's frame.
Every cell must lie within RADIUS metres (horizontally) of where a moved object stood or now
stands; with no object moved, at most MAX_CELLS (default 0) cells may be reported. Prints each
cell, its kind and its distance to the nearest moved object's old and new place."""
import json
import math
import re
import sys

stats = json.load(open(sys.argv[1]))
tx, ty, tz, qx, qy, qz, qw = (float(v) for v in sys.argv[2].split(","))
radius = float(sys.argv[4])
max_unmoved = int(sys.argv[5]) if len(sys.argv) > 5 else 0
moved = []
for line in open(sys.argv[3]):
    m = re.match(r"moved (\S+) from (\S+) to (\S+),", line)
    if m:
        moved.append((m.group(1), [float(v) for v in m.group(2).split(",")],
                      [float(v) for v in m.group(3).split(",")]))


def rotate(v):
    # v' = q v q*, via t = 2 q_vec x v; v' = v + w t + q_vec x t
    x, y, z = v
    t = (2 * (qy * z - qz * y), 2 * (qz * x - qx * z), 2 * (qx * y - qy * x))
    return (x + qw * t[0] + (qy * t[2] - qz * t[1]),
            y + qw * t[1] + (qz * t[0] - qx * t[2]),
            z + qw * t[2] + (qx * t[1] - qy * t[0]))


cells = stats["localization"]["changes"]
check = stats["localization"]["change_check"]
print(f"{len(cells)} change cells; {check}")
stray = 0
for c in cells:
    r = rotate((c["x"], c["y"], c["z"]))
    p = (r[0] + tx, r[1] + ty, r[2] + tz)
    near = [(math.dist(p[:2], a[:2]), math.dist(p[:2], b[:2]), name) for name, a, b in moved]
    best = min((min(a, b), name) for a, b, name in near) if near else (math.inf, "-")
    stray += best[0] > radius
    print(f"  {c.get('kind', '?'):9s} ({p[0]:.2f}, {p[1]:.2f}, {p[2]:.2f}) {c['points']} points: "
          f"{best[0]:.2f} m from the {best[1]}" + ("  <- nothing moved here" if best[0] > radius else ""))
if not moved:
    sys.exit(0 if len(cells) <= max_unmoved else 1)
sys.exit(0 if stray == 0 else 1)
