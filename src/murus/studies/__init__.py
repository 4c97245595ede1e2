"""Sweeps over parameters and record suites: rocking spectra, fragility, study files, executors.

A study is a grid of parameters of a rocking case times a set of ground motions
(:mod:`murus.studies.study`), resolved into a :class:`~murus.studies.sweep.Plan` and run in
chunks on a ``concurrent.futures.Executor`` — serial, a local process pool or a Dask cluster
(:mod:`murus.studies.executors`, the only module that imports Dask) — with each finished chunk
stored so that an interrupted run resumes (:func:`~murus.studies.sweep.run_plan`). Results are
xarray Datasets (dims: the swept parameters and ``record``; units in ``attrs``) written to
NetCDF with h5netcdf.

- :func:`rocking_spectrum`, :func:`plot_rocking_spectrum`, :func:`plot_overturning_map`
  (EURODYN (2020), §4.1);
- :func:`fragility`, :func:`fit_fragility`, :func:`fit_msa`, :func:`fit_ida`,
  :func:`plot_fragility`, :func:`restraint_configs`;
- :func:`load_study`, :func:`make_study`, :func:`run_study`, :func:`run_plan`,
  :func:`study_status`, :func:`open_result`, :func:`open_executor`; :func:`run_tasks`, the
  generic engine (any picklable function, dependent tasks) of :func:`run_plan` and of the
  behaviour-factor study of :mod:`murus.retaining.study`.

Names are imported on first use (PEP 562): ``import murus.studies`` loads neither numba, xarray
nor Dask.
"""

from murus._lazy import lazy_exports

_EXPORTS = {
    "open_executor": "executors",
    "ExecutorHandle": "executors",
    "SerialExecutor": "executors",
    "RecordSet": "records",
    "IntensityMeasure": "records",
    "Dim": "sweep",
    "Point": "sweep",
    "Plan": "sweep",
    "StudyError": "sweep",
    "run_plan": "sweep",
    "run_tasks": "sweep",
    "study_status": "sweep",
    "open_result": "sweep",
    "write_netcdf": "sweep",
    "Study": "study",
    "load_study": "study",
    "make_study": "study",
    "run_study": "study",
    "rocking_spectrum": "spectrum",
    "spectrum_case": "spectrum",
    "plot_rocking_spectrum": "spectrum",
    "plot_overturning_map": "spectrum",
    "FragilityFit": "fragility",
    "fit_msa": "fragility",
    "fit_ida": "fragility",
    "fit_fragility": "fragility",
    "fragility": "fragility",
    "fragility_curve": "fragility",
    "restraint_configs": "fragility",
    "plot_fragility": "fragility",
}

__all__ = sorted(_EXPORTS)

#: Deprecated name (DeprecationWarning on call; removed in the next release).
_EXPORTS["seed002_configs"] = "fragility"

__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, globals())
