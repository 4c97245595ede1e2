"""Chunks are stored as they finish; a re-run computes only the missing ones and gives the
Dataset of an uninterrupted run; failing chunks are retried, then recorded (issue 7, item 2)."""

import json

import numpy as np
import pytest
import xarray as xr

from murus.studies.faults import FailTimes, Interrupt, Touch
from murus.studies.sweep import StudyError, open_result, run_plan, study_status


@pytest.fixture(scope="module")
def clean(records):
    from studies_inputs import small_study

    plan = small_study(records).plan()
    return run_plan(plan, "serial")


def ran(folder):
    return sorted({int(p.name.split("-")[1]) for p in folder.glob("ran-*")})


def test_interrupted_run_resumes(plan, clean, tmp_path):
    out = tmp_path / "study"
    with pytest.raises(KeyboardInterrupt):
        run_plan(plan, "serial", out=out, hook=Interrupt(3))
    st = study_status(out)
    assert st["done"] == [0, 1, 2] and st["missing"] == [3, 4, 5] and not st["result"]
    assert not list((out / "chunks").glob(".*"))  # no temporary file left behind
    marks = tmp_path / "marks"
    marks.mkdir()
    ds = run_plan(plan, "serial", out=out, hook=Touch(str(marks)))
    assert ran(marks) == [3, 4, 5]  # only the missing chunks were computed
    xr.testing.assert_identical(ds, clean)
    xr.testing.assert_identical(open_result(out / "result.nc"), clean)
    assert study_status(out)["complete"]


def test_rerun_computes_only_deleted_chunks(plan, clean, tmp_path):
    out = tmp_path / "study"
    run_plan(plan, "serial", out=out)
    (out / "chunks" / "c00001.npz").unlink()
    (out / "chunks" / "c00004.npz").write_bytes(b"damaged")  # a damaged file is recomputed
    marks = tmp_path / "marks"
    marks.mkdir()
    ds = run_plan(plan, "serial", out=out, hook=Touch(str(marks)))
    assert ran(marks) == [1, 4]
    xr.testing.assert_identical(ds, clean)


def test_retry_then_success(plan, clean, tmp_path):
    ds = run_plan(plan, "serial", retries=2, hook=FailTimes(str(tmp_path), chunk=2, times=2))
    assert len(list(tmp_path.glob("fail-2-*"))) == 3
    xr.testing.assert_identical(ds, clean)


def test_failed_chunk_recorded_then_recovered(plan, clean, tmp_path):
    out = tmp_path / "study"
    ds = run_plan(plan, "serial", out=out, retries=1,
                  hook=FailTimes(str(tmp_path), chunk=4, times=-1))
    assert len(list(tmp_path.glob("fail-4-*"))) == 2  # first attempt + one retry
    assert ds.attrs["n_failed_chunks"] == 1
    fails = json.loads(ds.attrs["failures"])
    assert fails["4"]["attempts"] == 2 and "injected failure" in fails["4"]["error"]
    assert json.loads((out / "failures.json").read_text())["4"]["nodes"] == [8, 10]
    # nodes 8, 9 (K/K_d = 0.8, both scales) are NaN and flagged; the rest is the clean run
    th = ds["theta_max_over_alpha"].stack(node=("K_over_Kd", "motion.scale"))
    assert np.isnan(th.isel(node=[8, 9])).all() and ds["failed"].sum() == 2 * 4
    good = ds["failed"] == 0
    assert ds["theta_max"].where(good).equals(clean["theta_max"].where(good))
    st = study_status(out)
    assert list(st["failed"]) == [4] and not st["missing"]
    again = run_plan(plan, "serial", out=out)  # no fault this time: the failed chunk reruns
    xr.testing.assert_identical(again, clean)
    assert not (out / "failures.json").exists()


