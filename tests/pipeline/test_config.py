"""The configuration file: defaults round-trip, errors name the key, overrides are checked."""

from __future__ import annotations

import sys

import floorscan
import numpy as np
import pytest
from conftest import affine_table
from floorscan import read_scans_csv
from floorscan.cli import main
from floorscan.formats.image_io import write_png
from floorscan.options import defaults
from floorscan.pipeline.config import Config
from floorscan.pipeline.config_tables import SHARED_WITH_RANGER

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib


def test_default_config_round_trips_through_toml():
    text = Config().to_toml()
    assert Config.from_toml(text) == Config()
    cfg = Config.from_toml(
        "[ranger]\nthreshold = 9\nmax_range_m = 3.5\n[sensors.visual]\nhit_nats = 1.2\n"
    )
    assert cfg.ranger.threshold == 9.0 and isinstance(cfg.ranger.threshold, float)
    assert cfg.ranger.max_range_m == 3.5
    assert (
        cfg.sensors.visual.hit_nats == 1.2
        and cfg.sensors.laser.hit_nats == Config().sensors.laser.hit_nats
    )
    assert Config.from_toml(cfg.to_toml()) == cfg


@pytest.mark.parametrize(
    "text,key",
    [
        ("[ranger]\nthreshhold = 3\n", "ranger.threshhold"),
        ("[rangr]\n", "rangr"),
        ("[ranger]\ncolumns = 'many'\n", "ranger.columns"),
        ("[ranger]\ncolumns = 2.5\n", "ranger.columns"),
        ("[calibration]\nextrapolate = 1\n", "calibration.extrapolate"),
        ("[sensors.visual]\nhit = 1\n", "sensors.visual.hit"),
        ("[grid]\ncell_size_m = nan\n", "grid.cell_size_m"),
        ("[map]\ncell_size_m = nan\n", "grid.cell_size_m"),  # the older spelling of [grid]
        ("[ranger]\nhalf_width_px = 0\n", "ranger.half_width_px"),
        ("[ranger]\nrefinement = 'best'\n", "ranger.refinement"),
        ("[local_map]\nsize_m = 0.01\n", "local_map.size_m"),
        ("[sensors]\ntoo_close = 'maybe'\n", "sensors.too_close"),
        ("[appearance]\nmin_run_px = 0\n", "appearance.min_run_px"),
        ("ranger = 3\n", "ranger"),
    ],
)
def test_unknown_or_ill_typed_keys_name_the_key(text, key):
    with pytest.raises(floorscan.ConfigError, match=key.replace(".", r"\.")):
        Config.from_toml(text)


def test_overrides_replace_dotted_keys_and_are_checked():
    cfg = Config().with_overrides(
        {"ranger.threshold": 7.5, "ranger.columns": None, "grid.cell_size_m": 0.05}
    )
    assert cfg.ranger.threshold == 7.5 and cfg.grid.cell_size_m == 0.05
    assert cfg.ranger.columns == defaults("ranger")["columns"]
    with pytest.raises(floorscan.ConfigError, match="ranger.nope"):
        Config().with_overrides({"ranger.nope": 1})
    with pytest.raises(floorscan.ConfigError, match="ranger.columns"):
        Config().with_overrides({"ranger.columns": "x"})


def test_an_unset_optional_key_of_a_nested_table_is_overridden_as_the_file_sets_it():
    """`[slam.matcher] rejection_threshold` is unset by default (left out of the printed
    defaults): an override sets it as a TOML file does, and a misspelt one is still refused."""
    from_file = Config.from_toml("[slam.matcher]\nrejection_threshold = 3.0\n")
    over = Config().with_overrides({"slam.matcher.rejection_threshold": 3.0})
    assert over == from_file
    assert over.slam.options()["matcher"]["rejection_threshold"] == 3.0
    with pytest.raises(floorscan.ConfigError, match=r"slam\.matcher\.rejection_threshol\b"):
        Config().with_overrides({"slam.matcher.rejection_threshol": 3.0})
    with pytest.raises(floorscan.ConfigError, match=r"slam\.nope\.rejection_threshold"):
        Config().with_overrides({"slam.nope.rejection_threshold": 3.0})


