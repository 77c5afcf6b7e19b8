#!/usr/bin/env python3
"""changes_near.py STATS_JSON ALIGNMENT X,Y,Z [RADIUS]: exit 0 when replay's stats.json reports a
scene change cell (localization.changes, in the prior map's frame) within RADIUS metres (default
1.0) of the point X,Y,Z of the ground truth's frame; ALIGNMENT x,y,z,qx,qy,qz,qw (`handscan eval
--start-in-frame`) moves the cells from the estimate's frame into the ground truth's. Prints the
nearest cell and its distance."""
import json
import math
import sys

stats = json.load(open(sys.argv[1]))
tx, ty, tz, qx, qy, qz, qw = (float(v) for v in sys.argv[2].split(","))
target = [float(v) for v in sys.argv[3].split(",")]
radius = float(sys.argv[4]) if len(sys.argv) > 4 else 1.0


def rotate(v):
    # v' = q v q*, via t = 2 q_vec x v; v' = v + w t + q_vec x t
    x, y, z = v
    t = (2 * (qy * z - qz * y), 2 * (qz * x - qx * z), 2 * (qx * y - qy * x))
    return (x + qw * t[0] + (qy * t[2] - qz * t[1]),
            y + qw * t[1] + (qz * t[0] - qx * t[2]),
            z + qw * t[2] + (qx * t[1] - qy * t[0]))


best = None
for cell in stats["localization"]["changes"]:
    r = rotate((cell["x"], cell["y"], cell["z"]))
    p = (r[0] + tx, r[1] + ty, r[2] + tz)
    d = math.dist(p, target)
    if best is None or d < best[0]:
        best = (d, p, cell["points"])
if best is None:
    print("no change cell reported")
    sys.exit(1)
print(f"nearest change cell ({best[1][0]:.2f}, {best[1][1]:.2f}, {best[1][2]:.2f}) with "
      f"{best[2]} points, {best[0]:.2f} m from ({target[0]}, {target[1]}, {target[2]})")
sys.exit(0 if best[0] <= radius else 1)
