"""The one base of murus errors: :class:`MurusError`, which carries where the offending input is.

Every error class of murus derives from :class:`MurusError`. An error raised on bad input carries
the location of that input as a **key path** (:attr:`MurusError.key`): a tuple of table and key
names, and indices of array entries, relative to what the raising function was given, e.g.
``("tie",)`` from :class:`murus.rocking.model.RockingModel` (its ``tie`` argument), which the
case-file layer prefixes into ``("restraint", "tie")``; or ``("blocks", 2, "width")`` (the key
``width`` of the third ``[[blocks]]`` entry). A case-file error (:class:`murus.config.CaseError`)
also carries its source file (:attr:`MurusError.source`); :func:`murus.config.key_line` turns a key
path into the line of the file, and :func:`murus.config.fail_at` writes the one-line message
``FILE line N: [key] what is wrong``. Code never recovers a location from the message text:
it reads :attr:`~MurusError.key`.

Why a mix-in base and not ``class MurusError(ValueError)``: the errors of bad input are
``ValueError`` subclasses (callers and the command line catch ``ValueError``) and stay so
(``class GeometryError(MurusError, ValueError)``), while the one error of a missing optional
dependency (:class:`murus.motion.records.RecordsExtraMissing`) is an ``ImportError`` and must
stay one, so that ``except ValueError`` never swallows an installation hint. Both share the
same base, and ``except MurusError`` catches every error murus raises on purpose.
"""

from __future__ import annotations

__all__ = ["MurusError", "KeyPath", "key_name"]

#: A key path: table and key names (str) and array-of-table indices (int, from 0).
KeyPath = tuple


class MurusError(Exception):
    """Base of every murus error.

    Parameters
    ----------
    *args
        The message (one line), as for any exception.
    key : tuple of str and int, optional
        Key path of the offending input (module docstring), ``()`` when unknown.
    source : str or pathlib.Path, optional
        The file the input comes from (a case file), ``None`` when unknown.

    Attributes
    ----------
    key : tuple
        The key path (``()`` when unknown).
    source : pathlib.Path or str or None
        The source file.

    Notes
    -----
    The attributes survive pickling (an error raised in a worker process keeps its key).
    """

    def __init__(self, *args, key: KeyPath = (), source=None) -> None:
        super().__init__(*args)
        self.key = tuple(key or ())
        self.source = source

    def __reduce__(self):
        return (_rebuild, (type(self), self.args, self.__dict__))


def _rebuild(cls, args, state):
    """Unpickle a :class:`MurusError` whose class has its own ``__init__`` signature."""
    obj = cls.__new__(cls, *args)
    obj.args = args
    obj.__dict__.update(state)
    return obj


def key_name(key: KeyPath) -> str:
    """The key path written as in a message: ``("blocks", 2, "width")`` is ``blocks[2].width``,
    ``()`` is ``(top level)``.

    Parameters
    ----------
    key : tuple of str and int
        A key path.

    Returns
    -------
    str
        The dotted name, with ``[i]`` for array-of-table entries.
    """
    out = ""
    for x in key:
        if isinstance(x, int):
            out += f"[{x}]"
        else:
            out += ("." if out else "") + str(x)
    return out or "(top level)"
