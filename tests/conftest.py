from pathlib import Path

import pytest

DATA = Path(__file__).parent / "data"

#: Test folders that ``make test`` (pytest-xdist, ``--dist loadgroup``) runs on one worker each:
#: their first tests compile large numba kernels (the coupled model's step inlines the continuum,
#: interface and DEM kernels: minutes, cold), which two workers would otherwise compile twice at
#: the same time on the machine's two cores.
XDIST_GROUPS = ("tests/continuum/",)


@pytest.hookimpl(tryfirst=True, optionalhook=True)
def pytest_xdist_make_scheduler(config, log):
    """The loadgroup schedule with the folders of ``XDIST_GROUPS`` as groups. Grouping by
    ``xdist_group`` marks added at collection does not work with pytest 9.2 (pytest-xdist 3.8
    groups by rewriting node ids, which pytest 9.2 no longer reads: pytest-xdist issue #1386),
    so the scheduler groups by node id itself."""
    if config.getoption("dist") != "loadgroup":
        return None
    from xdist.scheduler import LoadGroupScheduling

    class FolderGroups(LoadGroupScheduling):
        def _split_scope(self, nodeid):
            for folder in XDIST_GROUPS:
                if nodeid.startswith(folder):
                    return folder
            return super()._split_scope(nodeid)

    return FolderGroups(config, log)


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
