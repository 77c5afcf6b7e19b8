"""Reads handscan's cloud.ply with Debian's python3-open3d (independent of our code) and compares
point count, bounds and colours with expected.json."""
import json
import sys

import numpy as np
import open3d as o3d

directory = sys.argv[1]
expected = json.load(open(f"{directory}/expected.json"))
cloud = o3d.io.read_point_cloud(f"{expected['dir']}/cloud.ply")
pts = np.asarray(cloud.points)
cols = np.asarray(cloud.colors)


def fail(msg):
    print(f"check_ply: {msg}", file=sys.stderr)
    sys.exit(1)


if len(pts) != expected["count"]:
    fail(f"point count {len(pts)} != {expected['count']}")
if not np.allclose(pts.min(axis=0), expected["min"], atol=1e-4) or not np.allclose(pts.max(axis=0), expected["max"], atol=1e-4):
    fail(f"bounds {pts.min(axis=0)}..{pts.max(axis=0)}")
if len(cols) != len(pts):
    fail("no colours")
rgb = np.rint(cols * 255.0)
if not np.allclose(rgb.sum(axis=0), expected["sum_rgb"], atol=0.5):
    fail(f"colour sums {rgb.sum(axis=0)} != {expected['sum_rgb']}")
if list(rgb[0].astype(int)) != expected["first_rgb"]:
    fail(f"first colour {rgb[0]} != {expected['first_rgb']}")
print(f"check_ply: ok, {len(pts)} points, bounds and colours match")
