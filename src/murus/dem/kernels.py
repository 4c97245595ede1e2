"""Numerical kernels of the 2D distinct-element engine (numba, no I/O, no Python objects).

Storage (structure of arrays, built by :mod:`murus.dem.model`)
---------------------------------------------------------------
The kernels take the arrays grouped in the named tuples of :mod:`murus.dem._kdata` (bodies
:class:`~murus.dem._kdata.Bodies`, shapes :class:`~murus.dem._kdata.Shapes`, joints
:class:`~murus.dem._kdata.Joints`, candidate pairs :class:`~murus.dem._kdata.Contacts`, step
inputs :class:`~murus.dem._kdata.Drive` read per step as a :class:`~murus.dem._kdata.Frame`) and
read them by name; small float records have the declared layouts ``F_*``, ``J_*``, ``P_*``,
``E_*``, ``C_*``, ``S_*``, ``W_*``, ``Q_*`` below. One exception: the per-pair body of the
parallel contact loop (:func:`process_pair`) takes the arrays bare, unpacked from the
structures by :func:`_contacts_parallel` outside the loop, because numba compiles a parallel
loop whose body reads arrays out of a tuple without its ``noalias`` attributes (2.1 times
slower); and inside a parallel loop the kernels write a structure's array through its field
position (``bodies[IB_BPOS]``), because numba drops a write through a named-tuple attribute
there (numba issues #5872, #7135).

- bodies ``b``: ``bpos (nb, 2)`` centroid [m], ``bang`` angle [rad, counter-clockwise],
  ``bvel (nb, 2)`` [m/s] and ``bomg`` [rad/s] at the half step ``t - dt/2``, ``bmass`` [kg],
  ``binert`` [kg m²] about the centroid, ``bkin`` (0 dynamic, 1 fixed, 2 moved by the base
  motion, 3 moved at its prescribed velocity ``bpresc``), ``brad`` bounding radius about the
  centroid [m];
- shapes ``s``: ``sbody``, ``skind`` (0 polygon, 1 disc), ``svs``/``svn`` range into the
  local-vertex array ``lv`` (core vertices of a polygon relative to the body centroid at angle 0,
  the disc centre for a disc), ``srad`` (rounding radius of a polygon, radius of a disc),
  ``sgroup`` (joint group); ``wv`` holds the same vertices in world coordinates;
- candidate pairs ``k`` (shape a < shape b) with up to two sub-contacts (slots) each: the slot
  key ``sid`` (a global vertex index, the "feature"), the float record ``sf[k, slot, F_*]``, the
  broken flag ``sbr`` (cohesion and tension at their residual values), the joint index ``pj``
  and ``pbond`` (1: new sub-contacts of the pair start bonded).

Rounded polygons (UDEC "corner rounding")
-----------------------------------------
A polygon is the Minkowski sum of its *core* (the user polygon offset inwards by the rounding
radius r) and a disc of radius r, so that every contact, vertex-to-vertex included, has a normal
defined by the closest points of the cores. Polygon-polygon contacts follow the clipping scheme
of Box2D (E. Catto): the reference edge is the edge of largest separation (separating-axis
test); the incident edge of the other core is clipped to the span of the reference edge; each end
of the clipped segment is a sub-contact keyed by the vertex that bounds it (a vertex of the
incident polygon, or an end of the reference edge). When the cores are apart and the closest
points are two vertices (non-parallel edges), a single vertex-to-vertex sub-contact takes the
normal along the line joining them. Tributary length of a sub-contact: half the clipped overlap
of the cores plus the rounding (an edge-to-edge interface of length L: two points with L/2 each;
a vertex on a face: half the incident edge), so that the contact stiffness is ``kn L t``.

Joint law (Savalle et al. (2022), eqs. 3-4; UDEC "Coulomb slip" joint model)
----------------------------------------------------------------------------
Per sub-contact, tributary area ``A = L t``: normal force ``Fn = -kn A g`` (g the gap, negative
in penetration; the total form of eq. 3, identical to the incremental form for a spring born at
zero gap, and exactly conservative); shear force incremental, ``Fs <- Fs - ks A du_s`` with
``du_s`` the relative tangential displacement of the step (eq. 3), limited by
``|Fs| <= c A + Fn tan(phi)`` (eq. 4); tension ``Fn >= -T A``. A sub-contact that fails in
tension or shear takes the residual cohesion and tension. Sign conventions: the normal ``n``
points from shape a to shape b, the tangent ``t = (-ny, nx)``; ``Fn > 0`` is compression; the
force on b is ``Fn n + Fs t``. Discs carry a rolling moment ``Mr <- Mr - kr dtheta_rel``
with ``kr = ks A r_eff²`` limited by ``mu_r r_eff Fn`` (elastic-plastic rolling resistance).

Integration (Savalle et al. (2022), eq. 2; central differences / leapfrog)
--------------------------------------------------------------------------
``v(t + dt/2) = v(t - dt/2) + a(t) dt``, ``x(t + dt) = x(t) + v(t + dt/2) dt`` for the two
translations and the rotation. Damping: Cundall's local non-viscous damping, a force
``-alpha |F| sign(v)`` per degree of freedom; mass-proportional (Rayleigh) damping
``-alpha_M m (v - v_base)`` on the velocity relative to the base motion, treated by the
central-difference average ``(v_old + v_new) / 2`` (as in UDEC/FLAC), so that it is stable for
any ``alpha_M dt``.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from murus._jit import guard_cache as _guard_cache
from murus.dem._kdata import (
    IB_BANG,
    IB_BOMG,
    IB_BPOS,
    IB_BSNAP,
    IB_BVEL,
    IS_WV,
    Contacts,
    Frame,
    PairMotion,
    SubContact,
)

# ---- slot record fields --------------------------------------------------------------------
F_FN = 0  # normal force [N], > 0 compression
F_FS = 1  # shear force [N] along t = (-ny, nx), on shape b
F_MR = 2  # rolling moment on shape b [N m]
F_PX = 3  # contact point [m]
F_PY = 4
F_NX = 5  # unit normal from a to b
F_NY = 6
F_KNA = 7  # kn A [N/m]
F_KSA = 8  # ks A [N/m]
F_KRA = 9  # rolling stiffness [N m/rad]
F_GAP = 10  # gap between rounded surfaces [m]
NSF = 11

# ---- joint property columns ------------------------------------------------------------------
J_KN = 0  # normal stiffness per unit area [Pa/m]
J_KS = 1  # shear stiffness per unit area [Pa/m]
J_TANPHI = 2  # tan(friction angle)
J_C = 3  # cohesion [Pa]
J_T = 4  # tensile strength [Pa]
J_CRES = 5  # residual cohesion [Pa]
J_TRES = 6  # residual tensile strength [Pa]
J_MUROLL = 7  # rolling friction coefficient [-]
J_CDAMP = 8  # contact damping: critical-damping ratio zeta of the normal dashpot [-] (0: none)
NJ = 9

# ---- parameter vector ------------------------------------------------------------------------
P_DT = 0  # time step [s]
P_THICK = 1  # out-of-plane thickness [m]
P_ALOCAL = 2  # local damping coefficient [-]
P_AMASS = 3  # mass-proportional damping alpha_M [1/s]
P_MARGIN = 4  # broad-phase margin [m]
P_REACH = 5  # largest positive gap at which a sub-contact is kept [m]
P_PARMIN = 6  # smallest number of pairs for the parallel loop
P_DREL = 7  # frame of the damping: 1 the base motion, 0 the fixed frame
NP = 8

# ---- energy accumulators ---------------------------------------------------------------------
E_WBASE = 0  # work done by the kinematic bodies on the system [J]
E_WDAMP = 1  # work of the damping forces (negative) [J]
E_DSLIP = 2  # frictional (slip) dissipation [J]
E_DROLL = 3  # rolling-resistance dissipation [J]
E_DBREAK = 4  # elastic energy released by breaking or opening sub-contacts [J]
E_WEXT = 5  # work of the external (applied) body forces ``bext`` [J]
E_WTILT = 6  # work of a time-varying gravity, -sum m x . dg/dt dt, and of its jumps [J]
E_DDASH = 7  # dissipation of the contact dashpots (J_CDAMP) [J]
NE = 8

# ---- counters ----------------------------------------------------------------------------------
C_STEP = 0
C_REBUILD = 1
C_UPDATES = 2  # sub-contact updates
C_NEED_REBUILD = 3  # 1: rebuild the pair list at the next step
NC = 4

# ---- per-pair record of a step (``pw``, written by the contact loop) ---------------------------
W_SLIP = 0  # slip dissipation [J]
W_ROLL = 1  # rolling dissipation [J]
W_BREAK = 2  # energy released by breaking or opening [J]
W_FX = 3  # resultant force of the pair's sub-contacts on body b [N]
W_FY = 4
W_MB = 5  # its moment about the centroid of body b [N m]
W_MA = 6  # its moment about the centroid of body a [N m] (the reaction on a is the opposite)
W_DFX = 7  # of it, the force of the contact dashpots on body b [N] (written when J_CDAMP > 0)
W_DFY = 8
W_DMB = 9  # its moment about the centroid of body b [N m]
W_DMA = 10  # its moment about the centroid of body a [N m]
NW = 12

# ---- partial sums of a block of bodies (``part[blk, Q_*]``, written by the body update) ----
Q_UNBAL = 0  # max unbalanced force of a dynamic body [N]
Q_WDAMP = 1  # work of the damping forces [J]
Q_WBASE = 2  # work of the kinematic bodies [J]
Q_WEXT = 3  # work of the external forces [J]
Q_NEED = 4  # 1.0: a body has moved far enough to rebuild the pair list
Q_WTILT = 5  # work of a time-varying gravity [J]
NQ = 6

# ---- chunk statistics --------------------------------------------------------------------------
S_UNBAL = 0  # max unbalanced force of a dynamic body at the last step [N]
S_MEANF = 1  # mean contact force magnitude over active sub-contacts [N]
S_NACTIVE = 2  # active sub-contacts
NS = 4


@njit(cache=True, error_model="numpy", inline="always")
def _clamp01(x):
    if x < 0.0:
        return 0.0
    if x > 1.0:
        return 1.0
    return x


@njit(cache=True, error_model="numpy", inline="always")
def _shape_vertices(s, bpos, bang, shapes):
    """World coordinates of the local vertices of shape s (``shapes``: :class:`Shapes`)."""
    svs = shapes.svs
    lv = shapes.lv
    wv = shapes[IS_WV]  # written inside the body loop: by position (murus.dem._kdata)
    b = shapes.sbody[s]
    c = math.cos(bang[b])
    sn = math.sin(bang[b])
    for k in range(svs[s], svs[s] + shapes.svn[s]):
        wv[k, 0] = bpos[b, 0] + c * lv[k, 0] - sn * lv[k, 1]
        wv[k, 1] = bpos[b, 1] + sn * lv[k, 0] + c * lv[k, 1]


@njit(cache=True, error_model="numpy")
def world_vertices(bpos, bang, shapes):
    """World coordinates ``shapes.wv`` of every local vertex (polygon cores, disc centres) of
    the bodies at ``bpos`` [m], ``bang`` [rad]."""
    for s in range(shapes.sbody.size):
        _shape_vertices(s, bpos, bang, shapes)


@njit(cache=True, error_model="numpy")
def incidence(owner, nb):
    """Entries of each body (compressed rows): ``idx[ptr[b]:ptr[b + 1]]`` are the indices e of
    the entries with ``owner[e] == b``, in increasing order."""
    ptr = np.zeros(nb + 1, np.int64)
    for e in range(owner.size):
        ptr[owner[e] + 1] += 1
    for b in range(nb):
        ptr[b + 1] += ptr[b]
    fill = ptr[:-1].copy()
    idx = np.empty(owner.size, np.int64)
    for e in range(owner.size):
        idx[fill[owner[e]]] = e
        fill[owner[e]] += 1
    return ptr, idx


@njit(cache=True, error_model="numpy")
def shape_boxes(shapes, margin):
    """Bounding boxes of the rounded shapes inflated by ``margin`` [m], for sort and sweep
    (the blocks' broad phase, :func:`broad_phase`, and the zone-block interface's,
    :mod:`murus.continuum.interface`).

    Parameters
    ----------
    shapes : Shapes
        The shapes (world vertices ``wv`` current).
    margin : float
        Inflation [m].

    Returns
    -------
    tuple
        ``(box, order, wmax)``: boxes ``(ns, 4)`` (x0, y0, x1, y1) [m], the shapes in the order
        of their x0, the largest box width [m].
    """
    wv = shapes.wv
    svs = shapes.svs
    svn = shapes.svn
    srad = shapes.srad
    ns = svs.size
    box = np.empty((ns, 4))
    wmax = 0.0
    for s in range(ns):
        x0 = np.inf
        y0 = np.inf
        x1 = -np.inf
        y1 = -np.inf
        for k in range(svs[s], svs[s] + svn[s]):
            x0 = min(x0, wv[k, 0])
            x1 = max(x1, wv[k, 0])
            y0 = min(y0, wv[k, 1])
            y1 = max(y1, wv[k, 1])
        e = srad[s] + margin
        box[s, 0] = x0 - e
        box[s, 1] = y0 - e
        box[s, 2] = x1 + e
        box[s, 3] = y1 + e
        wmax = max(wmax, box[s, 2] - box[s, 0])
    order = np.argsort(box[:, 0], kind="mergesort")
    return box, order, wmax


@njit(cache=True, error_model="numpy")
def broad_phase(shapes, bkin, margin):
    """Candidate pairs (a < b) of ``shapes`` (:class:`Shapes`) by sort and sweep on the
    bounding boxes inflated by ``margin`` [m], sorted by the key a * ns + b. Pairs of one body
    and pairs of two non-dynamic bodies (``bkin``) are left out."""
    sbody = shapes.sbody
    ns = sbody.size
    box, order, _ = shape_boxes(shapes, margin)
    cap = 4 * ns + 16
    keys = np.empty(cap, np.int64)
    n = 0
    for ii in range(ns):
        i = order[ii]
        for jj in range(ii + 1, ns):
            j = order[jj]
            if box[j, 0] > box[i, 2]:
                break
            if box[j, 1] > box[i, 3] or box[j, 3] < box[i, 1]:
                continue
            bi = sbody[i]
            bj = sbody[j]
            if bi == bj or (bkin[bi] != 0 and bkin[bj] != 0):
                continue
            if n == cap:
                cap *= 2
                nk = np.empty(cap, np.int64)
                nk[:n] = keys[:n]
                keys = nk
            keys[n] = min(i, j) * ns + max(i, j)
            n += 1
    keys = np.sort(keys[:n])
    pairs = np.empty((n, 2), np.int64)
    for k in range(n):
        pairs[k, 0] = keys[k] // ns
        pairs[k, 1] = keys[k] % ns
    return pairs


@njit(cache=True, error_model="numpy")
def transfer(old, new_pairs, sgroup, jtab, bond_new):
    """The :class:`Contacts` of the pair list ``new_pairs``, carrying the sub-contact state of
    the pairs present in both it and ``old`` (merge on sorted keys); the joint of a pair from
    the groups ``sgroup`` of its shapes and the table ``jtab``; new pairs start bonded when
    ``bond_new`` is 1."""
    n = new_pairs.shape[0]
    pj = np.empty(n, np.int64)
    for k in range(n):
        pj[k] = jtab[sgroup[new_pairs[k, 0]], sgroup[new_pairs[k, 1]]]
    return merge_contacts(old, new_pairs, sgroup.size, pj, bond_new)


@njit(cache=True, error_model="numpy")
def merge_contacts(old, new_pairs, ns, pj, bond_new):
    """The :class:`Contacts` of the pair list ``new_pairs`` (rows (a, b) sorted by the key
    ``a * ns + b``) with joint rows ``pj``, carrying the slots, broken flags and bond of the
    pairs present in ``old`` too (merge on sorted keys); new pairs start bonded when
    ``bond_new`` is 1. The blocks' :func:`transfer` and the zone-block interface's
    (:func:`murus.continuum.interface.transfer`) share it."""
    old_pairs = old.pairs
    old_sid = old.sid
    old_sf = old.sf
    old_sbr = old.sbr
    old_pbond = old.pbond
    n = new_pairs.shape[0]
    nold = old_pairs.shape[0]
    sid = np.full((n, 2), -1, np.int64)
    sf = np.zeros((n, 2, NSF))
    sbr = np.zeros((n, 2), np.int8)
    pbond = np.zeros(n, np.int8)
    i = 0
    for k in range(n):
        key = new_pairs[k, 0] * ns + new_pairs[k, 1]
        while i < nold and old_pairs[i, 0] * ns + old_pairs[i, 1] < key:
            i += 1
        if i < nold and old_pairs[i, 0] * ns + old_pairs[i, 1] == key:
            pbond[k] = old_pbond[i]
            for o in range(2):
                sid[k, o] = old_sid[i, o]
                sbr[k, o] = old_sbr[i, o]
                for f in range(NSF):
                    sf[k, o, f] = old_sf[i, o, f]
        else:
            pbond[k] = bond_new
    return Contacts(new_pairs, pj, pbond, sid, sf, sbr)


@njit(cache=True, error_model="numpy")
def transfer_arrays(old, new_pairs, sgroup, jtab, bond_new):
    """:func:`transfer` for a caller in Python: the arrays of the new :class:`Contacts` as a
    plain tuple (numba boxes a named tuple by calling its Python class, which crashes the
    process when a Ctrl-C is pending at that moment)."""
    c = transfer(old, new_pairs, sgroup, jtab, bond_new)
    return (c.pairs, c.pj, c.pbond, c.sid, c.sf, c.sbr)


# ---- narrow phase ----------------------------------------------------------------------------


@njit(cache=True, error_model="numpy")
def _sat(wv, a0, na, b0, nb):
    """Largest separation of core b from the edges of core a, and that edge."""
    best = -np.inf
    be = 0
    for i in range(na):
        ax = wv[a0 + i, 0]
        ay = wv[a0 + i, 1]
        j1 = a0 + (i + 1) % na
        ex = wv[j1, 0] - ax
        ey = wv[j1, 1] - ay
        L = math.sqrt(ex * ex + ey * ey)
        nx = ey / L
        ny = -ex / L
        m = np.inf
        for j in range(nb):
            d = nx * (wv[b0 + j, 0] - ax) + ny * (wv[b0 + j, 1] - ay)
            if d < m:
                m = d
        if m > best:
            best = m
            be = i
    return best, be


@njit(cache=True, error_model="numpy")
def _seg_dist(p1x, p1y, q1x, q1y, p2x, p2y, q2x, q2y):
    """Closest points of segments p1q1 and p2q2 (Ericson 2005, as in Box2D): fractions and
    points."""
    d1x = q1x - p1x
    d1y = q1y - p1y
    d2x = q2x - p2x
    d2y = q2y - p2y
    rx = p1x - p2x
    ry = p1y - p2y
    dd1 = d1x * d1x + d1y * d1y
    dd2 = d2x * d2x + d2y * d2y
    rd1 = rx * d1x + ry * d1y
    rd2 = rx * d2x + ry * d2y
    d12 = d1x * d2x + d1y * d2y
    den = dd1 * dd2 - d12 * d12
    f1 = 0.0
    if den != 0.0:
        f1 = _clamp01((d12 * rd2 - rd1 * dd2) / den)
    f2 = (d12 * f1 + rd2) / dd2
    if f2 < 0.0:
        f2 = 0.0
        f1 = _clamp01(-rd1 / dd1)
    elif f2 > 1.0:
        f2 = 1.0
        f1 = _clamp01((d12 - rd1) / dd1)
    return f1, f2, p1x + f1 * d1x, p1y + f1 * d1y, p2x + f2 * d2x, p2y + f2 * d2y


# The narrow phase returns its sub-contacts as scalars (a count, then for each of the two
# points its key and (px, py, nx, ny, gap, trib)): no array is allocated per pair and step.
_NONE = (0, -1, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)


@njit(cache=True, error_model="numpy")
def collide_pp(wv, a0, na, ra, b0, nb, rb, reach):
    """Sub-contacts of two rounded convex polygons (cores ``wv[a0:a0+na]``, ``wv[b0:b0+nb]``,
    counter-clockwise), n from a to b: ``(cnt, id0, px0, py0, nx0, ny0, gap0, trib0, id1, px1,
    py1, nx1, ny1, gap1, trib1)`` with ``cnt`` 0, 1 or 2 and ``id`` the key of each point."""
    rr = ra + rb
    sepA, eA = _sat(wv, a0, na, b0, nb)
    if sepA > rr + reach:
        return _NONE
    sepB, eB = _sat(wv, b0, nb, a0, na)
    if sepB > rr + reach:
        return _NONE
    sep = max(sepA, sepB)
    flip = sepB > sepA + 0.01 * rr
    if flip:
        R0 = b0
        nR = nb
        rR = rb
        I0 = a0
        nI = na
        rI = ra
        e = eB
        sg = -1.0
    else:
        R0 = a0
        nR = na
        rR = ra
        I0 = b0
        nI = nb
        rI = rb
        e = eA
        sg = 1.0
    ir1 = R0 + e
    ir2 = R0 + (e + 1) % nR
    r1x = wv[ir1, 0]
    r1y = wv[ir1, 1]
    tx = wv[ir2, 0] - r1x
    ty = wv[ir2, 1] - r1y
    L = math.sqrt(tx * tx + ty * ty)
    tx /= L
    ty /= L
    nx = ty
    ny = -tx
    # incident edge: the most anti-parallel edge of I
    best = np.inf
    ie = 0
    for j in range(nI):
        j0 = I0 + j
        j1 = I0 + (j + 1) % nI
        ex = wv[j1, 0] - wv[j0, 0]
        ey = wv[j1, 1] - wv[j0, 1]
        d = (nx * ey - ny * ex) / math.sqrt(ex * ex + ey * ey)
        if d < best:
            best = d
            ie = j
    ii1 = I0 + ie
    ii2 = I0 + (ie + 1) % nI
    i1x = wv[ii1, 0]
    i1y = wv[ii1, 1]
    i2x = wv[ii2, 0]
    i2y = wv[ii2, 1]
    ex = i2x - i1x
    ey = i2y - i1y
    LI = math.sqrt(ex * ex + ey * ey)
    cross = (tx * ey - ty * ex) / LI
    r2x = wv[ir2, 0]
    r2y = wv[ir2, 1]
    if sep > 1e-3 * rr and abs(cross) > 1e-6:
        f1, f2, c1x, c1y, c2x, c2y = _seg_dist(r1x, r1y, r2x, r2y, i1x, i1y, i2x, i2y)
        if (f1 == 0.0 or f1 == 1.0) and (f2 == 0.0 or f2 == 1.0):
            dx = c2x - c1x
            dy = c2y - c1y
            d = math.sqrt(dx * dx + dy * dy)
            if d - rr > reach:
                return _NONE
            mx = dx / d
            my = dy / d
            h = 0.5 * (d - rR + rI)
            return (1, ir1 if f1 == 0.0 else ir2, c2x - mx * h, c2y - my * h, sg * mx, sg * my,
                    d - rr, 0.5 * min(L, LI) + 0.5 * rr,
                    -1, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    # clip the incident edge to the span [0, L] of the reference edge
    s1 = tx * (i1x - r1x) + ty * (i1y - r1y)
    s2 = tx * (i2x - r1x) + ty * (i2y - r1y)
    ds = s2 - s1
    if abs(ds) < 1e-12 * L:
        return _NONE
    ua = (0.0 - s1) / ds
    ub = (L - s1) / ds
    u0 = max(0.0, min(ua, ub))
    u1 = min(1.0, max(ua, ub))
    if u1 < u0:
        return _NONE
    Lc = abs(ds) * (u1 - u0)
    trib = 0.5 * Lc + 0.5 * rr
    nend = 2
    if Lc <= 1e-9 * L:
        nend = 1
        trib = 0.5 * LI + 0.5 * rr
    # the two ends of the clipped segment (the second only when nend == 2)
    cnt = 0
    id0 = -1
    id1 = -1
    p0x = p0y = g0 = 0.0
    p1x = p1y = g1 = 0.0
    for q in range(nend):
        u = u0 if q == 0 else u1
        px = i1x + u * ex
        py = i1y + u * ey
        sp = nx * (px - r1x) + ny * (py - r1y)
        if sp - rr > reach:
            continue
        if u == 0.0:
            key = ii1
        elif u == 1.0:
            key = ii2
        else:
            s = s1 + u * ds
            key = ir1 if abs(s) < abs(s - L) else ir2
        h = 0.5 * (sp - rR + rI)
        if cnt == 0:
            id0 = key
            p0x = px - nx * h
            p0y = py - ny * h
            g0 = sp - rr
        else:
            id1 = key
            p1x = px - nx * h
            p1y = py - ny * h
            g1 = sp - rr
        cnt += 1
    return (cnt, id0, p0x, p0y, sg * nx, sg * ny, g0, trib,
            id1, p1x, p1y, sg * nx, sg * ny, g1, trib)


@njit(cache=True, error_model="numpy", inline="always")
def point_separation(wv, a0, na, px, py):
    """Largest signed distance [m] of the point (px, py) from the lines of the core edges of
    the polygon ``wv[a0:a0+na]`` (counter-clockwise; positive outside), and the edge (local
    index) that gives it: negative when the point is inside the core, where that edge is the
    one of least penetration. Shared by the disc contact (:func:`collide_pd`) and the
    gridpoint contact of the zone-block interface (:mod:`murus.continuum.interface`).

    Parameters
    ----------
    wv : ndarray (nv, 2)
        World vertices [m].
    a0, na : int
        First vertex and vertex count of the polygon.
    px, py : float
        The point [m].

    Returns
    -------
    tuple
        ``(distance, edge)``.
    """
    best = -np.inf
    be = 0
    for i in range(na):
        ax = wv[a0 + i, 0]
        ay = wv[a0 + i, 1]
        j1 = a0 + (i + 1) % na
        ex = wv[j1, 0] - ax
        ey = wv[j1, 1] - ay
        L = math.sqrt(ex * ex + ey * ey)
        d = (ey * (px - ax) - ex * (py - ay)) / L
        if d > best:
            best = d
            be = i
    return best, be


@njit(cache=True, error_model="numpy")
def collide_pd(wv, a0, na, ra, cx, cy, rd, reach):
    """Rounded polygon (core ``wv[a0:a0+na]``, rounding ra) against a disc (centre, radius):
    ``(cnt, px, py, nx, ny, gap, trib)``, one sub-contact at most, n from the polygon to the
    disc."""
    # largest separation of the centre from the core edges
    best, be = point_separation(wv, a0, na, cx, cy)
    rr = ra + rd
    if best > rr + reach:
        return 0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    if best <= 0.0:  # centre inside the core: the face of least penetration
        ax = wv[a0 + be, 0]
        ay = wv[a0 + be, 1]
        j1 = a0 + (be + 1) % na
        ex = wv[j1, 0] - ax
        ey = wv[j1, 1] - ay
        L = math.sqrt(ex * ex + ey * ey)
        nx = ey / L
        ny = -ex / L
        d = best
    else:  # closest point of the core boundary
        dmin = np.inf
        qx = 0.0
        qy = 0.0
        for i in range(na):
            ax = wv[a0 + i, 0]
            ay = wv[a0 + i, 1]
            j1 = a0 + (i + 1) % na
            ex = wv[j1, 0] - ax
            ey = wv[j1, 1] - ay
            u = _clamp01(((cx - ax) * ex + (cy - ay) * ey) / (ex * ex + ey * ey))
            px = ax + u * ex
            py = ay + u * ey
            dd = (cx - px) ** 2 + (cy - py) ** 2
            if dd < dmin:
                dmin = dd
                qx = px
                qy = py
        d = math.sqrt(dmin)
        if d - rr > reach:
            return 0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
        nx = (cx - qx) / d
        ny = (cy - qy) / d
    h = 0.5 * (d - ra + rd)  # midway between the rounded polygon and the disc surfaces
    return 1, cx - nx * h, cy - ny * h, nx, ny, d - rr, 2.0 * rd


@njit(cache=True, error_model="numpy", inline="always")
def collide_dd(a, b, wv, svs, srad, reach):
    """Sub-contact of discs a < b, as returned by :func:`collide_pp`."""
    ia = svs[a]
    ib = svs[b]
    dx = wv[ib, 0] - wv[ia, 0]
    dy = wv[ib, 1] - wv[ia, 1]
    d = math.sqrt(dx * dx + dy * dy)
    ra = srad[a]
    rb = srad[b]
    if d - ra - rb > reach or d == 0.0:
        return _NONE
    nx = dx / d
    ny = dy / d
    h = 0.5 * (d - rb + ra)
    return (1, ia, wv[ia, 0] + nx * h, wv[ia, 1] + ny * h, nx, ny, d - ra - rb,
            2.0 * ra * rb / (ra + rb), -1, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)


@njit(cache=True, error_model="numpy", inline="always")
def collide(a, b, wv, svs, svn, skind, srad, reach):
    """Sub-contacts of shapes a < b, as returned by :func:`collide_pp` (the key of a point is a
    global vertex index: the disc centre for a disc)."""
    ka = skind[a]
    kb = skind[b]
    if ka == 0 and kb == 0:
        return collide_pp(wv, svs[a], svn[a], srad[a], svs[b], svn[b], srad[b], reach)
    if ka == 1 and kb == 1:
        return collide_dd(a, b, wv, svs, srad, reach)
    if ka == 0:
        ic = svs[b]
        c, px, py, nx, ny, g, tr = collide_pd(wv, svs[a], svn[a], srad[a], wv[ic, 0],
                                              wv[ic, 1], srad[b], reach)
    else:
        ic = svs[a]
        c, px, py, nx, ny, g, tr = collide_pd(wv, svs[b], svn[b], srad[b], wv[ic, 0],
                                              wv[ic, 1], srad[a], reach)
        nx = -nx
        ny = -ny
    if c == 0:
        return _NONE
    return (1, ic, px, py, nx, ny, g, tr, -1, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)


@njit(cache=True, error_model="numpy", inline="always")
def _joint_law(o, k, sf, sbr, pb, jprops, jp, rolling, reff, pt, pm, cst):
    """Joint law of one new sub-contact ``pt`` (:class:`SubContact`) matched to the old slot
    ``o`` of pair k (slot records ``sf``, broken flags ``sbr``: :class:`Contacts`; -1: new),
    with joint row ``jp`` of
    ``jprops``, rolling resistance when ``rolling`` (effective radius ``reff`` [m]), the
    motion ``pm`` (:class:`PairMotion`) of the pair's bodies and ``cst = (thick, reach, dt)``.
    Returns ``(keep, broken, pb, fn, fs, mr, kna, ksa, kra, d_slip, d_roll, d_break)`` with
    ``pb`` the pair's bond flag after the step (reads the old slot, writes nothing)."""
    thick, reach, dt = cst
    px = pt.px
    py = pt.py
    nx = pt.nx
    ny = pt.ny
    gap = pt.gap
    trib = pt.trib
    d_slip = 0.0
    d_roll = 0.0
    d_break = 0.0
    kn = jprops[jp, J_KN]
    ks = jprops[jp, J_KS]
    tanphi = jprops[jp, J_TANPHI]
    muroll = jprops[jp, J_MUROLL]
    area = trib * thick
    if o >= 0:
        fs = sf[k, o, F_FS]
        mr = sf[k, o, F_MR]
        broken = sbr[k, o]
        ksa_old = sf[k, o, F_KSA]
        kra_old = sf[k, o, F_KRA]
    else:
        fs = 0.0
        mr = 0.0
        broken = 1 - pb
        ksa_old = 0.0
        kra_old = 0.0
    if broken:
        cA = jprops[jp, J_CRES] * area
        tA = jprops[jp, J_TRES] * area
    else:
        cA = jprops[jp, J_C] * area
        tA = jprops[jp, J_T] * area
    kna = kn * area
    ksa = ks * area
    fn = -kna * gap
    if fn < -tA:
        if not broken:  # tensile failure: residual strength from now on
            broken = 1
            pb = 0
            d_break += 0.5 * tA * tA / kna
            tA = jprops[jp, J_TRES] * area
            cA = jprops[jp, J_CRES] * area
        fn = -tA
    kra = 0.0
    if gap > reach or (gap > 0.0 and tA == 0.0):
        # open: no force; the shear spring releases its energy
        if ksa_old > 0.0:
            d_break += 0.5 * fs * fs / ksa_old
        if o >= 0 and kra_old > 0.0:
            d_break += 0.5 * mr * mr / kra_old
        if gap > reach:
            return False, broken, pb, 0.0, 0.0, 0.0, kna, ksa, 0.0, d_slip, d_roll, d_break
        fn = 0.0
        fs = 0.0
        mr = 0.0
    else:
        # relative velocity of b with respect to a at the contact point
        wa = pm.wa
        wb = pm.wb
        rvx = (pm.vbx - wb * (py - pm.yb)) - (pm.vax - wa * (py - pm.ya))
        rvy = (pm.vby + wb * (px - pm.xb)) - (pm.vay + wa * (px - pm.xa))
        dus = (-ny * rvx + nx * rvy) * dt
        fs_t = fs - ksa * dus
        fmax = cA + fn * tanphi
        if fmax < 0.0:
            fmax = 0.0
        if abs(fs_t) > fmax:
            if not broken and (cA > 0.0 or tA > 0.0):  # shear failure
                broken = 1
                pb = 0
                cA = jprops[jp, J_CRES] * area
                tA = jprops[jp, J_TRES] * area
                if fn < -tA:
                    fn = -tA
                fmax = cA + fn * tanphi
                if fmax < 0.0:
                    fmax = 0.0
            if abs(fs_t) > fmax:
                # dissipation consistent with the trapezoid work of the leapfrog:
                # (|Fs_trial| - Fmax) (Fs_old sign + Fmax) / (2 ks A)
                sg_t = 1.0 if fs_t > 0.0 else -1.0
                d_slip += (abs(fs_t) - fmax) * (sg_t * fs + fmax) / (2.0 * ksa)
                fs = sg_t * fmax
            else:
                fs = fs_t
        else:
            fs = fs_t
        if rolling:
            kra = ksa * reff * reff
            mr_t = mr - kra * (wb - wa) * dt
            mlim = muroll * reff * max(fn, 0.0)
            if abs(mr_t) > mlim:
                sg_t = 1.0 if mr_t > 0.0 else -1.0
                d_roll += (abs(mr_t) - mlim) * (sg_t * mr + mlim) / (2.0 * kra)
                mr = sg_t * mlim
            else:
                mr = mr_t
    return True, broken, pb, fn, fs, mr, kna, ksa, kra, d_slip, d_roll, d_break


