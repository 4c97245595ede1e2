"""Numerical kernels of the 2D distinct-element engine (numba, no I/O, no Python objects).

Storage (structure of arrays, built by :mod:`murus.dem.model`)
---------------------------------------------------------------
- bodies ``b``: ``bpos (nb, 2)`` centroid [m], ``bang`` angle [rad, counter-clockwise],
  ``bvel (nb, 2)`` [m/s] and ``bomg`` [rad/s] at the half step ``t - dt/2``, ``bmass`` [kg],
  ``binert`` [kg m²] about the centroid, ``bkin`` (0 dynamic, 1 fixed, 2 moved by the base
  motion), ``brad`` bounding radius about the centroid [m];
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

Joint law (seed 001 eqs. 3-4, UDEC "Coulomb slip" joint model)
--------------------------------------------------------------
Per sub-contact, tributary area ``A = L t``: normal force ``Fn = -kn A g`` (g the gap, negative
in penetration; the total form of eq. 3, identical to the incremental form for a spring born at
zero gap, and exactly conservative); shear force incremental, ``Fs <- Fs - ks A du_s`` with
``du_s`` the relative tangential displacement of the step (eq. 3), limited by
``|Fs| <= c A + Fn tan(phi)`` (eq. 4); tension ``Fn >= -T A``. A sub-contact that fails in
tension or shear takes the residual cohesion and tension. Sign conventions: the normal ``n``
points from shape a to shape b, the tangent ``t = (-ny, nx)``; ``Fn > 0`` is compression; the
force on b is ``Fn n + Fs t``. Discs carry a rolling moment ``Mr <- Mr - kr dtheta_rel``
with ``kr = ks A r_eff²`` limited by ``mu_r r_eff Fn`` (elastic-plastic rolling resistance).

Integration (seed 001 eq. 2, central differences / leapfrog)
-----------------------------------------------------------
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
NJ = 8

# ---- parameter vector ------------------------------------------------------------------------
P_DT = 0  # time step [s]
P_THICK = 1  # out-of-plane thickness [m]
P_ALOCAL = 2  # local damping coefficient [-]
P_AMASS = 3  # mass-proportional damping alpha_M [1/s]
P_MARGIN = 4  # broad-phase margin [m]
P_REACH = 5  # largest positive gap at which a sub-contact is kept [m]
P_PARMIN = 6  # smallest number of pairs for the parallel loop
NP = 8

# ---- energy accumulators ---------------------------------------------------------------------
E_WBASE = 0  # work done by the kinematic bodies on the system [J]
E_WDAMP = 1  # work of the damping forces (negative) [J]
E_DSLIP = 2  # frictional (slip) dissipation [J]
E_DROLL = 3  # rolling-resistance dissipation [J]
E_DBREAK = 4  # elastic energy released by breaking or opening sub-contacts [J]
E_WEXT = 5  # work of the external (applied) body forces ``bext`` [J]
NE = 8

# ---- counters ----------------------------------------------------------------------------------
C_STEP = 0
C_REBUILD = 1
C_UPDATES = 2  # sub-contact updates
C_NEED_REBUILD = 3  # 1: rebuild the pair list at the next step
NC = 4

# ---- chunk statistics --------------------------------------------------------------------------
S_UNBAL = 0  # max unbalanced force of a dynamic body at the last step [N]
S_MEANF = 1  # mean contact force magnitude over active sub-contacts [N]
S_NACTIVE = 2  # active sub-contacts
NS = 4


@njit(cache=True, inline="always")
def _clamp01(x):
    if x < 0.0:
        return 0.0
    if x > 1.0:
        return 1.0
    return x


@njit(cache=True)
def world_vertices(bpos, bang, sbody, svs, svn, lv, wv):
    """World coordinates of every local vertex (polygon cores, disc centres)."""
    for s in range(sbody.size):
        b = sbody[s]
        c = math.cos(bang[b])
        sn = math.sin(bang[b])
        for k in range(svs[s], svs[s] + svn[s]):
            wv[k, 0] = bpos[b, 0] + c * lv[k, 0] - sn * lv[k, 1]
            wv[k, 1] = bpos[b, 1] + sn * lv[k, 0] + c * lv[k, 1]


@njit(cache=True)
def broad_phase(wv, svs, svn, srad, sbody, bkin, margin):
    """Candidate pairs (a < b) by sort and sweep on the bounding boxes inflated by ``margin``,
    sorted by the key a * ns + b. Pairs of one body and pairs of two non-dynamic bodies are
    left out."""
    ns = sbody.size
    box = np.empty((ns, 4))
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
    order = np.argsort(box[:, 0], kind="mergesort")
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


@njit(cache=True)
def transfer(old_pairs, old_sid, old_sf, old_sbr, old_pbond, new_pairs, ns, jtab, sgroup,
             bond_new):
    """Carry the sub-contact state of the pairs present in both lists (merge on sorted keys)."""
    n = new_pairs.shape[0]
    nold = old_pairs.shape[0]
    sid = np.full((n, 2), -1, np.int64)
    sf = np.zeros((n, 2, NSF))
    sbr = np.zeros((n, 2), np.int8)
    pbond = np.zeros(n, np.int8)
    pj = np.empty(n, np.int64)
    i = 0
    for k in range(n):
        a = new_pairs[k, 0]
        b = new_pairs[k, 1]
        key = a * ns + b
        pj[k] = jtab[sgroup[a], sgroup[b]]
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
    return sid, sf, sbr, pbond, pj


# ---- narrow phase ----------------------------------------------------------------------------


@njit(cache=True)
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


@njit(cache=True)
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


@njit(cache=True)
def collide_pp(wv, a0, na, ra, b0, nb, rb, reach, oid, og):
    """Sub-contacts of two rounded convex polygons (cores ``wv[a0:a0+na]``, ``wv[b0:b0+nb]``,
    counter-clockwise). Writes ``oid[c]`` (key) and ``og[c] = (px, py, nx, ny, gap, trib)``
    with n from a to b; returns the count (0, 1 or 2)."""
    rr = ra + rb
    sepA, eA = _sat(wv, a0, na, b0, nb)
    if sepA > rr + reach:
        return 0
    sepB, eB = _sat(wv, b0, nb, a0, na)
    if sepB > rr + reach:
        return 0
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
                return 0
            mx = dx / d
            my = dy / d
            h = 0.5 * (d - rR + rI)
            oid[0] = ir1 if f1 == 0.0 else ir2
            og[0, 0] = c2x - mx * h
            og[0, 1] = c2y - my * h
            og[0, 2] = sg * mx
            og[0, 3] = sg * my
            og[0, 4] = d - rr
            og[0, 5] = 0.5 * min(L, LI) + 0.5 * rr
            return 1
    # clip the incident edge to the span [0, L] of the reference edge
    s1 = tx * (i1x - r1x) + ty * (i1y - r1y)
    s2 = tx * (i2x - r1x) + ty * (i2y - r1y)
    ds = s2 - s1
    if abs(ds) < 1e-12 * L:
        return 0
    ua = (0.0 - s1) / ds
    ub = (L - s1) / ds
    u0 = max(0.0, min(ua, ub))
    u1 = min(1.0, max(ua, ub))
    if u1 < u0:
        return 0
    Lc = abs(ds) * (u1 - u0)
    trib = 0.5 * Lc + 0.5 * rr
    nend = 2
    if Lc <= 1e-9 * L:
        nend = 1
        trib = 0.5 * LI + 0.5 * rr
    cnt = 0
    for q in range(nend):
        u = u0 if q == 0 else u1
        px = i1x + u * ex
        py = i1y + u * ey
        sp = nx * (px - r1x) + ny * (py - r1y)
        if sp - rr > reach:
            continue
        if u == 0.0:
            oid[cnt] = ii1
        elif u == 1.0:
            oid[cnt] = ii2
        else:
            s = s1 + u * ds
            oid[cnt] = ir1 if abs(s) < abs(s - L) else ir2
        h = 0.5 * (sp - rR + rI)
        og[cnt, 0] = px - nx * h
        og[cnt, 1] = py - ny * h
        og[cnt, 2] = sg * nx
        og[cnt, 3] = sg * ny
        og[cnt, 4] = sp - rr
        og[cnt, 5] = trib
        cnt += 1
    return cnt


@njit(cache=True)
def collide_pd(wv, a0, na, ra, cx, cy, rd, reach, og):
    """Rounded polygon (core ``wv[a0:a0+na]``, rounding ra) against a disc (centre, radius):
    one sub-contact, n from the polygon to the disc. Returns the count."""
    # largest separation of the centre from the core edges
    best = -np.inf
    be = 0
    for i in range(na):
        ax = wv[a0 + i, 0]
        ay = wv[a0 + i, 1]
        j1 = a0 + (i + 1) % na
        ex = wv[j1, 0] - ax
        ey = wv[j1, 1] - ay
        L = math.sqrt(ex * ex + ey * ey)
        d = (ey * (cx - ax) - ex * (cy - ay)) / L
        if d > best:
            best = d
            be = i
    rr = ra + rd
    if best > rr + reach:
        return 0
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
            return 0
        nx = (cx - qx) / d
        ny = (cy - qy) / d
    h = 0.5 * (d - ra + rd)  # midway between the rounded polygon and the disc surfaces
    og[0, 0] = cx - nx * h
    og[0, 1] = cy - ny * h
    og[0, 2] = nx
    og[0, 3] = ny
    og[0, 4] = d - rr
    og[0, 5] = 2.0 * rd
    return 1


@njit(cache=True)
def collide(a, b, wv, svs, svn, skind, srad, reach, oid, og):
    """Sub-contacts of shapes a < b (keys in ``oid``, geometry in ``og``); returns the count."""
    ka = skind[a]
    kb = skind[b]
    if ka == 0 and kb == 0:
        return collide_pp(wv, svs[a], svn[a], srad[a], svs[b], svn[b], srad[b], reach, oid, og)
    if ka == 1 and kb == 1:
        ia = svs[a]
        ib = svs[b]
        dx = wv[ib, 0] - wv[ia, 0]
        dy = wv[ib, 1] - wv[ia, 1]
        d = math.sqrt(dx * dx + dy * dy)
        ra = srad[a]
        rb = srad[b]
        if d - ra - rb > reach or d == 0.0:
            return 0
        nx = dx / d
        ny = dy / d
        h = 0.5 * (d - rb + ra)
        og[0, 0] = wv[ia, 0] + nx * h
        og[0, 1] = wv[ia, 1] + ny * h
        og[0, 2] = nx
        og[0, 3] = ny
        og[0, 4] = d - ra - rb
        og[0, 5] = 2.0 * ra * rb / (ra + rb)
        oid[0] = ia
        return 1
    if ka == 0:
        ic = svs[b]
        c = collide_pd(wv, svs[a], svn[a], srad[a], wv[ic, 0], wv[ic, 1], srad[b], reach, og)
        oid[0] = ic
        return c
    ic = svs[a]
    c = collide_pd(wv, svs[b], svn[b], srad[b], wv[ic, 0], wv[ic, 1], srad[a], reach, og)
    if c == 1:
        og[0, 2] = -og[0, 2]
        og[0, 3] = -og[0, 3]
    oid[0] = ic
    return c


@njit(cache=True)
def process_pair(k, pairs, pj, pbond, sid, sf, sbr, dis, wv, svs, svn, skind, srad, sbody,
                 bpos, bvel, bomg, jprops, dt, thick, reach, scr_i, scr_f):
    """Narrow phase and joint law of pair k: updates its two slots in place and writes the
    energy dissipated in the step to ``dis[k]`` (slip, rolling, breaking/opening).
    ``scr_i``, ``scr_f``: reserved scratch (unused)."""
    a = pairs[k, 0]
    b = pairs[k, 1]
    # small local arrays (numba's allocator is thread-safe and cheap; views of shared scratch
    # arrays are slower in the parallel loop because of reference counting)
    oid = np.empty(2, np.int64)
    match = np.full(2, -1, np.int64)
    newid = np.full(2, -1, np.int64)
    newbr = np.zeros(2, np.int64)
    og = np.empty((2, 6))
    newsf = np.zeros((2, NSF))
    cnt = collide(a, b, wv, svs, svn, skind, srad, reach, oid, og)
    ba = sbody[a]
    bb = sbody[b]
    jp = pj[k]
    kn = jprops[jp, J_KN]
    ks = jprops[jp, J_KS]
    tanphi = jprops[jp, J_TANPHI]
    muroll = jprops[jp, J_MUROLL]
    rolling = muroll > 0.0 and (skind[a] == 1 or skind[b] == 1)
    reff = 0.0
    if rolling:
        if skind[a] == 1 and skind[b] == 1:
            reff = srad[a] * srad[b] / (srad[a] + srad[b])
        elif skind[a] == 1:
            reff = srad[a]
        else:
            reff = srad[b]
    # match the new points to the old slots: same key, else the nearest old point within the
    # rounding (a vertex passing the end of an edge changes key at an unchanged position)
    used0 = False
    used1 = False
    for c in range(cnt):
        if sid[k, 0] == oid[c] and not used0:
            match[c] = 0
            used0 = True
        elif sid[k, 1] == oid[c] and not used1:
            match[c] = 1
            used1 = True
    tol = srad[a] + srad[b]
    for c in range(cnt):
        if match[c] >= 0:
            continue
        bestd = tol
        for o in range(2):
            if sid[k, o] < 0 or (o == 0 and used0) or (o == 1 and used1):
                continue
            dd = math.sqrt((sf[k, o, F_PX] - og[c, 0]) ** 2 + (sf[k, o, F_PY] - og[c, 1]) ** 2)
            if dd < bestd:
                bestd = dd
                match[c] = o
        if match[c] == 0:
            used0 = True
        elif match[c] == 1:
            used1 = True
    d_slip = 0.0
    d_roll = 0.0
    d_break = 0.0
    # shear and rolling energy of the old slots that disappear (the normal spring energy of a
    # separating contact is given back as work of the normal force over the step)
    for o in range(2):
        if sid[k, o] >= 0 and not ((o == 0 and used0) or (o == 1 and used1)):
            if sf[k, o, F_KSA] > 0.0:
                d_break += 0.5 * sf[k, o, F_FS] ** 2 / sf[k, o, F_KSA]
            if sf[k, o, F_KRA] > 0.0:
                d_break += 0.5 * sf[k, o, F_MR] ** 2 / sf[k, o, F_KRA]
    nkeep = 0
    vax = bvel[ba, 0]
    vay = bvel[ba, 1]
    wa = bomg[ba]
    vbx = bvel[bb, 0]
    vby = bvel[bb, 1]
    wb = bomg[bb]
    xa = bpos[ba, 0]
    ya = bpos[ba, 1]
    xb = bpos[bb, 0]
    yb = bpos[bb, 1]
    for c in range(cnt):
        px = og[c, 0]
        py = og[c, 1]
        nx = og[c, 2]
        ny = og[c, 3]
        gap = og[c, 4]
        area = og[c, 5] * thick
        o = match[c]
        if o >= 0:
            fs = sf[k, o, F_FS]
            mr = sf[k, o, F_MR]
            broken = sbr[k, o]
            ksa_old = sf[k, o, F_KSA]
        else:
            fs = 0.0
            mr = 0.0
            broken = 1 - pbond[k]
            ksa_old = 0.0
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
                pbond[k] = 0
                d_break += 0.5 * tA * tA / kna
                tA = jprops[jp, J_TRES] * area
                cA = jprops[jp, J_CRES] * area
            fn = -tA
        if gap > reach or (gap > 0.0 and tA == 0.0):
            # open: no force; the shear spring releases its energy
            if ksa_old > 0.0:
                d_break += 0.5 * fs * fs / ksa_old
            if o >= 0 and sf[k, o, F_KRA] > 0.0:
                d_break += 0.5 * mr * mr / sf[k, o, F_KRA]
            if gap > reach:
                continue
            fn = 0.0
            fs = 0.0
            mr = 0.0
            kra = 0.0
        else:
            # relative velocity of b with respect to a at the contact point
            rvx = (vbx - wb * (py - yb)) - (vax - wa * (py - ya))
            rvy = (vby + wb * (px - xb)) - (vay + wa * (px - xa))
            dus = (-ny * rvx + nx * rvy) * dt
            fs_t = fs - ksa * dus
            fmax = cA + fn * tanphi
            if fmax < 0.0:
                fmax = 0.0
            if abs(fs_t) > fmax:
                if not broken and (cA > 0.0 or tA > 0.0):  # shear failure
                    broken = 1
                    pbond[k] = 0
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
            kra = 0.0
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
        newid[nkeep] = oid[c]
        newbr[nkeep] = broken
        newsf[nkeep, F_FN] = fn
        newsf[nkeep, F_FS] = fs
        newsf[nkeep, F_MR] = mr
        newsf[nkeep, F_PX] = px
        newsf[nkeep, F_PY] = py
        newsf[nkeep, F_NX] = nx
        newsf[nkeep, F_NY] = ny
        newsf[nkeep, F_KNA] = kna
        newsf[nkeep, F_KSA] = ksa
        newsf[nkeep, F_KRA] = kra
        newsf[nkeep, F_GAP] = gap
        nkeep += 1
    for o in range(2):
        sid[k, o] = newid[o]
        sbr[k, o] = newbr[o]
        for f in range(NSF):
            sf[k, o, f] = newsf[o, f]
    dis[k, 0] = d_slip
    dis[k, 1] = d_roll
    dis[k, 2] = d_break
    return nkeep


@njit(cache=True, parallel=True)
def _contacts_parallel(pairs, pj, pbond, sid, sf, sbr, dis, wv, svs, svn, skind, srad, sbody,
                       bpos, bvel, bomg, jprops, dt, thick, reach, nact, scr_i, scr_f):
    for k in prange(pairs.shape[0]):
        nact[k] = process_pair(k, pairs, pj, pbond, sid, sf, sbr, dis, wv, svs, svn, skind,
                               srad, sbody, bpos, bvel, bomg, jprops, dt, thick, reach, scr_i,
                               scr_f)


@njit(cache=True)
def _contacts_serial(pairs, pj, pbond, sid, sf, sbr, dis, wv, svs, svn, skind, srad, sbody,
                     bpos, bvel, bomg, jprops, dt, thick, reach, nact, scr_i, scr_f):
    for k in range(pairs.shape[0]):
        nact[k] = process_pair(k, pairs, pj, pbond, sid, sf, sbr, dis, wv, svs, svn, skind,
                               srad, sbody, bpos, bvel, bomg, jprops, dt, thick, reach, scr_i,
                               scr_f)


@njit(cache=True)
def body_forces(pairs, sid, sf, sbody, bpos, nb, fb):
    """Sum the sub-contact forces and moments on the bodies (serial, deterministic order)."""
    fb[:, :] = 0.0
    for k in range(pairs.shape[0]):
        ba = sbody[pairs[k, 0]]
        bb = sbody[pairs[k, 1]]
        for o in range(2):
            if sid[k, o] < 0:
                continue
            fn = sf[k, o, F_FN]
            fs = sf[k, o, F_FS]
            nx = sf[k, o, F_NX]
            ny = sf[k, o, F_NY]
            fx = fn * nx - fs * ny
            fy = fn * ny + fs * nx
            px = sf[k, o, F_PX]
            py = sf[k, o, F_PY]
            mr = sf[k, o, F_MR]
            fb[bb, 0] += fx
            fb[bb, 1] += fy
            fb[bb, 2] += (px - bpos[bb, 0]) * fy - (py - bpos[bb, 1]) * fx + mr
            fb[ba, 0] -= fx
            fb[ba, 1] -= fy
            fb[ba, 2] -= (px - bpos[ba, 0]) * fy - (py - bpos[ba, 1]) * fx + mr


@njit(cache=True)
def run_chunk(nsteps, P, E, C, S, vhalf, vfull, grav,
              bpos, bang, bvel, bomg, bmass, binert, bkin, brad, blast, bsnap,
              sbody, skind, svs, svn, srad, sgroup, lv, wv, jprops, jtab,
              pairs, pj, pbond, sid, sf, sbr, bext):
    """Advance ``nsteps`` central-difference steps (seed 001 eq. 2).

    ``vhalf[i]`` / ``vfull[i]``: base-motion velocity [m/s] at t_i + dt/2 and t_i; ``grav[i]``
    the gravity vector [m/s²] at t_i; ``bext (nb, 3)`` an external force (Fx, Fy) [N] and
    moment about the centroid [N m] on each dynamic body, constant over the chunk (its work is
    accumulated in ``E[E_WEXT]``; ignored on kinematic bodies). ``bsnap`` receives the state at
    the time of the last force evaluation (x, y, angle, and the mid-step velocities vx, vy,
    omega), the time at which the contact forces and the work accumulators are consistent
    (energy snapshots). Returns the (possibly rebuilt) pair arrays."""
    dt = P[P_DT]
    thick = P[P_THICK]
    alocal = P[P_ALOCAL]
    amass = P[P_AMASS]
    margin = P[P_MARGIN]
    reach = P[P_REACH]
    parmin = int(P[P_PARMIN])
    nb = bmass.size
    ns = sbody.size
    fb = np.zeros((nb, 3))
    cm = 0.5 * amass * dt
    cap = pairs.shape[0] + 16
    dis = np.empty((cap, 3))
    nact = np.empty(cap, np.int64)
    scr_i = np.empty((cap, 8), np.int64)
    scr_f = np.empty((cap, 2, 6 + NSF))
    for i in range(nsteps):
        world_vertices(bpos, bang, sbody, svs, svn, lv, wv)
        if C[C_NEED_REBUILD] == 0:
            for b in range(nb):
                dx = bpos[b, 0] - blast[b, 0]
                dy = bpos[b, 1] - blast[b, 1]
                if math.sqrt(dx * dx + dy * dy) + abs(bang[b] - blast[b, 2]) * brad[b] \
                        > 0.5 * margin:
                    C[C_NEED_REBUILD] = 1
                    break
        if C[C_NEED_REBUILD] != 0:
            newp = broad_phase(wv, svs, svn, srad, sbody, bkin, margin)
            sid, sf, sbr, pbond, pj = transfer(pairs, sid, sf, sbr, pbond, newp, ns, jtab,
                                               sgroup, 0)
            pairs = newp
            for b in range(nb):
                blast[b, 0] = bpos[b, 0]
                blast[b, 1] = bpos[b, 1]
                blast[b, 2] = bang[b]
            C[C_NEED_REBUILD] = 0
            C[C_REBUILD] += 1
        npair = pairs.shape[0]
        if npair > cap:
            cap = npair + npair // 4 + 16
            dis = np.empty((cap, 3))
            nact = np.empty(cap, np.int64)
            scr_i = np.empty((cap, 8), np.int64)
            scr_f = np.empty((cap, 2, 6 + NSF))
        if npair >= parmin:
            _contacts_parallel(pairs, pj, pbond, sid, sf, sbr, dis, wv, svs, svn, skind, srad,
                               sbody, bpos, bvel, bomg, jprops, dt, thick, reach, nact, scr_i,
                               scr_f)
        else:
            _contacts_serial(pairs, pj, pbond, sid, sf, sbr, dis, wv, svs, svn, skind, srad,
                             sbody, bpos, bvel, bomg, jprops, dt, thick, reach, nact, scr_i,
                             scr_f)
        nactive = 0
        for k in range(npair):
            E[E_DSLIP] += dis[k, 0]
            E[E_DROLL] += dis[k, 1]
            E[E_DBREAK] += dis[k, 2]
            nactive += nact[k]
        C[C_UPDATES] += nactive
        body_forces(pairs, sid, sf, sbody, bpos, nb, fb)
        gx = grav[i, 0]
        gy = grav[i, 1]
        ubx = vfull[i, 0]
        uby = vfull[i, 1]
        unbal = 0.0
        wdamp = 0.0
        wbase = 0.0
        wext = 0.0
        for b in range(nb):
            kin = bkin[b]
            if kin == 0:
                m = bmass[b]
                fx = fb[b, 0] + m * gx + bext[b, 0]
                fy = fb[b, 1] + m * gy + bext[b, 1]
                mz = fb[b, 2] + bext[b, 2]
                un = math.sqrt(fx * fx + fy * fy + (mz / brad[b]) ** 2)
                if un > unbal:
                    unbal = un
                # relative velocities (half step) for the damping
                wx = bvel[b, 0] - ubx
                wy = bvel[b, 1] - uby
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
                vx1 = (vx0 * (1.0 - cm) + dt * (fx + dfx) / m + 2.0 * cm * ubx) / (1.0 + cm)
                vy1 = (vy0 * (1.0 - cm) + dt * (fy + dfy) / m + 2.0 * cm * uby) / (1.0 + cm)
                w1 = (w0 * (1.0 - cm) + dt * (mz + dmz) / I) / (1.0 + cm)
                vmx = 0.5 * (vx0 + vx1)
                vmy = 0.5 * (vy0 + vy1)
                wm = 0.5 * (w0 + w1)
                wdamp += dt * ((dfx - amass * m * (vmx - ubx)) * vmx
                               + (dfy - amass * m * (vmy - uby)) * vmy
                               + (dmz - amass * I * wm) * wm)
                wext += dt * (bext[b, 0] * vmx + bext[b, 1] * vmy + bext[b, 2] * wm)
                bsnap[b, 0] = bpos[b, 0]
                bsnap[b, 1] = bpos[b, 1]
                bsnap[b, 2] = bang[b]
                bsnap[b, 3] = vmx
                bsnap[b, 4] = vmy
                bsnap[b, 5] = wm
                bvel[b, 0] = vx1
                bvel[b, 1] = vy1
                bomg[b] = w1
                bpos[b, 0] += vx1 * dt
                bpos[b, 1] += vy1 * dt
                bang[b] += w1 * dt
            elif kin == 2:
                # the body imposes the base motion: its work on the system is -F . v
                wbase -= dt * (fb[b, 0] * ubx + fb[b, 1] * uby)
                bsnap[b, 0] = bpos[b, 0]
                bsnap[b, 1] = bpos[b, 1]
                bsnap[b, 2] = bang[b]
                bsnap[b, 3] = ubx
                bsnap[b, 4] = uby
                bsnap[b, 5] = 0.0
                bvel[b, 0] = vhalf[i, 0]
                bvel[b, 1] = vhalf[i, 1]
                bomg[b] = 0.0
                bpos[b, 0] += vhalf[i, 0] * dt
                bpos[b, 1] += vhalf[i, 1] * dt
        E[E_WDAMP] += wdamp
        E[E_WBASE] += wbase
        E[E_WEXT] += wext
        C[C_STEP] += 1
        S[S_UNBAL] = unbal
        S[S_NACTIVE] = nactive
    # mean contact force at the end of the chunk
    tot = 0.0
    na = 0
    for k in range(pairs.shape[0]):
        for o in range(2):
            if sid[k, o] >= 0:
                tot += math.sqrt(sf[k, o, F_FN] ** 2 + sf[k, o, F_FS] ** 2)
                na += 1
    S[S_MEANF] = tot / na if na > 0 else 0.0
    return pairs, pj, pbond, sid, sf, sbr
