from pathlib import Path

import pytest

DATA = Path(__file__).parent / "data"


@pytest.fixture
def data_dir() -> Path:
    return DATA


@pytest.fixture(scope="session")
def small_wall_packing():
    """Settled disc packing behind DSRW1 scaled to H = 0.6 m (B = 0.4 m), W = 1 m, discs of mean
    radius 0.02 m, seed 0: about 400 discs. It is what ``DiscreteBackfill(wall, 1.0,
    radius=0.02)`` generates by default, so the tests of the backfill (tests/retaining/
    test_backfill.py: the settled container and the discrete collapse run) build it once per
    session instead of once per test (the generation is the slow part, several seconds)."""
    from murus.retaining.backfill import generate_packing
    from murus.retaining.geometry import preset

    wall = preset("DSRW1", height=0.6, base_width=0.4, top_width=None)
    return generate_packing(wall, 1.0, radius=0.02, seed=0)