def test_config_command_prints_and_checks(tmp_path, capsys):
    assert main(["config", "--default"]) == 0
    out = capsys.readouterr().out
    assert Config.from_toml(out) == Config()
    bad = tmp_path / "bad.toml"
    bad.write_text("[map]\nsize = 3\n")
    assert main(["config", "--check", str(bad)]) == 1
    assert "map.size" in capsys.readouterr().err


def test_every_printed_default_is_the_rust_default(capsys):
    """`config --default` prints the Rust `impl Default` of each options table, read back."""
    assert main(["config", "--default"]) == 0
    printed = tomllib.loads(capsys.readouterr().out)
    ranger = {k: v for k, v in printed["ranger"].items() if k not in RANGER_EXTRAS}
    assert ranger == defaults("ranger")
    appearance = {
        k: v
        for k, v in printed["appearance"].items()
        if k not in ("snap_rows", "snap_fraction", "texture_share")
    }
    expected = {k: v for k, v in defaults("appearance").items() if k not in SHARED_WITH_RANGER}
    assert appearance == expected
    grid = {k: v for k, v in defaults("grid").items() if v is not None}  # TOML has no null
    assert printed["grid"] == grid
    local = {k: v for k, v in defaults("local_map").items() if k != "grid"}  # grid: [grid]
    assert printed["local_map"] == local
    assert printed["sensors"] == defaults("inserter")
    # The shared appearance fields are the ranger's; the local map's grid is [grid].
    assert {k: defaults("appearance")[k] for k in SHARED_WITH_RANGER} == {
        k: defaults("ranger")[k] for k in SHARED_WITH_RANGER
    }
    assert defaults("local_map")["grid"] == defaults("grid")


RANGER_EXTRAS = ("kind", "auto_threshold", "auto_threshold_k")


def test_older_spellings_of_config_files_still_read():
    old = Config.from_toml(
        "[ranger]\nhalf_width = 3\nrefine = 'none'\nbottom_margin = 5\n"
        "[appearance]\nmin_run = 4\nfeatures = 'colour_texture'\n"
        "[map]\ncell_size_m = 0.05\nlocal_size_m = 2.0\n"
    )
    new = Config.from_toml(
        "[ranger]\nhalf_width_px = 3\nrefinement = 'first_crossing'\nstart = {bottom_margin = 5}\n"
        "[appearance]\nmin_run_px = 4\nfeatures = 'colour_and_texture'\n"
        "[grid]\ncell_size_m = 0.05\n[local_map]\nsize_m = 2.0\n"
    )
    assert old == new
    assert "half_width_px = 3" in old.to_toml() and "half_width =" not in old.to_toml()


def test_a_bad_value_gives_the_same_error_from_toml_kwargs_and_cli(tmp_path, capsys):
    """One rule (the Rust validate) and one message naming the key, however the value came."""
    table = affine_table(64, 48)
    table.save(tmp_path / "table.json")
    with pytest.raises(floorscan.OptionError) as kwargs:
        floorscan.VisualRanger(table, half_width_px=0)
    reason = str(kwargs.value).split("`half_width_px`: ", 1)[1]
    assert "\n" not in str(kwargs.value) and reason.startswith("must be in 1..=")
    bad = tmp_path / "bad.toml"
    bad.write_text("[ranger]\nhalf_width_px = 0\n")
    with pytest.raises(floorscan.ConfigError) as toml:
        Config.load(bad)
    assert str(toml.value).endswith(f"invalid option `ranger.half_width_px`: {reason}")
    image = tmp_path / "f.png"
    write_png(image, np.full((48, 64), 100, np.uint8))
    scan = ["scan", "--table", str(tmp_path / "table.json"), str(image), "-o", "s.csv"]
    assert main([*scan, "--half-width-px", "0"]) == 1
    err = capsys.readouterr().err.strip()
    assert err.endswith(f"invalid option `ranger.half_width_px`: {reason}") and "\n" not in err
    assert main([*scan, "--config", str(bad)]) == 1
    assert capsys.readouterr().err.strip().endswith(f"`ranger.half_width_px`: {reason}")
    # Type errors and unknown keys too: the serde error, with the key.
    with pytest.raises(floorscan.OptionError, match="invalid option `threshold`: "):
        floorscan.VisualRanger(table, threshold="high")
    with pytest.raises(floorscan.OptionError, match="`half_width`: unknown option"):
        floorscan.VisualRanger(table, half_width=4)