@njit(cache=True, error_model="numpy", inline="always")
def _store(k, slot, sid, sf, sbr, key, broken, fsm, stiff, pt, pm):
    """Write a sub-contact (key ``key``, broken flag, forces ``fsm = (fn, fs, mr)``,
    stiffnesses ``stiff = (kna, ksa, kra)``, point ``pt``: :class:`SubContact`) to slot
    ``slot`` of pair k (``sid``, ``sf``, ``sbr``: :class:`Contacts`); returns its force on body
    b and its moments about the centroids of b and a (``pm``: :class:`PairMotion`)
    ``(fx, fy, mb, ma)``."""
    fn, fs, mr = fsm
    kna, ksa, kra = stiff
    px = pt.px
    py = pt.py
    nx = pt.nx
    ny = pt.ny
    sid[k, slot] = key
    sbr[k, slot] = broken
    sf[k, slot, F_FN] = fn
    sf[k, slot, F_FS] = fs
    sf[k, slot, F_MR] = mr
    sf[k, slot, F_PX] = px
    sf[k, slot, F_PY] = py
    sf[k, slot, F_NX] = nx
    sf[k, slot, F_NY] = ny
    sf[k, slot, F_KNA] = kna
    sf[k, slot, F_KSA] = ksa
    sf[k, slot, F_KRA] = kra
    sf[k, slot, F_GAP] = pt.gap
    fx = fn * nx - fs * ny
    fy = fn * ny + fs * nx
    return (fx, fy, (px - pm.xb) * fy - (py - pm.yb) * fx + mr,
            (px - pm.xa) * fy - (py - pm.ya) * fx + mr)


