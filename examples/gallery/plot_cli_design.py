"""
The command line from Python: ``murus design``
==============================================

Everything the ``murus`` command does, the Python API does in a few lines; the command line is
a thin layer over it. Here the ``murus design tie`` and ``murus design resonance`` commands
(EURODYN (2020), eqs. 8 and 12) run in-process with typer's test runner, as a user would type
them in a terminal.
"""

from typer.testing import CliRunner

from murus.cli import app

runner = CliRunner()
for args in (["--help"], ["design", "tie", "--help"]):
    result = runner.invoke(app, args)
    print(f"$ murus {' '.join(args)}  (exit code {result.exit_code})")
    print("\n".join(result.output.splitlines()[:12]))
    print()