def test_scan_reads_the_config_file(tmp_path):
    """`floorscan scan --config`: the file's [ranger] table, flags over it."""
    table = affine_table(64, 48)
    table.save(tmp_path / "table.json")
    v = np.arange(48)[:, None]
    image = write_png(
        tmp_path / "f.png", (np.where(v >= 20, 90, 110) * np.ones((1, 64))).astype(np.uint8)
    )
    cfg = tmp_path / "c.toml"
    # A fixed threshold (no per-frame terms); the step is 20 (R = 10): no boundary at 50.
    cfg.write_text("[ranger]\nthreshold = 50\nnoise_multiple = 0\ncontrast = 0\ncolumns = 4\n")
    base = ["scan", "--table", str(tmp_path / "table.json"), str(image), "--config", str(cfg)]
    assert main([*base, "-o", str(tmp_path / "a.csv")]) == 0
    a = read_scans_csv(tmp_path / "a.csv")[0]
    assert len(a) == 4 and "boundary" not in a.status
    assert main([*base, "-o", str(tmp_path / "b.csv"), "--threshold", "5"]) == 0
    b = read_scans_csv(tmp_path / "b.csv")[0]
    assert len(b) == 4 and set(b.status) == {"boundary"}


def test_the_local_map_takes_its_visual_evidence_from_its_own_table():
    """`[local_map.visual]` sets the local map's increments, `[sensors.visual]` the global
    map's: the same boundary adds 2.0 nats to one and 1.0 to the other."""
    from floorscan import LocalMap, OccupancyGrid, Scan
    from floorscan.pipeline.mapper import grid_kwargs, local_map_kwargs

    cfg = Config.from_toml(
        "[sensors.visual]\nhit_nats = 1.0\nmiss_nats = -0.3\n"
        "[local_map.visual]\nhit_nats = 2.0\nmiss_nats = -1.0\n"
    )
    view = Scan.from_arrays(
        timestamp=0.0,
        columns=[0],
        rows=[100.0],
        status=["boundary"],
        x=[1.02],
        y=[0.02],
        near_x=[0.3],
        near_y=[0.02],
    )
    local, world = LocalMap(**local_map_kwargs(cfg)), OccupancyGrid(**grid_kwargs(cfg))
    local.insert_scan(view)
    world.insert_scan(view, (0.0, 0.0, 0.0))
    assert local.log_odds().max() == pytest.approx(2.0) and local.log_odds().min() == -1.0
    assert world.log_odds().max() == pytest.approx(1.0) and world.log_odds().min() == -0.3


@pytest.mark.parametrize(
    "toml, key",
    [
        ("[ranger]\ncolumns = 100000\n", "columns"),
        ("[ranger.start]\nbottom_margin = 100000\n", "bottom_margin"),
    ],
)
def test_config_check_with_a_table_refuses_what_run_refuses(tmp_path, capsys, toml, key):
    """Options that depend on the image's size: `config --check` alone cannot judge them (it
    says so), with `--table` it refuses them with the very message `run` gives."""
    table = affine_table(width=320, height=240)
    table.save(tmp_path / "table.json")
    cfg = tmp_path / "c.toml"
    cfg.write_text(toml)
    write_png(tmp_path / "frame.png", np.full((240, 320), 100, np.uint8))
    # what `floorscan scan` (the same range sensor as `run`) says about this file
    assert (
        main(
            [
                "scan",
                "--table",
                str(tmp_path / "table.json"),
                "--config",
                str(cfg),
                str(tmp_path / "frame.png"),
                "-o",
                str(tmp_path / "s.csv"),
            ]
        )
        == 1
    )
    run_says = capsys.readouterr().err.strip().split(": error: ", 1)[1]
    assert key in run_says
    assert main(["config", "--check", str(cfg), "--table", str(tmp_path / "table.json")]) == 1
    assert capsys.readouterr().err.strip().split(": error: ", 1)[1] == run_says
    assert main(["config", "--check", str(cfg)]) == 0
    assert "not checked against an image size" in capsys.readouterr().err
