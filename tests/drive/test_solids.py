"""Truth's inside test against matplotlib's point-in-polygon on random polygons."""

from __future__ import annotations

import numpy as np
from floorscan.drive import Solids
from matplotlib.path import Path


def test_inside_agrees_with_matplotlib_on_random_polygons():
    rng = np.random.default_rng(3)
    polys = []
    for _ in range(6):
        n = int(rng.integers(3, 9))
        ang = np.sort(rng.uniform(0, 2 * np.pi, n))
        rad = rng.uniform(0.3, 1.0, n)
        c = rng.uniform(-3, 3, 2)
        polys.append(np.stack([c[0] + rad * np.cos(ang), c[1] + rad * np.sin(ang)], 1))
    s = Solids.of_polygons(polys)
    paths = [Path(p) for p in polys]
    for x, y in rng.uniform(-4, 4, (2000, 2)):
        expected = any(p.contains_point((x, y)) for p in paths)
        assert s.inside(x, y) == expected
