"""The evidence layer from Python: analytic sums past the clamp, the .evidence.npz file and
its refusals, and the merge of `floorscan run` outputs against one grid fed every recording
and a plain numpy sum."""

from __future__ import annotations

import numpy as np
import pytest
from fleet_recordings import make_recording, sum_by_hand
from floorscan import OccupancyGrid
from floorscan.cli import main
from floorscan.errors import FileFormatError, GeometryError, OptionError, UnsupportedVersionError
from floorscan.mapping.evidence import EvidenceMap, merge_evidence
from floorscan.pipeline.config import Config
from floorscan.pipeline.mapper import Mapper
from floorscan.pipeline.sources import DatasetSource
from synthetic_dataset import camera_table


def test_evidence_sums_every_scan_past_the_clamp():
    # A 1 m beam along +x in 0.1 m cells, 30 times: cells 0..9 free, cell 10 hit, every time.
    g = OccupancyGrid(cell_size_m=0.1, keep_evidence=True)
    for _ in range(30):
        g.insert_laser([1.0], angles=[0.0], range_max_m=5.0, pose=(0.05, 0.05, 0.0))
    ev = g.evidence()
    assert ev.values.shape == (1, 11) and ev.origin_m == pytest.approx((0.0, 0.0))
    assert list(ev.values[0]) == [30 * -400] * 10 + [30 * 850]
    # The clamped map stops at the clamps; the evidence clamped once says the same here.
    raw = g.raw()
    assert list(raw[0]) == [-2000] * 10 + [3500]
    assert np.array_equal(ev.clamped(), raw)
    with pytest.raises(OptionError, match="keep_evidence"):
        OccupancyGrid().evidence()


def test_evidence_file_round_trip_and_refusals(tmp_path):
    ev = EvidenceMap(
        values=np.array([[1, -2, 3]], dtype=np.int32),
        cell_size_m=0.05,
        origin_m=(1.5, -0.25),
        clamp_min_nats=-3.0,
        recordings=("a", "b"),
    )
    back = EvidenceMap.load(ev.save(tmp_path / "m.evidence.npz"))
    assert np.array_equal(back.values, ev.values) and back.values.dtype == np.int32
    assert (back.cell_size_m, back.origin_m, back.recordings) == (0.05, (1.5, -0.25), ("a", "b"))
    assert back.options == ev.options
    (tmp_path / "junk.npz").write_bytes(b"not a zip")
    with pytest.raises(FileFormatError, match="cannot read"):
        EvidenceMap.load(tmp_path / "junk.npz")
    np.savez(tmp_path / "other.npz", evidence=np.zeros((1, 1), np.int32))
    with pytest.raises(FileFormatError, match="not a floorscan evidence"):
        EvidenceMap.load(tmp_path / "other.npz")
    np.savez(tmp_path / "v2.npz", format=np.array("floorscan-evidence"), version=np.array(2))
    with pytest.raises(UnsupportedVersionError, match="version 2"):
        EvidenceMap.load(tmp_path / "v2.npz")
    fields = dict(np.load(tmp_path / "m.evidence.npz"))
    fields["evidence"] = fields["evidence"].astype(np.float32)
    np.savez(tmp_path / "float.npz", **fields)
    with pytest.raises(FileFormatError, match="int32"):
        EvidenceMap.load(tmp_path / "float.npz")
    del fields["cell_size_m"]
    np.savez(tmp_path / "missing.npz", **fields)
    with pytest.raises(FileFormatError, match="missing"):
        EvidenceMap.load(tmp_path / "missing.npz")


def test_evidence_records_the_ray_walk_and_merges_only_one(tmp_path):
    # A diagonal beam clears different cells under the two walks (the thin walk fewer), so
    # the file says which one its free evidence followed.
    def beam(walk):
        g = OccupancyGrid(cell_size_m=0.1, keep_evidence=True, ray_walk=walk)
        g.insert_laser([1.0], angles=[0.6], range_max_m=5.0, pose=(0.05, 0.05, 0.0))
        return g.evidence(name=walk)

    exact, thin = beam("exact"), beam("thin")
    assert (exact.ray_walk, thin.ray_walk) == ("exact", "thin")
    assert (exact.values < 0).sum() > (thin.values < 0).sum()
    back = EvidenceMap.load(thin.save(tmp_path / "thin.evidence.npz"))
    assert back.ray_walk == "thin" and np.array_equal(back.values, thin.values)
    # A file written before the walk was recorded reads as unknown; a bad value is refused.
    fields = dict(np.load(tmp_path / "thin.evidence.npz"))
    del fields["ray_walk"]
    np.savez(tmp_path / "old.npz", **fields)
    old = EvidenceMap.load(tmp_path / "old.npz")
    assert old.ray_walk is None and np.array_equal(old.values, thin.values)
    fields["ray_walk"] = np.array("diagonal")
    np.savez(tmp_path / "bad.npz", **fields)
    with pytest.raises(FileFormatError, match="ray_walk"):
        EvidenceMap.load(tmp_path / "bad.npz")
    # So is one built by hand (the same list of walks as the grid's options).
    for bad in ("diagonal", 3):
        with pytest.raises(OptionError, match="ray_walk"):
            EvidenceMap(values=thin.values, cell_size_m=0.1, origin_m=(0.0, 0.0), ray_walk=bad)
    # Merging: one walk keeps it, an unknown one makes the result unknown, two walks refuse.
    assert merge_evidence([thin, back]).ray_walk == "thin"
    assert merge_evidence([thin, old]).ray_walk is None
    with pytest.raises(OptionError, match="ray walks"):
        merge_evidence([exact, thin])
    assert (
        EvidenceMap.load(merge_evidence([thin, back]).save(tmp_path / "m.npz")).ray_walk == "thin"
    )


