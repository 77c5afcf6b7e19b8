"""Checks a browser's screenshot of report.html shows the top-down map, not a blank page: enough
non-white pixels, the height colour map's hues (turbo: blue, green, yellow, red) in quantity, and
the trajectory's magenta line. Reads the PNG with Debian's python3-open3d."""
import sys

import numpy as np
import open3d as o3d

img = np.asarray(o3d.io.read_image(sys.argv[1]))[:, :, :3].astype(int)
h, w, _ = img.shape
r, g, b = img[:, :, 0], img[:, :, 1], img[:, :, 2]
non_white = np.mean((r < 235) | (g < 235) | (b < 235))
hues = {
    "blue": (b > 150) & (r < 100) & (g < 200),
    "green/cyan": (g > 150) & (r < 150),
    "yellow/orange": (r > 180) & (g > 120) & (b < 100),
    "red": (r > 150) & (g < 90) & (b < 60),
}
counts = {k: int(v.sum()) for k, v in hues.items()}
magenta = int(((r > 200) & (g < 80) & (b > 200)).sum())
print(f"check_screenshot: {w}x{h}, {100 * non_white:.1f} % non-white, hues {counts}, magenta {magenta}")
if non_white < 0.10:
    sys.exit("check_screenshot: the page is (nearly) blank")
if sum(c > 1500 for c in counts.values()) < 2:
    sys.exit("check_screenshot: the height-coloured map is not on screen")
if magenta < 200:
    sys.exit("check_screenshot: no trajectory line")
print("check_screenshot: ok, the top-down map is shown")
