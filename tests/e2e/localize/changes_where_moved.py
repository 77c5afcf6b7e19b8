#!/usr/bin/env python3
"""changes_where_moved.py STATS_JSON ALIGNMENT SIM_STDOUT RADIUS [MAX_CELLS] [--maps S1_PLY S2_PLY
[--min-recall R]]: checks replay's
change report (stats.json localization.changes, in the prior map's frame) against the objects
`handscan sim --scene-change` moved (its stdout: "moved NAME from X,Y,Z to X,Y,Z, ..."). ALIGNMENT
x,y,z,qx,qy,qz,qw (`handscan eval --start-in-frame`) moves the cells into the ground truth's frame.
Every cell must lie within RADIUS metres (horizontally) of where a moved object stood or now
stands; with no object moved, at most MAX_CELLS (default 0) cells may be reported. Prints each
cell, its kind and its distance to the nearest moved object's old and new place.
Precision: the share of the cells within RADIUS of a moved object. Recall: the share of the
moved objects both sessions saw (--maps: their map.ply, in the prior's frame; session 1 has
points within 0.8 m of the object's old place, session 2 within 0.8 m of its old or new place)
with a cell within RADIUS of where it stood or stands; below --min-recall fails."""
import json
import math
import re
import sys

import struct

args, maps, min_recall = [], None, 0.0
rest = sys.argv[1:]
while rest:
    a = rest.pop(0)
    if a == "--maps":
        maps = (rest.pop(0), rest.pop(0))
    elif a == "--min-recall":
        min_recall = float(rest.pop(0))
    else:
        args.append(a)
stats = json.load(open(args[0]))
tx, ty, tz, qx, qy, qz, qw = (float(v) for v in args[1].split(","))
radius = float(args[3])
max_unmoved = int(args[4]) if len(args) > 4 else 0
moved = []
for line in open(args[2]):
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
def cell_at(c):
    r = rotate((c["x"], c["y"], c["z"]))
    return (r[0] + tx, r[1] + ty, r[2] + tz)


for c in cells:
    p = cell_at(c)
    near = [(math.dist(p[:2], a[:2]), math.dist(p[:2], b[:2]), name) for name, a, b in moved]
    best = min((min(a, b), name) for a, b, name in near) if near else (math.inf, "-")
    stray += best[0] > radius
    print(f"  {c.get('kind', '?'):9s} ({p[0]:.2f}, {p[1]:.2f}, {p[2]:.2f}) {c['points']} points: "
          f"{best[0]:.2f} m from the {best[1]}" + ("  <- nothing moved here" if best[0] > radius else ""))
if not moved:
    sys.exit(0 if len(cells) <= max_unmoved else 1)


def ply_xy(path):
    """The horizontal place of each point of replay's map.ply (x, y, z float first, 25 bytes
    a point), moved into the ground truth's frame."""
    with open(path, "rb") as f:
        n = 0
        while (line := f.readline().decode().strip()) != "end_header":
            if line.startswith("element vertex"):
                n = int(line.split()[2])
        data = f.read(n * 25)
    for x, y, z, *_ in struct.iter_unpack("<fffBBBHd", data):
        r = rotate((x, y, z))
        yield (r[0] + tx, r[1] + ty)


def seen_near(path, places):
    count = [0] * len(places)
    for p in ply_xy(path):
        for i, c in enumerate(places):
            if (p[0] - c[0]) ** 2 + (p[1] - c[1]) ** 2 < 0.64:
                count[i] += 1
    return count


placed = [p for _, a, b in moved for p in (a, b)]
found = [any(min(math.dist(cell_at(c)[:2], a[:2]), math.dist(cell_at(c)[:2], b[:2])) <= radius
             for c in cells) for _, a, b in moved]
seen = [True] * len(moved)
if maps:
    s1, s2 = seen_near(maps[0], placed), seen_near(maps[1], placed)
    seen = [s1[2 * i] >= 100 and (s2[2 * i] >= 100 or s2[2 * i + 1] >= 100)
            for i in range(len(moved))]
for (name, _, _), f, v in zip(moved, found, seen):
    print(f"  {name}: {'seen by both' if v else 'not seen by both'}, {'reported' if f else 'not reported'}")
precision = (len(cells) - stray) / len(cells) if cells else 1.0
n_seen = sum(seen)
recall = sum(f for f, v in zip(found, seen) if v) / n_seen if n_seen else 1.0
print(f"precision {precision:.2f} ({len(cells) - stray} of {len(cells)} cells), recall {recall:.2f} "
      f"({sum(f for f, v in zip(found, seen) if v)} of {n_seen} objects seen by both)")
sys.exit(0 if stray == 0 and recall >= min_recall else 1)