@njit(cache=True, error_model="numpy", inline="always")
def _nearest_slot(k, sf, s0, s1, used0, used1, px, py, tol):
    """The unused old slot of pair k nearest to the new point (px, py), within ``tol``:
    ``(slot or -1, used0, used1)``."""
    best = -1
    bestd = tol
    if s0 >= 0 and not used0:
        dd = math.sqrt((sf[k, 0, F_PX] - px) ** 2 + (sf[k, 0, F_PY] - py) ** 2)
        if dd < bestd:
            bestd = dd
            best = 0
    if s1 >= 0 and not used1:
        dd = math.sqrt((sf[k, 1, F_PX] - px) ** 2 + (sf[k, 1, F_PY] - py) ** 2)
        if dd < bestd:
            best = 1
    if best == 0:
        used0 = True
    elif best == 1:
        used1 = True
    return best, used0, used1


@njit(cache=True, error_model="numpy", inline="always")
def _released(k, o, sf):
    """Shear and rolling spring energy [J] of the old slot o of pair k."""
    e = 0.0
    if sf[k, o, F_KSA] > 0.0:
        e += 0.5 * sf[k, o, F_FS] ** 2 / sf[k, o, F_KSA]
    if sf[k, o, F_KRA] > 0.0:
        e += 0.5 * sf[k, o, F_MR] ** 2 / sf[k, o, F_KRA]
    return e


