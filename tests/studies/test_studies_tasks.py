"""The generic task runner of murus.studies (run_tasks): any picklable function, dependent
tasks queued from results, retries then recorded failures, progress, and a study folder whose
tasks are files (study_status with task_files)."""

import json
import operator

import pytest

from murus.studies.faults import FailTimes, Interrupt
from murus.studies.sweep import (
    StudyError,
    check_folder,
    prepare_folder,
    run_tasks,
    study_status,
    write_json,
)


def test_dependent_tasks_progress_and_order():
    got, prog = {}, []

    def on_result(i, res):
        got[i] = res
        if i < 3:  # stage 2: task 3 + i needs the result of task i
            return [(3 + i, res * 10)]
        return None

    fails = run_tasks(operator.neg, [(0, 1), (1, 2), (2, 3)], "serial", on_result=on_result,
                      progress=lambda *a: prog.append(a), total=6)
    assert fails == {}
    assert got == {0: -1, 1: -2, 2: -3, 3: 10, 4: 20, 5: 30}
    assert prog[0] == (0, 6, 0) and prog[-1] == (6, 6, 0) and len(prog) == 7


def test_retries_then_failure_recorded(tmp_path):
    got = {}
    fails = run_tasks(abs, [(0, -1), (1, -2), (2, -3)], "serial", retries=1,
                      on_result=lambda i, r: got.__setitem__(i, r),
                      hook=FailTimes(str(tmp_path), chunk=1, times=-1))
    assert got == {0: 1, 2: 3}
    assert list(fails) == [1] and fails[1]["attempts"] == 2
    assert "injected failure" in fails[1]["error"]
    (tmp_path / "x").mkdir()
    again = {}
    ok = run_tasks(abs, [(1, -2)], "serial", retries=2,
                   on_result=lambda i, r: again.__setitem__(i, r),
                   hook=FailTimes(str(tmp_path / "x"), chunk=1, times=2))
    assert ok == {} and again == {1: 2}  # failed twice, then ran
    assert len(list((tmp_path / "x").glob("fail-1-*"))) == 3


def test_process_pool_runs_dependent_tasks():
    got = {}

    def on_result(i, res):
        got[i] = res
        return [(10 + i, res)] if i < 10 else None

    fails = run_tasks(operator.neg, [(i, i) for i in range(4)], "process", workers=2,
                      on_result=on_result)
    assert fails == {}
    assert got == {**{i: -i for i in range(4)}, **{10 + i: i for i in range(4)}}


def test_interrupt_is_not_retried():
    def boom(i):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_tasks(operator.neg, [(0, 1), (1, 2)], "serial", on_result=lambda i, r: None,
                  hook=boom)


def test_folder_with_task_files(tmp_path):
    out = tmp_path / "s"
    meta = {"name": "t", "unit": "cases", "result_file": "table.csv",
            "task_files": ["cases/a.json", "cases/b.json"]}
    check_folder(out, "d1")  # nothing there: accepted, nothing written
    assert not out.exists()
    prepare_folder(out, "d1", meta)
    assert not (out / "chunks").exists()
    (out / "cases").mkdir()
    write_json(out / "cases" / "b.json", {"x": 1})
    st = study_status(out)
    assert st["unit"] == "cases" and st["total"] == 2 and st["done"] == [1]
    assert st["missing"] == [0] and not st["complete"] and not st["result"]
    write_json(out / "failures.json", {"0": {"error": "E", "attempts": 3}})
    assert list(study_status(out)["failed"]) == [0]
    prepare_folder(out, "d1", meta)  # the same study: accepted
    with pytest.raises(StudyError, match="different study"):
        check_folder(out, "d2")
    with pytest.raises(StudyError, match="different study"):
        prepare_folder(out, "d2", meta)
    assert json.loads((out / "study.json").read_text())["digest"] == "d1"




def test_interrupt_keeps_finished_tasks_and_abandons_long_ones():
    import time

    got = {}
    # task 2 is interrupted at once while task 0 (0.2 s) and task 1 (60 s) run on the other
    # workers: task 0 finishes within the grace time and is stored, task 1 is abandoned (its
    # worker killed: with the old rule of waiting for it, it would have been stored), the
    # queued task 3 is dropped (unless task 0 finished before task 2 failed: then it ran on the
    # worker freed by task 0, within the grace time, and is stored too)
    with pytest.raises(KeyboardInterrupt):
        run_tasks(time.sleep, [(0, 0.2), (1, 60.0), (2, 0.0), (3, 0.0)], "process",
                  workers=3, window=3, on_result=lambda i, r: got.__setitem__(i, r),
                  hook=Interrupt(2), grace=3.0)
    assert got.get(0, 1) is None and 1 not in got and 2 not in got


def _numba_like(x):
    """A Ctrl-C that arrives inside a numba kernel comes out as a SystemError caused by the
    KeyboardInterrupt (numba's "returned a result with an exception set")."""
    try:
        raise KeyboardInterrupt
    except KeyboardInterrupt as exc:
        raise SystemError("CPUDispatcher(run_chunk) returned a result with an exception "
                          "set") from exc


def test_interrupt_wrapped_by_numba_stops_the_run():
    got = {}
    with pytest.raises(KeyboardInterrupt):  # not retried as an ordinary failure
        run_tasks(_numba_like, [(0, 1), (1, 2)], "serial", retries=2,
                  on_result=lambda i, r: got.__setitem__(i, r))
    assert got == {}


def test_limiting_the_threads_leaves_the_environment_as_it_was(monkeypatch):
    """``limit_threads`` in a process that has imported numba (a forked worker, or the
    caller's process when tasks run there) limits the threads of this thread and leaves
    ``NUMBA_NUM_THREADS`` alone: numba refuses a changed value at its next compilation once its
    threads run, so every later compilation in the process failed."""
    import os

    import numba

    from murus.studies.executors import limit_threads

    monkeypatch.delenv("NUMBA_NUM_THREADS", raising=False)
    before = numba.get_num_threads()
    try:
        limit_threads(1)
        assert numba.get_num_threads() == 1
        assert "NUMBA_NUM_THREADS" not in os.environ
    finally:
        numba.set_num_threads(before)
