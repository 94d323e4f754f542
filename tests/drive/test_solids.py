"""Truth's inside test against matplotlib's point-in-polygon on random polygons."""

from __future__ import annotations

import numpy as np
import pytest
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


def test_nearest_is_the_closest_of_densely_sampled_boundary_points():
    rng = np.random.default_rng(5)
    polys = [
        rng.uniform(-3, 3, 2) + rng.uniform(0.2, 1.0, (4, 2)) * [[1, 1], [-1, 1], [-1, -1], [1, -1]]
        for _ in range(3)
    ]
    s = Solids.of_polygons(polys)
    # the boundary sampled every 0.1 mm: the nearest sample is within that of the exact point
    samples = np.concatenate(
        [
            a + np.linspace(0, 1, int(np.hypot(*(b - a)) / 1e-4) + 2)[:, None] * (b - a)
            for p in polys
            for a, b in zip(p, np.roll(p, -1, axis=0))
        ]
    )
    for x, y in rng.uniform(-4, 4, (50, 2)):
        q = np.array(s.nearest(x, y))
        d = np.hypot(samples[:, 0] - x, samples[:, 1] - y)
        assert np.hypot(*(q - [x, y])) == pytest.approx(d.min(), abs=1e-4)
        assert np.hypot(*(q - samples[d.argmin()])) < 1e-3 + 1e-4
    assert np.isnan(Solids.of_polygons([]).nearest(0.0, 0.0)).all()