@njit(cache=True, error_model="numpy", inline="always")
def _dashpot(c, pt, pm):
    """Force [N] (compression positive) of the normal dashpot of coefficient ``c`` [N s/m] of
    the sub-contact ``pt`` (:class:`SubContact`) of the pair of motion ``pm``
    (:class:`PairMotion`): ``-c v_n`` while the surfaces overlap (gap < 0) and close
    (v_n < 0, v_n the relative normal velocity of b with respect to a at the contact point),
    0 otherwise: it damps the approach of an impact, not the separation, and never pulls."""
    if pt.gap >= 0.0:
        return 0.0
    px = pt.px
    py = pt.py
    rvx = (pm.vbx - pm.wb * (py - pm.yb)) - (pm.vax - pm.wa * (py - pm.ya))
    rvy = (pm.vby + pm.wb * (px - pm.xb)) - (pm.vay + pm.wa * (px - pm.xa))
    vn = pt.nx * rvx + pt.ny * rvy
    if vn >= 0.0:
        return 0.0
    return -c * vn


@njit(cache=True, error_model="numpy", inline="always")
def _reduced_mass(ba, bb, bmass, bkin):
    """Reduced mass [kg] of bodies ba and bb (a kinematic body counts as infinitely heavy)."""
    if bkin[ba] != 0:
        return bmass[bb]
    if bkin[bb] != 0:
        return bmass[ba]
    return bmass[ba] * bmass[bb] / (bmass[ba] + bmass[bb])


