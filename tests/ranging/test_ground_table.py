"""GroundTable: interpolation, no-ground propagation, model-based tables, files and errors."""

from __future__ import annotations

import json

import floorscan
import numpy as np
import pytest
from floorscan import CameraMount, GroundTable, Lens
from hypothesis import given, settings
from hypothesis import strategies as st


def affine(u, v):
    return 2.0 - 0.01 * v + 0.003 * u, 0.4 - 0.005 * u + 0.001 * v


@settings(max_examples=60, deadline=None)
@given(u=st.floats(0, 99), v=st.floats(0, 59), spacing=st.integers(1, 17))
def test_lookup_is_exact_on_an_affine_mapping(u, v, spacing):
    t = GroundTable.from_function(affine, image_width=100, image_height=60, spacing_px=spacing)
    x, y = t.lookup(u, v)
    ex, ey = affine(u, v)
    assert x == pytest.approx(ex, abs=1e-9) and y == pytest.approx(ey, abs=1e-9)


def test_vectorised_lookup_matches_scalar_and_keeps_shape():
    t = GroundTable.from_function(affine, image_width=100, image_height=60, spacing_px=8)
    u = np.array([[1.0, 50.5], [99.0, 3.25]])
    v = np.array([[0.0, 20.0], [59.0, 40.0]])
    x, y = t.lookup(u, v)
    assert x.shape == (2, 2)
    for i in range(2):
        for j in range(2):
            assert (x[i, j], y[i, j]) == pytest.approx(t.lookup(u[i, j], v[i, j]))


def test_no_ground_propagates_and_outside_is_none():
    def ground(u, v):
        x, y = affine(u, v)
        return np.where(v < 16, np.nan, x), y

    t = GroundTable.from_function(ground, image_width=64, image_height=48, spacing_px=8)
    assert t.lookup(10.0, 12.0) is None  # cell between node rows 8 and 16
    assert t.lookup(10.0, 16.0) is not None
    assert t.lookup(-1.0, 30.0) is None
    assert t.lookup(10.0, 48.0) is None


def test_file_round_trip_and_atomic_save(tmp_path):
    t = GroundTable.from_function(affine, image_width=40, image_height=30, spacing_px=4)
    t = t.with_metadata({"source": "test", "n": 3})
    path = t.save(tmp_path / "t.json")
    back = GroundTable.load(path)
    assert back == t
    assert back.metadata == {"source": "test", "n": 3}
    assert [p.name for p in tmp_path.iterdir()] == ["t.json"]  # no temporary left behind


def test_damaged_and_other_version_files_are_clear_errors(tmp_path):
    t = GroundTable.from_function(affine, image_width=40, image_height=30, spacing_px=4)
    text = t.to_json()
    (tmp_path / "cut.json").write_text(text[: len(text) // 2])
    with pytest.raises(floorscan.FileFormatError):
        GroundTable.load(tmp_path / "cut.json")
    doc = json.loads(text)
    doc["version"] = 99
    (tmp_path / "v99.json").write_text(json.dumps(doc))
    with pytest.raises(floorscan.UnsupportedVersionError, match="version 99"):
        GroundTable.load(tmp_path / "v99.json")
    with pytest.raises(floorscan.FileFormatError):
        GroundTable.load(tmp_path / "missing.json")
    doc = json.loads(text)
    doc["x_m"] = doc["x_m"][:-1]
    (tmp_path / "short.json").write_text(json.dumps(doc))
    with pytest.raises(floorscan.FileFormatError):
        GroundTable.load(tmp_path / "short.json")


def test_wrong_array_shapes_are_table_errors():
    with pytest.raises(floorscan.TableError, match=r"\(nodes_v, nodes_u\)"):
        GroundTable.from_arrays(
            np.zeros((3, 3)), np.zeros((3, 3)), image_width=40, image_height=30, spacing_px=4
        )
    with pytest.raises(floorscan.TableError):
        GroundTable.node_shape_for(image_width=40, image_height=30, spacing_px=0)


def test_table_from_a_pinhole_camera_matches_analytic_geometry():
    # Pinhole looking down at tilt t from height h: the principal ray meets the floor at h / tan t;
    # pixel row v sees depression angle t + atan((v - cy) / f).
    f, h, tilt = 200.0, 0.5, 0.6
    lens = Lens.pinhole(fx=f, fy=f, cx=160.0, cy=120.0)  # nodes (spacing 1) are exact
    t = GroundTable.from_camera(
        lens,
        CameraMount(height_m=h, tilt_rad=tilt),
        image_width=320,
        image_height=240,
        spacing_px=1,
    )
    for v in (120.0, 150.0, 200.0, 239.0):
        x, y = t.lookup(160.0, v)
        assert x == pytest.approx(h / np.tan(tilt + np.arctan((v - 120.0) / f)), rel=1e-9)
        assert y == pytest.approx(0.0, abs=1e-9)
    # A pixel right of centre sees ground to the right (negative y, REP 103).
    assert t.lookup(250.0, 200.0)[1] < 0
    # Tilted down by less than half the vertical field of view (atan(120 / 200) = 0.54 rad), the
    # top rows look above the horizon: no ground there.
    shallow = GroundTable.from_camera(
        lens, CameraMount(height_m=h, tilt_rad=0.3), image_width=320, image_height=240
    )
    assert shallow.lookup(160.0, 0.0) is None
    assert t.lookup(160.0, 0.0) is not None


def test_invalid_lens_and_mount_are_option_errors():
    with pytest.raises(floorscan.OptionError):
        Lens.pinhole(fx=0, fy=1, cx=0, cy=0)
    with pytest.raises(floorscan.OptionError):
        CameraMount(height_m=-1.0, tilt_rad=0.3)
    with pytest.raises(floorscan.OptionError):
        Lens.from_dict({"model": "orthographic"})
