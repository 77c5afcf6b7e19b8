#!/usr/bin/env python3
"""perturb_pose.py "x,y,z,qx,qy,qz,qw" METRES DEGREES: the pose moved METRES horizontally (along
x 0.8, y 0.6) and turned DEGREES about the vertical, printed in the same form (an operator's
imprecise start hint for `handscan replay --initial-pose`)."""
import math
import sys

x, y, z, qx, qy, qz, qw = (float(v) for v in sys.argv[1].split(","))
m, deg = float(sys.argv[2]), float(sys.argv[3])
h = math.radians(deg) / 2.0
# Rz(deg) * q (world-frame yaw): (0, 0, sin h, cos h) * (qx, qy, qz, qw)
rz, rw = math.sin(h), math.cos(h)
nx = rw * qx - rz * qy
ny = rw * qy + rz * qx
nz = rw * qz + rz * qw
nw = rw * qw - rz * qz
print(f"{x + 0.8 * m:.6f},{y + 0.6 * m:.6f},{z:.6f},{nx:.9f},{ny:.9f},{nz:.9f},{nw:.9f}")
