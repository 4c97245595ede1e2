"""EN 1996-1-1 compressed length against Mordant et al. (SERIES), Table 2 and closed forms."""

import csv

import numpy as np
import pytest

from murus import G
from murus.eurocode.ec6 import EC6Error, EquivalentStatic, compressive_length, kern_limit


def rows(data_dir):
    with open(data_dir / "eurocode" / "mordant_series_table2.csv") as fh:
        return list(csv.DictReader(line for line in fh if not line.startswith("#")))


def test_series_table2_to_0p1_mm(data_dir):
    case = EquivalentStatic(mass=5000.0, height=1.80, factor=2.5)
    for r in rows(data_dir):
        L, a = float(r["L_m"]), float(r["level_g"])
        lin = case.compressive_length(L, a, "linear") * 1e3
        con = case.compressive_length(L, a, "constant") * 1e3
        assert con == pytest.approx(float(r["constant_mm"]), abs=0.1)
        assert lin == pytest.approx(float(r["expected_linear_mm"]), abs=0.1)
    # the one printed value the assumptions do not give: 1201.9 mm is e = 0.6494 m, the
    # eccentricity of 0.1443 g, while the constant column of the same row is exactly 0.15 g
    e = 1.05 - 1.2019 / 3
    assert e / (2.5 * 1.8) == pytest.approx(0.1443, abs=1e-4)


def test_closed_forms_and_limits():
    L, N = 2.0, 1000.0
    # whole section compressed up to the kern, then 3 (L/2 - e), then zero
    assert kern_limit(L) == pytest.approx(L / 6)
    assert compressive_length(N, N * L / 6, L) == pytest.approx(L)
    assert compressive_length(N, N * 0.5, L) == pytest.approx(1.5)
    assert compressive_length(N, N * 1.0, L) == 0.0
    assert compressive_length(N, -N * 0.5, L) == pytest.approx(1.5)  # sign of M irrelevant
    # constant block: L - 2e; both coincide at e = L/2 (zero) and the linear one is longer
    e = np.linspace(0, 1.2, 50)
    lin = compressive_length(np.full(50, N), N * e, L)
    con = compressive_length(np.full(50, N), N * e, L, "constant")
    assert np.all(lin >= con - 1e-15)
    assert np.allclose(con, np.clip(L - 2 * e, 0, None))
    # continuity of the linear law at the kern
    assert compressive_length(N, N * (L / 6 + 1e-12), L) == pytest.approx(L, abs=1e-10)


def test_equivalent_static_forces():
    N, M = EquivalentStatic().forces(0.1)
    assert N == pytest.approx(5000 * G)
    assert M == pytest.approx(2.5 * 0.1 * 5000 * G * 1.8)


@pytest.mark.parametrize("args, word", [((0.0, 1.0, 1.0), "axial"), ((1.0, 1.0, -1.0), "length"),
                                         ((1.0, float("nan"), 1.0), "moment")])
def test_bad_input(args, word):
    with pytest.raises(EC6Error, match=word):
        compressive_length(*args)
    with pytest.raises(EC6Error, match="distribution"):
        compressive_length(1.0, 0.1, 1.0, "parabolic")