@njit(cache=True, error_model="numpy", inline="always")
def process_pair(k, pairs, pj, pbond, sid, sf, sbr, pw, wv, svs, svn, skind, srad, sbody,
                 bpos, bvel, bomg, bmass, bkin, jprops, dt, thick, reach, discs):
    """Narrow phase and joint law of pair k (the arrays of :class:`Contacts`, then of
    :class:`Shapes` and :class:`Bodies`, unpacked by :func:`_contacts_parallel`; joint rows
    ``jprops``; time step ``dt`` [s], thickness ``thick`` [m], largest kept gap ``reach``
    [m]): updates its two slots in place and writes the
    energy dissipated in the step (slip, rolling, breaking/opening) and the resultant of its
    sub-contacts on body b with its moments about both centroids to ``pw[k]`` (``W_*``).
    With contact damping (``J_CDAMP`` zeta > 0), each overlapping and closing sub-contact also
    carries the normal dashpot force ``-c v_n`` (:func:`_dashpot`), ``c = 2 zeta sqrt(kn A
    m_eff)`` with ``m_eff`` the reduced mass of the two bodies (:func:`_reduced_mass`): added
    to the resultant and written apart to ``pw[k, W_DFX:W_DMA + 1]`` for its work
    (:func:`dashpot_work`); the slot keeps the spring force (``F_FN``), which alone sets the
    friction limit and the elastic energy. Without contact damping the branch is skipped and
    the operations are those of the undamped law.
    Returns the number of sub-contacts kept. Allocates nothing (scalars only): it runs once
    per candidate pair and step, in a parallel loop. ``discs`` (a constant where it is inlined):
    the pair is known to be two discs (one sub-contact at most, no branch on shape kinds).

    Bare arrays, not the named structures: the parallel loop that inlines this function keeps
    numba's ``noalias`` code generation only when no array of its body is read out of a tuple
    (numba gives it up as soon as the loop body aliases an argument), and that code is twice as
    fast (benchmarks/ab_dem.py)."""
    a = pairs[k, 0]
    b = pairs[k, 1]
    s0 = sid[k, 0]
    s1 = sid[k, 1]
    if discs:
        (cnt, id0, px0, py0, nx0, ny0, g0, l0,
         id1, px1, py1, nx1, ny1, g1, l1) = collide_dd(a, b, wv, svs, srad, reach)
    else:
        (cnt, id0, px0, py0, nx0, ny0, g0, l0,
         id1, px1, py1, nx1, ny1, g1, l1) = collide(a, b, wv, svs, svn, skind, srad, reach)
    if cnt == 0 and s0 < 0 and s1 < 0:  # apart, and no sub-contact to release
        pw[k, W_SLIP] = 0.0
        pw[k, W_ROLL] = 0.0
        pw[k, W_BREAK] = 0.0
        return 0
    # match the new points to the old slots: same key, else the nearest old point within the
    # rounding (a vertex passing the end of an edge changes key at an unchanged position)
    m0 = -1
    m1 = -1
    used0 = False
    used1 = False
    if cnt >= 1:
        if s0 == id0:
            m0 = 0
            used0 = True
        elif s1 == id0:
            m0 = 1
            used1 = True
    if not discs and cnt >= 2:
        if s0 == id1 and not used0:
            m1 = 0
            used0 = True
        elif s1 == id1 and not used1:
            m1 = 1
            used1 = True
    tol = srad[a] + srad[b]
    if cnt >= 1 and m0 < 0:
        m0, used0, used1 = _nearest_slot(k, sf, s0, s1, used0, used1, px0, py0, tol)
    if not discs and cnt >= 2 and m1 < 0:
        m1, used0, used1 = _nearest_slot(k, sf, s0, s1, used0, used1, px1, py1, tol)
    # shear and rolling energy of the old slots that disappear (the normal spring energy of a
    # separating contact is given back as work of the normal force over the step)
    d_break = 0.0
    if s0 >= 0 and not used0:
        d_break += _released(k, 0, sf)
    if s1 >= 0 and not used1:
        d_break += _released(k, 1, sf)
    d_slip = 0.0
    d_roll = 0.0
    keep0 = False
    keep1 = False
    if cnt >= 1:
        ba = sbody[a]
        bb = sbody[b]
        jp = pj[k]
        muroll = jprops[jp, J_MUROLL]
        rolling = muroll > 0.0 and (discs or skind[a] == 1 or skind[b] == 1)
        reff = 0.0
        if rolling:
            if discs or (skind[a] == 1 and skind[b] == 1):
                reff = srad[a] * srad[b] / (srad[a] + srad[b])
            elif skind[a] == 1:
                reff = srad[a]
            else:
                reff = srad[b]
        pm = PairMotion(bvel[ba, 0], bvel[ba, 1], bomg[ba], bpos[ba, 0], bpos[ba, 1],
                        bvel[bb, 0], bvel[bb, 1], bomg[bb], bpos[bb, 0], bpos[bb, 1])
        cst = (thick, reach, dt)
        pb = pbond[k]
        pt0 = SubContact(px0, py0, nx0, ny0, g0, l0)
        pt1 = SubContact(px1, py1, nx1, ny1, g1, l1)
        # both laws read the old slots before either is written. One inlined copy of the law
        # for both sub-contacts, in a loop of one or two passes: the two copies of the law
        # inlined one after the other cost numba 32 s more to compile the contact loop (of 93
        # s), for no speed (benchmarks/ab_dem.py, BENCHMARKS.md, session 22)
        nlaw = 1 if discs or cnt < 2 else 2
        br0 = 0
        br1 = 0
        fn0 = 0.0
        fs0 = 0.0
        mr0 = 0.0
        kna0 = 0.0
        ksa0 = 0.0
        kra0 = 0.0
        fn1 = 0.0
        fs1 = 0.0
        mr1 = 0.0
        kna1 = 0.0
        ksa1 = 0.0
        kra1 = 0.0
        for o in range(nlaw):
            pt = pt0 if o == 0 else pt1
            mo = m0 if o == 0 else m1
            (keep, br, pb, fn, fs, mr, kna, ksa, kra, ds, dr, db) = _joint_law(
                mo, k, sf, sbr, pb, jprops, jp, rolling, reff, pt, pm, cst)
            d_slip += ds
            d_roll += dr
            d_break += db
            if o == 0:
                keep0 = keep
                br0 = br
                fn0 = fn
                fs0 = fs
                mr0 = mr
                kna0 = kna
                ksa0 = ksa
                kra0 = kra
            else:
                keep1 = keep
                br1 = br
                fn1 = fn
                fs1 = fs
                mr1 = mr
                kna1 = kna
                ksa1 = ksa
                kra1 = kra
        pbond[k] = pb
        slot = 0
        rfx = 0.0
        rfy = 0.0
        rmb = 0.0
        rma = 0.0
        if keep0:
            fx, fy, mb, ma = _store(k, 0, sid, sf, sbr, id0, br0, (fn0, fs0, mr0),
                                    (kna0, ksa0, kra0), pt0, pm)
            rfx += fx
            rfy += fy
            rmb += mb
            rma += ma
            slot = 1
        if not discs and keep1:
            fx, fy, mb, ma = _store(k, slot, sid, sf, sbr, id1, br1, (fn1, fs1, mr1),
                                    (kna1, ksa1, kra1), pt1, pm)
            rfx += fx
            rfy += fy
            rmb += mb
            rma += ma
            slot += 1
        cz = jprops[jp, J_CDAMP]
        if cz > 0.0:
            # contact damping (joint column J_CDAMP): the dashpots of the kept sub-contacts
            meff = _reduced_mass(ba, bb, bmass, bkin)
            dfx = 0.0
            dfy = 0.0
            dmb = 0.0
            dma = 0.0
            if keep0:
                fd = _dashpot(2.0 * cz * math.sqrt(kna0 * meff), pt0, pm)
                if fd > 0.0:
                    fx = fd * pt0.nx
                    fy = fd * pt0.ny
                    dfx += fx
                    dfy += fy
                    dmb += (pt0.px - pm.xb) * fy - (pt0.py - pm.yb) * fx
                    dma += (pt0.px - pm.xa) * fy - (pt0.py - pm.ya) * fx
            if not discs and keep1:
                fd = _dashpot(2.0 * cz * math.sqrt(kna1 * meff), pt1, pm)
                if fd > 0.0:
                    fx = fd * pt1.nx
                    fy = fd * pt1.ny
                    dfx += fx
                    dfy += fy
                    dmb += (pt1.px - pm.xb) * fy - (pt1.py - pm.yb) * fx
                    dma += (pt1.px - pm.xa) * fy - (pt1.py - pm.ya) * fx
            pw[k, W_DFX] = dfx
            pw[k, W_DFY] = dfy
            pw[k, W_DMB] = dmb
            pw[k, W_DMA] = dma
            rfx += dfx
            rfy += dfy
            rmb += dmb
            rma += dma
        nkeep = slot
        pw[k, W_FX] = rfx
        pw[k, W_FY] = rfy
        pw[k, W_MB] = rmb
        pw[k, W_MA] = rma
    else:
        nkeep = 0
    for o in range(nkeep, 2):
        sid[k, o] = -1
        sbr[k, o] = 0
    pw[k, W_SLIP] = d_slip
    pw[k, W_ROLL] = d_roll
    pw[k, W_BREAK] = d_break
    return nkeep


