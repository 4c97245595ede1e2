"""Ground motions: the :class:`GroundMotion` type, readers and writers, processing, intensity
measures, response spectra, synthetic signals and artificial spectrum-compatible records.

SI units: s, m/s², m/s, m. Heavy modules (scipy.signal, h5py, matplotlib) are imported lazily.

>>> from murus.motion import GroundMotion, read, write
>>> from murus.motion import synthetic, spectra, measures, processing
>>> from murus.motion.components import rotate, rotd_spectrum, read_components
"""

from murus._lazy import lazy_exports
from murus.motion.core import GroundMotion
from murus.motion.io import MotionFormatError, read, write

__all__ = ["GroundMotion", "read", "write", "MotionFormatError", "suite", "RecordsExtraMissing"]


def suite(name: str = "farfield", components: str = "both", normalized: bool = False):
    """FEMA P695 record set (needs ``pip install murus[records]``); see
    :func:`murus.motion.records.suite`.

    Parameters
    ----------
    name : str
        ``"farfield"``, ``"nearfield_pulse"`` or ``"nearfield_no_pulse"``.
    components : str
        Which horizontal components (see :func:`murus.motion.records.suite`).
    normalized : bool
        Multiply by the FEMA P695 normalisation factor.

    Returns
    -------
    list of GroundMotion

    References
    ----------
    FEMA P695 (2009), Appendix A.
    """
    from murus.motion.records import suite as _suite

    return _suite(name, components, normalized)


__getattr__, __dir__ = lazy_exports(
    __name__, {"RecordsExtraMissing": "records"}, globals(),
    submodules=("synthetic", "spectra", "measures", "processing", "artificial", "records", "io",
                "plots", "networks", "components", "seismo"))
