import os
from pathlib import Path

import pytest

DATA = Path(__file__).parent / "data"

#: Tests that run the large numba kernels (the distinct-element contact loop, the coupled
#: model of stones and zones): minutes to compile, cold. They are collected after the others,
#: and :func:`_one_cold_compile_at_a_time` keeps the two workers of ``make test`` from compiling
#: them at the same moment on the machine's two cores.
HEAVY = ("tests/continuum/", "tests/dem/", "tests/retaining/", "tests/test_limit.py",
         "tests/test_threads.py")
#: The test collected first, so that a worker starts on it at once: it compiles the contact
#: loop and the coupled kernels (about four minutes, cold) while the other worker runs the
#: light tests.
FIRST = ("tests/continuum/test_continuum_coupled.py::"
         "test_block_on_an_elastic_layer_settles_to_the_closed_form")


def pytest_collection_modifyitems(config, items):
    """Reorder the collection (the order in which pytest-xdist hands the tests to the workers,
    in consecutive batches): :data:`FIRST`, the light tests, then the :data:`HEAVY` ones."""
    first = [it for it in items if it.nodeid == FIRST]
    rest = [it for it in items if it.nodeid != FIRST]
    items[:] = (first + [it for it in rest if not it.nodeid.startswith(HEAVY)]
                + [it for it in rest if it.nodeid.startswith(HEAVY)])


_COMPILED = []


@pytest.fixture(autouse=True)
def _one_cold_compile_at_a_time(request, tmp_path_factory):
    """The first :data:`HEAVY` test of each pytest-xdist worker runs under a lock shared by
    the workers: the first worker to get there compiles the large kernels into numba's disk
    cache; the other, arriving meanwhile, waits for it and then loads them from the cache
    (seconds) instead of compiling them a second time beside it (which cost the suite over two
    minutes). No lock in a single process."""
    if (_COMPILED or os.environ.get("PYTEST_XDIST_WORKER") is None
            or not request.node.nodeid.startswith(HEAVY)):
        yield
        return
    _COMPILED.append(request.node.nodeid)
    import fcntl

    lock = tmp_path_factory.getbasetemp().parent / "murus-kernels.lock"
    with open(lock, "a") as fh:
        fcntl.flock(fh, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(fh, fcntl.LOCK_UN)


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
