"""One error base (issue 16, item 3): every murus error is a MurusError carrying the key path of
the offending input; the key path, not the message text, gives the file and line."""

from __future__ import annotations

import importlib
import inspect
import pickle
import pkgutil
from pathlib import Path

import pytest
from typer.testing import CliRunner

import murus
from murus.config import CaseError, fail_at, key_line, load_toml
from murus.errors import MurusError, key_name

# modules that need an optional extra (a missing one is not a murus error class)
_OPTIONAL = ("dask", "distributed", "h5py", "pyvista", "vtk")


def _murus_exceptions() -> list[type]:
    found = {}
    for info in pkgutil.walk_packages(murus.__path__, "murus."):
        try:
            mod = importlib.import_module(info.name)
        except ImportError as exc:  # pragma: no cover - an optional extra missing
            if any(name in str(exc) for name in _OPTIONAL):
                continue
            raise
        for _, obj in inspect.getmembers(mod, inspect.isclass):
            if issubclass(obj, BaseException) and obj.__module__.startswith("murus"):
                found[f"{obj.__module__}.{obj.__qualname__}"] = obj
    return list(found.values())


def test_every_murus_error_derives_from_murus_error():
    classes = _murus_exceptions()
    assert len(classes) >= 30  # the error classes of the package (31 when written)
    for cls in classes:
        if issubclass(cls, Warning) or cls is MurusError:
            continue
        assert issubclass(cls, MurusError), cls
        # bad input stays a ValueError; the missing optional extra stays an ImportError
        assert issubclass(cls, ValueError) != issubclass(cls, ImportError), cls


def test_key_and_source_survive_pickling():
    from murus.rocking.model import ModelError

    exc = pickle.loads(pickle.dumps(ModelError("tie height", key=("tie",), source="a.toml")))
    assert (str(exc), exc.key, exc.source) == ("tie height", ("tie",), "a.toml")
    case = pickle.loads(pickle.dumps(fail_at(Path("c.toml"), "[body]\nwidth = 1\n",
                                             ("body", "width"), "bad")))
    assert (str(case), case.key, case.reason) == ("c.toml line 2: [body.width] bad",
                                                  ("body", "width"), "bad")


TOML = """\
# a case
[body]
width = 0.6

[restraint.tie]
stiffness = 7e4
height = 3.5
[sweep]
"restraint.tie.stiffness" = [1.0, 2.0]
body.height = [3.0]
[[blocks]]
x = 1
[[blocks]]
x = 2
"""


@pytest.mark.parametrize(("loc", "line"), [
    (("body", "width"), 3), (("restraint", "tie"), 5), (("restraint", "tie", "height"), 7),
    (("restraint", "tie", "x"), 5),  # a default: the line of its table
    (("sweep", "restraint.tie.stiffness"), 9), (("sweep", "body.height"), 10),
    (("sweep", "body", "height"), 10), (("blocks", 1, "x"), 14), (("blocks", 0), 11),
    (("motion",), None)])
def test_key_path_maps_to_line(loc, line):
    assert key_line(TOML, loc) == line


def test_key_path_maps_to_file_and_line_in_cli_message(tmp_path):
    from murus.cliutil import error_line
    from murus.rocking.model import ModelError

    f = tmp_path / "case.toml"
    f.write_text(TOML)
    assert str(fail_at(f, TOML, ("restraint", "tie", "height"), "too high")) == \
        "case.toml line 7: [restraint.tie.height] too high"
    assert str(fail_at(f, TOML, ("blocks", 1, "x"), "bad", indices=True)) == \
        "case.toml line 14: [blocks[1].x] bad"
    # an error of a model object that carries its key path and source: the CLI locates it
    exc = ModelError("tie height 3.5 m is above the wall", key=("restraint", "tie"), source=f)
    assert error_line(exc) == "case.toml line 5: [restraint.tie] tie height 3.5 m is above " \
        "the wall"
    assert key_name(("blocks", 1, "x")) == "blocks[1].x" and key_name(()) == "(top level)"


# ------------------------------------------------------- the four former message-matching sites
ROCKING = """\
[body]
width = 0.6
height = 3.0
density = 2000.0
[motion]
type = "free"
theta0_over_alpha = 0.5
"""


@pytest.mark.parametrize(("extra", "key", "line"), [
    ("[restraint.tie]\nstiffness = 7e4\nheight = 3.5\n", ("restraint", "tie"), 8),
    ("[restraint.damper]\ncoefficient = 1e3\nheight = 2.0\nx = 0.4\n",
     ("restraint", "damper"), 8),
    ("[restraint]\nmotion_sides = \"one\"\n", ("restraint", "motion_sides"), 9),
    ("[restraint.transverse_walls]\nstiffness = 4.5e8\neffective_height = 3.0\n",
     ("restraint", "transverse_walls"), 8),
])
def test_rocking_case_locates_model_errors_by_key(tmp_path, extra, key, line):
    from murus.rocking.case import build, load_case

    f = tmp_path / "case.toml"
    f.write_text(ROCKING + extra)
    cfg, path, text = load_case(f)
    with pytest.raises(CaseError) as info:
        build(cfg, path, text)
    assert info.value.key == key and info.value.source == f
    assert str(info.value).startswith(f"case.toml line {line}: [{'.'.join(key)}] ")