@njit(cache=True, error_model="numpy", inline="always")
def _process(k, pairs, pj, pbond, sid, sf, sbr, pw, wv, svs, svn, skind, srad, sbody, bpos, bvel,
             bomg, bmass, bkin, jprops, dt, thick, reach):
    """:func:`process_pair`, in its copy specialised to two discs when both shapes of pair k
    are discs."""
    if skind[pairs[k, 0]] == 1 and skind[pairs[k, 1]] == 1:
        return process_pair(k, pairs, pj, pbond, sid, sf, sbr, pw, wv, svs, svn, skind, srad,
                            sbody, bpos, bvel, bomg, bmass, bkin, jprops, dt, thick, reach, True)
    return process_pair(k, pairs, pj, pbond, sid, sf, sbr, pw, wv, svs, svn, skind, srad, sbody,
                        bpos, bvel, bomg, bmass, bkin, jprops, dt, thick, reach, False)


@njit(cache=True, error_model="numpy", parallel=True)
def _contacts_parallel(c, pw, shapes, bodies, jprops, dt, thick, reach, nact):
    """The contact loop (:func:`process_pair` of every pair of ``c``), parallel over the
    pairs; ``nact[k]`` the number of sub-contacts kept by pair k. The structures are unpacked
    here, outside the loop (:func:`process_pair`)."""
    pairs, pj, pbond, sid, sf, sbr = c
    wv = shapes.wv
    svs = shapes.svs
    svn = shapes.svn
    skind = shapes.skind
    srad = shapes.srad
    sbody = shapes.sbody
    bpos = bodies.bpos
    bvel = bodies.bvel
    bomg = bodies.bomg
    bmass = bodies.bmass
    bkin = bodies.bkin
    for k in prange(pairs.shape[0]):
        nact[k] = _process(k, pairs, pj, pbond, sid, sf, sbr, pw, wv, svs, svn, skind, srad,
                           sbody, bpos, bvel, bomg, bmass, bkin, jprops, dt, thick, reach)


@njit(cache=True, error_model="numpy")
def _contacts_serial(c, pw, shapes, bodies, jprops, dt, thick, reach, nact):
    """:func:`_contacts_parallel` on one thread: the reference of the parallel loop in the
    tests and benchmarks (the engine itself calls only the parallel loop, whose numbers do not
    depend on the thread count)."""
    pairs, pj, pbond, sid, sf, sbr = c
    for k in range(pairs.shape[0]):
        nact[k] = _process(k, pairs, pj, pbond, sid, sf, sbr, pw, shapes.wv, shapes.svs,
                           shapes.svn, shapes.skind, shapes.srad, shapes.sbody, bodies.bpos,
                           bodies.bvel, bodies.bomg, bodies.bmass, bodies.bkin, jprops, dt,
                           thick, reach)


@njit(cache=True, error_model="numpy")
def damped(jprops):
    """True when a joint row of ``jprops`` has contact damping (``J_CDAMP`` > 0)."""
    for j in range(jprops.shape[0]):
        if jprops[j, J_CDAMP] > 0.0:
            return True
    return False


@njit(cache=True, error_model="numpy")
def dashpot_work(c, nact, pw, jprops, sbody, bodies, dt):
    """Energy [J] dissipated in the step by the contact dashpots (:func:`process_pair`): minus
    the work of their forces ``pw[k, W_DFX:W_DMA + 1]`` with the mid-step velocities of the
    bodies (``bodies.bsnap[:, 3:6]``, written by the body update), the form in which the
    central-difference scheme changes the kinetic energy, so that the balance closes exactly.
    Called after the body update of a step, only when the model has contact damping
    (:func:`damped`)."""
    pairs = c.pairs
    pj = c.pj
    sn = bodies.bsnap
    d = 0.0
    for k in range(pairs.shape[0]):
        if nact[k] == 0 or jprops[pj[k], J_CDAMP] <= 0.0:
            continue
        ba = sbody[pairs[k, 0]]
        bb = sbody[pairs[k, 1]]
        fx = pw[k, W_DFX]
        fy = pw[k, W_DFY]
        d -= dt * (fx * (sn[bb, 3] - sn[ba, 3]) + fy * (sn[bb, 4] - sn[ba, 4])
                   + pw[k, W_DMB] * sn[bb, 5] - pw[k, W_DMA] * sn[ba, 5])
    return d


#: number of fixed blocks of the parallel body loops: their partial sums are combined in a fixed
#: order, so that results do not depend on the number of threads
NBLK = 64


@njit(cache=True, error_model="numpy")
def _sum_pairs(pairs, sbody, nact, pw, E, fb):
    """Scatter the pair resultants ``pw[k, W_FX:W_MA + 1]`` (written by the contact loop) to
    the bodies, and add the step's dissipation of every pair to ``E`` (serial, in pair order).
    Returns the number of active sub-contacts."""
    fb[:, :] = 0.0
    d0 = 0.0
    d1 = 0.0
    d2 = 0.0
    nactive = 0
    for k in range(pairs.shape[0]):
        if nact[k] == 0 and pw[k, W_BREAK] == 0.0:
            continue
        nactive += nact[k]
        d0 += pw[k, W_SLIP]
        d1 += pw[k, W_ROLL]
        d2 += pw[k, W_BREAK]
        if nact[k] == 0:
            continue
        ba = sbody[pairs[k, 0]]
        bb = sbody[pairs[k, 1]]
        fx = pw[k, W_FX]
        fy = pw[k, W_FY]
        fb[bb, 0] += fx
        fb[bb, 1] += fy
        fb[bb, 2] += pw[k, W_MB]
        fb[ba, 0] -= fx
        fb[ba, 1] -= fy
        fb[ba, 2] -= pw[k, W_MA]
    E[E_DSLIP] += d0
    E[E_DROLL] += d1
    E[E_DBREAK] += d2
    return nactive


