"""Geometry of the rocking bodies against EURODYN (2020), Table 1 and Mordant et al. (SERIES), §3.1
(closed forms)."""

import csv
import math

import pytest

from murus.rocking import BodyError, RigidBlock, restrained_wall_block, series_clay_wall


def _table1(data_dir):
    with open(data_dir / "rocking" / "eurodyn2020_table1.csv") as fh:
        rows = [r for r in csv.DictReader(line for line in fh if not line.startswith("#"))]
    return rows


def test_eurodyn2020_table1_within_half_percent(data_dir):
    rows = _table1(data_dir)
    assert len(rows) == 6
    for row in rows:
        blk = restrained_wall_block(row["label"])
        assert blk.slenderness == pytest.approx(float(row["lambda"]), rel=1e-12)
        assert blk.height == pytest.approx(float(row["h_m"]), rel=1e-12)
        # the table rounds m to 1 kg, R to 0.01 m: 0.5 % covers the rounding (R: 0.33 % worst)
        assert blk.mass == pytest.approx(float(row["m_kg"]), rel=5e-3)
        assert blk.R == pytest.approx(float(row["R_m"]), rel=5e-3)
        assert blk.I_O == pytest.approx(float(row["I0_kgm2"]), rel=5e-3)


@pytest.mark.parametrize(
    "kind, alpha, R, p, e",
    [
        ("long", 0.528074, 2.083867, 2.169699, 0.492228),
        ("short", 0.197396, 1.835647, 2.311745, 12.0 / 13.0),
    ],
)
def test_series_walls_top_mass(kind, alpha, R, p, e):
    w = series_clay_wall(kind)
    assert w.mass == 5000.0
    assert w.alpha == pytest.approx(alpha, abs=1e-6)
    assert w.R == pytest.approx(R, abs=1e-6)
    assert w.p == pytest.approx(p, abs=1e-6)
    assert w.housner_restitution() == pytest.approx(e, abs=1e-6)
    # mass on top: I_O = m R^2 (Mordant et al. (SERIES), eq. 4), e = cos 2 alpha (eq. 10)
    assert w.I_O == pytest.approx(w.mass * w.R**2, rel=1e-12)
    assert w.housner_restitution() == pytest.approx(math.cos(2 * w.alpha), rel=1e-12)


def test_housner_rectangle():
    b = RigidBlock(width=0.25, height=1.0, density=2000.0)
    assert b.housner_restitution() == pytest.approx(0.9118, abs=5e-5)
    assert b.housner_restitution() == pytest.approx(1 - 1.5 * math.sin(b.alpha) ** 2, rel=1e-12)
    assert b.I_O == pytest.approx(4.0 / 3.0 * b.mass * b.R**2, rel=1e-12)
    assert b.uplift_acceleration == pytest.approx(2.4525, rel=1e-12)


def test_self_weight_and_top_mass_combine():
    # uniform rectangle of mass m_b plus a top mass m_t: centre of gravity and inertia by hand
    b = RigidBlock(width=1.0, height=2.0, thickness=0.5, density=1000.0, top_mass=1000.0)
    assert b.body_mass == pytest.approx(1000.0)
    assert b.z_G == pytest.approx(1.5)
    assert b.I_O == pytest.approx(1000 * (1 + 4) / 3 + 1000 * (4 + 0.25))
    assert b.alpha == pytest.approx(math.atan(0.5 / 1.5))


@pytest.mark.parametrize(
    "kwargs, key",
    [
        ({"width": 0.0, "height": 1.0, "density": 1.0}, "width"),
        ({"width": 1.0, "height": -1.0, "density": 1.0}, "height"),
        ({"width": 1.0, "height": 1.0, "density": -1.0}, "density"),
        ({"width": 1.0, "height": 1.0}, "no mass"),
        ({"width": 1.0, "height": 1.0, "density": float("nan")}, "density"),
    ],
)
def test_bad_bodies(kwargs, key):
    with pytest.raises(BodyError, match=key):
        RigidBlock(**kwargs)


def test_lumped_masses_on_the_centreline():
    """Floors carried by a façade: masses m_i at heights y_i on the centreline. Centre of
    gravity and inertia about a corner by hand; a mass at the top is the top mass."""
    b = RigidBlock(width=0.5, height=6.0, density=2000.0, masses=((3000.0, 3.0), (2000.0, 6.0)))
    mb = 2000.0 * 0.5 * 6.0
    assert b.mass == pytest.approx(mb + 5000.0)
    assert b.z_G == pytest.approx((mb * 3.0 + 3000 * 3.0 + 2000 * 6.0) / (mb + 5000.0))
    assert b.I_O == pytest.approx(mb * (0.25 + 36.0) / 3 + 3000 * (9 + 0.0625)
                                  + 2000 * (36 + 0.0625))
    top = RigidBlock(width=0.5, height=6.0, density=2000.0, top_mass=2000.0)
    same = RigidBlock(width=0.5, height=6.0, density=2000.0, masses=[[2000.0, 6.0]])
    for q in ("mass", "z_G", "I_O", "R", "alpha", "p"):
        assert getattr(same, q) == pytest.approx(getattr(top, q), rel=1e-14)
    assert same.masses == ((2000.0, 6.0),)


@pytest.mark.parametrize("masses, msg", [
    (((1.0, 7.0),), "above the top"),
    (((-1.0, 1.0),), "masses\\[0\\] mass"),
    (((1.0,),), "pair"),
    ((1.0,), "pairs"),
])
def test_bad_lumped_masses(masses, msg):
    with pytest.raises(BodyError, match=msg):
        RigidBlock(width=0.5, height=6.0, density=2000.0, masses=masses)
