"""Classification of tests as cantilever, hybrid or rocking (murus.identify.classify) on
synthetic rotation histories of each class."""

import numpy as np
import pytest

from murus.identify.classify import ClassifyError, Criterion, classify, lifted_length
from murus.identify.testdata import ShakingTableTest

T = np.arange(2000) / 100.0


def _histories(kind, seed=0):
    """Rotation histories [rad]: a cantilever bends (top rotation from the wall's deformation,
    small rotation at the base joint), a rocking wall rotates as a rigid body (base = top),
    a hybrid does both."""
    rng = np.random.default_rng(seed)
    bend = 2e-4 * np.sin(2 * np.pi * 6.0 * T) * np.exp(-0.1 * T)
    rock = {"cantilever": 0.0, "hybrid": 4e-4, "rocking": 8e-3}[kind]
    base_elastic = 0.1 * bend
    rigid = rock * np.sin(2 * np.pi * 1.3 * T) * (T > 5)
    noise = 2e-6 * rng.standard_normal((2, T.size))
    rot_bottom = base_elastic + rigid + noise[0]
    rot_top = base_elastic + bend + rigid + noise[1]
    return rot_bottom, rot_top


@pytest.mark.parametrize("kind", ["cantilever", "hybrid", "rocking"])
def test_each_class(kind):
    c = classify(*_histories(kind), name=kind)
    assert c.label == kind
    assert c.to_dict()["class"] == kind


def test_ratios_and_thresholds():
    rb, rt = _histories("hybrid")
    c = classify(rb, rt)
    assert 0.3 <= c.ratio < 0.8
    assert classify(rb, rt, Criterion(cantilever_below=0.0, rocking_above=c.ratio)).label \
        == "rocking"
    assert classify(rb, rt, Criterion(cantilever_below=c.ratio + 1e-9,
                                      rocking_above=0.9)).label == "cantilever"
    # below the minimum rotation a test is a cantilever whatever the ratio
    assert classify(1e-6 * rt, 1e-6 * rt).label == "cantilever"
    assert classify(rt, rt, Criterion(min_rotation=0.0)).label == "rocking"


def test_criterion_and_input_errors():
    with pytest.raises(ClassifyError, match="cantilever_below <= rocking_above"):
        Criterion(cantilever_below=0.9, rocking_above=0.5)
    with pytest.raises(ClassifyError, match="same length"):
        classify(np.zeros(3), np.zeros(4))
    t = ShakingTableTest(name="x", sampling_rate=10.0, wall_length=1.0, wall_height=1.0,
                         channels={"table_acc": np.zeros(5), "top_acc": np.zeros(5)})
    from murus.identify.classify import classify_test

    with pytest.raises(ClassifyError, match="rot_bottom and rot_top"):
        classify_test(t)


def test_lifted_length_of_rigid_rocking():
    """Rigid rocking about the corners: the lifted length is L whenever theta != 0 (with no
    closure) and 0 at rest (Mordant et al. (SERIES), Figures 19-20)."""
    L, x = 0.72, np.linspace(0.02, 0.70, 5)
    th = 5e-3 * np.sin(2 * np.pi * 1.0 * T) * (T > 10)
    d = np.where(th > 0, (L - x)[:, None] * np.sin(th), -x[:, None] * np.sin(th))
    ch = {"table_acc": np.zeros(T.size), "top_acc": np.zeros(T.size),
          "rot_bottom": th, "rot_top": th}
    ch.update({f"lvdt_{k + 1}": d[k] for k in range(5)})
    test = ShakingTableTest(name="S08", sampling_rate=100.0, wall_length=L, wall_height=1.8,
                            channels=ch, lvdt_positions=x)
    t, lift = lifted_length(test)
    assert np.all(lift[T <= 10] == 0.0)
    moving = (T > 10) & (np.abs(th) > 0)
    np.testing.assert_allclose(lift[moving], L, atol=1e-12)
    # with a closure of 10 um the lifted length is L - 10 um / |sin theta|, clipped
    t, lift = lifted_length(test, closure=1e-5)
    big = np.abs(th) > 1e-3
    np.testing.assert_allclose(lift[big], L - 1e-5 / np.abs(np.sin(th[big])), rtol=1e-9)
