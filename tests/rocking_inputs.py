"""Small shared inputs of the command-line tests of the rocking engine
(tests/rocking/test_cli_run.py, tests/test_output_safety.py): a case file and its record. ``tests/``
is on ``sys.path`` through its conftest.py."""

import math

import numpy as np


def rocking_case(duration: float, body: str = "", motion: str = "") -> str:
    """Case file of a 0.25 x 1.0 m block (2000 kg/m³, Housner restitution) driven by
    ``record.csv`` in g, event-driven for ``duration`` [s]; ``body`` and ``motion`` add lines to
    those tables."""
    return ("\n[body]\nwidth = 0.25\nheight = 1.0\nthickness = 1.0\ndensity = 2000.0\n" + body
            + '[restitution]\nlaw = "housner"\n[motion]\nfile = "record.csv"\nunits = "g"\n'
            + motion + f'[solver]\nmethod = "event"\nduration = {duration!r}\n')


def write_record(folder, name: str = "record.csv", amp_g: float = 0.5, seconds: float = 3.0):
    """A decaying 2 Hz sine of amplitude ``amp_g`` [g], ``seconds`` long at 0.01 s, as CSV."""
    t = np.arange(0, seconds, 0.01)
    a = amp_g * np.sin(2 * math.pi * 2.0 * t) * np.exp(-t)
    np.savetxt(folder / name, np.column_stack([t, a]), delimiter=",", fmt="%.6f")
