"""Python front end of the 2D distinct-element engine: bodies, joints, base motion, state.

Conventions: SI units (m, kg, s, N, rad); x horizontal, y upward, gravity ``-g y`` by default;
angles counter-clockwise; polygons counter-clockwise (clockwise input is reversed); all masses
and inertias per out-of-plane ``thickness`` [m] (default 1 m, plane strain per metre of wall).

Bodies are rigid: a convex polygon, a disc, or a clump (one rigid body made of several convex
parts). Kinematic bodies do not respond to forces: ``"fixed"`` stays in place, ``"base"`` moves
with the base motion (a :class:`~murus.motion.core.GroundMotion`, whose piecewise-linear
acceleration is integrated exactly, i.e. the trapezoid rule at the samples, or a callable
velocity ``v(t) -> vx`` or ``(vx, vy)`` in closed form), ``"prescribed"`` moves with its own
velocity ``(vx, vy, omega)`` set by :meth:`Model.set_velocity` (a servo-controlled platen, a
container wall pushed by hand), held constant until changed. The work that the moving kinematic
bodies do on the others is counted in the energy balance (``base_work``).

Polygon corners are rounded with the radius ``rounding`` (UDEC's corner rounding; default 0.5 %
of the shortest polygon edge): contacts are computed between the cores (polygons offset inwards
by the rounding), which gives vertex-to-vertex contacts a normal. A sub-contact at a corner thus
acts at the corner's rounding centre: lever arms are short by the rounding radius.

>>> from murus.dem import Model, Joint
>>> m = Model(joint=Joint(kn=1e9, ks=1e9, friction_deg=35))
>>> base = m.add_rectangle(2.0, 0.2, center=(0.0, -0.1), kinematic="fixed")
>>> blocks = [m.add_rectangle(0.4, 0.2, center=(0.0, 0.1 + 0.2 * i)) for i in range(3)]
>>> res = m.settle()
>>> bool(res.converged)
True
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable, Sequence

import numpy as np

from murus import G
from murus.dem import _kdata as kd
from murus.dem import kernels as K
from murus.dem.materials import Joint
from murus.errors import MurusError

__all__ = ["Model", "ModelError", "polygon_properties"]


class ModelError(MurusError, ValueError):
    """Invalid model input (one-line message)."""


_KIN = {None: 0, "dynamic": 0, "fixed": 1, "base": 2, "prescribed": 3}


def polygon_properties(v: np.ndarray) -> tuple[float, np.ndarray, float]:
    """Area [m²], centroid [m] and polar second moment of area about the centroid [m⁴] of a
    simple polygon with counter-clockwise vertices ``v (k, 2)``.

    Parameters
    ----------
    v : numpy.ndarray
        Vertices ``(k, 2)`` [m], counter-clockwise.

    Returns
    -------
    tuple
        Area [m²], centroid ``(2,)`` [m], polar second moment [m⁴].
    """
    x = v[:, 0]
    y = v[:, 1]
    x1 = np.roll(x, -1)
    y1 = np.roll(y, -1)
    cr = x * y1 - x1 * y
    A = 0.5 * cr.sum()
    cx = ((x + x1) * cr).sum() / (6 * A)
    cy = ((y + y1) * cr).sum() / (6 * A)
    Jo = ((x * x + x * x1 + x1 * x1 + y * y + y * y1 + y1 * y1) * cr).sum() / 12.0
    J = Jo - A * (cx * cx + cy * cy)
    return float(A), np.array([cx, cy]), float(J)


def _clean_polygon(vertices, where: str) -> np.ndarray:
    """Counter-clockwise convex polygon without repeated or collinear vertices; ``where``
    names it in errors ("body 3", "body 3 part 1")."""
    v = np.asarray(vertices, dtype=float)
    if v.ndim != 2 or v.shape[1] != 2 or v.shape[0] < 3:
        raise ModelError(f"{where}: a polygon needs at least 3 vertices (k, 2), got shape "
                         f"{v.shape}")
    if not np.all(np.isfinite(v)):
        raise ModelError(f"{where}: the polygon has non-finite vertices")
    A, _, _ = polygon_properties(v)
    if A == 0:
        raise ModelError(f"{where}: the polygon has zero area")
    if A < 0:
        v = v[::-1].copy()
    # drop repeated and collinear vertices
    scale = np.ptp(v, axis=0).max()
    keep = []
    n = len(v)
    for i in range(n):
        p0 = v[i - 1]
        p1 = v[i]
        p2 = v[(i + 1) % n]
        e0 = p1 - p0
        e1 = p2 - p1
        if np.hypot(*e0) <= 1e-12 * scale:
            continue
        cr = e0[0] * e1[1] - e0[1] * e1[0]
        if abs(cr) <= 1e-12 * np.hypot(*e0) * max(np.hypot(*e1), 1e-300):
            continue
        keep.append(i)
    v = v[keep]
    n = len(v)
    for i in range(n):
        e0 = v[i] - v[i - 1]
        e1 = v[(i + 1) % n] - v[i]
        if e0[0] * e1[1] - e0[1] * e1[0] < 0:
            raise ModelError(f"{where}: the polygon is not convex: split it into a clump")
    return v


def _core(v: np.ndarray, r: float, index: int) -> np.ndarray:
    """Polygon offset inwards by r (the core of the rounded polygon)."""
    n = len(v)
    e = np.roll(v, -1, axis=0) - v
    L = np.hypot(e[:, 0], e[:, 1])
    nin = np.column_stack([-e[:, 1], e[:, 0]]) / L[:, None]  # inward normals (CCW)
    core = np.empty_like(v)
    for i in range(n):
        n1 = nin[i - 1]
        n2 = nin[i]
        core[i] = v[i] + r * (n1 + n2) / (1.0 + n1 @ n2)
    ec = np.roll(core, -1, axis=0) - core
    ok = np.einsum("ij,ij->i", ec, e) > 0.0
    if not ok.all():
        raise ModelError(f"rounding {r:g} m too large for polygon {index} (shortest edge "
                         f"{L.min():g} m): lower Model(rounding=...)")
    return core


class Model:
    """A 2D distinct-element model (see the module docstring for conventions).

    Parameters
    ----------
    thickness : out-of-plane thickness [m] of all bodies and joints.
    gravity : acceleration of gravity [m/s²], acting along -y.
    joint : default :class:`Joint` of every pair of groups.
    rounding : corner rounding radius [m] (None: 0.5 % of the shortest polygon edge).
    margin : broad-phase margin [m] (None: 10 % of the median size of the dynamic shapes).
    safety : time-step safety factor on ``min sqrt(m / k)`` (default 0.2, about 1/7 of the
        central-difference stability limit of a body between springs).
    """

    def __init__(self, thickness: float = 1.0, gravity: float = G, joint: Joint | None = None,
                 rounding: float | None = None, margin: float | None = None,
                 safety: float = 0.2) -> None:
        if not thickness > 0:
            raise ModelError(f"thickness must be positive [m], got {thickness!r}")
        if not (0 < safety <= 1):
            raise ModelError(f"safety must be in (0, 1], got {safety!r}")
        if rounding is not None and not rounding > 0:
            raise ModelError(f"rounding must be positive [m], got {rounding!r}")
        self.thickness = float(thickness)
        self._gravity = float(gravity)
        self.safety = float(safety)
        self.rounding = None if rounding is None else float(rounding)
        self.margin = None if margin is None else float(margin)
        self._joints: list[Joint] = [joint or Joint()]
        self._groups: dict[str, int] = {"default": 0}
        self._pair_joint: dict[tuple[int, int], int] = {}
        self._bodies: list[dict] = []
        self._built = False
        self.dt: float | None = None
        # base motion and gravity schedule
        self._motion_kind = "none"  # none | record | callable
        self._motion_dt = 0.0
        self._motion_acc = np.zeros(0)
        self._motion_accv = np.zeros(0)
        self._motion_callable: Callable | None = None
        self.tilt_rate = 0.0  # [rad/s]
        self.tilt0 = 0.0  # [rad]
        self.tilt_t0 = 0.0  # model time [s] at which the tilt is tilt0
        self.time_offset = 0.0
        self.step_offset = 0
        self.history: dict[str, list] = {}
        self.probes: dict[str, object] = {}

    # ------------------------------------------------------------------ building
    def _group(self, name: str) -> int:
        if name not in self._groups:
            self._groups[name] = len(self._groups)
        return self._groups[name]

    def _check_open(self) -> None:
        if self._built:
            raise ModelError("add all bodies and joints before the first settle/run")

    def _add(self, parts, density, kinematic, group) -> int:
        self._check_open()
        if kinematic not in _KIN:
            raise ModelError(f"kinematic must be None, 'fixed', 'base' or 'prescribed', got "
                             f"{kinematic!r}")
        if not (density > 0 and math.isfinite(density)):
            raise ModelError(f"density must be positive [kg/m³], got {density!r}")
        self._bodies.append({"parts": parts, "density": float(density),
                             "kin": _KIN[kinematic], "group": self._group(group)})
        return len(self._bodies) - 1

    def add_polygon(self, vertices, density: float = 2000.0, kinematic: str | None = None,
                    group: str = "default") -> int:
        """A rigid convex polygon (world vertices [m], counter-clockwise); returns its body
        index."""
        v = _clean_polygon(vertices, f"body {len(self._bodies)}")
        return self._add([("poly", v)], density, kinematic, group)

    def add_rectangle(self, width: float, height: float, center=(0.0, 0.0), angle: float = 0.0,
                      density: float = 2000.0, kinematic: str | None = None,
                      group: str = "default") -> int:
        """A rectangle ``width x height`` [m] centred at ``center``, rotated by ``angle`` [rad]
        counter-clockwise."""
        if not (width > 0 and height > 0):
            raise ModelError(f"rectangle sizes must be positive, got {width!r} x {height!r}")
        v = np.array([[-width / 2, -height / 2], [width / 2, -height / 2],
                      [width / 2, height / 2], [-width / 2, height / 2]])
        c, s = math.cos(angle), math.sin(angle)
        v = v @ np.array([[c, s], [-s, c]]) + np.asarray(center, float)
        return self.add_polygon(v, density, kinematic, group)

    def add_disc(self, center, radius: float, density: float = 2000.0,
                 kinematic: str | None = None, group: str = "default") -> int:
        """A rigid disc (centre [m], radius [m])."""
        if not radius > 0:
            raise ModelError(f"disc radius must be positive, got {radius!r}")
        return self._add([("disc", np.asarray(center, float), float(radius))], density,
                         kinematic, group)

    def add_clump(self, parts: Sequence, density: float = 2000.0, kinematic: str | None = None,
                  group: str = "default") -> int:
        """One rigid body made of several convex parts: each part a polygon (vertex array) or a
        disc ``("disc", center, radius)``. Parts may touch but not overlap (the mass is the sum
        of the parts': an overlap deeper than 1e-9 of the clump's size is an error)."""
        out = []
        for p in parts:
            if isinstance(p, tuple) and len(p) == 3 and p[0] == "disc":
                if not p[2] > 0:
                    raise ModelError(f"disc radius must be positive, got {p[2]!r}")
                out.append(("disc", np.asarray(p[1], float), float(p[2])))
            else:
                out.append(("poly", _clean_polygon(p, f"body {len(self._bodies)} part {len(out)}")))
        if not out:
            raise ModelError("a clump needs at least one part")
        _check_parts_apart(out, f"body {len(self._bodies)}")
        return self._add(out, density, kinematic, group)

    def set_joint(self, joint: Joint, group_a: str | None = None,
                  group_b: str | None = None) -> None:
        """Joint of the pair of groups (a, b); without groups, the default joint."""
        self._check_open()
        if group_a is None and group_b is None:
            self._joints[0] = joint
            return
        ga = self._group(group_a or "default")
        gb = self._group(group_b or group_a or "default")
        self._joints.append(joint)
        self._pair_joint[(min(ga, gb), max(ga, gb))] = len(self._joints) - 1

    def update_joint(self, joint: Joint, group_a: str | None = None,
                     group_b: str | None = None) -> None:
        """Change the properties of an existing joint during the analysis (e.g. lower the
        friction after settling); the state of the sub-contacts is kept."""
        if group_a is None and group_b is None:
            j = 0
        else:
            ga = self._groups[group_a or "default"]
            gb = self._groups[group_b or group_a or "default"]
            j = self._pair_joint.get((min(ga, gb), max(ga, gb)), 0)
        self._joints[j] = joint
        if self._built:
            self.jprops[j] = joint.row()
            self.P[K.P_REACH] = float(np.max(self.jprops[:, K.J_T] / self.jprops[:, K.J_KN]))

    def set_velocity(self, body: int, vx: float = 0.0, vy: float = 0.0,
                     omega: float = 0.0) -> None:
        """Velocity [m/s, m/s, rad/s] of a ``kinematic="prescribed"`` body from now on (the
        rotation about its centroid)."""
        self.build()
        if not (0 <= body < self.nbody) or self.bkin[body] != _KIN["prescribed"]:
            raise ModelError(f"body {body} is not a kinematic='prescribed' body")
        v = (float(vx), float(vy), float(omega))
        if not all(math.isfinite(x) for x in v):
            raise ModelError(f"body {body}: the velocity must be finite, got {v}")
        self.bpresc[body] = v

    def set_base_motion(self, motion=None, velocity: Callable | None = None) -> None:
        """Motion of the ``kinematic="base"`` bodies: a GroundMotion (``acc`` and optional
        ``acc_v`` [m/s²], zero after its end) or a callable ``velocity(t) -> vx`` or
        ``(vx, vy)`` [m/s] (vectorised over a time array)."""
        if (motion is None) == (velocity is None):
            raise ModelError("give either a GroundMotion or a velocity callable")
        if motion is not None:
            self._motion_kind = "record"
            self._motion_dt = float(motion.dt)
            self._motion_acc = np.asarray(motion.acc, float).copy()
            av = getattr(motion, "acc_v", None)
            self._motion_accv = (np.zeros_like(self._motion_acc) if av is None
                                 else np.asarray(av, float).copy())
            self._motion_callable = None
        else:
            if not callable(velocity):
                raise ModelError("velocity must be a callable v(t)")
            self._motion_kind = "callable"
            self._motion_callable = velocity

    def set_tilt(self, rate_deg_per_s: float, start_deg: float = 0.0) -> None:
        """Tilting table: gravity rotates at ``rate`` [deg/s] from ``start`` [deg] at the
        current model time; a positive tilt pushes the bodies towards +x (g = g (sin beta,
        -cos beta)). The energy balance counts the change of the gravitational energy caused by
        the jump to ``start`` and, during the run, the work of the rotating gravity
        (``energy()["tilt_work"]``)."""
        def change():
            self.tilt_rate = math.radians(rate_deg_per_s)
            self.tilt0 = math.radians(start_deg)
            self.tilt_t0 = self.time
        self._rebase_gravity(change)

    @property
    def gravity(self) -> float:
        """Magnitude of gravity [m/s²]; changing it between runs is counted in the energy
        balance like a change of tilt."""
        return self._gravity

    @gravity.setter
    def gravity(self, value: float) -> None:
        def change():
            self._gravity = float(value)
        self._rebase_gravity(change)

    def _potential(self) -> float:
        """Gravitational energy [J] of the dynamic bodies at the energy snapshot."""
        dyn = self.bkin == 0
        g = self.gravity_vector([self.snap_time])[0]
        return -float(np.sum(self.bmass[dyn] * (self.bsnap[dyn, :2] @ g)))

    def _rebase_gravity(self, change) -> None:
        # a sudden change of the gravity vector changes the potential energy of the bodies
        # without any work of the forces: booked as work of the tilt so that the balance holds
        built = self._built and getattr(self, "bsnap", None) is not None
        pe0 = self._potential() if built else 0.0
        change()
        if built:
            self.E[K.E_WTILT] += self._potential() - pe0

    # ------------------------------------------------------------------ arrays
    def build(self) -> None:
        """Freeze the geometry into the kernel arrays (done by the first settle/run)."""
        if self._built:
            return
        if not self._bodies:
            raise ModelError("the model has no bodies")
        polys = [p[1] for b in self._bodies for p in b["parts"] if p[0] == "poly"]
        if self.rounding is None:
            emin = min((np.hypot(*(np.roll(v, -1, 0) - v).T).min() for v in polys),
                       default=1.0)
            self.rounding = 0.005 * emin
        t = self.thickness
        nb = len(self._bodies)
        bpos = np.zeros((nb, 2))
        bmass = np.zeros(nb)
        binert = np.zeros(nb)
        bkin = np.zeros(nb, np.int64)
        brad = np.zeros(nb)
        blen = np.zeros(nb)
        sbody, skind, svs, svn, srad, sgroup = [], [], [], [], [], []
        lv, ov, ovs = [], [], []
        nv = 0
        pi_ = 0
        for ib, b in enumerate(self._bodies):
            rho = b["density"]
            M = 0.0
            S = np.zeros(2)
            J0 = 0.0  # about the origin
            for p in b["parts"]:
                if p[0] == "poly":
                    A, c, J = polygon_properties(p[1])
                else:
                    A = math.pi * p[2] ** 2
                    c = p[1]
                    J = 0.5 * A * p[2] ** 2
                mpart = rho * t * A
                M += mpart
                S += mpart * c
                J0 += rho * t * J + mpart * (c @ c)
            cg = S / M
            bpos[ib] = cg
            bmass[ib] = M
            binert[ib] = J0 - M * (cg @ cg)
            bkin[ib] = b["kin"]
            for p in b["parts"]:
                sbody.append(ib)
                sgroup.append(b["group"])
                svs.append(nv)
                if p[0] == "poly":
                    v = p[1]
                    core = _core(v, self.rounding, pi_)
                    pi_ += 1
                    skind.append(0)
                    srad.append(self.rounding)
                    svn.append(len(v))
                    lv.append(core - cg)
                    ov.append(v - cg)
                    ovs.append(len(ov) - 1)
                    nv += len(v)
                    brad[ib] = max(brad[ib], np.hypot(*(v - cg).T).max())
                    blen[ib] = max(blen[ib], np.hypot(*(np.roll(v, -1, 0) - v).T).max())
                else:
                    skind.append(1)
                    srad.append(p[2])
                    svn.append(1)
                    lv.append((p[1] - cg)[None, :])
                    nv += 1
                    brad[ib] = max(brad[ib], np.hypot(*(p[1] - cg)) + p[2])
                    blen[ib] = max(blen[ib], 2 * p[2])
        self.bpos = bpos
        self.bang = np.zeros(nb)
        self.bvel = np.zeros((nb, 2))
        self.bomg = np.zeros(nb)
        self.bmass = bmass
        self.binert = binert
        self.bkin = bkin
        self.brad = brad
        self.blen = blen
        self.blast = np.column_stack([bpos, np.zeros(nb)])
        self.bext = np.zeros((nb, 3))  # external force (Fx, Fy) [N] and moment [N m]
        self.bpresc = np.zeros((nb, 3))  # velocity (vx, vy, omega) of "prescribed" bodies
        self.bref = np.column_stack([bpos, np.zeros(nb)])
        self.bsnap = np.zeros((nb, 6))  # set by snapshot() at the end of the build
        self.sbody = np.array(sbody, np.int64)
        self.skind = np.array(skind, np.int64)
        self.svs = np.array(svs, np.int64)
        self.svn = np.array(svn, np.int64)
        self.srad = np.array(srad, float)
        self.sgroup = np.array(sgroup, np.int64)
        self.lv = np.ascontiguousarray(np.vstack(lv))
        self.wv = np.zeros_like(self.lv)
        self._outer = [o.copy() for o in ov]  # outer polygons, body frame
        self.poly_shape = np.array([s for s in range(len(sbody)) if skind[s] == 0], np.int64)
        self.disc_shape = np.array([s for s in range(len(sbody)) if skind[s] == 1], np.int64)
        ng = len(self._groups)
        jtab = np.zeros((ng, ng), np.int64)
        for (ga, gb), j in self._pair_joint.items():
            jtab[ga, gb] = jtab[gb, ga] = j
        self.jtab = jtab
        self.jprops = np.vstack([j.row() for j in self._joints])
        dyn = self.bkin == 0
        sizes = [2 * self.brad[self.sbody[s]] if self.skind[s] == 0 else 2 * self.srad[s]
                 for s in range(len(sbody)) if dyn[self.sbody[s]]]
        if self.margin is None:
            self.margin = 0.1 * float(np.median(sizes)) if sizes else 0.1
        self.P = np.zeros(K.NP)
        self.P[K.P_THICK] = t
        self.P[K.P_MARGIN] = self.margin
        self.P[K.P_REACH] = float(np.max(self.jprops[:, K.J_T] / self.jprops[:, K.J_KN]))
        self.P[K.P_PARMIN] = 1024  # parallel contact loop from 1024 pairs (thread overhead)
        self.P[K.P_DREL] = 1.0  # damping on velocities relative to the base
        self.E = np.zeros(K.NE)
        self.C = np.zeros(K.NC, np.int64)
        self.S = np.zeros(K.NS)
        self.E0 = 0.0
        # first pair list: the sub-contacts present at the start are bonded
        shapes = kd.pack(kd.Shapes, self)
        K.world_vertices(self.bpos, self.bang, shapes)
        pairs = K.broad_phase(shapes, self.bkin, self.margin)
        empty = kd.Contacts(np.zeros((0, 2), np.int64), np.zeros(0, np.int64),
                            np.zeros(0, np.int8), np.zeros((0, 2), np.int64),
                            np.zeros((0, 2, K.NSF)), np.zeros((0, 2), np.int8))
        contacts = K.transfer_arrays(empty, pairs, self.sgroup, self.jtab, 1)
        for name, a in zip(kd.Contacts._fields, contacts, strict=True):
            setattr(self, name, a)
        self._built = True
        from murus.dem.engine import detect
        detect(self)
        self.reset_reference()

    # ------------------------------------------------------------------ state queries
    @property
    def nbody(self) -> int:
        return len(self._bodies)

    @property
    def time(self) -> float:
        """Model time [s] (settling does not advance it)."""
        if not self._built or self.dt is None:
            return self.time_offset
        return self.time_offset + (int(self.C[K.C_STEP]) - self.step_offset) * self.dt

    @property
    def steps(self) -> int:
        return int(self.C[K.C_STEP]) if self._built else 0

    def gravity_vector(self, t) -> np.ndarray:
        """Gravity [m/s²] at times t (n, 2)."""
        beta = self.tilt_angle(t)
        return self.gravity * np.column_stack([np.sin(beta), -np.cos(beta)])

    def tilt_angle(self, t) -> np.ndarray:
        """Tilt of gravity [rad] at times t."""
        return self.tilt0 + self.tilt_rate * (np.asarray(t, float) - self.tilt_t0)

    def gravity_rate(self, t) -> np.ndarray:
        """Time derivative of the gravity vector [m/s³] at times t (n, 2)."""
        beta = self.tilt_angle(t)
        return self.gravity * self.tilt_rate * np.column_stack([np.cos(beta), np.sin(beta)])

    def base_velocity(self, t) -> np.ndarray:
        """Velocity of the ``"base"`` bodies [m/s] at times t (n, 2)."""
        return motion_velocity(self, t)

    # ------------------------------------------------------------------ outputs
    def world_polygons(self) -> list[np.ndarray]:
        """Outer vertices (k, 2) [m] of every polygon shape in world coordinates."""
        self.build()
        out = []
        for i, s in enumerate(self.poly_shape):
            b = self.sbody[s]
            c, sn = math.cos(self.bang[b]), math.sin(self.bang[b])
            R = np.array([[c, -sn], [sn, c]])
            out.append(self._outer[i] @ R.T + self.bpos[b])
        return out

    def discs(self) -> tuple[np.ndarray, np.ndarray]:
        """Centres (n, 2) [m] and radii (n,) [m] of the disc shapes."""
        self.build()
        K.world_vertices(self.bpos, self.bang, kd.pack(kd.Shapes, self))
        idx = self.svs[self.disc_shape]
        return self.wv[idx].copy(), self.srad[self.disc_shape].copy()

    def body_of_polygon(self) -> np.ndarray:
        self.build()
        return self.sbody[self.poly_shape].copy()

    def body_of_disc(self) -> np.ndarray:
        self.build()
        return self.sbody[self.disc_shape].copy()

    def body_displacement(self) -> np.ndarray:
        """Centroid displacement (nbody, 2) [m] since the reference state."""
        self.build()
        return self.bpos - self.bref[:, :2]

    def body_rotation(self) -> np.ndarray:
        """Rotation (nbody,) [rad] since the reference state."""
        self.build()
        return self.bang - self.bref[:, 2]

    def contacts_array(self) -> np.ndarray:
        """Active sub-contacts, rows (x, y, fn, fs, nx, ny) [m, N, N, -]."""
        self.build()
        on = self.sid >= 0
        f = self.sf[on]
        return np.column_stack([f[:, K.F_PX], f[:, K.F_PY], f[:, K.F_FN], f[:, K.F_FS],
                                f[:, K.F_NX], f[:, K.F_NY]])

    def contact_pairs(self) -> np.ndarray:
        """Bodies (a, b) of each active sub-contact (rows match :meth:`contacts_array`)."""
        self.build()
        on = self.sid >= 0
        ba = np.repeat(self.sbody[self.pairs[:, 0]][:, None], 2, 1)[on]
        bb = np.repeat(self.sbody[self.pairs[:, 1]][:, None], 2, 1)[on]
        return np.column_stack([ba, bb])

    def energy(self) -> dict:
        """Energy terms [J] since the reference state (see :mod:`murus.dem.engine`)."""
        from murus.dem.engine import energy
        return energy(self)

    def snapshot(self) -> None:
        """Energy snapshot of the current state (positions and half-step velocities)."""
        self.bsnap = np.column_stack([self.bpos, self.bang, self.bvel, self.bomg])
        self.snap_time = self.time

    def reset_reference(self) -> None:
        """Displacements, rotations and energy balance measured from now on."""
        self.build()
        self.bref = np.column_stack([self.bpos, self.bang])
        self.E[:] = 0.0
        cp = self.__dict__.get("coupled")
        if cp is not None:  # the zones and the interface of a coupled model too
            cp.reset_reference()
        e = self.energy()
        self.E0 = e["kinetic"] + e["gravity"] + e["elastic"]

    # ------------------------------------------------------------------ running
    def settle(self, **kw):
        """Static solution with local damping: see :func:`murus.dem.engine.settle`."""
        from murus.dem.engine import settle
        return settle(self, **kw)

    def run(self, duration: float | None = None, **kw):
        """Dynamic run: see :func:`murus.dem.engine.run`."""
        from murus.dem.engine import run
        return run(self, duration, **kw)

    def stable_dt(self) -> float:
        from murus.dem.engine import stable_dt
        return stable_dt(self)

    # ------------------------------------------------------------------ checkpoint
    # the kernel state (murus.dem._kdata: a field added there is saved and loaded) and the
    # model's own arrays
    _ARRAYS = kd.STATE_ARRAYS + ("blen", "bref", "poly_shape", "disc_shape", "P", "E", "C", "S",
                                 "_motion_acc", "_motion_accv")
    #: arrays that checkpoints written before they existed lack: zeros (nbody, 3) on load
    _ZERO_IF_MISSING = ("bext", "bpresc")

    def save(self, path) -> None:
        """Whole state to an ``.npz`` file (a callable base motion and custom probes are not
        saved: set them again after :meth:`load`), written atomically and durably
        (:func:`murus.outputs.atomic_write`: a crash never leaves a half checkpoint). Blocks
        coupled with zones save through :meth:`murus.continuum.CoupledModel.save`."""
        self.build()
        if self.__dict__.get("coupled") is not None:
            from murus.continuum.coupled import CoupledError

            raise CoupledError("these blocks are coupled with zones: save the coupled model "
                               "(CoupledModel.save)", key=("save",))
        arrays, meta = self.checkpoint_arrays()
        arrays["meta"] = np.array(json.dumps(meta))
        write_npz(path, arrays)

    def checkpoint_arrays(self) -> tuple[dict, dict]:
        """The arrays and the metadata (JSON-able) of a checkpoint (:meth:`save`)."""
        self.build()
        arrays = {name.lstrip("_"): getattr(self, name) for name in self._ARRAYS}
        for i, o in enumerate(self._outer):
            arrays[f"outer_{i}"] = o
        for name, h in self.history.items():
            arrays[f"hist__{name}"] = np.asarray(h, float)
        meta = {
            "thickness": self.thickness, "gravity": self.gravity, "safety": self.safety,
            "rounding": self.rounding, "margin": self.margin, "dt": self.dt,
            "motion_kind": self._motion_kind, "motion_dt": self._motion_dt,
            "tilt_rate": self.tilt_rate, "tilt0": self.tilt0, "tilt_t0": self.tilt_t0,
            "time_offset": self.time_offset,
            "step_offset": self.step_offset, "E0": self.E0, "snap_time": self.snap_time,
            "groups": self._groups,
            "nouter": len(self._outer), "history": list(self.history),
            "probes": {k: getattr(p, "spec", None) for k, p in self.probes.items()},
            "bodies": [{"kin": b["kin"], "group": b["group"], "density": b["density"]}
                       for b in self._bodies],
        }
        return arrays, meta

    @classmethod
    def load(cls, path) -> Model:
        """A model saved by :meth:`save`, ready to resume."""
        with np.load(path, allow_pickle=False) as z:
            meta = json.loads(str(z["meta"]))
            m = cls(thickness=meta["thickness"], gravity=meta["gravity"], safety=meta["safety"],
                    rounding=meta["rounding"], margin=meta["margin"])
            m.restore_arrays(z, meta)
        return m

    def restore_arrays(self, z, meta: dict) -> None:
        """Set the state from the arrays ``z`` (a mapping) and metadata of a checkpoint
        (:meth:`checkpoint_arrays`)."""
        from murus.dem.engine import probe_from_spec

        m = self
        nb = z["bpos"].shape[0]
        for name in self._ARRAYS:
            key = name.lstrip("_")
            if key not in z and name in self._ZERO_IF_MISSING:
                setattr(m, name, np.zeros((nb, 3)))
            else:
                setattr(m, name, np.array(z[key], copy=True))
        m._outer = [np.array(z[f"outer_{i}"], copy=True) for i in range(meta["nouter"])]
        m.history = {k: list(z[f"hist__{k}"]) for k in meta["history"]}
        m.dt = meta["dt"]
        m._motion_kind = meta["motion_kind"]
        m._motion_dt = meta["motion_dt"]
        m.tilt_rate = meta["tilt_rate"]
        m.tilt0 = meta["tilt0"]
        m.tilt_t0 = meta.get("tilt_t0", 0.0)
        m.time_offset = meta["time_offset"]
        m.step_offset = meta["step_offset"]
        m.E0 = meta["E0"]
        m.snap_time = meta["snap_time"]
        m._groups = meta["groups"]
        m._bodies = [dict(b, parts=[]) for b in meta["bodies"]]
        if m.jprops.shape[1] < K.NJ:  # a checkpoint written before the J_CDAMP column
            m.jprops = np.hstack([m.jprops, np.zeros((m.jprops.shape[0],
                                                      K.NJ - m.jprops.shape[1]))])
        m._joints = [Joint.from_row(r) for r in m.jprops]
        m._built = True
        for k, spec in meta["probes"].items():
            if spec is not None:
                m.probes[k] = probe_from_spec(spec)
        if m._motion_kind == "callable":
            m._motion_kind = "none"  # to be set again with set_base_motion(velocity=...)


def write_npz(path, arrays: dict) -> None:
    """``np.savez`` of ``arrays`` to an open file, or atomically and durably to a path (``.npz``
    appended as np.savez does; :func:`murus.outputs.atomic_write`)."""
    if hasattr(path, "write"):  # an open file
        np.savez(path, **arrays)
        return
    from murus.outputs import atomic_write

    dest = str(path) if str(path).endswith(".npz") else f"{path}.npz"
    atomic_write(dest, lambda tmp: np.savez(tmp, **arrays))


def _check_parts_apart(parts, where: str) -> None:
    """ModelError when two parts of a clump overlap by more than 1e-9 of the clump's size [m]
    (penetration depth by separating axes, :func:`murus.dem.case.check_overlaps`' geometry)."""
    from murus.dem.case import _bbox, _overlap

    box = _bbox(parts)
    tol = 1e-9 * float(max(box[2] - box[0], box[3] - box[1]))
    for i in range(len(parts) - 1):
        for j in range(i + 1, len(parts)):
            d = _overlap([parts[i]], [parts[j]])
            if d > tol:
                raise ModelError(f"{where}: clump parts {i} and {j} overlap by {d:.3g} m (their "
                                 "common area would be counted twice in the mass): split the "
                                 "clump into parts that only touch")


def motion_velocity(holder, t) -> np.ndarray:
    """Velocity of a base [m/s] at times t (n, 2), from the motion a model holds: its
    ``_motion_kind`` ("record": the accelerations ``_motion_acc`` and ``_motion_accv`` [m/s²]
    sampled at ``_motion_dt`` [s], integrated exactly, zero after their end; "callable":
    ``_motion_callable(t)`` returning vx or (vx, vy); else at rest). One function for the
    blocks and the zones, so that both read the same base motion.

    Parameters
    ----------
    holder : object
        A :class:`Model` or a :class:`murus.continuum.ContinuumModel`.
    t : array_like
        Times [s].

    Returns
    -------
    ndarray (n, 2)
    """
    t = np.atleast_1d(np.asarray(t, float))
    out = np.zeros((t.size, 2))
    if holder._motion_kind == "record":
        for j, acc in enumerate((holder._motion_acc, holder._motion_accv)):
            out[:, j] = _record_velocity(acc, holder._motion_dt, t)
    elif holder._motion_kind == "callable":
        v = holder._motion_callable(t)
        if isinstance(v, tuple):
            out[:, 0] = v[0]
            out[:, 1] = v[1]
        else:
            out[:, 0] = v
    return out


def _record_velocity(acc: np.ndarray, dt: float, t: np.ndarray) -> np.ndarray:
    """Exact velocity of a piecewise-linear acceleration record (zero after its end) at times t:
    the trapezoid rule at the samples and the quadratic in between."""
    n = acc.size
    if n == 0:
        return np.zeros_like(t)
    V = np.zeros(n)
    V[1:] = np.cumsum(0.5 * dt * (acc[:-1] + acc[1:]))
    i = np.floor(t / dt).astype(np.int64)
    i = np.clip(i, 0, n - 1)
    tau = t - i * dt
    a0 = acc[i]
    a1 = np.where(i + 1 < n, acc[np.minimum(i + 1, n - 1)], 0.0)
    last = i >= n - 1
    v = V[i] + a0 * tau + (a1 - a0) * tau * tau / (2 * dt)
    v = np.where(last, V[-1], v)  # after the last sample the acceleration is zero
    return np.where(t < 0, 0.0, v)
