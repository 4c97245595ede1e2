"""Collapse load factor of a rigid-block assembly: the static (equilibrium) linear programme of
Livesley (1978), with associative or non-associative (Gilbert et al. 2006) Coulomb friction.

Unknowns per interface (see :mod:`murus.limit.model`): the normal forces ``n1``, ``n2`` [N] at
its two end points (compression positive) and the shear force ``s`` [N] along its tangent, all
acting on block ``b`` (their opposites on block ``a``); and the load factor ``lambda``. For every
block that is not a support, three equilibrium equations (forces along x and y, moment about the
centroid)::

    B q + lambda f_L = -f_D

with the dead load ``f_D`` (the weights, ``-m g`` along y) and the live load ``f_L``:

- ``load="horizontal"``: ``f_L = direction m g`` along x (a horizontal body force proportional
  to the weights; ``lambda`` is the horizontal acceleration in units of g);
- ``load="tilt"``: the base tilts by ``theta``: ``f_D = -m g cos(theta)`` along y,
  ``f_L = m g`` along x and the critical tilt solves ``lambda(theta) = sin(theta)``. The result
  gives ``angle_deg`` = theta and ``load_factor = tan(theta)`` (equal to the horizontal load
  factor when no joint has cohesion or tension).

Yield conditions per interface of length ``L`` and area ``A = L x thickness`` [m²], with the
joint's friction coefficient ``mu``, cohesion ``c`` and tensile strength ``t`` [Pa]:

- no tension beyond ``t``: ``n1, n2 >= -t A / 2`` (a dry joint: ``n1, n2 >= 0``), which keeps
  the resultant inside the interface (the moment condition ``|m| <= N L / 2``);
- Coulomb friction: ``|s| <= mu (n1 + n2) + c A``.

``lambda`` is maximised with :func:`scipy.optimize.linprog` (HiGHS). The mechanism (virtual
velocities ``u``, ``v`` [m/s] and ``omega`` [rad/s] of the blocks, normalised so that the largest
velocity component of a block is 1 and the live load does positive work) is the vector of the
duals (marginals) of the equilibrium equations.

**Associative friction** (``friction="associative"``) is the LP above: by normality the
mechanism dilates (a sliding joint opens by ``tan(phi)`` per unit slip), which overestimates the
strength of dry joints. **Non-associative friction** (the default) follows the iterative scheme
of Gilbert et al. (2006): the Coulomb condition of each interface is replaced by a shear
capacity fixed by the normal force ``N_prev`` of the previous iteration,
``|s| <= mu N_prev + c A`` (a normal-force-dependent cohesion: a yield line parallel to the
normal-force axis, whose flow rule slides without dilatancy), starting from the associative
solution; the LP is solved again with the updated capacities, relaxed
(``N_prev <- N_prev + relax (N - N_prev)``, default ``relax = 0.5``, which damps the two-cycles
of the normal forces that the plain update falls into), until the load factor is steady
(relative spread below ``tol`` over :data:`WINDOW` successive LP solutions). A statically
indeterminate assembly has many LP optima with the same load factor and different normal
forces, between which the capacities would jump from one iteration to the next; a tiny weight
on the total normal force in the objective (:data:`REGULARISATION` per unit of the total live
load) picks the optimum with the least normal forces. The forces returned are those of the
iterate of the last window that comes closest to the Coulomb condition with its own normal
forces; the load factor and the mechanism are those of one more LP with that iterate's
capacities and without the weight: the mechanism slides without dilatancy; the forces returned
are, among the optimal force fields of that LP, those closest to Coulomb with their own normal
forces (a second LP minimising the sum of the excesses ``|s| - mu N - c A``;
``LimitResult.coulomb_residual``: 0 when they obey it). ``LimitResult.converged`` is False
when ``max_iter`` LP solutions did not settle. When the associative mechanism slips at no
interface, the associative solution already meets every condition of the non-associative
problem (no slip, no dilatancy) and is returned after one LP.

The paper's scheme is reconstructed from its description (Gilbert et al. (2006), abstract and
section 3: successive LP sub-problems with a modified Mohr-Coulomb surface at each interface,
updated at each iteration until a converged solution is obtained); the relaxation, the
regularisation and the convergence test are ours, not the paper's. The solution of a
non-associative problem need not be unique, and the iteration's end point depends on its
path: on the wall panel of ``examples/limit/wall_panel.toml`` variants of the scheme (relaxation
1 or 0.5, regularisation 1e-6 to 1e-4) end between 0.4559 and 0.4583, a spread of 0.5 %,
against 0.4857 with associative friction; on the 50-block wall of
``examples/dem/running_bond_wall.toml`` between 0.47150 and 0.47162 (associative 0.55291).
The steady load factor does not guarantee exact consistency: the forces of the iterates of
the panel exceed Coulomb by up to 3.5 % of a block's weight at some interface (0.015 for the
50-block wall, 0.37 for the window wall of ``examples/limit/ftl_wall3_window.toml``); the
forces returned, chosen among the optima of the last LP, exceed it by 1.2e-4, 5e-6 and 2e-7 of
a block's weight (``coulomb_residual``). The non-associative values of walls are estimates to
about 1 % (the spread of the variants above).

References
----------
Livesley, R. K. (1978). Limit analysis of structures formed from rigid blocks. International
Journal for Numerical Methods in Engineering 12(12), 1853-1871. doi:10.1002/nme.1620121207

Gilbert, M., Casapulla, C., Ahmed, H. M. (2006). Limit analysis of masonry block structures
with non-associative frictional joints using linear programming. Computers & Structures
84(13-14), 873-887. doi:10.1016/j.compstruc.2006.02.005
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from murus.limit.model import Assembly, Interfaces, LimitModelError, check, find_interfaces

#: Weight of the total normal force in the objective of the non-associative LPs, per unit of
#: total weight of the free blocks (see :func:`analyse`).
REGULARISATION = 1e-6
#: Number of LP unknowns above which HiGHS's interior-point method (with crossover) replaces
#: its dual simplex (about 10 times faster on a wall of 500 blocks, same load factor to 1e-7).
IPM_ABOVE = 2000
#: LP solutions over which the non-associative load factor must be steady.
WINDOW = 5

__all__ = ["LimitResult", "LimitError", "analyse", "PointLoad"]

LOADS = ("horizontal", "tilt")
FRICTIONS = ("non-associative", "associative")


class LimitError(LimitModelError):
    """The LP has no solution: unbounded load factor, or no equilibrium for any load factor.

    Attributes
    ----------
    row : int or None
        The free block (its index among the free blocks) the trouble is found at, if known.
    """

    row = None


def _lp_error(msg: str, row) -> LimitError:
    exc = LimitError(msg, key=("blocks",))
    exc.row = None if row is None else int(row)
    return exc


#: Bound on the load factor: an LP optimum at it is reported as unbounded [-].
LAMBDA_MAX = 1e6


@dataclass
class PointLoad:
    """A force on a block, applied at a point (e.g. a backfill thrust).

    Attributes
    ----------
    block : int
        The block.
    force : tuple of float
        ``(Fx, Fy)`` [N] (per out-of-plane thickness of the assembly).
    point : tuple of float
        Point of application ``(x, y)`` [m].
    live : bool
        False: part of the dead load; True: multiplied by the load factor.
    """

    block: int
    force: tuple
    point: tuple
    live: bool = False


@dataclass
class LimitResult:
    """Collapse of a rigid-block assembly, made by :func:`analyse`.

    Attributes
    ----------
    load_factor : float
        Collapse load factor lambda [-] (horizontal: the horizontal acceleration in g; tilt:
        ``tan(theta)``).
    load : str
        ``"horizontal"`` or ``"tilt"``.
    direction : int
        +1 (load along +x) or -1.
    friction : str
        ``"non-associative"`` or ``"associative"``.
    angle_deg : float
        Critical tilt angle [deg] (``load="tilt"``; NaN otherwise).
    mechanism : numpy.ndarray
        ``(nblock, 3)``: virtual velocities ``u``, ``v`` [m/s] and ``omega`` [rad/s] of the
        blocks' centroids (supports 0), normalised (module docstring).
    interfaces : Interfaces
        The interfaces.
    n1, n2, shear : numpy.ndarray
        Normal forces at the end points and shear force [N] of each interface at collapse.
    iterations : int
        LP solutions of the non-associative scheme (1 for associative).
    converged : bool
        The non-associative scheme converged (always True for associative).
    assembly : Assembly
        The blocks.
    """

    load_factor: float
    load: str
    direction: int
    friction: str
    angle_deg: float
    mechanism: np.ndarray
    interfaces: Interfaces
    n1: np.ndarray
    n2: np.ndarray
    shear: np.ndarray
    iterations: int
    converged: bool
    assembly: Assembly = field(repr=False)
    history: list = field(default_factory=list, repr=False)

    @property
    def normal(self) -> np.ndarray:
        """Normal force N = n1 + n2 [N] per interface (compression positive)."""
        return self.n1 + self.n2

    @property
    def eccentricity(self) -> np.ndarray:
        """Position [m] of the normal resultant along the tangent from the interface's mid
        point (NaN where N = 0)."""
        N = self.normal
        L = self.interfaces.length
        with np.errstate(invalid="ignore", divide="ignore"):
            e = 0.5 * L * (self.n2 - self.n1) / N
        return np.where(np.abs(N) > 1e-12 * max(1.0, np.abs(N).max(initial=0.0)), e, np.nan)

    @property
    def coulomb_residual(self) -> float:
        """Largest excess of shear over the Coulomb capacity of its own normal force,
        ``max(|s| - mu N - c A)``, over the largest block weight [-] (0 when the forces obey
        Coulomb's law everywhere; the non-associative scheme's measure of consistency)."""
        itf = self.interfaces
        A = itf.length * self.assembly.thickness
        ex = np.abs(self.shear) - itf.friction * self.normal - itf.cohesion * A
        W = float(self.assembly.mass.max(initial=0.0) * self.assembly.gravity) or 1.0
        return max(float(ex.max(initial=0.0)), 0.0) / W

    def summary(self) -> dict:
        """Load factor, tilt angle, friction, sizes and the mechanism (per block
        ``{"block", "u", "v", "omega"}``)."""
        asm = self.assembly
        mech = [{"block": int(i), "name": asm.names[i], "u": float(m[0]), "v": float(m[1]),
                 "omega": float(m[2])} for i, m in enumerate(self.mechanism)
                if not asm.support[i]]
        return {"load_factor": float(self.load_factor), "load": self.load,
                "direction": int(self.direction), "friction": self.friction,
                "angle_deg": float(self.angle_deg), "blocks": int(asm.nblock),
                "interfaces": int(len(self.interfaces)), "iterations": int(self.iterations),
                "converged": bool(self.converged),
                "coulomb_residual": self.coulomb_residual,
                "units": {"load_factor": "-", "angle_deg": "deg", "u": "m/s", "v": "m/s",
                          "omega": "rad/s"},
                "mechanism": mech}

    def joints_csv(self) -> str:
        """One line per interface: blocks, end points [m], N, n1, n2, S [N], eccentricity
        [m], length [m]."""
        itf = self.interfaces
        head = ("a,b,x1_m,y1_m,x2_m,y2_m,length_m,N_N,n1_N,n2_N,S_N,eccentricity_m")
        cols = np.column_stack([itf.a, itf.b, itf.p1, itf.p2, itf.length, self.normal,
                                self.n1, self.n2, self.shear, self.eccentricity])
        lines = [head]
        for r in cols:
            lines.append(",".join([str(int(r[0])), str(int(r[1]))]
                                  + [f"{x:.10g}" for x in r[2:]]))
        return "\n".join(lines) + "\n"


# ---------------------------------------------------------------------- assembly of the LP
def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]


def equilibrium_matrix(asm: Assembly, itf: Interfaces):
    """The equilibrium matrix ``B`` (scipy.sparse CSR, ``3 nfree x 3 k``) of the free blocks
    (rows ``3 r``, ``3 r + 1``, ``3 r + 2``: Fx, Fy, moment about the centroid of the r-th free
    block) and the row of each block (-1 for a support). Columns: ``n1`` (k), ``n2`` (k),
    ``s`` (k)."""
    from scipy.sparse import csr_matrix

    k = len(itf)
    row = -np.ones(asm.nblock, dtype=int)
    free = np.nonzero(~asm.support)[0]
    row[free] = np.arange(len(free))
    nrm, tan = itf.normal, itf.tangent
    pm = itf.midpoint
    ii, jj, vv = [], [], []
    idx = np.arange(k)
    for blk, sgn in ((itf.b, 1.0), (itf.a, -1.0)):
        r = row[blk]
        on = r >= 0
        r, c = r[on], asm.centroid[blk[on]]
        i1, i2, i3 = idx[on], idx[on] + k, idx[on] + 2 * k
        n, t = nrm[on], tan[on]
        for comp in (0, 1):
            ii += [3 * r + comp] * 3
            jj += [i1, i2, i3]
            vv += [sgn * n[:, comp], sgn * n[:, comp], sgn * t[:, comp]]
        ii += [3 * r + 2] * 3
        jj += [i1, i2, i3]
        vv += [sgn * _cross(itf.p1[on] - c, n), sgn * _cross(itf.p2[on] - c, n),
               sgn * _cross(pm[on] - c, t)]
    B = csr_matrix((np.concatenate(vv), (np.concatenate(ii), np.concatenate(jj))),
                   shape=(3 * len(free), 3 * k))
    return B, row


def _loads(asm: Assembly, row: np.ndarray, dead_y: float, live_x: float, point_loads):
    """Dead and live load vectors over the equilibrium rows."""
    nf = int((row >= 0).sum())
    fD = np.zeros(3 * nf)
    fL = np.zeros(3 * nf)
    free = np.nonzero(row >= 0)[0]
    W = asm.mass[free] * asm.gravity
    fD[3 * row[free] + 1] = dead_y * W
    fL[3 * row[free]] = live_x * W
    for p in point_loads or ():
        r = row[p.block]
        if r < 0:
            continue
        F = np.asarray(p.force, float)
        arm = np.asarray(p.point, float) - asm.centroid[p.block]
        vec = fL if p.live else fD
        vec[3 * r:3 * r + 2] += F
        vec[3 * r + 2] += arm[0] * F[1] - arm[1] * F[0]
    return fD, fL


def _solve_lp(B, fD, fL, itf, A, slope, const, reg=0.0):
    """One LP: maximise lambda subject to equilibrium, ``n1, n2 >= -t A / 2`` and the shear
    condition ``|s| <= slope (n1 + n2) + const`` (``slope`` [-], ``const`` [N] per interface;
    bounds on ``s`` when every slope is 0); ``reg`` [1/N] weighs the total normal force in the
    objective. Returns (lambda, n1, n2, s, duals) or raises :class:`LimitError`.

    The LP is solved in scaled units (forces over the largest load component, moments over the
    median interface length times it), which HiGHS needs for walls of hundreds of blocks."""
    from scipy.sparse import diags

    Ws, r = _scales(B, fD, fL, itf)
    lam, n1, n2, s, y = _lp(diags(r) @ B, r * fD / Ws, r * fL / Ws, -0.5 * itf.tensile * A / Ws,
                            slope, np.asarray(const) / Ws, reg * Ws)
    return lam, n1 * Ws, n2 * Ws, s * Ws, r * y / Ws


def _scales(B, fD, fL, itf):
    """The LP's units (:func:`_solve_lp`): the force scale (the largest load component [N])
    and the row factors of the equilibrium equations (1 for forces, one over the median
    interface length for moments)."""
    Ws = max(np.abs(fD).max(initial=0.0), np.abs(fL).max(initial=0.0), 1e-300)
    Ls = float(np.median(itf.length)) if len(itf) else 1.0
    r = np.ones(B.shape[0])
    r[2::3] = 1.0 / Ls
    return Ws, r


def _lp(B, fD, fL, lo_n, slope, const, reg):
    """The LP of :func:`_solve_lp` in its scaled units."""
    from scipy.optimize import linprog
    from scipy.sparse import csr_matrix, hstack, vstack
    from scipy.sparse import eye as speye

    k = len(lo_n)
    Aeq = hstack([B, csr_matrix(fL.reshape(-1, 1))], format="csr")
    c = np.zeros(3 * k + 1)
    c[-1] = -1.0
    c[:2 * k] = reg
    bounds = np.empty((3 * k + 1, 2))
    bounds[:2 * k, 0] = np.concatenate([lo_n, lo_n])
    bounds[:2 * k, 1] = np.inf
    bounds[-1] = (-LAMBDA_MAX, LAMBDA_MAX)
    Aub = bub = None
    if np.any(slope != 0):
        bounds[2 * k:3 * k] = (-np.inf, np.inf)
        eye = speye(k, format="csr")
        mu = _diag(slope)
        Aub = vstack([hstack([-mu, -mu, eye, csr_matrix((k, 1))]),
                      hstack([-mu, -mu, -eye, csr_matrix((k, 1))])], format="csr")
        bub = np.concatenate([const, const])
    else:
        cap = np.maximum(const, 0.0)  # a capacity below 0 (tension) is 0
        bounds[2 * k:3 * k, 0] = -cap
        bounds[2 * k:3 * k, 1] = cap
    method = "highs-ipm" if 3 * k + 1 > IPM_ABOVE else "highs"
    res = linprog(c, A_ub=Aub, b_ub=bub, A_eq=Aeq, b_eq=-fD, bounds=bounds, method=method)
    if res.status == 2:
        raise _lp_error("no equilibrium for any load factor: the block cannot carry its "
                        "weight through its interfaces (check how it rests on the others)",
                        _worst_row(Aeq, fD, Aub, bub, bounds))
    if res.status != 0:
        raise _lp_error(f"the linear programme failed: {res.message}", None)
    x = res.x
    if x[-1] >= LAMBDA_MAX * (1 - 1e-9):
        y = np.abs(np.asarray(res.eqlin.marginals)).reshape(-1, 3)[:, :2].max(1)
        raise _lp_error("the load factor is unbounded: the block can move without any "
                        "resistance, or no mechanism can form (joints with enough cohesion or "
                        "tension, blocks locked between supports)", int(np.argmax(y)))
    return x[-1], x[:k], x[k:2 * k], x[2 * k:3 * k], res.eqlin.marginals


def _closest_to_coulomb(B, fD, fL, itf, A, cap, lam):
    """Among the optimal force fields of the capacity LP (equilibrium at ``lam``, ``|s| <=
    cap``, the no-tension bounds), those closest to Coulomb with their own normal forces: an LP
    minimising the sum of the excesses ``t >= |s| - mu (n1 + n2) - c A``. Returns (n1, n2, s,
    largest excess [N]) or None when HiGHS does not solve it (the caller keeps its forces)."""
    from scipy.optimize import linprog
    from scipy.sparse import csr_matrix, diags, hstack, vstack
    from scipy.sparse import eye as speye

    k = len(itf)
    Ws, r = _scales(B, fD, fL, itf)
    Bs = diags(r) @ B
    # the load factor a hair below the LP's, so that round-off cannot make it infeasible
    rhs = -(r * fD + (lam - 1e-9 * max(1.0, abs(lam))) * r * fL) / Ws
    Aeq = hstack([Bs, csr_matrix((B.shape[0], k))], format="csr")
    mu = diags(itf.friction, format="csr")
    eye = speye(k, format="csr")
    Aub = vstack([hstack([-mu, -mu, eye, -eye]), hstack([-mu, -mu, -eye, -eye])], format="csr")
    cA = itf.cohesion * A / Ws
    bub = np.concatenate([cA, cA])
    lo_n = -0.5 * itf.tensile * A / Ws
    capn = np.maximum(np.asarray(cap, float), 0.0) / Ws
    bounds = np.vstack([np.column_stack([lo_n, np.full(k, np.inf)]),
                        np.column_stack([lo_n, np.full(k, np.inf)]),
                        np.column_stack([-capn, capn]),
                        np.column_stack([np.zeros(k), np.full(k, np.inf)])])
    c = np.concatenate([np.zeros(3 * k), np.ones(k)])
    method = "highs-ipm" if 4 * k > IPM_ABOVE else "highs"
    res = linprog(c, A_ub=Aub, b_ub=bub, A_eq=Aeq, b_eq=rhs, bounds=bounds, method=method)
    if res.status != 0:
        return None
    x = res.x * Ws
    return x[:k], x[k:2 * k], x[2 * k:3 * k], float(x[3 * k:].max(initial=0.0))


def _worst_row(Aeq, fD, Aub, bub, bounds) -> int | None:
    """The free block whose equilibrium is furthest from reachable: the largest residual of a
    phase-1 LP (minimise the sum of the residuals of the equilibrium equations)."""
    from scipy.optimize import linprog
    from scipy.sparse import csr_matrix, eye, hstack

    m, nv = Aeq.shape
    A = hstack([Aeq, eye(m), -eye(m)], format="csr")
    c = np.concatenate([np.zeros(nv), np.ones(2 * m)])
    b = np.concatenate([bounds, np.column_stack([np.zeros(2 * m), np.full(2 * m, np.inf)])])
    Aub2 = None if Aub is None else hstack([Aub, csr_matrix((Aub.shape[0], 2 * m))],
                                           format="csr")
    res = linprog(c, A_ub=Aub2, b_ub=bub, A_eq=A, b_eq=-fD, bounds=b, method="highs")
    if res.status != 0:
        return None
    r = (res.x[nv:nv + m] + res.x[nv + m:]).reshape(-1, 3).sum(1)
    return int(np.argmax(r))


def _diag(v):
    from scipy.sparse import diags

    return diags(v, format="csr")


def _mechanism(asm, row, duals, fL) -> np.ndarray:
    mech = np.zeros((asm.nblock, 3))
    free = np.nonzero(row >= 0)[0]
    d = np.asarray(duals, float).reshape(-1, 3)
    work = float(fL @ duals)
    if work < 0:
        d = -d
    scale = np.abs(d[:, :2]).max(initial=0.0)
    if scale <= 0:
        scale = np.abs(d).max(initial=0.0)
    if scale > 0:
        d = d / scale
    mech[free] = d
    return mech


def _collapse(asm, itf, B, row, fD, fL, friction, tol, max_iter, relax):
    """Load factor at collapse for given dead and live loads, with the chosen friction
    (module docstring). Returns (lambda, n1, n2, s, duals, LP solutions, converged,
    history of lambda)."""
    A = itf.length * asm.thickness
    cA = itf.cohesion * A
    lam, n1, n2, s, du = _solve_lp(B, fD, fL, itf, A, itf.friction, cA)
    hist = [lam]
    if friction == "associative" or not _slides(asm, itf, row, du):
        # without sliding, normality does not matter: the associative solution is the
        # non-associative one
        return lam, n1, n2, s, du, 1, True, hist
    zero = np.zeros(len(itf))
    scale = max(np.abs(fD).max(initial=0.0), np.abs(fL).max(initial=0.0), 1e-300)
    reg = REGULARISATION / max(np.abs(fL).sum(), 1e-300)
    Np = n1 + n2
    converged = False
    it = 1
    window = []  # the last WINDOW iterates: (Coulomb violation, n1, n2, s, capacities)
    for _ in range(max_iter):
        it += 1
        cap = itf.friction * Np + cA
        lam, n1, n2, s, du = _solve_lp(B, fD, fL, itf, A, zero, cap, reg)
        N = n1 + n2
        hist.append(lam)
        viol = float(np.max(np.abs(s) - itf.friction * N - cA, initial=0.0)) / scale
        window = (window + [(viol, n1, n2, s, cap)])[-WINDOW:]
        last = np.asarray(hist[-WINDOW:])
        if len(window) == WINDOW and np.ptp(last) <= tol * max(1.0, abs(lam)):
            converged = True
            break
        Np = np.maximum(Np + relax * (N - Np), -cA / np.maximum(itf.friction, 1e-300))
    # the forces: the iterate of the window closest to Coulomb with its own normal forces;
    # the load factor and mechanism: its capacities without the regularisation
    viol, n1, n2, s, cap = min(window, key=lambda w: w[0])
    lam, _, _, _, du = _solve_lp(B, fD, fL, itf, A, zero, cap)
    hist.append(lam)
    # the forces: among the optimal ones of that LP, those closest to Coulomb with their own
    # normal forces (on the walls of the examples and the tests they obey it exactly)
    best = _closest_to_coulomb(B, fD, fL, itf, A, cap, lam)
    if best is not None and best[3] < viol * scale:
        n1, n2, s = best[0], best[1], best[2]
    return lam, n1, n2, s, du, it, converged, hist


def _slides(asm, itf, row, duals) -> bool:
    """True when the mechanism of ``duals`` slips along some interface (relative tangential
    velocity at its mid point above 1e-9 of the largest block velocity)."""
    d = np.zeros((asm.nblock, 3))
    free = row >= 0
    d[free] = np.asarray(duals, float).reshape(-1, 3)
    pm = itf.midpoint
    t = itf.tangent

    def vel(blk):
        r = pm - asm.centroid[blk]
        v = d[blk]
        return np.column_stack([v[:, 0] - v[:, 2] * r[:, 1], v[:, 1] + v[:, 2] * r[:, 0]])

    slip = ((vel(itf.b) - vel(itf.a)) * t).sum(1)
    size = max(np.abs(d[:, :2]).max(initial=0.0), 1e-300)
    return bool(np.abs(slip).max(initial=0.0) > 1e-9 * size)


def analyse(model, load: str = "horizontal", friction: str = "non-associative",
            direction: int = 1, point_loads=None, tol: float = 1e-6, max_iter: int = 200,
            relax: float = 0.5) -> LimitResult:
    """Collapse load factor, mechanism and joint forces of a rigid-block assembly (module
    docstring).

    Parameters
    ----------
    model : Assembly or path-like
        An :class:`~murus.limit.model.Assembly`, or a DEM case file (TOML,
        :func:`murus.limit.model.from_case`).
    load : {"horizontal", "tilt"}
        A horizontal body force proportional to the weights, or the tilt of the base.
    friction : {"non-associative", "associative"}
        Coulomb friction without dilatancy (Gilbert et al. (2006), default) or with normality.
    direction : {1, -1}
        Sense of the load along x.
    point_loads : list of PointLoad, optional
        Extra forces [N] on the blocks (dead, or live: multiplied by the load factor).
    tol : float
        Relative convergence tolerance of the load factor in the non-associative scheme.
    max_iter : int
        Largest number of non-associative iterations.
    relax : float
        Relaxation of the normal forces between iterations (0 < relax <= 1).

    Returns
    -------
    LimitResult

    Raises
    ------
    LimitModelError
        Bad model (overlapping blocks, no interface, a block without support), naming the
        block; :class:`LimitError` when the LP is unbounded or infeasible.

    References
    ----------
    Livesley (1978), doi:10.1002/nme.1620121207; Gilbert, Casapulla and Ahmed (2006),
    doi:10.1016/j.compstruc.2006.02.005.
    """
    if load not in LOADS:
        raise LimitModelError(f"load must be one of {', '.join(LOADS)}, got {load!r}",
                              key=("load",))
    if friction not in FRICTIONS:
        raise LimitModelError(f"friction must be one of {', '.join(FRICTIONS)}, got "
                              f"{friction!r}", key=("friction",))
    if direction not in (1, -1):
        raise LimitModelError(f"direction must be 1 or -1, got {direction!r}",
                              key=("direction",))
    if not 0 < relax <= 1:
        raise LimitModelError(f"relax must be in (0, 1], got {relax!r}", key=("relax",))
    if isinstance(model, Assembly):
        return _analyse(model, load, friction, direction, point_loads, tol, max_iter, relax)
    from murus.dem.case import fail_at
    from murus.limit.model import from_case

    path = Path(model)
    asm = from_case(path)
    try:
        return _analyse(asm, load, friction, direction, point_loads, tol, max_iter, relax)
    except LimitModelError as exc:
        if not exc.key:
            raise
        raise fail_at(path, path.read_text(encoding="utf-8"), exc.key, str(exc)) from None


def _analyse(asm, load, friction, direction, point_loads, tol, max_iter, relax):
    itf = find_interfaces(asm)
    check(asm, itf)
    B, row = equilibrium_matrix(asm, itf)
    src = asm.source

    def solve(cos_t):
        fD, fL = _loads(asm, row, -cos_t, float(direction), point_loads)
        try:
            return _collapse(asm, itf, B, row, fD, fL, friction, tol, max_iter, relax), fL
        except LimitError as exc:
            if exc.row is None:
                exc.source = src
                raise
            named = asm.error(int(np.nonzero(row >= 0)[0][exc.row]), str(exc))
            raise LimitError(*named.args, key=named.key, source=named.source) from None

    (lam, n1, n2, s, du, it, conv, hist), fL = solve(1.0)
    angle = math.nan
    if load == "tilt":
        cohesive = bool((itf.cohesion > 0).any() or (itf.tensile > 0).any() or point_loads)
        if not cohesive:
            th = math.atan(lam)
        else:
            from scipy.optimize import brentq

            def f(th):
                return solve(math.cos(th))[0][0] - math.sin(th)

            lo, hi = -0.5 * math.pi + 1e-9, 0.5 * math.pi - 1e-9
            th = brentq(f, lo, hi, xtol=1e-12) if f(lo) * f(hi) < 0 else math.atan(lam)
        (lam, n1, n2, s, du, it, conv, hist), fL = solve(math.cos(th))
        angle = math.degrees(th)
        lam = math.tan(th)
    mech = _mechanism(asm, row, du, fL)
    return LimitResult(float(lam), load, int(direction), friction, angle, mech, itf, n1, n2, s,
                       int(it), bool(conv), asm, hist)
