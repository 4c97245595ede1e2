from pathlib import Path

import pytest

DATA = Path(__file__).parent / "data"

#: Test folders that ``make test`` (pytest-xdist, ``--dist loadgroup``) runs on one worker each:
#: their first tests compile large numba kernels (the coupled model's step inlines the continuum,
#: interface and DEM kernels: minutes, cold), which two workers would otherwise compile twice at
#: the same time on the machine's two cores.
XDIST_GROUPS = ("tests/continuum/",)
#: Long tests taken out of their folder's group and collected mid-way through the suite: the
#: shipped command's collapse run (about 170 s) would otherwise lengthen the continuum group,
#: the suite's longest unit on one worker (its first test compiles the coupled kernels, about
#: 180 s cold); scheduled mid-way, it runs on whichever worker is free, after those kernels are
#: in numba's cache.
MIDWAY = ("tests/continuum/test_continuum_retaining_backfill.py::"
          "test_the_shipped_command_reproduces_the_validated_a_col",)


#: Folders collected last: their tests run the distinct-element kernels, which the continuum
#: group's first test compiles on its worker (with the coupled ones) during the first minutes;
#: the other worker meanwhile runs the rest, then finds these kernels in numba's cache instead
#: of compiling them a second time at the same moment.
LATE = ("tests/dem/", "tests/retaining/")


def pytest_collection_modifyitems(config, items):
    """Reorder the collection (the order in which ``--dist loadgroup`` hands the units to the
    workers): the folders of :data:`LATE` last, the tests of :data:`MIDWAY` in the middle."""
    def late(it):
        return it.nodeid.startswith(LATE)

    mid = [it for it in items if it.nodeid in MIDWAY]
    rest = [it for it in items if it.nodeid not in MIDWAY]
    rest = [it for it in rest if not late(it)] + [it for it in rest if late(it)]
    k = len(rest) // 2
    items[:] = rest[:k] + mid + rest[k:]


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
            if nodeid in MIDWAY:
                return nodeid
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