def test_rocking_model_error_carries_its_argument():
    from murus.rocking.body import RigidBlock
    from murus.rocking.model import ModelError, RockingModel
    from murus.rocking.restitution import Housner
    from murus.rocking.restraints import Tie

    body = RigidBlock(0.6, 3.0, 1.0, 2000.0)
    with pytest.raises(ModelError) as info:
        RockingModel(body, Housner(), tie=Tie(7e4, 3.5))
    assert info.value.key == ("tie",)


def test_study_locates_inline_case_errors_by_key(tmp_path):
    from murus.studies.study import load_study

    f = tmp_path / "study.toml"
    f.write_text("[case.body]\nwidth = 0.6\nheight = 3.0\ndensity = 2000.0\n"
                 "[case.motion]\ntype = \"sine-pulse\"\namplitude = 1.0\nfrequency = 2.0\n"
                 "[case.restraint.tie]\nstiffness = 7e4\nheight = 3.5\n"
                 "[sweep]\n\"motion.frequency\" = [1.0, 2.0]\n")
    with pytest.raises(CaseError) as info:
        load_study(f).plan()
    assert info.value.key == ("case", "restraint", "tie")
    assert str(info.value).startswith("study.toml line 9: [case.restraint.tie] tie height 3.5 m "
                                      "is above the wall")
    assert str(info.value).endswith("(at motion.frequency = 1)")


def test_study_sweep_key_line_from_config(tmp_path):
    from murus.studies.study import load_study

    f = tmp_path / "study.toml"
    f.write_text("[case.body]\nwidth = 0.6\nheight = 3.0\ndensity = 2000.0\n"
                 "[case.motion]\ntype = \"sine-pulse\"\namplitude = 1.0\nfrequency = 2.0\n"
                 "[sweep]\n\"motion.frequency\" = [1.0]\n\"body.nothing\" = [1.0]\n")
    with pytest.raises(CaseError) as info:
        load_study(f).plan()
    assert info.value.key == ("sweep", "body.nothing")
    assert str(info.value).startswith("study.toml line 11: [sweep.body.nothing] ")


def test_retaining_study_locates_wall_errors_by_key(tmp_path):
    from murus.retaining.geometry import GeometryError, preset
    from murus.retaining.study import behaviour_study

    with pytest.raises(GeometryError) as info:
        preset("DSRW1", stone_height=-0.1)
    assert info.value.key == ("stone_height",)
    f = tmp_path / "bf.toml"
    text = "[wall]\npreset = 'DSRW1'\nstone_height = -0.1\n[cases]\nfrequencies = [5.0]\n"
    f.write_text(text)
    data, text = load_toml(f)
    with pytest.raises(CaseError) as info:
        behaviour_study(data, f, text)
    assert info.value.key == ("wall", "stone_height")
    assert str(info.value).startswith("bf.toml line 3: [wall.stone_height] stone_height must")
    # the DEM wall of a mock-up without courses: the key of the DemWallError
    data, text = {"wall": {"preset": "mockup-1.3"}, "cases": {"frequencies": [5.0]}}, ""
    with pytest.raises(CaseError) as info:
        behaviour_study(data)
    assert info.value.key == ("wall", "stone_height")
    assert str(info.value).startswith("[wall.stone_height] mockup H/B=1.3: the courses are "
                                      "unknown")


def test_retaining_cli_names_the_option_from_the_key(tmp_path):
    from murus.cli import app

    res = CliRunner().invoke(app, ["retaining", "behaviour-factor", "--preset", "DSRW1",
                                   "--stone-height", "-0.1", "--out", str(tmp_path / "o")])
    assert res.exit_code == 2
    # the key ("wall", "stone_height") names the option, once (the reason's own parameter
    # name is not repeated after it)
    assert "error: --stone-height must be > 0, got -0.1" in res.output
    res = CliRunner().invoke(app, ["retaining", "behaviour-factor", "--preset", "mockup-1.3",
                                   "--out", str(tmp_path / "o")])
    assert res.exit_code == 2 and "error: --stone-height mockup H/B=1.3: the courses" \
        in res.output


def test_executor_options_are_one_shared_set():
    from murus.retaining.cli import behaviour_factor_cmd
    from murus.studies.cli import run

    names = ("executor", "workers", "scheduler", "dask", "serial")
    a = inspect.signature(run).parameters
    b = inspect.signature(behaviour_factor_cmd).parameters
    for n in names:
        assert a[n].default is b[n].default, n
