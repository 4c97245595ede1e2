"""Serial, process-pool and local Dask runs of a sweep give the same Dataset bit for bit, and a
worker killed in the middle of a sweep loses nothing (issue 7, items 1-2)."""

import numpy as np
import pytest
import xarray as xr
from studies_inputs import small_study

from murus.studies.executors import SerialExecutor, open_executor
from murus.studies.faults import KillOnce
from murus.studies.sweep import run_plan

pytest.importorskip("distributed")


@pytest.fixture(scope="module")
def serial_result(records):
    plan = small_study(records).plan()
    return plan, run_plan(plan, "serial")


@pytest.fixture(scope="module")
def dask_local():
    with open_executor("dask", workers=2) as h:
        yield h


def test_plan_layout(serial_result):
    plan, ds = serial_result
    assert plan.shape == (6, 2) and plan.n_records == 4
    assert plan.chunks() == [(0, 2), (2, 4), (4, 6), (6, 8), (8, 10), (10, 12)]  # 8 histories
    assert ds["theta_max_over_alpha"].dims == ("K_over_Kd", "motion.scale", "record")
    assert ds["theta_max"].attrs["units"] == "rad"
    assert not ds["failed"].any()
    th = ds["theta_max_over_alpha"].values
    assert np.isfinite(th).all() and (th > 0).sum() > 10  # most cases rock
    # K = 0: no tie and no walls (eq. 11); K > 0: walls from eq. 11, stiffer with K
    assert (ds["tie_stiffness"].sel(K_over_Kd=0.0) == 0.0).all()
    assert np.isnan(ds["bed_stiffness"].sel(K_over_Kd=0.0)).all()
    kb = ds["bed_stiffness"].isel({"motion.scale": 0}).values[1:]
    assert np.all(np.diff(kb) > 0)


def test_serial_executor_is_an_executor():
    f = SerialExecutor().submit(divmod, 7, 2)
    assert f.result() == (3, 1)
    g = SerialExecutor().submit(divmod, 1, 0)
    assert isinstance(g.exception(), ZeroDivisionError)


def test_process_pool_identical(serial_result):
    plan, ds = serial_result
    other = run_plan(plan, "process", workers=2)
    xr.testing.assert_identical(ds, other)
    assert np.array_equal(ds["theta_max"].values, other["theta_max"].values, equal_nan=True)


def test_process_pool_survives_killed_worker(serial_result, tmp_path):
    plan, ds = serial_result
    out = run_plan(plan, "process", workers=2, hook=KillOnce(str(tmp_path), chunk=2))
    assert (tmp_path / "killed-2").exists()  # the worker did die
    xr.testing.assert_identical(ds, out)


def test_dask_local_identical(serial_result, dask_local):
    plan, ds = serial_result
    other = run_plan(plan, dask_local)
    xr.testing.assert_identical(ds, other)


def test_dask_worker_killed_mid_sweep(serial_result, dask_local, tmp_path):
    """A task kills its own worker process once (marker file): Dask reschedules it on the
    restarted worker, nothing is lost and the numbers are those of the serial run."""
    plan, ds = serial_result
    out = run_plan(plan, dask_local, out=tmp_path / "study",
                   hook=KillOnce(str(tmp_path), chunk=3))
    assert (tmp_path / "killed-3").exists()
    assert out.attrs["n_failed_chunks"] == 0
    xr.testing.assert_identical(ds, out)
    assert len(list((tmp_path / "study" / "chunks").glob("c*.npz"))) == len(plan.chunks())


def test_dask_scheduler_address(serial_result, dask_local):
    """``--scheduler tcp://HOST:PORT``: a client on a running cluster."""
    plan, ds = serial_result
    addr = dask_local._cluster.scheduler_address
    assert addr.startswith("tcp://127.0.0.1:")
    with open_executor("dask", scheduler=addr) as h:
        assert h.workers >= 1 and h.describe()["scheduler"] == addr
        xr.testing.assert_identical(run_plan(plan, h), ds)


def test_unreachable_scheduler_is_one_line_error():
    from murus.studies.executors import ExecutorError

    with pytest.raises(ExecutorError, match="cannot reach the Dask scheduler"):
        open_executor("dask", scheduler="tcp://127.0.0.1:9", timeout=2)