@njit(cache=True, error_model="numpy", inline="always")
def _advance(b, dt, sx, sy, sw, vx, vy, w, bodies):
    """Body b of ``bodies`` (:class:`Bodies`): snapshot of the state at the time of the forces
    (position, angle and the velocities ``sx, sy, sw`` at that time), then the new half-step
    velocity ``vx, vy, w`` and the move over ``dt``."""
    # written inside the body loop: by position (murus.dem._kdata)
    bpos = bodies[IB_BPOS]
    bang = bodies[IB_BANG]
    bvel = bodies[IB_BVEL]
    bsnap = bodies[IB_BSNAP]
    bsnap[b, 0] = bpos[b, 0]
    bsnap[b, 1] = bpos[b, 1]
    bsnap[b, 2] = bang[b]
    bsnap[b, 3] = sx
    bsnap[b, 4] = sy
    bsnap[b, 5] = sw
    bvel[b, 0] = vx
    bvel[b, 1] = vy
    bodies[IB_BOMG][b] = w
    bpos[b, 0] += vx * dt
    bpos[b, 1] += vy * dt
    bang[b] += w * dt


@njit(cache=True, error_model="numpy", inline="always")
def _update_block(blk, P, fr, fb, bodies, shapes, part, bsp, bsh):
    """Central-difference update (module doc) of the :class:`Bodies` of block ``blk`` (of
    ``NBLK``) under the contact resultants ``fb``, then the world coordinates of the
    :class:`Shapes` of each body (``bsp``, ``bsh``: :func:`incidence` of ``shapes.sbody``) for
    the next step; ``fr`` the step's base velocities and gravity (:class:`Frame`);
    ``part[blk, Q_*]`` the block's partial sums (max unbalanced force, damping work, base
    work, external work, rebuild needed, work of the tilt)."""
    bpos = bodies.bpos
    bang = bodies.bang
    bvel = bodies.bvel
    bomg = bodies.bomg
    bmass = bodies.bmass
    binert = bodies.binert
    bkin = bodies.bkin
    brad = bodies.brad
    blast = bodies.blast
    bpresc = bodies.bpresc
    bext = bodies.bext
    nb = bmass.size
    dt = P[P_DT]
    alocal = P[P_ALOCAL]
    amass = P[P_AMASS]
    drel = P[P_DREL]
    margin = P[P_MARGIN]
    cm = 0.5 * amass * dt
    ubx = fr.vx
    uby = fr.vy
    gx = fr.gx
    gy = fr.gy
    gdx = fr.gdx
    gdy = fr.gdy
    # the frame of the damping: the base (drel = 1) or the fixed frame (drel = 0)
    dbx = drel * ubx
    dby = drel * uby
    half = 0.5 * margin
    if True:
        lo = blk * nb // NBLK
        hi = (blk + 1) * nb // NBLK
        unbal = 0.0
        wdamp = 0.0
        wbase = 0.0
        wext = 0.0
        need = 0.0
        wtilt = 0.0
        for b in range(lo, hi):
            kin = bkin[b]
            if kin == 0:
                m = bmass[b]
                fx = fb[b, 0] + m * gx + bext[b, 0]
                fy = fb[b, 1] + m * gy + bext[b, 1]
                mz = fb[b, 2] + bext[b, 2]
                un = math.sqrt(fx * fx + fy * fy + (mz / brad[b]) ** 2)
                if un > unbal:
                    unbal = un
                # velocities (half step) relative to the damping frame
                wx = bvel[b, 0] - dbx
                wy = bvel[b, 1] - dby
                wz = bomg[b]
                dfx = 0.0
                dfy = 0.0
                dmz = 0.0
                if alocal > 0.0:
                    if wx != 0.0:
                        dfx = -alocal * abs(fx) * (1.0 if wx > 0.0 else -1.0)
                    if wy != 0.0:
                        dfy = -alocal * abs(fy) * (1.0 if wy > 0.0 else -1.0)
                    if wz != 0.0:
                        dmz = -alocal * abs(mz) * (1.0 if wz > 0.0 else -1.0)
                I = binert[b]
                vx0 = bvel[b, 0]
                vy0 = bvel[b, 1]
                w0 = bomg[b]
                vx1 = (vx0 * (1.0 - cm) + dt * (fx + dfx) / m + 2.0 * cm * dbx) / (1.0 + cm)
                vy1 = (vy0 * (1.0 - cm) + dt * (fy + dfy) / m + 2.0 * cm * dby) / (1.0 + cm)
                w1 = (w0 * (1.0 - cm) + dt * (mz + dmz) / I) / (1.0 + cm)
                vmx = 0.5 * (vx0 + vx1)
                vmy = 0.5 * (vy0 + vy1)
                wm = 0.5 * (w0 + w1)
                wdamp += dt * ((dfx - amass * m * (vmx - dbx)) * vmx
                               + (dfy - amass * m * (vmy - dby)) * vmy
                               + (dmz - amass * I * wm) * wm)
                wext += dt * (bext[b, 0] * vmx + bext[b, 1] * vmy + bext[b, 2] * wm)
                wtilt -= dt * m * (bpos[b, 0] * gdx + bpos[b, 1] * gdy)
                _advance(b, dt, vmx, vmy, wm, vx1, vy1, w1, bodies)
            elif kin >= 2:
                # moved by the base motion (2) or at its prescribed velocity (3): its work on
                # the system is -(F . v + M omega), with v at the time of the forces
                if kin == 2:
                    vfx = ubx
                    vfy = uby
                    vhx = fr.vhx
                    vhy = fr.vhy
                    om = 0.0
                else:
                    vfx = vhx = bpresc[b, 0]
                    vfy = vhy = bpresc[b, 1]
                    om = bpresc[b, 2]
                wbase -= dt * (fb[b, 0] * vfx + fb[b, 1] * vfy + fb[b, 2] * om)
                _advance(b, dt, vfx, vfy, om, vhx, vhy, om, bodies)
            # rebuild test for the next step (as :func:`_moved`)
            dx = bpos[b, 0] - blast[b, 0]
            dy = bpos[b, 1] - blast[b, 1]
            if math.sqrt(dx * dx + dy * dy) + abs(bang[b] - blast[b, 2]) * brad[b] > half:
                need = 1.0
            for j in range(bsp[b], bsp[b + 1]):
                _shape_vertices(bsh[j], bpos, bang, shapes)
        part[blk, Q_UNBAL] = unbal
        part[blk, Q_WDAMP] = wdamp
        part[blk, Q_WBASE] = wbase
        part[blk, Q_WEXT] = wext
        part[blk, Q_NEED] = need
        part[blk, Q_WTILT] = wtilt


@njit(cache=True, error_model="numpy", parallel=True)
def _update_bodies_par(P, fr, fb, bodies, shapes, part, bsp, bsh):
    """:func:`_update_block` of every block, parallel over the blocks."""
    for blk in prange(NBLK):
        _update_block(blk, P, fr, fb, bodies, shapes, part, bsp, bsh)


@njit(cache=True, error_model="numpy")
def _update_bodies_ser(P, fr, fb, bodies, shapes, part, bsp, bsh):
    """:func:`_update_bodies_par` on one thread."""
    for blk in range(NBLK):
        _update_block(blk, P, fr, fb, bodies, shapes, part, bsp, bsh)


@njit(cache=True, error_model="numpy", inline="always")
def _frame(i, drive):
    """Row i of the step inputs ``drive`` (:class:`Drive`) of :func:`run_chunk`, as a
    :class:`Frame`."""
    return Frame(drive.vfull[i, 0], drive.vfull[i, 1], drive.vhalf[i, 0], drive.vhalf[i, 1],
                 drive.grav[i, 0], drive.grav[i, 1], drive.gdot[i, 0], drive.gdot[i, 1])


@njit(cache=True, error_model="numpy")
def _moved(bodies, margin):
    """True when a body of ``bodies`` (:class:`Bodies`) has moved by more than half the
    broad-phase margin [m] since the last rebuild of the pair list (translation plus rotation
    times the bounding radius)."""
    bpos = bodies.bpos
    bang = bodies.bang
    blast = bodies.blast
    brad = bodies.brad
    for b in range(bpos.shape[0]):
        dx = bpos[b, 0] - blast[b, 0]
        dy = bpos[b, 1] - blast[b, 1]
        if math.sqrt(dx * dx + dy * dy) + abs(bang[b] - blast[b, 2]) * brad[b] > 0.5 * margin:
            return True
    return False


