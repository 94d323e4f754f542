"""The appearance ranger's refresh from floor driven over (pipeline.driven_floor): a rug the
robot drove across is floor when a second one of its colour comes into view, against the same
run with the refresh off; boundaries passed beside or seen too long ago teach nothing."""

from __future__ import annotations

import floorscan as fs
import numpy as np
import pytest
from floorscan.pipeline import driven_floor
from floorscan.pipeline.config import Config
from floorscan.pipeline.driven_floor import DrivenFloor
from floorscan.pipeline.mapper import Mapper
from floorscan.ranging.appearance import NO_SAMPLE
from floorscan.ranging.scan import ColumnStatus

W, H = 320, 240
FLOOR, RUG = (120, 110, 90), (40, 70, 170)
RUGS = ((1.5, 1.9), (4.0, 4.4))  # world x [m] of two rugs of one colour across the corridor


def ahead_m(v):
    """Ground ahead of the camera seen by image row v [m] (the table below)."""
    return 0.3 + (H - np.asarray(v, float)) * 0.01


def table() -> fs.GroundTable:
    def ground(u, v):
        return ahead_m(v), (W / 2 - np.asarray(u, float)) * 0.004

    return fs.GroundTable.from_function(ground, image_width=W, image_height=H, spacing_px=8)


def frame(x_robot: float, seed: int) -> np.ndarray:
    """What the camera (on the robot's origin, looking along +x) sees at x_robot."""
    x = x_robot + ahead_m(np.arange(H))
    on_rug = np.zeros(H, bool)
    for a, b in RUGS:
        on_rug |= (x >= a) & (x <= b)
    img = np.where(on_rug[:, None, None], RUG, FLOOR) * np.ones((H, W, 3))
    img += np.random.default_rng(seed).integers(-5, 6, size=img.shape)
    return np.clip(img, 0, 255).astype(np.uint8)


def drive(radius_m: float):
    """Drives from x = 0 to 2.5 m at 5 cm a frame; returns the last scan and the mapper."""
    cfg = Config().with_overrides(
        {"ranger.kind": "appearance", "appearance.driven_floor_radius_m": radius_m}
    )
    mapper = Mapper(table(), cfg)
    for k, x in enumerate(np.arange(0.0, 2.5001, 0.05)):
        scan = mapper.process(frame(x, k), timestamp=0.1 * k, pose=(float(x), 0.0, 0.0))
    return scan, mapper


def test_a_rug_driven_over_is_floor_when_the_next_one_comes_into_view():
    off_scan, off = drive(0.0)
    on_scan, on = drive(0.1)
    assert off.driven_floor is None
    # Without the refresh the second rug (1.5 m ahead) stops every column at its near edge.
    assert set(off_scan.status) == {"boundary"}
    np.testing.assert_allclose(off_scan.x, RUGS[1][0] - 2.5, atol=0.03)
    # With it, the boundaries of the first rug within 10 cm of the path were driven through,
    # and their pixels made the rug's colour floor: the corridor is free to the top.
    assert on.driven_floor.boundaries_driven > 0
    assert on.driven_floor.samples_learned >= 8
    assert set(on_scan.status) == {"no_boundary"}


class FakeRanger:
    """Stands in for the appearance ranger: one boundary straight ahead of the camera."""

    def __init__(self, x_ahead_m: float, y_m: float = 0.0):
        self.learned = []
        self.x, self.y = x_ahead_m, y_m
        self.visible = True

    @property
    def last_scan(self):
        status = ColumnStatus.BOUNDARY if self.visible else ColumnStatus.NO_BOUNDARY

        class S:
            status_codes = np.array([status], np.uint8)
            x = np.array([self.x])
            y = np.array([self.y])

        return S()

    def boundary_samples(self):
        return np.array([[7, 8, 9, NO_SAMPLE]], np.uint32)

    def learn_driven_floor(self, samples):
        self.learned.append(np.asarray(samples).copy())
        return int((np.asarray(samples) != NO_SAMPLE).sum())


@pytest.mark.parametrize(
    "path_y, wait_s, reached",
    [(0.0, 0.0, True), (0.05, 0.0, True), (0.15, 0.0, False), (0.0, 40.0, False)],
    ids=["through", "within-radius", "beside", "too-old"],
)
def test_only_boundaries_reached_in_time_are_handed_over(path_y, wait_s, reached):
    ranger = FakeRanger(1.0)
    d = DrivenFloor(ranger, 0.1)
    # the camera, 0.2 m ahead of the origin and turned to the left, sees the boundary 1 m
    # ahead of it: from a robot at (1, 0) facing +x, the world point (1.2, 1.0)
    d.update((1.0, 0.0, 0.0), (0.2, 0.0, np.pi / 2), 0.0)
    assert d.pending(0.0) == 1
    ranger.visible = False  # later frames see no boundary
    hits = d.update((1.2 + path_y, 1.0, 0.0), (0.0, 0.0, 0.0), wait_s + 0.5)
    assert bool(hits) is reached
    if reached:
        assert [s.tolist() for s in ranger.learned] == [[[7, 8, 9, NO_SAMPLE]]]
        assert d.pending(wait_s + 0.5) == 0  # handed over once, then forgotten


def test_the_memory_is_a_bounded_ring(monkeypatch):
    monkeypatch.setattr(driven_floor, "MAX_PENDING", 3)
    ranger = FakeRanger(1.0)
    d = DrivenFloor(ranger, 0.1)
    for k in range(5):  # five frames from the start, each remembering the boundary at (1, 0)
        d.update((0.0, 0.0, 0.0), (0.0, 0.0, 0.0), 0.3 * k)
    assert d.pending(1.2) == 3  # the oldest two were overwritten
    ranger.visible = False
    assert d.update((1.0, 0.05, 0.0), (0.0, 0.0, 0.0), 1.5) == 3
