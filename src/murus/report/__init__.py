"""One-page HTML reports of murus output folders (``murus report DIR``).

:func:`build_report` turns any output folder of murus (a rocking run, a DEM run, a retaining
collapse run or behaviour-factor study, a rocking spectrum or fragility study, a mechanism
check, a limit analysis, a lab sequence) into one self-contained HTML page: the input echoed
(the case file named on the recorded command line, else the command line itself), the results
with their units, the verdicts highlighted, every figure embedded as a ``data:`` URI, the
tables (CSV heads) and the references of the methods used. The page loads no external
resource (no scripts, style sheets, fonts or images from elsewhere) and has a print style
sheet (A4, no page break inside a figure or a table), so that a browser prints it cleanly to
PDF. :func:`write_report` writes it as ``DIR/report.html`` through :mod:`murus.outputs`.

The kind of folder is detected from its files (:func:`detect`): the summary's fields, the
study's ``study.json``, a lab ``report.md``; a folder of no known kind still gets a report
(every JSON as a table, every CSV's head, every figure).
"""

from murus._lazy import lazy_exports

_EXPORTS = {"KINDS": "build", "build_report": "build", "detect": "build",
            "write_report": "build"}

__all__ = sorted(_EXPORTS)

# lazy: the command module imports this package on the `murus --help` path
__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, globals())