def test_merge_refuses_other_lattices_and_options():
    a = EvidenceMap(values=np.ones((2, 2), np.int32), cell_size_m=0.04, origin_m=(0.0, 0.0))
    with pytest.raises(OptionError, match="cell size"):
        merge_evidence([a, EvidenceMap(values=a.values, cell_size_m=0.05, origin_m=(0.0, 0.0))])
    with pytest.raises(GeometryError, match="lattice"):
        merge_evidence([a, EvidenceMap(values=a.values, cell_size_m=0.04, origin_m=(0.01, 0.0))])
    with pytest.raises(OptionError, match="clamp_max_nats"):
        merge_evidence(
            [
                a,
                EvidenceMap(
                    values=a.values, cell_size_m=0.04, origin_m=(0.0, 0.0), clamp_max_nats=2.0
                ),
            ]
        )
    with pytest.raises(OptionError, match="no evidence"):
        merge_evidence([])


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """Two recordings of the room from different start poses, each through `floorscan run`
    at their odometry poses (`[slam] mode = "off"`: one mapper fed both then places every
    frame where each run did)."""
    d = tmp_path_factory.mktemp("ev")
    camera_table().save(d / "table.json")
    (d / "off.toml").write_text('[slam]\nmode = "off"\n')
    out = {}
    for name, start, seed in (("a", (0.0, 0.0, 0.0), 1), ("b", (0.8, 0.4, 1.2), 2)):
        make_recording(d / name, n=25, seed=seed, start=start)
        rc = main(
            [
                "run",
                str(d / name),
                "--table",
                str(d / "table.json"),
                "--config",
                str(d / "off.toml"),
                "-o",
                str(d / f"out-{name}"),
            ]
        )
        assert rc == 0
        out[name] = d / f"out-{name}"
    return d, out


def test_merging_runs_equals_one_grid_fed_both_and_the_plain_sum(runs, tmp_path):
    d, out = runs
    a = EvidenceMap.load(out["a"] / "map.evidence.npz")
    b = EvidenceMap.load(out["b"] / "map.evidence.npz")
    assert a.values.shape != b.values.shape or a.origin_m != b.origin_m  # different extents
    ab, ba = merge_evidence([a, b]), merge_evidence([b, a])
    assert np.array_equal(ab.values, ba.values)
    assert ab.origin_m == pytest.approx(ba.origin_m, abs=1e-12)
    origin, total = sum_by_hand([a, b])
    assert np.array_equal(ab.values, total) and ab.origin_m == pytest.approx(origin, abs=1e-12)
    # One mapper fed both recordings' frames keeps the same evidence.
    mapper = Mapper(camera_table(), Config.from_dict({"slam": {"mode": "off"}}))
    for name in ("a", "b"):
        src = DatasetSource(d / name)
        for frame in src:
            mapper.process(
                frame.image,
                timestamp=frame.timestamp,
                pose=src.odometry.pose_at(frame.timestamp).as_tuple(),
            )
    one = mapper.global_map.evidence()
    assert np.array_equal(one.values, ab.values)
    assert one.origin_m == pytest.approx(ab.origin_m, abs=1e-9)
    # The merged map on disk is the sum clamped once.
    rc = main(["merge", str(out["a"] / "map.yaml"), str(out["b"]), "-o", str(tmp_path / "m")])
    assert rc == 0
    disk = EvidenceMap.load(tmp_path / "m" / "map.evidence.npz")
    assert np.array_equal(disk.values, ab.values) and disk.recordings == ("out-a", "out-b")
    merged_map = OccupancyGrid.load(tmp_path / "m" / "map.yaml")
    expected = OccupancyGrid.from_evidence(ab)
    e = merged_map.extent
    assert np.array_equal(merged_map.occupancy_classes(), expected.occupancy_classes(extent=e))


def test_merge_command_refuses_a_map_without_evidence(runs, tmp_path, capsys):
    d, out = runs
    lone = tmp_path / "lone"
    lone.mkdir()
    for f in ("map.yaml", "map.pgm"):
        (lone / f).write_bytes((out["a"] / f).read_bytes())
    rc = main(["merge", str(out["a"]), str(lone / "map.yaml"), "-o", str(tmp_path / "m")])
    assert rc == 1
    assert "no evidence file map.evidence.npz" in capsys.readouterr().err
    assert not (tmp_path / "m").exists()
