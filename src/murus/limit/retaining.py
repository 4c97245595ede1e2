"""Limit analysis of a dry-stone retaining wall of :mod:`murus.retaining` with its backfill
thrust as a load: the pseudo-static resistance by rigid blocks, side by side with the
Coulomb-wedge joint checks of :mod:`murus.retaining.pseudostatic`.

The wall section (frame of :mod:`murus.retaining.geometry`: x into the backfill, z up, toe at
the origin) is cut along its bed joints into courses, each a monolithic rigid block (the
"perfect stones" of Savalle et al. (2022), §4.4, no rotation of the stones inside a course),
on a fixed foundation under the base joint. For a horizontal seismic coefficient ``kh`` the
backfill pushes with the Mononobe-Okabe thrust ``E(kh) = 1/2 gamma K_AE H_b²`` of
:func:`murus.retaining.pseudostatic.earth_thrust` (the same ``delta``, wedge angle and ``kv = 0``
as the pseudo-static check), inclined by ``delta`` to the normal of the back face, distributed
over the back face as a triangular pressure (resultant at ``H_b / 3``, the default of
:class:`murus.retaining.pseudostatic.Assumptions`): each course carries the resultant of the
pressure on its own stretch of back face, as a dead load. The inertia ``kh W`` acts out of the
slope (along -x): the load factor ``lambda(kh)`` of :func:`murus.limit.analyse` with
``direction=-1``, and the resistance is ``A = kh g`` where ``lambda(kh) = kh`` (bisection).

The joint checks consider the wall above each bed joint sliding or overturning as one block;
the limit analysis considers every mechanism of the courses (several joints at once) with
non-associative friction, so it gives at most the joint checks' value when both share the
thrust model.

References
----------
Savalle, N., Vincens, E., Hans, S., Lourenço, P. B. (2022). Dry-stone retaining walls under
seismic loading (the DSRW walls of Table 5); EN 1998-5:2004 Annex E (Mononobe-Okabe).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from murus.limit.model import Assembly
from murus.limit.solve import LimitError, PointLoad, analyse

__all__ = ["RetainingLimit", "wall_assembly", "course_thrusts", "retaining_limit"]


@dataclass
class RetainingLimit:
    """Result of :func:`retaining_limit`.

    Attributes
    ----------
    kh : float
        Critical horizontal seismic coefficient [-].
    A : float
        Pseudo-static resistance ``kh g`` [m/s²].
    result : murus.limit.LimitResult
        The limit analysis at ``kh`` (mechanism, joint forces).
    """

    kh: float
    A: float
    result: object


def wall_assembly(wall) -> Assembly:
    """The courses of ``wall`` (a :class:`murus.retaining.geometry.RetainingWall` with stone
    courses) as blocks on a fixed foundation (block 0); course k (block k + 1) lies between bed
    joints k and k + 1. Unit weight ``wall.wall_unit_weight`` [N/m³], joint friction
    ``wall.joint_friction_deg`` on every bed joint, 1 m of wall."""
    from murus import G
    from murus.retaining.geometry import clip_above

    joints = wall.joints
    n0 = np.asarray(joints[0].normal)
    f0, b0 = np.asarray(joints[0].front), np.asarray(joints[0].back)
    polys = [[tuple(f0 - 0.5 * n0), tuple(b0 - 0.5 * n0), tuple(b0), tuple(f0)]]
    for k, j in enumerate(joints):
        p = clip_above(list(wall.polygon), j.front, j.normal)
        if k + 1 < len(joints):
            up = joints[k + 1]
            p = clip_above(p, up.front, (-up.normal[0], -up.normal[1]))
        polys.append(p)
    return Assembly.from_polygons(polys, supports=[0], density=wall.wall_unit_weight / G,
                                  friction_deg=wall.joint_friction_deg, gravity=G, tol=1e-7)


def _back_z(wall, joint) -> float:
    """Height [m] where ``joint`` meets the back face (the heel when it ends on the base)."""
    return wall.part_above(joint).back_bottom[1]


def course_thrusts(wall, kh: float, assumptions=None) -> list:
    """The backfill thrust on each course under ``kh`` (``kv = 0``) as dead
    :class:`~murus.limit.solve.PointLoad` s [N/m] (module docstring)."""
    from murus.retaining.pseudostatic import Assumptions, earth_thrust

    asm = assumptions or Assumptions()
    delta = asm.delta(wall)
    joints = wall.joints
    top = wall.back_top[1]
    zb = [_back_z(wall, j) for j in joints] + [top]
    Hb = top - zb[0]
    Es, dE = earth_thrust(wall, Hb, kh, 0.0, delta, asm.thrust, asm.seismic_angle)
    E = Es + dE
    ux, uz = -math.sin(wall.psi - delta), -math.cos(wall.psi - delta)
    loads = []
    for k in range(len(joints)):
        d_b, d_t = top - zb[k], top - zb[k + 1]
        if d_b - d_t <= 1e-12:
            continue
        F = E * (d_b ** 2 - d_t ** 2) / Hb ** 2
        d = (2.0 / 3.0) * (d_b ** 3 - d_t ** 3) / (d_b ** 2 - d_t ** 2)
        z = top - d
        x = wall.base_width - wall.internal_batter * z
        loads.append(PointLoad(k + 1, (F * ux, F * uz), (x, z)))
    return loads


def retaining_limit(wall, assumptions=None, friction: str = "non-associative",
                    steps: int = 40) -> RetainingLimit:
    """Pseudo-static resistance of ``wall`` by limit analysis (module docstring).

    Parameters
    ----------
    wall : murus.retaining.geometry.RetainingWall
        The wall (with stone courses).
    assumptions : murus.retaining.pseudostatic.Assumptions, optional
        The thrust model (default: that of the pseudo-static check).
    friction : str
        As in :func:`murus.limit.analyse`.
    steps : int
        Bisection steps on ``kh``.

    Returns
    -------
    RetainingLimit
    """
    from murus import G
    from murus.retaining.pseudostatic import PseudoStaticError

    asm = wall_assembly(wall)

    def excess(kh):
        try:
            r = analyse(asm, friction=friction, direction=-1,
                        point_loads=course_thrusts(wall, kh, assumptions))
        except (LimitError, PseudoStaticError):
            return -1.0, None
        return r.load_factor - kh, r

    lo, hi = 0.0, 0.05
    while excess(hi)[0] > 0 and hi < 2.0:
        lo, hi = hi, 2 * hi
    for _ in range(steps):
        mid = 0.5 * (lo + hi)
        if excess(mid)[0] > 0:
            lo = mid
        else:
            hi = mid
    _, res = excess(lo)
    return RetainingLimit(lo, lo * G, res)