@njit(cache=True, error_model="numpy", inline="always")
def step_forces(P, E, C, S, bodies, shapes, joints, c, work):
    """The forces of one step on the bodies: the pair list rebuilt when due, the contact loop
    (:func:`_contacts_parallel`), the resultants scattered to the bodies (:func:`_sum_pairs`).

    The first half of a step of :func:`run_chunk`, also called by loops that add forces of their
    own before the bodies move (the zones of :mod:`murus.continuum`).

    Parameters
    ----------
    P, E, C, S : ndarray
        Parameters, energy accumulators, counters, statistics (``P_*``, ``E_*``, ``C_*``,
        ``S_*``).
    bodies, shapes, joints : Bodies, Shapes, Joints
        The state (:mod:`murus.dem._kdata`).
    c : Contacts
        The candidate pairs (a new structure when the list is rebuilt).
    work : tuple
        ``(pw, nact, fb)``: per-pair work records ``(cap, NW)``, active sub-contacts per pair
        ``(cap,)`` (both grown when the pairs outnumber them), and the body forces
        ``fb (nb, 3)`` [N, N m], overwritten with the contacts' resultants.

    Returns
    -------
    tuple
        ``(c, pw, nact, par)``: the pairs, the work records and whether the body update runs
        in parallel (at least ``P_PARMIN`` pairs).
    """
    pw, nact, fb = work
    if C[C_NEED_REBUILD] != 0:
        newp = broad_phase(shapes, bodies.bkin, P[P_MARGIN])
        c = transfer(c, newp, shapes.sgroup, joints.jtab, 0)
        bpos = bodies.bpos
        bang = bodies.bang
        blast = bodies.blast
        for b in range(bpos.shape[0]):
            blast[b, 0] = bpos[b, 0]
            blast[b, 1] = bpos[b, 1]
            blast[b, 2] = bang[b]
        C[C_NEED_REBUILD] = 0
        C[C_REBUILD] += 1
    npair = c.pairs.shape[0]
    if npair > pw.shape[0]:
        cap = npair + npair // 4 + 16
        pw = np.zeros((cap, NW))
        nact = np.zeros(cap, np.int64)
    _contacts_parallel(c, pw, shapes, bodies, joints.jprops, P[P_DT], P[P_THICK],
                       P[P_REACH], nact)
    nactive = _sum_pairs(c.pairs, shapes.sbody, nact, pw, E, fb)
    C[C_UPDATES] += nactive
    S[S_NACTIVE] = nactive
    return c, pw, nact, npair >= int(P[P_PARMIN])


@njit(cache=True, error_model="numpy", inline="always")
def step_update(P, E, C, S, fr, fb, bodies, shapes, bpart, inc, par):
    """The move of one step: the bodies under the forces ``fb`` (:func:`_update_block` over the
    ``NBLK`` blocks, parallel when ``par``), their partial sums combined in block order into
    the energies, the largest unbalanced force and the rebuild flag.

    The second half of a step of :func:`run_chunk`.

    Parameters
    ----------
    P, E, C, S : ndarray
        Parameters, energy accumulators, counters, statistics.
    fr : Frame
        The step's base velocities and gravity.
    fb : ndarray (nb, 3)
        Forces and moments on the bodies [N, N m].
    bodies, shapes : Bodies, Shapes
        The state, updated in place.
    bpart : ndarray (NBLK, NQ)
        Work array of the partial sums.
    inc : tuple
        ``(bsp, bsh)``: the shapes of each body (:func:`incidence`).
    par : bool
        Run the body loop in parallel.

    Returns
    -------
    None
    """
    bsp, bsh = inc
    if par:
        _update_bodies_par(P, fr, fb, bodies, shapes, bpart, bsp, bsh)
    else:
        _update_bodies_ser(P, fr, fb, bodies, shapes, bpart, bsp, bsh)
    unbal = 0.0
    wdamp = 0.0
    wbase = 0.0
    wext = 0.0
    need = 0.0
    wtilt = 0.0
    for blk in range(NBLK):
        unbal = max(unbal, bpart[blk, Q_UNBAL])
        wtilt += bpart[blk, Q_WTILT]
        wdamp += bpart[blk, Q_WDAMP]
        wbase += bpart[blk, Q_WBASE]
        wext += bpart[blk, Q_WEXT]
        need = max(need, bpart[blk, Q_NEED])
    if need > 0.0:
        C[C_NEED_REBUILD] = 1
    E[E_WDAMP] += wdamp
    E[E_WBASE] += wbase
    E[E_WEXT] += wext
    E[E_WTILT] += wtilt
    C[C_STEP] += 1
    S[S_UNBAL] = unbal


@njit(cache=True, error_model="numpy")
def run_chunk(nsteps, P, E, C, S, drive, bodies, shapes, joints, contacts):
    """Advance ``nsteps`` central-difference steps (Savalle et al. (2022), eq. 2).

    ``P``, ``E``, ``C``, ``S``: parameters, energy accumulators, counters and statistics
    (``P_*``, ``E_*``, ``C_*``, ``S_*`` fields); ``drive`` (:class:`Drive`): row i, the
    base-motion velocity [m/s] at t_i + dt/2 (``vhalf``) and t_i (``vfull``), the gravity vector
    [m/s²] at t_i (``grav``) and its rate [m/s³] (``gdot``; tilting table: the
    potential energy then changes with time, its rate ``-sum m x . gdot`` is accumulated in
    ``E[E_WTILT]``); ``bodies`` (:class:`Bodies`), ``shapes`` (:class:`Shapes`), ``joints``
    (:class:`Joints`) and ``contacts`` (:class:`Contacts`) the state, updated in place.
    ``bodies.bext (nb, 3)`` is an external force (Fx, Fy) [N] and
    moment about the centroid [N m] on each dynamic body, constant over the chunk (its work is
    accumulated in ``E[E_WEXT]``; ignored on kinematic bodies). ``bodies.bsnap`` receives the
    state at the time of the last force evaluation (x, y, angle, and the mid-step velocities
    vx, vy, omega), the time at which the contact forces and the work accumulators are
    consistent (energy snapshots). Returns the arrays of the (possibly rebuilt) :class:`Contacts`
    as a plain tuple, in the order of its fields.

    A step: the contact loop (narrow phase and joint law, a numba parallel loop over the pairs,
    each pair writing only its own record and its resultant in ``pw``), the resultants
    scattered to the bodies in pair order (serial), the body update (a parallel loop over
    ``NBLK`` fixed blocks of bodies whose partial sums are combined in block order), in which
    each body also updates the world coordinates of its shapes for the next step (two parallel
    regions per step).
    A run therefore gives the same numbers on any number of threads. Below ``P_PARMIN`` pairs
    the body loops are serial and the caller runs the contact loop on one thread
    (:func:`murus.dem.engine._chunk`): waking a second thread costs more than it saves there,
    and stalls on a loaded machine. The contact loop is always the parallel one, which numba
    compiles into code 2-5 times faster than a plain loop of the same body
    (benchmarks/RESULTS_dem.md)."""
    margin = P[P_MARGIN]
    bpos = bodies.bpos
    bang = bodies.bang
    nb = bodies.bmass.size
    c = contacts
    fb = np.zeros((nb, 3))
    cap = c.pairs.shape[0] + 16
    pw = np.zeros((cap, NW))
    nact = np.zeros(cap, np.int64)
    bpart = np.zeros((NBLK, NQ))
    if C[C_NEED_REBUILD] == 0 and _moved(bodies, margin):
        C[C_NEED_REBUILD] = 1
    # the body update keeps the world vertices current from here on
    world_vertices(bpos, bang, shapes)
    bsp, bsh = incidence(shapes.sbody, nb)
    cdamp = damped(joints.jprops)
    for i in range(nsteps):
        c, pw, nact, par = step_forces(P, E, C, S, bodies, shapes, joints, c, (pw, nact, fb))
        step_update(P, E, C, S, _frame(i, drive), fb, bodies, shapes, bpart, (bsp, bsh), par)
        if cdamp:
            E[E_DDASH] += dashpot_work(c, nact, pw, joints.jprops, shapes.sbody, bodies,
                                       P[P_DT])
    # mean contact force at the end of the chunk
    tot = 0.0
    na = 0
    sid = c.sid
    sf = c.sf
    for k in range(c.pairs.shape[0]):
        for o in range(2):
            if sid[k, o] >= 0:
                tot += math.sqrt(sf[k, o, F_FN] ** 2 + sf[k, o, F_FS] ** 2)
                na += 1
    S[S_MEANF] = tot / na if na > 0 else 0.0
    # a plain tuple, in the order of Contacts._fields: numba boxes a named tuple by calling its
    # Python class, and a Ctrl-C pending at that moment crashed the process (SIGSEGV)
    return (c.pairs, c.pj, c.pbond, c.sid, c.sf, c.sbr)


# numba's cache checks only this file: flush it when the structure layouts and field positions
# it compiles in (murus.dem._kdata) change
_guard_cache(globals(), deps=("murus.dem._kdata",))
