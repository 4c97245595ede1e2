"""Strict, physical case-file input (issue 15 items 8-9): numbers given as strings or booleans
are refused, values far outside physical sense are refused with the limit named, an empty case
file says it is empty, a UTF-16 file is called UTF-16, and a bad motion file named in a case file
is reported with the case file and key."""

import warnings

import pytest

from murus.config import PHYSICAL_LIMITS, CaseError
from murus.rocking.case import build, load_case

BODY = """[body]
width = {width}
height = 1.8
thickness = 0.138
top_mass = 5000.0

[motion]
type = "sine-pulse"
amplitude_g = 0.30
frequency = 2.0
scale = {scale}
"""


def _case(tmp_path, width="0.72", scale="1.0", text=None):
    p = tmp_path / "wall.toml"
    p.write_text(text if text is not None else BODY.format(width=width, scale=scale),
                 encoding="utf-8")
    return p


def _error(p) -> str:
    with pytest.raises(CaseError) as exc:
        cfg, path, text = load_case(p)
        build(cfg, path, text)
    msg = str(exc.value)
    assert "\n" not in msg
    return msg


def test_good_case_accepted(tmp_path):
    cfg, path, text = load_case(_case(tmp_path))
    assert cfg.body.width == 0.72
    # an integer where a float is expected is a number: accepted
    cfg, _, _ = load_case(_case(tmp_path, width="1"))
    assert cfg.body.width == 1.0


@pytest.mark.parametrize("value, kind", [('"0.6"', "a string"), ("true", "a boolean")])
def test_number_as_string_or_boolean_refused(tmp_path, value, kind):
    msg = _error(_case(tmp_path, width=value))
    assert "wall.toml line 2: [body.width]" in msg and f"not {kind}" in msg


@pytest.mark.parametrize("key, value", [("width", "6e9"), ("scale", "-1e9")])
def test_far_outside_physical_sense_refused_with_limit(tmp_path, key, value):
    msg = _error(_case(tmp_path, **{key: value}))
    limit = PHYSICAL_LIMITS[key][0]
    assert f"[{'body' if key == 'width' else 'motion'}.{key}]" in msg
    assert f"at most {limit:g}" in msg


def test_vanishing_length_refused_with_its_minimum(tmp_path):
    """A 6 nm wall is no wall: the smallest non-zero length is named (issue 15, item 8)."""
    from murus.config import PHYSICAL_MINIMA

    msg = _error(_case(tmp_path, width="6e-9"))
    assert "[body.width]" in msg and f"at least {PHYSICAL_MINIMA['width']:g} m" in msg
    load_case(_case(tmp_path, width=repr(PHYSICAL_MINIMA["width"])))  # the minimum itself


def test_limits_leave_room_for_real_walls(tmp_path):
    """The largest masonry walls and the mock-ups of Savalle et al. (2022) (44 mm stones) stay
    inside."""
    assert PHYSICAL_LIMITS["height"][0] >= 100.0 and PHYSICAL_LIMITS["width"][0] >= 100.0
    load_case(_case(tmp_path, width="0.044", scale="-2.5"))


def test_empty_and_comment_only_case_files(tmp_path):
    assert "the case file is empty" in _error(_case(tmp_path, text="  \n\n"))
    assert "only comments" in _error(_case(tmp_path, text="# nothing here\n"))


def test_utf16_case_file_named(tmp_path):
    p = tmp_path / "wall.toml"
    p.write_text(BODY.format(width="0.72", scale="1.0"), encoding="utf-16")
    assert "UTF-16 text" in _error(p)


def test_bad_motion_file_names_case_file_and_key(tmp_path):
    rec = tmp_path / "record.csv"
    rec.write_text("0.0,0.1\n0.01,0.2\n0.005,0.0\n", encoding="utf-8")
    text = ("[body]\nwidth = 0.72\nheight = 1.8\ntop_mass = 5000.0\n\n"
            "[motion]\nfile = \"record.csv\"\nunits = \"g\"\n")
    msg = _error(_case(tmp_path, text=text))
    assert msg.startswith("wall.toml line 7: [motion.file] motion file record.csv line 3")
    assert "time 0.005 s does not increase (previous 0.01 s)" in msg
    assert "np.float64" not in msg


def test_utf16_motion_file_named(tmp_path):
    from murus.motion import MotionFormatError, read

    p = tmp_path / "r.csv"
    p.write_text("# units: g\n0,0\n0.01,0.1\n", encoding="utf-16")
    with pytest.raises(MotionFormatError, match="UTF-16 text: save it as UTF-8"):
        read(p)


def test_warnings_become_one_line_notes(capsys):
    from murus import cliutil

    with warnings.catch_warnings():
        cliutil.warnings_as_notes()
        warnings.warn("the record is\n short", UserWarning, stacklevel=1)
    err = capsys.readouterr().err
    assert err == "note: the record is short\n"


def test_cli_physical_limits_named():
    from typer.testing import CliRunner

    from murus.cli import app

    r = CliRunner().invoke(app, ["retaining", "pseudo-static", "--preset", "DSRW1",
                                 "--kv-ratio", "5"])
    assert r.exit_code == 2
    assert "--kv-ratio 5 is outside the physical range" in r.output
    assert "at most 1" in r.output and len(r.output.strip().splitlines()) == 1
    r = CliRunner().invoke(app, ["design", "tie", "--width", "0.6", "--height", "6e9"])
    assert r.exit_code == 2 and "--height 6e+09 m is outside" in r.output


def test_error_lines_have_no_numpy_reprs():
    import numpy as np

    from murus.cliutil import plain

    msg = f"time {np.float64(5.0)!r} s after {np.int64(3)!r}, flag {np.bool_(True)!r}\n next"
    assert plain(msg) == "time 5.0 s after 3, flag True next"


def test_cli_messages_name_options_not_python_parameters():
    from typer.testing import CliRunner

    from murus.cli import app

    r = CliRunner().invoke(app, ["retaining", "pseudo-static", "--preset", "DSRW1",
                                 "--kv-ratio", "nan"])
    assert r.exit_code == 2 and "--kv-ratio nan: not a finite number" in r.output
    r = CliRunner().invoke(app, ["design", "damper", "--block", "block1", "--delta-t", "-10"])
    assert r.exit_code == 2 and "--delta-t" in r.output and "delta_t" not in r.output


def test_option_words_leave_case_file_keys_alone():
    """Case-file messages name keys (``[wall.stone_height]``), not options."""
    from types import SimpleNamespace

    from murus.cliutil import option_words

    opt = SimpleNamespace(name="stone_height", opts=["--stone-height"])
    ctx = SimpleNamespace(command=SimpleNamespace(params=[opt]))
    msg = "bad.toml line 1: [wall.stone_height] give stone_height"
    assert option_words(msg, ctx) == msg
    assert option_words("stone_height must be > 0", ctx) == "--stone-height must be > 0"
    assert option_words("see [wall.stone_height]", ctx) == "see [wall.stone_height]"
