"""Options read from Python (keyword arguments, TOML tables) by the bindings' options.rs: a value of
the wrong type is one OptionError line naming the key, what was expected in a user's words and the
value given, for every field of every options type the native module checks."""

import numbers

import floorscan
import floorscan._native as native
import pytest


def _option_types():
    for sub in ("ranging", "mapping", "drive", "formats", "sim"):
        mod = getattr(native, sub)
        for name in dir(mod):
            if name.startswith("check_") and hasattr(mod, "default_" + name[len("check_") :]):
                yield f"{sub}.{name}", getattr(mod, name), getattr(mod, "default_" + name[6:])()


OPTION_TYPES = list(_option_types())


def _wrong_values(default):
    """(wrong value, words the message must use, the value the message shows, its key path
    below the field) for a field whose default is ``default``; a table's fields one by one."""
    if isinstance(default, dict):
        return [
            ({k: v}, words, shown, f".{k}{path}")
            for k, d in default.items()
            for v, words, shown, path in _wrong_values(d)
        ]
    return [
        (v, words, v[0] if isinstance(v, list) and words == "a number" else v, "")
        for v, words in _scalar_wrong_values(default)
    ]


def _scalar_wrong_values(default):
    if isinstance(default, bool):
        return [("yes", "true or false")]
    if isinstance(default, numbers.Integral):
        return [(2.5, "a whole number"), ("3", "a whole number")]
    if isinstance(default, numbers.Real):
        return [("x", "a number")]
    if (
        isinstance(default, list)
        and default
        and all(isinstance(v, numbers.Real) and not isinstance(v, bool) for v in default)
    ):
        return [(3.0, "a list"), (["a"] * len(default), "a number")]
    return []


def test_the_native_module_checks_option_types():
    assert len(OPTION_TYPES) >= 5, [n for n, _, _ in OPTION_TYPES]


@pytest.mark.parametrize("name,check,defaults", OPTION_TYPES, ids=[n for n, _, _ in OPTION_TYPES])
def test_a_value_of_the_wrong_type_is_one_line_in_users_words(name, check, defaults):
    tried = 0
    for key, default in defaults.items():
        for value, words, shown, path in _wrong_values(default):
            with pytest.raises(floorscan.OptionError) as e:
                check({key: value})
            msg = str(e.value)
            tried += 1
            assert "\n" not in msg
            for leak in ("TypeError", "OverflowError", "unexpected type", "PyString"):
                assert leak not in msg, msg
            if "is none of the forms this option takes" in msg:
                # A field of several forms (a count, a list or a table) names itself and the
                # whole value given.
                assert msg.startswith(f"invalid option `{key}`: {value!r} is none"), msg
                continue
            assert f"`{key}{path}" in msg, msg
            assert f"expected {words}" in msg, msg
            assert msg.endswith(f"got {shown!r}"), msg
    assert tried, f"{name}: no field of a scalar, list or table type"


def test_a_negative_count_and_a_bad_name_say_what_is_expected():
    with pytest.raises(
        floorscan.OptionError, match=r"`min_run_px`: expected a whole number >= 0, got -1$"
    ):
        native.ranging.check_appearance_options({"min_run_px": -1})
    with pytest.raises(
        floorscan.OptionError, match=r"`refinement`: expected one of the option's names"
    ):
        native.ranging.check_ranger_options({"refinement": 3})


def test_enum_choices_come_from_the_schema_and_agree_with_the_pipeline():
    """The drive's sensor, table and ranger kinds are the core's enums: the ranger kinds are
    the pipeline's (a drive takes what `[ranger] kind` takes)."""
    from floorscan.drive import SENSORS, TABLES, DriveOptions
    from floorscan.options import choices
    from floorscan.pipeline.mapper import RANGER_KINDS

    assert choices("drive_run", "ranger") == RANGER_KINDS
    assert SENSORS == ("camera", "laser") and TABLES == ("calibrated", "exact")
    assert choices("drive_run", "seconds") == ()  # a number, no enum
    with pytest.raises(floorscan.OptionError, match="sensor"):
        DriveOptions(sensor="sonar")
    with pytest.raises(floorscan.OptionError, match="replan_every"):
        DriveOptions(replan_every=0)