def test_folder_of_another_study_refused(plan, records, tmp_path):
    from studies_inputs import small_study

    out = tmp_path / "study"
    run_plan(plan, "serial", out=out)
    other = small_study(records, n_k=5).plan()
    with pytest.raises(StudyError, match="different study"):
        run_plan(other, "serial", out=out)


def test_netcdf_round_trip(plan, clean, tmp_path):
    from murus.studies.sweep import write_netcdf

    p = write_netcdf(clean, tmp_path / "r.nc")
    back = open_result(p)
    xr.testing.assert_identical(back, clean)
    assert back["theta_max"].attrs["units"] == "rad"
    study = json.loads(back.attrs["study"])
    assert study["sweep"]["motion.scale"] == [0.6, 1.0]
    assert study["case"]["restraint"]["transverse_walls"]["stiffness"] == "eq11"


def _flip(path, at=None):
    data = bytearray(path.read_bytes())
    i = len(data) // 2 if at is None else at
    data[i] ^= 0x01
    path.write_bytes(bytes(data))


def test_damaged_chunks_reported_and_recomputed(plan, clean, tmp_path):
    """Item 4 of issue 15: a truncated chunk and one with a flipped byte are reported as
    damaged by the status (not done), and a resume recomputes exactly them, giving the
    Dataset of an uninterrupted run (a truncated npz used to crash the resume)."""
    from murus.studies.sweep import check_file

    out = tmp_path / "study"
    run_plan(plan, "serial", out=out)
    for p in sorted((out / "chunks").glob("*.npz")):  # each chunk carries its checksum
        assert check_file(p) is None
        assert p.with_name(p.name + ".sha256").read_text().split()[1] == p.name
    c1, c4 = out / "chunks" / "c00001.npz", out / "chunks" / "c00004.npz"
    c1.write_bytes(c1.read_bytes()[: c1.stat().st_size // 2])  # truncated
    _flip(c4)  # one byte flipped inside the archive
    st = study_status(out)
    assert sorted(st["damaged"]) == [1, 4] and st["done"] == [0, 2, 3, 5]
    assert not st["complete"] and not st["missing"]
    assert "checksum" in st["damaged"][1] and st["paths"][4] == "chunks/c00004.npz"
    marks = tmp_path / "marks"
    marks.mkdir()
    ds = run_plan(plan, "serial", out=out, hook=Touch(str(marks)))
    assert ran(marks) == [1, 4]
    xr.testing.assert_identical(ds, clean)
    st = study_status(out)
    assert st["complete"] and not st["damaged"]


def test_status_cli_names_damaged_chunks(plan, tmp_path):
    from typer.testing import CliRunner

    from murus.studies.cli import app

    out = tmp_path / "study"
    run_plan(plan, "serial", out=out)
    c2 = out / "chunks" / "c00002.npz"
    c2.write_bytes(c2.read_bytes()[:100])
    r = CliRunner().invoke(app, ["status", str(out)])
    assert r.exit_code == 0
    assert "5/6 chunks done, 0 missing, 1 damaged" in r.output
    assert "damaged chunk 2 (chunks/c00002.npz): checksum mismatch" in r.output


def test_chunks_of_older_folders_without_checksum(plan, clean, tmp_path):
    """A folder written before the checksums: a chunk that reads back counts as done, a
    truncated one as damaged, and the resume recomputes only that one."""
    out = tmp_path / "study"
    run_plan(plan, "serial", out=out)
    for p in (out / "chunks").glob("*.sha256"):
        p.unlink()
    c3 = out / "chunks" / "c00003.npz"
    c3.write_bytes(c3.read_bytes()[:-40])
    st = study_status(out)
    assert list(st["damaged"]) == [3] and len(st["done"]) == 5
    marks = tmp_path / "marks"
    marks.mkdir()
    ds = run_plan(plan, "serial", out=out, hook=Touch(str(marks)))
    assert ran(marks) == [3]
    xr.testing.assert_identical(ds, clean)
