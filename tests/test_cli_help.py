"""Help texts keep their units: ``[m]``, ``[deg]`` and ``[output]`` are text, not rich markup
(typer's default markup mode swallowed every bracketed unit of every option)."""

import pytest
from typer.testing import CliRunner

from murus.cli import app


@pytest.mark.parametrize("args, text", [
    (["design", "tie", "--help"], "Wall height h [m]."),
    (["study", "run", "--help"], "[output] folder"),
    (["retaining", "pseudo-static", "--help"], "[deg]"),
])
def test_units_survive_in_help(args, text):
    r = CliRunner().invoke(app, args, env={"COLUMNS": "100"})
    assert r.exit_code == 0, r.output
    assert text in " ".join(r.output.split())
