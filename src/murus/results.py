"""One protocol for the results of murus's engines, in the manner of the result bunch of
``scipy.integrate.solve_ivp``: every run returns an object with

- ``status``: what ended the run (an int code for the rocking engines, a word for the
  distinct-element engine);
- ``message``: a one-line human-readable account of it;
- ``success``: ``True`` when the run reached its end (or its stop condition);

times named ``t`` (the output grid) and ``t_*`` (the time of an event, e.g. ``t_overturn``),
one name per quantity, and ``summary()``: a dict of plain numbers (what ``summary.json`` holds).
The CLI dispatches on the class of a result (:meth:`Result.headline`), never on its keys.

The rocking (:class:`murus.rocking.engine.RockingResult`), Winkler
(:class:`murus.rocking.winkler.WinklerResult`) and distinct-element
(:class:`murus.dem.engine.RunResult`, :class:`murus.dem.engine.SettleResult`) results derive
from :class:`Result`.

References
----------
SciPy, ``scipy.integrate.solve_ivp`` (the ``OdeResult`` bunch: ``t``, ``status``, ``message``,
``success``), https://docs.scipy.org/doc/scipy/reference/generated/scipy.integrate.solve_ivp.html
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from typing import Any, ClassVar


class Result:
    """Base of the results of murus's engines (see the module docstring).

    Subclasses are dataclasses that hold ``status`` and ``message``; they override
    :attr:`success` when their status is not the int 0 of a completed run, and
    :meth:`headline` for the one line the CLI prints.
    """

    status: int | str
    message: str

    @property
    def success(self) -> bool:
        """True when the run reached its end (status 0)."""
        return self.status == 0

    def summary(self) -> dict:  # pragma: no cover - every engine defines its own
        """Plain-number summary (what ``summary.json`` holds)."""
        raise NotImplementedError

    def headline(self) -> str:
        """The one line that the CLI prints after a run (without the case name)."""
        return self.message


@dataclass
class RunHistory(Result):
    """The sampled history of an explicit run (the distinct-element and continuum engines):
    ``result[name]`` is ``values[name]``; :attr:`ok` and :attr:`success` are true for the
    statuses in :attr:`OK`.

    Attributes
    ----------
    t : ndarray
        Sample times [s].
    values : dict
        name -> ndarray sampled at ``t``.
    status : str
        What ended the run.
    message : str
        One-line account of how the run ended (empty when completed).
    steps : int
        Steps taken by this call [-].
    wall : float
        Wall-clock time of this call [s].
    dt : float
        Time step [s].
    """

    #: The statuses that are a result.
    OK: ClassVar[tuple[str, ...]] = ("completed",)

    t: Any
    values: dict = field(default_factory=dict)
    status: str = "completed"
    message: str = ""
    steps: int = 0
    wall: float = 0.0
    dt: float = 0.0

    def __getitem__(self, name):
        return self.values[name]

    @property
    def ok(self) -> bool:
        """True when the run reached its end (or its stop condition, where that counts)."""
        return self.status in self.OK

    @property
    def success(self) -> bool:
        """:attr:`ok`."""
        return self.ok


def deprecated_alias(new: str, old: str, since: str = "issue 16"):
    """A read-only property ``old`` that returns the attribute ``new`` with a
    :class:`DeprecationWarning` (old names stay readable for one release).

    Parameters
    ----------
    new : str
        The attribute's name now.
    old : str
        Its earlier name.
    since : str
        When it was renamed (for the message).

    Returns
    -------
    property
    """

    def get(self):
        warnings.warn(f"{type(self).__name__}.{old} is deprecated ({since}); use .{new}",
                      DeprecationWarning, stacklevel=2)
        return getattr(self, new)

    return property(get, doc=f"Deprecated alias of :attr:`{new}`.")
