"""Solver defaults of the rocking engines, declared once (a light module: no numba, no numpy;
the study layer reads them without loading the kernels)."""

#: Default relative tolerance of the event-driven rigid-base integrator (absolute: ``RTOL *
#: alpha``), used by :func:`murus.rocking.simulate`, :func:`~murus.rocking.simulate_batch`, case
#: files, studies and rocking spectra. Against the accurate reference of VALIDATION.md ("The rest
#: rule against an accurate solver", 576 runs on FEMA P695 records) 1e-11 reproduces every
#: overturning verdict and every count of significant impacts, and theta_max within 6.5e-8
#: where the response is not chaotic; 1e-9 flipped 1 verdict and 3 counts, 1e-10 one count.
#: It costs 1.10 times the batch time of 1e-9 (BENCHMARKS.md).
RTOL = 1e-11

#: Default relative tolerance of the Winkler-base integrator, from the API and from case files
#: (case files used 1e-9 before it was the API default too).
WINKLER_RTOL = 1e-9
