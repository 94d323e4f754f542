"""The configuration file: defaults round-trip, errors name the key, overrides are checked."""

from __future__ import annotations

import floorscan
import pytest
from floorscan.cli import main
from floorscan.pipeline.config import Config


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
        ("[map]\ncell_size_m = nan\n", "map.cell_size_m"),
        ("ranger = 3\n", "ranger"),
    ],
)
def test_unknown_or_ill_typed_keys_name_the_key(text, key):
    with pytest.raises(floorscan.ConfigError, match=key.replace(".", r"\.")):
        Config.from_toml(text)


def test_overrides_replace_dotted_keys_and_are_checked():
    cfg = Config().with_overrides(
        {"ranger.threshold": 7.5, "ranger.columns": None, "map.cell_size_m": 0.05}
    )
    assert cfg.ranger.threshold == 7.5 and cfg.ranger.columns == 64 and cfg.map.cell_size_m == 0.05
    with pytest.raises(floorscan.ConfigError, match="ranger.nope"):
        Config().with_overrides({"ranger.nope": 1})
    with pytest.raises(floorscan.ConfigError, match="ranger.columns"):
        Config().with_overrides({"ranger.columns": "x"})


def test_config_command_prints_and_checks(tmp_path, capsys):
    assert main(["config", "--default"]) == 0
    out = capsys.readouterr().out
    assert Config.from_toml(out) == Config()
    bad = tmp_path / "bad.toml"
    bad.write_text("[map]\nsize = 3\n")
    assert main(["config", "--check", str(bad)]) == 1
    assert "map.size" in capsys.readouterr().err
