"""Shaking-table test processing (Mordant et al. (SERIES), §2, issue 8): the test file format and
sequences (:mod:`~murus.identify.testdata`), white-noise modal identification
(:mod:`~murus.identify.modal`), compressive length from base transducers
(:mod:`~murus.identify.compressive`), cantilever / hybrid / rocking classification
(:mod:`~murus.identify.classify`), virtual test sequences (:mod:`~murus.identify.synth`), the
Timoshenko cantilever (:mod:`~murus.identify.cantilever`) and the calibration of the rocking
model (:mod:`~murus.identify.calibrate`); the whole processing of a sequence, behind ``murus lab
sequence``, is :func:`~murus.identify.pipeline.process_sequence`.

Names are imported on first use (PEP 562), so importing the package loads neither scipy nor
matplotlib.

>>> from murus.identify import read_sequence, evolution, compressive_table, classify_sequence
"""

from murus._lazy import lazy_exports

_EXPORTS = {
    "TestDataError": "testdata",
    "ShakingTableTest": "testdata",
    "TestSequence": "testdata",
    "SequenceEntry": "testdata",
    "read_test": "testdata",
    "write_test": "testdata",
    "read_sequence": "testdata",
    "write_sequence": "testdata",
    "ModalError": "modal",
    "FRF": "modal",
    "Mode": "modal",
    "ModalResult": "modal",
    "Evolution": "modal",
    "frf": "modal",
    "identify": "modal",
    "evolution": "modal",
    "transmissibility": "modal",
    "CompressiveError": "compressive",
    "contact_length": "compressive",
    "test_contact": "compressive",
    "compressive_table": "compressive",
    "ClassifyError": "classify",
    "Criterion": "classify",
    "Classification": "classify",
    "classify": "classify",
    "classify_test": "classify",
    "classify_sequence": "classify",
    "lifted_length": "classify",
    "modal_response": "synth",
    "SynthWall": "synth",
    "synthesize_tests": "synth",
    "synthesize_sequence": "synth",
    "Cantilever": "cantilever",
    "CantileverError": "cantilever",
    "CalibrationError": "calibrate",
    "CalibrationResult": "calibrate",
    "Measurement": "calibrate",
    "calibrate": "calibrate",
    "SequenceReport": "pipeline",
    "process_sequence": "pipeline",
}

__all__ = sorted(_EXPORTS)

__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, globals())
