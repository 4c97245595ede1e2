"""``murus retaining`` sub-app: output, JSON, one-line errors with exit code 2, light imports."""

import json
import subprocess
import sys

import pytest
from typer.testing import CliRunner

from murus.retaining.cli import app

runner = CliRunner()


def _cli(*args):
    return runner.invoke(app, list(args))


def _err(r):
    return (r.stderr if r.stderr else r.output).strip()


def test_pseudo_static_text():
    r = _cli("pseudo-static", "--preset", "DSRW1")
    assert r.exit_code == 0, r.output
    assert "A_pseudo = 1.588" in r.output and "overturning" in r.output
    assert "joint 0" in r.output and "delta = 25.133 deg" in r.output
    r = _cli("pseudo-static", "--preset", "DSRW1", "--kv-ratio", "0.5")
    assert r.exit_code == 0, r.output
    assert "A_pseudo = 1.469" in r.output
    assert "kv upwards" in r.output and "kv downwards" in r.output


def test_pseudo_static_json_and_options():
    r = _cli("pseudo-static", "--preset", "DSRW1", "--kv-ratio", "0.5", "--json")
    assert r.exit_code == 0, r.output
    d = json.loads(r.output)
    assert d["wall"] == "DSRW1" and d["mode"] == "overturning" and d["joint"] == 0
    assert abs(d["A_pseudo"] / 1.50 - 1) < 0.05
    assert d["A_pseudo"] == pytest.approx(d["kh"] * d["g"], rel=1e-14)
    assert d["kv"] == pytest.approx(0.5 * d["kh"]) and d["kv_sign"] == "upwards"
    assert set(d["by_sign"]) == {"upwards", "downwards"}
    assert d["assumptions"]["dynamic_point"] == pytest.approx(1 / 3)
    r = _cli("pseudo-static", "--preset", "DSRW1", "--interface-delta", "--dynamic-point", "0.5",
             "--json")
    d2 = json.loads(r.output)
    assert d2["delta_deg_used"] == pytest.approx(37.7) and d2["A_pseudo"] > 1.7
    r = _cli("pseudo-static", "--preset", "DSRW1", "--delta", "0", "--base", "horizontal",
             "--json")
    assert json.loads(r.output)["delta_deg_used"] == 0.0
    r = _cli("pseudo-static", "--preset", "mockup-1.3", "--json")
    assert json.loads(r.output)["mode"] == "sliding"


def test_geometry_command():
    r = _cli("geometry", "--preset", "DSRW1")
    assert r.exit_code == 0, r.output
    assert "25 bed joints" in r.output and "area = 1.60174" in r.output
    d = json.loads(_cli("geometry", "--preset", "DSRW4", "--json").output)
    assert d["area_m2"] == pytest.approx(1.75) and len(d["joints"]) == 25
    assert d["polygon"][2] == [0.7, 2.5]


@pytest.mark.parametrize("args, word", [
    (["pseudo-static", "--preset", "DSRW9"], "unknown preset 'DSRW9'"),
    (["pseudo-static", "--preset", "DSRW1", "--delta", "50"], "exceeds the backfill friction"),
    (["pseudo-static", "--preset", "DSRW1", "--dynamic-point", "2"], "--dynamic-point"),
    (["pseudo-static", "--preset", "DSRW1", "--thrust", "x"], "thrust must be"),
    (["pseudo-static", "--preset", "DSRW1", "--kv-ratio", "-1"], "--kv-ratio"),
    (["pseudo-static", "--preset", "DSRW1", "--base", "flat"], "base must be"),
    (["pseudo-static", "--preset", "DSRW1", "--interface-delta", "--delta", "10"], "not several"),
    (["pseudo-static", "--preset", "mockup-x"], "unknown mock-up"),
    (["geometry", "--preset", "nope"], "unknown preset"),
])
def test_bad_input_exit_2_one_line(args, word):
    r = _cli(*args)
    assert r.exit_code == 2
    err = _err(r)
    assert len(err.splitlines()) == 1, err
    assert err.startswith("error: ") and word in err, err


def test_imports_stay_light():
    code = ("import sys; import murus.retaining.cli; "
            "bad = [m for m in ('numba', 'matplotlib', 'scipy', 'numpy') if m in sys.modules]; "
            "from typer.testing import CliRunner; "
            "r = CliRunner().invoke(murus.retaining.cli.app, ['pseudo-static', '--preset', "
            "'DSRW1']); assert r.exit_code == 0, r.output; "
            "bad += [m for m in ('numba', 'matplotlib') if m in sys.modules]; print(bad)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    assert out.stdout.strip() == "[]", out.stdout + out.stderr


@pytest.mark.parametrize("args, word", [
    (["--backfill", "thrust", "--width", "5"], "need --backfill discrete or continuum"),
    (["--backfill", "discrete", "--boundary", "free-field"], "boundary must be one of"),
    (["--backfill", "soil"], "backfill must be 'thrust', 'discrete' or 'continuum'"),
    (["--damping-frame", "relative"], "--damping-frame must be 'base' or 'absolute'"),
    (["--backfill", "thrust", "--subcycle", "auto"], "--subcycle needs --backfill continuum"),
    (["--subcycle", "0"], "--subcycle must be 'auto' or a positive integer"),
    (["--subcycle", "fast"], "--subcycle must be 'auto' or a positive integer"),
])
def test_collapse_backfill_options_bad_input(tmp_path, args, word):
    out = tmp_path / "out"
    r = _cli("collapse", "--preset", "DSRW1", "--out", str(out), *args)
    assert r.exit_code == 2
    err = _err(r)
    assert len(err.splitlines()) == 1 and err.startswith("error: ") and word in err, err
    assert not out.exists()


def test_collapse_subcycle_beyond_its_limit(tmp_path):
    """The subcycle's limit needs the built model: the error comes once it is built (after
    the progress line of the run), one error line, exit 2, nothing written."""
    out = tmp_path / "out"
    r = _cli("collapse", "--preset", "DSRW1", "--out", str(out), "--subcycle", "100000")
    assert r.exit_code == 2
    err = [x for x in _err(r).splitlines() if x.startswith("error: ")]
    assert len(err) == 1 and "subcycle = 100000: must be an integer in [1, " in err[0], err
    assert _err(r).splitlines()[-1] == err[0]
    assert not out.exists()
