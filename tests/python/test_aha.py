"""ctest python.aha: the AHA 17-segment assignment of cases/heart/plot_heart.py on single-node
"elements" placed around a synthetic LV (base z = 0, apex z = -10): anterior = +y, septal = -x,
basal/mid/apical rings by depth, the apex cap below 90 % of the length."""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(sys.argv[1], "cases", "heart"))
import plot_heart  # noqa: E402

cases = []  # (depth fraction, angle deg, expected segment)
for k, angle in enumerate((90, 150, 210, 270, 330, 30)):  # anterior, anteroseptal, ... anterolateral
    cases.append((0.2, angle, 1 + k))
    cases.append((0.5, angle, 7 + k))
for k, angle in enumerate((90, 180, 270, 0)):  # apical anterior, septal, inferior, lateral
    cases.append((0.8, angle, 13 + k))
cases.append((0.95, 45, 17))
pts = [[0.0, 0.0, 0.0], [0.0, 0.0, -10.0]]  # base and apex on the axis fix z range and centre
for depth, angle, _ in cases:
    a = np.radians(angle)
    pts.append([5 * np.cos(a), 5 * np.sin(a), -10.0 * depth])
points = np.array(pts)
conn = np.arange(2, len(pts)).reshape(-1, 1)
seg = plot_heart.aha_segments(points, conn)
expected = np.array([c[2] for c in cases])
assert np.array_equal(seg, expected), list(zip(seg, expected))
print("aha segments: ok (%d points)" % len(cases))
