import os
from pathlib import Path

import pytest

DATA = Path(__file__).parent / "data"

#: Tests that run the large numba kernels, minutes to compile cold: the distinct-element
#: contact loop (``"dem"``), and the coupled model of stones and zones on top of it
#: (``"coupled"``). They are collected after the others, and :func:`_one_cold_compile_at_a_time`
#: keeps the two workers of ``make test`` from compiling the same kernels at the same moment on
#: the machine's two cores.
NEEDS = {"tests/dem/": ("dem",), "tests/test_limit.py": ("dem",),
         "tests/test_threads.py": ("dem",), "tests/continuum/": ("dem", "coupled"),
         "tests/retaining/": ("dem", "coupled")}
#: The test collected first, so that a worker starts compiling those kernels at once (about
#: four minutes, cold) while the other one runs the light tests.
FIRST = ("tests/continuum/test_continuum_coupled.py::"
         "test_block_on_an_elastic_layer_settles_to_the_closed_form")


def _needs(nodeid: str) -> tuple[str, ...]:
    return next((v for k, v in NEEDS.items() if nodeid.startswith(k)), ())


def pytest_collection_modifyitems(config, items):
    """Reorder the collection (the order in which pytest-xdist hands the tests to the workers,
    in consecutive batches): :data:`FIRST`, the light tests, those that need the contact loop,
    then those that need the coupled kernels as well."""
    items.sort(key=lambda it: (it.nodeid != FIRST, len(_needs(it.nodeid))))


def _warm_dem():
    """Compile the contact loop and the DEM step (two blocks, a few steps)."""
    from murus.dem import Joint, Model

    m = Model(joint=Joint(kn=1e9, ks=1e9, friction_deg=30))
    m.add_rectangle(1.0, 0.2, center=(0.0, -0.1), kinematic="fixed")
    m.add_rectangle(0.3, 0.3, center=(0.0, 0.15))
    m.settle(tol=1e-3, max_steps=50)


def _warm_coupled():
    """Compile the coupled step (a block on an elastic layer of four zones, a few steps), and
    its subcycled form (the same model at a quarter of its time step, the zones stepped once
    every two steps of the block): without it each worker compiled the subcycled kernel
    (``run_chunk_sub``, about 45 s) for its own first subcycled test, at the same time."""
    from murus.continuum import verify as V

    cm = V.block_on_layer(2, 2)[0]
    cm.settle(tol=1e-3, max_steps=50)
    cm, dm = V.block_on_layer(2, 2)[:2]
    cm.set_dt(0.25 * dm.dt)
    cm.set_subcycle(2)
    cm.settle(tol=1e-3, max_steps=50)


_WARM = {"dem": _warm_dem, "coupled": _warm_coupled}
_DONE: set[str] = set()


@pytest.fixture(autouse=True)
def _one_cold_compile_at_a_time(request, tmp_path_factory):
    """Before the first test of a pytest-xdist worker that needs a family of large kernels
    (:data:`NEEDS`), compile it under a lock shared by the workers (a small model run a few
    steps): the first worker to get there compiles the kernels into numba's disk cache; the
    other, arriving meanwhile, waits for it and then loads them from the cache (seconds)
    instead of compiling them a second time beside it (which cost the suite two minutes and
    more). Nothing in a single process."""
    todo = [k for k in _needs(request.node.nodeid) if k not in _DONE]
    if todo and os.environ.get("PYTEST_XDIST_WORKER") is not None:
        import fcntl

        for k in todo:
            with open(tmp_path_factory.getbasetemp().parent / f"murus-{k}.lock", "a") as fh:
                fcntl.flock(fh, fcntl.LOCK_EX)
                try:
                    _WARM[k]()
                finally:
                    fcntl.flock(fh, fcntl.LOCK_UN)
            _DONE.add(k)
    yield


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
