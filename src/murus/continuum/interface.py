"""Interfaces between continuum zones and distinct-element blocks: the contact kernels that a
coupled time loop calls once per step (numba, no I/O, no allocation per step).

Two kinds of contact, both with the distinct-element joint law of the blocks
(:func:`murus.dem.kernels._joint_law` and :func:`murus.dem.kernels._store`, imported, so the
law is the same code as block-block joints; Savalle et al. (2022), eqs. 3-4; Itasca UDEC,
"Coulomb slip" joint and the zone-block interfaces of UDEC's deformable blocks):

1. **Gridpoints against blocks (node-to-segment).** Each interface gridpoint (a gridpoint on
   the zone boundary) against each candidate shape near it: for a rounded polygon, the nearest
   point ``q`` of the core boundary (the gap is the signed distance to the rounded surface,
   ``|p - q| - r``; a gridpoint inside the core takes minus its distance to the nearest core
   edge, the edge of least penetration), for a disc its centre. The normal ``n`` points from
   the gridpoint (side a: a point with no rotation) to the block (side b). The tributary length
   of a gridpoint contact is half of each interface edge that ends at the gridpoint (at the
   current coordinates), projected on the contact's tangent: on a flat or gently curved
   boundary, half of each adjacent edge; at a corner of the zone boundary (the top of a
   backfill against a wall), only the side that runs along the block's face; and of that, only
   the part that faces the block (the extent along the tangent of the block's core polygon,
   whose edges are the flat faces; of a disc, its diameter): a gridpoint under the end of a
   face, or at the joint between two blocks, shares its length with them instead of giving
   each its whole length. The contact area
   is that length times the thickness ``t``. The contact point is the gridpoint
   itself, so that the force on the block (at that point) and the reaction on the gridpoint
   have the same line of action: total force and total moment are exactly zero.
2. **Block corners against zone edges.** Each core vertex of a candidate polygon (the centre
   of a disc) whose projection on an interface edge ``(g0, g1)`` falls inside it
   (``0 <= s <= 1``), at a gap ``d - r`` no larger than the reach and no deeper than
   ``IP_DEPTH`` (by default a tenth of the shortest interface edge: a vertex deeper behind
   an edge is a vertex near another part of the boundary), with ``d`` the distance of the
   vertex from the edge line, positive outside the zones. The normal is the edge's outward
   normal, the contact point the projection of the vertex on the edge,
   ``(1 - s) x_g0 + s x_g1``; the reaction goes to the two gridpoints with
   the weights ``(1 - s, s)`` (so again no net force nor moment), and the velocity of side a at
   the contact point is ``(1 - s) v_g0 + s v_g1``.

   *Tributary length of a corner (the coverage rule).* Every point of a block face against
   the zones is carried once: by the gridpoints touching it (step 1: gap <= 0, or bonded and
   carrying a force), each over its tributary length along the face, or by the face's end
   vertices over what those leave uncovered next to them. A corner takes, from each of its
   two adjacent block edges that face the zone edge (outward normals at more than 90°), the
   part of the edge next to it that the tributary lengths of the gridpoints touching the edge
   this step do not cover, or half the edge when no gridpoint touches it (the measure of the
   distinct-element clipping, where a vertex on a face carries half the clipped incident
   edge), projected on the zone edge. So a flat face on a row of gridpoints carries ``kn t
   delta`` times its length, not more; a corner that pokes into a zone edge between two
   gridpoints of a coarse mesh is held by the edge with its full share; and as a gridpoint
   slides towards a block's corner, the corner's share shrinks with what the gridpoint covers,
   continuously. (An earlier rule gave a corner nothing from a face that any gridpoint
   touched, and the whole half face otherwise: a gridpoint coming under the face switched the
   corner's stiffness on and off, and a block sliding or shaken over the zones gained
   hundreds of joules, 0.3 to 0.6 of the input work, that fed spurious plastic flow.) A
   gridpoint whose nearest core point is a vertex covers both edges at that vertex. A disc
   gets ``2 R`` (the disc-polygon tributary of the blocks) unless a gridpoint touches it. The
   rule sets the tributary length of a corner contact when it forms or carries no force; a
   loaded one follows it down only (``corner_share="shrink"``, the default), or up and down
   (``"follow"``)
   (:func:`_kept_trib`: the coverage jumps when a gridpoint next to the corner starts or
   stops touching the face, and a stiffness that jumps up under load pumps energy into a
   rocking block). Of the vertices of a shape within reach of an edge, the two of least gap
   are kept (a convex shape touches a straight edge with two vertices at most).

The reach (largest positive gap at which a contact is kept, ``IP_REACH``) is by default twice
the joint's ``T / kn``: a bond pulled beyond its tensile strength then breaks through the joint
law and keeps its residual tension up to that gap (with the blocks' reach, ``T / kn``, a bond
would vanish at the very gap where it breaks). A dry joint (``T = 0``) has reach 0.

Contact state across steps (the distinct-element layout, :class:`murus.dem._kdata.Contacts`):
candidate pairs are rebuilt (:func:`rebuild`) when an interface gridpoint or a body has moved
by more than half the margin ``IP_MARGIN`` since the last rebuild (as the blocks do, with the
interface's own reference positions), and the state of a pair present before and after a
rebuild is carried over (merge on sorted keys). Node pairs ``(i, s)``: interface gridpoint
``i`` (local index into ``ig``) and shape ``s``, key ``i * ns + s``, one slot (slot 0; its key
``sid`` is the global index of the first vertex of the nearest core edge, the disc centre for
a disc), whose shear force carries over as long as the gridpoint touches the shape. Corner pairs
``(e, s)``: interface edge ``e`` and shape ``s``, key ``e * ns + s``, two slots keyed by the
vertex (global vertex index). The slot records ``sf[k, slot, F_*]`` and the broken flags are
those of :mod:`murus.dem.kernels`. The first pair list starts bonded (contacts present at the
start carry the joint's cohesion and tension), later ones unbonded, as for the blocks.
Contacts form and break as the blocks and the zones move apart and come back (Savalle et al.
(2022), Figure 11: the backfill follows the wall).

Every block takes part, dynamic or kinematic: zones against a rigid base or a fixed block are
the same contacts (the coupled loop applies the forces to the dynamic bodies only).

Energy: slip dissipation and the energy released by breaking or opening contacts are
accumulated in ``E[IE_DSLIP]`` and ``E[IE_DBREAK]`` exactly as the blocks'
(``E_DSLIP``, ``E_DBREAK`` of :mod:`murus.dem.kernels`); the elastic energy stored in the
interface springs is :func:`stored_energy`. A contact whose tributary length or plane changes
keeps its shear stress (its force scales with its stiffness, projected on the new tangent,
:func:`_carry`), and the elastic energy that the change of stiffness releases or adds, like
that of a contact formed already pressed, goes to ``E[IE_DBREAK]`` (negative when gained), so
that the balance of the coupled model (:meth:`murus.continuum.coupled.CoupledModel.energy`)
accounts for every joule the interface's discretisation moves. ``E[IE_WZONE]`` and
``E[IE_TZONE]`` hold the work of the interface forces on the zones (written by the coupled
loop). Rolling resistance is not applied at the interface (a gridpoint has no rotation to
take the reaction moment).

Units: SI; forces [N] for the out-of-plane thickness ``P_THICK`` (the blocks' thickness). A
continuum model per metre of thickness (:class:`murus.continuum.ContinuumModel`) takes the
gridpoint forces divided by the thickness.

Layouts: parameters ``IP_*``, energies ``IE_*``, counters ``IC_*`` below; structures
:class:`IfaceGeom`, :class:`GridSide`, :class:`IfaceState`, :class:`IfaceWork`.

References
----------
Savalle et al. (2022), eqs. 3-4 and Figure 11; Itasca UDEC, Theory and Background (contacts of
deformable blocks: gridpoint-to-edge contacts and the Coulomb slip joint); Cundall & Hart
(1992) (rounded corners and contact detection of the distinct element method).
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np
from numba import njit

from murus._jit import guard_cache as _guard_cache
from murus.continuum import DEFAULT_CORNER_SHARE
from murus.dem._kdata import Contacts, PairMotion, SubContact
from murus.dem.kernels import (
    F_FN,
    F_FS,
    F_KNA,
    F_KSA,
    F_NX,
    F_NY,
    F_PX,
    F_PY,
    J_KN,
    J_KS,
    J_T,
    NSF,
    _joint_law,
    _released,
    _store,
    merge_contacts,
    point_separation,
    shape_boxes,
)
from murus.errors import MurusError

__all__ = ["GridSide", "IfaceGeom", "IfaceState", "IfaceWork", "Interface", "InterfaceError",
           "CORNER_SHARES", "interface_forces", "step", "rebuild", "candidates", "transfer",
           "moved",
           "node_contacts", "corner_contacts", "stored_energy",
           "IP_DT", "IP_THICK", "IP_MARGIN", "IP_REACH", "IP_DEPTH", "IP_SHRINK", "NIP",
           "IE_DSLIP", "IE_DBREAK", "IE_WZONE", "IE_TZONE", "NIE", "IC_STEP", "IC_REBUILD",
           "IC_NEED_REBUILD",
           "IC_NODES", "IC_CORNERS", "NIC"]

# ---- parameter vector ------------------------------------------------------------------------
IP_DT = 0  # time step [s]
IP_THICK = 1  # out-of-plane thickness [m]
IP_MARGIN = 2  # broad-phase margin [m]
IP_REACH = 3  # largest positive gap at which a contact is kept [m] (max T / kn)
IP_DEPTH = 4  # deepest penetration of a block corner behind a zone edge that is a contact [m]
IP_SHRINK = 5  # 1: a loaded corner's share of a face may shrink, not grow (_kept_trib); 0: both
NIP = 6

# ---- energy accumulators ---------------------------------------------------------------------
IE_DSLIP = 0  # frictional (slip) dissipation [J]
IE_DBREAK = 1  # elastic energy released by breaking or opening contacts [J]
IE_WZONE = 2  # work of the interface forces on the zones' free gridpoints [J] (coupled loop)
IE_TZONE = 3  # of it, the half of the last step after the time of the stresses [J]
NIE = 4

# ---- counters --------------------------------------------------------------------------------
IC_STEP = 0
IC_REBUILD = 1
IC_NEED_REBUILD = 2  # 1: rebuild the candidate pairs at the next step
IC_NODES = 3  # active gridpoint contacts at the last step
IC_CORNERS = 4  # active corner contacts at the last step
NIC = 5

#: How a loaded corner contact's share of a block face follows the coverage rule (module doc):
#: "follow", up and down; "shrink", down only (:func:`_kept_trib`).
CORNER_SHARES = ("follow", "shrink")

GridSide = namedtuple("GridSide", ["gxy", "gvel"])
GridSide.__doc__ = """The zone side read by the interface kernels (a
:class:`murus.continuum._kdata.Grid` has the same fields and may be passed instead).

Attributes
----------
gxy : ndarray (ng, 2)
    Gridpoint coordinates [m].
gvel : ndarray (ng, 2)
    Gridpoint velocities at the half step ``t - dt/2`` [m/s].
"""

IfaceGeom = namedtuple("IfaceGeom", ["ig", "gloc", "ie", "jsel", "gep", "gei"])
IfaceGeom.__doc__ = """The interface (fixed during a run).

Attributes
----------
ig : ndarray (ni,) int64
    The interface gridpoints (global gridpoint indices, sorted).
gloc : ndarray (ng,) int64
    Local index into ``ig`` of each gridpoint, -1 off the interface.
ie : ndarray (ne, 2) int64
    The interface edges (global gridpoint indices), each a zone boundary edge oriented with
    its zone on the left (outward normal ``(dy, -dx) / L``).
jsel : ndarray (ngroup,) int64
    The joint row (of ``jprops``) of the contacts with the blocks of each group.
gep, gei : ndarray (ni + 1,), (2 ne,) int64
    The interface edges at each interface gridpoint (compressed rows): ``gei[gep[i]:gep[i + 1]]``
    are the edges (rows of ``ie``) that end at gridpoint ``ig[i]``.
"""

IfaceState = namedtuple("IfaceState", ["glast", "blast"])
IfaceState.__doc__ = """Reference positions of the last rebuild of the candidate pairs.

Attributes
----------
glast : ndarray (ni, 2)
    Positions of the interface gridpoints [m].
blast : ndarray (nb, 3)
    Positions and angles of the bodies (x, y [m], angle [rad]).
"""

IfaceWork = namedtuple("IfaceWork", ["fg", "fb", "eflag"])
IfaceWork.__doc__ = """Outputs and scratch arrays of a step (allocated once).

Attributes
----------
fg : ndarray (ng, 2)
    Interface forces on the gridpoints [N], added to by :func:`step`.
fb : ndarray (nb, 3)
    Interface forces (Fx, Fy) [N] and moments about the centroids [N m] on the bodies, added
    to by :func:`step`.
eflag : ndarray (nv, 2) float
    For each core edge (indexed by its first global vertex): the length along it [m], from its
    first (column 0) and from its last vertex (column 1), not covered by the tributary
    lengths of the gridpoints touching it in this step; for a disc (its centre), 0 when a
    gridpoint touches it; -1 where no gridpoint touches (the value between steps).
"""


# ---- candidate pairs -------------------------------------------------------------------------


@njit(cache=True, error_model="numpy")
def _query(box, order, x0s, wmax, qx0, qy0, qx1, qy1, keys, n, base, ns):
    """Append ``base * ns + s`` to ``keys`` (grown as needed) for every shape s whose box
    overlaps the query box; returns ``(keys, n)``."""
    lo = np.searchsorted(x0s, qx0 - wmax, side="left")
    hi = np.searchsorted(x0s, qx1, side="right")
    for j in range(lo, hi):
        s = order[j]
        if box[s, 2] < qx0 or box[s, 1] > qy1 or box[s, 3] < qy0:
            continue
        if n == keys.size:
            nk = np.empty(2 * keys.size + 16, np.int64)
            nk[:n] = keys[:n]
            keys = nk
        keys[n] = base * ns + s
        n += 1
    return keys, n


@njit(cache=True, error_model="numpy")
def candidates(geo, gxy, shapes, margin):
    """Candidate pairs of the interface: the shapes whose bounding box (rounded, inflated by
    ``margin``) holds an interface gridpoint or overlaps an interface edge's box (sort on x and
    binary search).

    Parameters
    ----------
    geo : IfaceGeom
        The interface.
    gxy : ndarray (ng, 2)
        Gridpoint coordinates [m].
    shapes : murus.dem._kdata.Shapes
        The blocks' shapes (``wv`` current).
    margin : float
        Broad-phase margin [m].

    Returns
    -------
    node_pairs : ndarray (n1, 2) int64
        Rows ``(interface gridpoint i, shape s)``, sorted by ``i * ns + s``.
    corner_pairs : ndarray (n2, 2) int64
        Rows ``(interface edge e, shape s)``, sorted by ``e * ns + s``.

    References
    ----------
    Itasca UDEC, Theory and Background (contact detection with a margin).
    """
    box, order, wmax = shape_boxes(shapes, margin)
    ns = box.shape[0]
    x0s = np.empty(ns)
    for j in range(ns):
        x0s[j] = box[order[j], 0]
    ig = geo.ig
    ie = geo.ie
    keys = np.empty(2 * ig.size + 16, np.int64)
    n = 0
    for i in range(ig.size):
        x = gxy[ig[i], 0]
        y = gxy[ig[i], 1]
        keys, n = _query(box, order, x0s, wmax, x, y, x, y, keys, n, i, ns)
    nk = np.sort(keys[:n])
    npairs = np.empty((n, 2), np.int64)
    for k in range(n):
        npairs[k, 0] = nk[k] // ns
        npairs[k, 1] = nk[k] % ns
    keys = np.empty(2 * ie.shape[0] + 16, np.int64)
    n = 0
    for e in range(ie.shape[0]):
        ax = gxy[ie[e, 0], 0]
        ay = gxy[ie[e, 0], 1]
        bx = gxy[ie[e, 1], 0]
        by = gxy[ie[e, 1], 1]
        keys, n = _query(box, order, x0s, wmax, min(ax, bx), min(ay, by), max(ax, bx),
                         max(ay, by), keys, n, e, ns)
    ck = np.sort(keys[:n])
    cpairs = np.empty((n, 2), np.int64)
    for k in range(n):
        cpairs[k, 0] = ck[k] // ns
        cpairs[k, 1] = ck[k] % ns
    return npairs, cpairs


@njit(cache=True, error_model="numpy")
def transfer(old, new_pairs, ns, jsel, sgroup, bond_new):
    """The contacts of a new pair list, carrying the slots of the pairs present in the old
    one too (:func:`murus.dem.kernels.merge_contacts`, as the blocks' transfer).

    Parameters
    ----------
    old : murus.dem._kdata.Contacts
        The current contacts.
    new_pairs : ndarray (n, 2) int64
        The new pair list, rows (i, s) sorted by ``i * ns + s``.
    ns : int
        Number of shapes.
    jsel : ndarray (ngroup,) int64
        Joint row of each block group: the joint of a pair is ``jsel[sgroup[s]]``.
    sgroup : ndarray (ns,) int64
        Group of each shape.
    bond_new : int
        1: the new pairs start bonded.

    Returns
    -------
    murus.dem._kdata.Contacts
        The new contacts.

    References
    ----------
    Itasca UDEC, Theory and Background (contact detection with a margin).
    """
    n = new_pairs.shape[0]
    pj = np.empty(n, np.int64)
    for k in range(n):
        pj[k] = jsel[sgroup[new_pairs[k, 1]]]
    return merge_contacts(old, new_pairs, ns, pj, bond_new)


@njit(cache=True, error_model="numpy")
def _released_pairs(old, new_pairs, ns):
    """Shear spring energy [J] of the active slots of ``old`` whose pair is not in
    ``new_pairs`` (a rebuild drops them: they are released)."""
    e = 0.0
    j = 0
    n = new_pairs.shape[0]
    for k in range(old.pairs.shape[0]):
        key = old.pairs[k, 0] * ns + old.pairs[k, 1]
        while j < n and new_pairs[j, 0] * ns + new_pairs[j, 1] < key:
            j += 1
        if j < n and new_pairs[j, 0] * ns + new_pairs[j, 1] == key:
            continue
        for o in range(2):
            if old.sid[k, o] >= 0:
                e += _released(k, o, old.sf)
    return e


@njit(cache=True, error_model="numpy")
def rebuild(P, E, C, geo, gxy, bodies, shapes, nodes, corners, state, bond_new):
    """Rebuild the candidate pairs (:func:`candidates`) and carry over the state of the pairs
    that remain (:func:`transfer`); the shear energy of active contacts whose pair left the
    list is added to ``E[IE_DBREAK]``; the reference positions ``state`` are reset.

    Parameters
    ----------
    P, E, C : ndarray
        Parameters ``IP_*``, energies ``IE_*`` [J] (added to), counters ``IC_*``.
    geo : IfaceGeom
        The interface.
    gxy : ndarray (ng, 2)
        Gridpoint coordinates [m].
    bodies, shapes : murus.dem._kdata.Bodies, murus.dem._kdata.Shapes
        The blocks (``shapes.wv`` current).
    nodes, corners : murus.dem._kdata.Contacts
        The current gridpoint and corner contacts.
    state : IfaceState
        Reference positions, reset here.
    bond_new : int
        1: the new pairs start bonded (the first list), 0: unbonded.

    Returns
    -------
    tuple of 12 arrays
        The arrays of the new node and corner contacts (the fields of
        :class:`murus.dem._kdata.Contacts` of the nodes, then of the corners): a plain tuple,
        which numba boxes without calling a Python class (as
        :func:`murus.dem.kernels.transfer_arrays`).

    References
    ----------
    Itasca UDEC, Theory and Background (contact detection with a margin).
    """
    ns = shapes.svs.size
    npairs, cpairs = candidates(geo, gxy, shapes, P[IP_MARGIN])
    E[IE_DBREAK] += (_released_pairs(nodes, npairs, ns) + _released_pairs(corners, cpairs, ns))
    nn = transfer(nodes, npairs, ns, geo.jsel, shapes.sgroup, bond_new)
    cc = transfer(corners, cpairs, ns, geo.jsel, shapes.sgroup, bond_new)
    ig = geo.ig
    for i in range(ig.size):
        state.glast[i, 0] = gxy[ig[i], 0]
        state.glast[i, 1] = gxy[ig[i], 1]
    bpos = bodies.bpos
    for b in range(bpos.shape[0]):
        state.blast[b, 0] = bpos[b, 0]
        state.blast[b, 1] = bpos[b, 1]
        state.blast[b, 2] = bodies.bang[b]
    C[IC_REBUILD] += 1
    C[IC_NEED_REBUILD] = 0
    return (nn.pairs, nn.pj, nn.pbond, nn.sid, nn.sf, nn.sbr,
            cc.pairs, cc.pj, cc.pbond, cc.sid, cc.sf, cc.sbr)


@njit(cache=True, error_model="numpy")
def moved(geo, gxy, bodies, state, margin):
    """Whether an interface gridpoint or a body has moved by more than half the margin since
    the last rebuild (a body: translation plus rotation times its bounding radius, as
    :func:`murus.dem.kernels._moved`).

    Parameters
    ----------
    geo : IfaceGeom
        The interface.
    gxy : ndarray (ng, 2)
        Gridpoint coordinates [m].
    bodies : murus.dem._kdata.Bodies
        The blocks.
    state : IfaceState
        Positions at the last rebuild.
    margin : float
        Broad-phase margin [m].

    Returns
    -------
    bool
        True when the candidate pairs must be rebuilt.

    References
    ----------
    Itasca UDEC, Theory and Background (contact detection with a margin).
    """
    h = 0.5 * margin
    ig = geo.ig
    for i in range(ig.size):
        dx = gxy[ig[i], 0] - state.glast[i, 0]
        dy = gxy[ig[i], 1] - state.glast[i, 1]
        if dx * dx + dy * dy > h * h:
            return True
    bpos = bodies.bpos
    for b in range(bpos.shape[0]):
        dx = bpos[b, 0] - state.blast[b, 0]
        dy = bpos[b, 1] - state.blast[b, 1]
        if (math.sqrt(dx * dx + dy * dy) + abs(bodies.bang[b] - state.blast[b, 2])
                * bodies.brad[b] > h):
            return True
    return False


# ---- narrow phase ----------------------------------------------------------------------------


@njit(cache=True, error_model="numpy", inline="always")
def _node_polygon(px, py, wv, a0, na, r, reach):
    """Gridpoint (px, py) against the rounded polygon of core ``wv[a0:a0+na]``, rounding r:
    ``(found, nx, ny, gap, e0, e1)`` with the normal from the gridpoint to the polygon, the gap
    to the rounded surface [m], and the core edges (first global vertex index) touched, ``e1``
    -1 unless the nearest core point is a vertex (then both edges at it)."""
    best, be = point_separation(wv, a0, na, px, py)
    if best - r > reach:
        return False, 0.0, 0.0, 0.0, -1, -1
    if best <= 0.0:  # inside the core: the edge of least penetration
        ax = wv[a0 + be, 0]
        ay = wv[a0 + be, 1]
        j1 = a0 + (be + 1) % na
        ex = wv[j1, 0] - ax
        ey = wv[j1, 1] - ay
        L = math.sqrt(ex * ex + ey * ey)
        return True, -ey / L, ex / L, best - r, a0 + be, -1
    dmin = np.inf
    qx = 0.0
    qy = 0.0
    e0 = -1
    e1 = -1
    for i in range(na):
        ax = wv[a0 + i, 0]
        ay = wv[a0 + i, 1]
        j1 = a0 + (i + 1) % na
        ex = wv[j1, 0] - ax
        ey = wv[j1, 1] - ay
        u = ((px - ax) * ex + (py - ay) * ey) / (ex * ex + ey * ey)
        if u < 0.0:
            u = 0.0
        elif u > 1.0:
            u = 1.0
        cx = ax + u * ex
        cy = ay + u * ey
        dd = (px - cx) ** 2 + (py - cy) ** 2
        if dd < dmin:
            dmin = dd
            qx = cx
            qy = cy
            e0 = a0 + i
            if u == 0.0:
                e1 = a0 + (i + na - 1) % na
            elif u == 1.0:
                e1 = j1
            else:
                e1 = -1
    d = math.sqrt(dmin)
    if d - r > reach:
        return False, 0.0, 0.0, 0.0, -1, -1
    return True, (qx - px) / d, (qy - py) / d, d - r, e0, e1


@njit(cache=True, error_model="numpy", inline="always")
def _carry(k, o, sf, nx, ny, ksa, kn_ratio):
    """Carry the shear force of old slot ``o`` of pair k over to the contact of this step,
    of unit normal (nx, ny), shear stiffness ``ksa`` [N/m] and normal stiffness ``kn_ratio``
    times the old one, in place; returns the elastic energy released [J] (negative: gained)
    by the change of stiffness (the normal spring's at its old gap).

    The contact keeps its shear stress, not its force, when its tributary length changes (a
    gridpoint whose neighbour comes under or leaves a block's face, a block corner whose
    adjacent faces change): the force scales with the new stiffness, as the normal force does
    through the gap. When the contact plane turned (a gridpoint going round a block's rounded
    corner), the force keeps its projection on the new tangent (UDEC, PFC: the shear force
    rotated with the contact plane). Without this a stiffness that shrinks under a kept force
    (``fs² / 2 ks A``) was taken for frictional slip, of up to a thousand joules in one step.
    """
    # the normal spring: its energy at the old gap, with the old and the new stiffness
    kno = sf[k, o, F_KNA]
    out = 0.0
    if kno > 0.0:
        fn = sf[k, o, F_FN]
        out = 0.5 * fn * fn / kno * (1.0 - kn_ratio)
    fs = sf[k, o, F_FS]
    ko = sf[k, o, F_KSA]
    if fs == 0.0 or ko <= 0.0:
        return out
    cth = nx * sf[k, o, F_NX] + ny * sf[k, o, F_NY]
    if cth < 0.0:
        cth = 0.0
    elif cth > 1.0:
        cth = 1.0
    before = 0.5 * fs * fs / ko
    if ksa <= 0.0:
        sf[k, o, F_FS] = 0.0
        return out + before
    f1 = fs * cth * ksa / ko
    sf[k, o, F_FS] = f1
    return out + before - 0.5 * f1 * f1 / ksa


@njit(cache=True, error_model="numpy", inline="always")
def _kept_trib(k, v, sid, sf, knt):
    """Tributary length [m] of the corner contact of vertex ``v`` in pair k if it carries a
    force (normal or shear), 0 otherwise (``knt``: the joint's normal stiffness times the
    thickness [N/m²]): the most that the contact may take this step with
    ``corner_share="shrink"``.

    A corner's share of a block face follows the coverage rule (module doc) when its contact
    forms or carries no force. The coverage jumps when a gridpoint next to the corner starts
    or stops touching the face, and a stiffness that jumps up under load (the stress kept)
    gives the contact energy: a rocking corner takes energy on every cycle, its stiffness
    growing when it is deep in the zone edge (the face lifted off the gridpoint) and
    shrinking when it is shallow. With the rule followed up and down ("follow") this gave
    all of the -14.6 mJ that the interface gained in 0.5 s of the H/B = 1.7 mock-up at the
    printed joint stiffness and set off a creep (VALIDATION.md, *Subcycling*). With
    "shrink", a shrinking stiffness releases energy (booked as breaking) and a growing one
    waits until the contact is unloaded, so the discretisation never gives energy to a
    loaded corner. While the face next to a loaded corner lifts off a gridpoint, the corner
    carries only what it carried with the gridpoint touching (it presses in deeper). Checked
    against references (VALIDATION.md, *The corner rule*): a block rocking freely on the
    springs keeps the half-period of the exact Winkler model within 1.1 % ("follow": 1 to 3 %
    short), and a stack rocking on a coarse layer rises as on a fine one, where the two rules
    agree ("follow": 10 to 20 times more, with energy its contacts create)."""
    for o in range(2):
        if sid[k, o] == v and (sf[k, o, F_FN] != 0.0 or sf[k, o, F_FS] != 0.0):
            return sf[k, o, F_KNA] / knt
    return 0.0


@njit(cache=True, error_model="numpy", inline="always")
def _corner_trib(wv, a0, na, k, tx, ty, nzx, nzy, eflag):
    """Tributary length [m] of core vertex ``a0 + k`` against a zone edge of unit direction
    (tx, ty) and outward normal (nzx, nzy): for each of its two adjacent core edges that faces
    the zone edge, the part of the edge next to the vertex that no gridpoint's tributary length
    covers this step (``eflag``; half the edge when no gridpoint touches it), projected on the
    zone edge (module doc, the coverage rule)."""
    trib = 0.0
    for side in range(2):
        i = (k + na - 1) % na if side == 0 else k  # edge i runs from vertex i to i + 1
        j1 = a0 + (i + 1) % na
        ex = wv[j1, 0] - wv[a0 + i, 0]
        ey = wv[j1, 1] - wv[a0 + i, 1]
        # outward normal of a counter-clockwise core edge: (ey, -ex) / L; facing: opposed to nz
        if ey * nzx - ex * nzy < 0.0:
            L = math.sqrt(ex * ex + ey * ey)
            # the vertex is the last of edge i on side 0, the first of edge k on side 1
            cov = eflag[a0 + i, 1 - side]
            part = 0.5 * L if cov < 0.0 else min(cov, L)
            if L > 0.0:
                trib += part * abs(ex * tx + ey * ty) / L
    return trib


@njit(cache=True, error_model="numpy", inline="always")
def _cover(eflag, wv, a0, na, e, px, py, qlo, qhi):
    """Record on core edge ``e`` (global index of its first vertex; shape vertices
    ``a0 .. a0 + na - 1``) that a gridpoint at (px, py), whose tributary extends from ``qlo``
    to ``qhi`` [m] along the edge's direction about it (qlo <= 0 <= qhi), covers part of it:
    the uncovered lengths from either end shrink to what is left (:func:`_corner_trib`)."""
    j1 = a0 + ((e - a0) + 1) % na
    ex = wv[j1, 0] - wv[e, 0]
    ey = wv[j1, 1] - wv[e, 1]
    L = math.sqrt(ex * ex + ey * ey)
    if L <= 0.0:
        return
    sa = ((px - wv[e, 0]) * ex + (py - wv[e, 1]) * ey) / L
    ua = min(max(sa + qlo, 0.0), L)
    ub = min(max(L - (sa + qhi), 0.0), L)
    if eflag[e, 0] < 0.0 or ua < eflag[e, 0]:
        eflag[e, 0] = ua
    if eflag[e, 1] < 0.0 or ub < eflag[e, 1]:
        eflag[e, 1] = ub


@njit(cache=True, error_model="numpy", inline="always")
def _half_edges(i, g, gxy, ie, gep, gei, dx, dy):
    """Extent ``(lo, hi)`` [m] along the unit direction (dx, dy) of the halves of gridpoint
    ``g``'s interface edges (local index ``i``), about the gridpoint (lo <= 0 <= hi)."""
    lo = 0.0
    hi = 0.0
    for j in range(gep[i], gep[i + 1]):
        e = gei[j]
        o = ie[e, 1] if ie[e, 0] == g else ie[e, 0]
        q = 0.5 * ((gxy[o, 0] - gxy[g, 0]) * dx + (gxy[o, 1] - gxy[g, 1]) * dy)
        if q < lo:
            lo = q
        if q > hi:
            hi = q
    return lo, hi


# ---- the step --------------------------------------------------------------------------------


@njit(cache=True, error_model="numpy")
def node_contacts(P, E, geo, side, bodies, shapes, jprops, c, work):
    """Step 1: the gridpoint contacts (module doc), with the blocks' joint law; the lengths of
    the core edges they cover are written to ``work.eflag`` for :func:`corner_contacts`.

    Parameters
    ----------
    P, E : ndarray
        Parameters ``IP_*``; energies ``IE_*`` [J], added to.
    geo : IfaceGeom
        The interface.
    side : GridSide
        Gridpoint coordinates [m] and half-step velocities [m/s].
    bodies, shapes : murus.dem._kdata.Bodies, murus.dem._kdata.Shapes
        The blocks.
    jprops : ndarray (nj, NJ)
        Joint rows.
    c : murus.dem._kdata.Contacts
        The node pairs and their slots, updated in place.
    work : IfaceWork
        Forces added to ``fg`` [N] and ``fb`` [N, N m]; ``eflag`` written.

    Returns
    -------
    int
        The number of active contacts.

    References
    ----------
    Savalle et al. (2022), eqs. 3-4; Itasca UDEC, Theory and Background.
    """
    gxy = side.gxy
    gvel = side.gvel
    ig = geo.ig
    ie = geo.ie
    gep = geo.gep
    gei = geo.gei
    wv = shapes.wv
    svs = shapes.svs
    svn = shapes.svn
    skind = shapes.skind
    srad = shapes.srad
    sbody = shapes.sbody
    bpos = bodies.bpos
    bvel = bodies.bvel
    bomg = bodies.bomg
    fg = work.fg
    fb = work.fb
    eflag = work.eflag
    pairs = c.pairs
    sid = c.sid
    sf = c.sf
    sbr = c.sbr
    pbond = c.pbond
    dt = P[IP_DT]
    thick = P[IP_THICK]
    reach = P[IP_REACH]
    cst = (thick, reach, dt)
    d_slip = 0.0
    d_break = 0.0
    nact = 0
    for k in range(pairs.shape[0]):
        i = pairs[k, 0]
        s = pairs[k, 1]
        g = ig[i]
        px = gxy[g, 0]
        py = gxy[g, 1]
        if skind[s] == 0:
            found, nx, ny, gap, e0, e1 = _node_polygon(px, py, wv, svs[s], svn[s], srad[s],
                                                       reach)
        else:
            ic = svs[s]
            dx = wv[ic, 0] - px
            dy = wv[ic, 1] - py
            d = math.sqrt(dx * dx + dy * dy)
            found = d - srad[s] <= reach and d > 0.0
            nx = dx / d if found else 0.0
            ny = dy / d if found else 0.0
            gap = d - srad[s]
            e0 = ic
            e1 = -1
        o = 0 if sid[k, 0] >= 0 else -1
        if not found:
            if o >= 0:
                d_break += _released(k, 0, sf)
            sid[k, 0] = -1
            sbr[k, 0] = 0
            continue
        # tributary length: the halves of the gridpoint's interface edges, projected on the
        # contact's tangent (the full half-edges on a flat boundary; at a corner of the zone
        # boundary, only the side along the block's face), and of them the part that faces
        # the block (its extent along the tangent, rounding included): a gridpoint near the
        # end of a block's face, or at the joint of two blocks, shares its length with them
        tx = -ny
        ty = nx
        smin = np.inf
        smax = -np.inf
        if skind[s] == 0:
            for j in range(svs[s], svs[s] + svn[s]):
                q = (wv[j, 0] - px) * tx + (wv[j, 1] - py) * ty
                smin = min(smin, q)
                smax = max(smax, q)
        else:
            q = (wv[svs[s], 0] - px) * tx + (wv[svs[s], 1] - py) * ty
            smin = q - srad[s]
            smax = q + srad[s]
        trib = 0.0
        for j in range(gep[i], gep[i + 1]):
            e = gei[j]
            o2 = ie[e, 1] if ie[e, 0] == g else ie[e, 0]
            q = 0.5 * ((gxy[o2, 0] - px) * tx + (gxy[o2, 1] - py) * ty)
            lo = max(min(q, 0.0), smin)
            hi = min(max(q, 0.0), smax)
            if hi > lo:
                trib += hi - lo
        if trib <= 0.0:
            if o >= 0:
                d_break += _released(k, 0, sf)
            sid[k, 0] = -1
            sbr[k, 0] = 0
            continue
        b = sbody[s]
        if o >= 0:
            jq = c.pj[k]
            kr = (jprops[jq, J_KN] * trib * thick / sf[k, o, F_KNA] if sf[k, o, F_KNA] > 0.0
                  else 1.0)
            d_break += _carry(k, o, sf, nx, ny, jprops[jq, J_KS] * trib * thick, kr)
        pm = PairMotion(gvel[g, 0], gvel[g, 1], 0.0, px, py, bvel[b, 0], bvel[b, 1], bomg[b],
                        bpos[b, 0], bpos[b, 1])
        pt = SubContact(px, py, nx, ny, gap, trib)
        (keep, br, pb, fn, fs, mr, kna, ksa, kra, ds, dr, db) = _joint_law(
            o, k, sf, sbr, pbond[k], jprops, c.pj[k], False, 0.0, pt, pm, cst)
        pbond[k] = pb
        d_slip += ds
        d_break += db
        if not keep:
            sid[k, 0] = -1
            sbr[k, 0] = 0
            continue
        if o < 0 and fn > 0.0 and kna > 0.0:  # formed already pressed: energy gained
            d_break -= 0.5 * fn * fn / kna
        fx, fy, mb, ma = _store(k, 0, sid, sf, sbr, e0, br, (fn, fs, mr), (kna, ksa, kra), pt,
                                pm)
        fb[b, 0] += fx
        fb[b, 1] += fy
        fb[b, 2] += mb
        fg[g, 0] -= fx
        fg[g, 1] -= fy
        if gap <= 0.0 or fn != 0.0:  # touching, or a bond holding: the face is carried
            if skind[s] == 0:
                for ee in (e0, e1):
                    if ee >= 0:
                        j1 = svs[s] + ((ee - svs[s]) + 1) % svn[s]
                        ux = wv[j1, 0] - wv[ee, 0]
                        uy = wv[j1, 1] - wv[ee, 1]
                        Lu = math.sqrt(ux * ux + uy * uy)
                        if Lu > 0.0:
                            lo, hi = _half_edges(i, g, gxy, ie, gep, gei, ux / Lu, uy / Lu)
                            _cover(eflag, wv, svs[s], svn[s], ee, px, py, lo, hi)
            else:
                eflag[e0, 0] = 0.0
        nact += 1
    E[IE_DSLIP] += d_slip
    E[IE_DBREAK] += d_break
    return nact


@njit(cache=True, error_model="numpy")
def corner_contacts(P, E, geo, side, bodies, shapes, jprops, c, work):
    """Step 2: the block corners (polygon core vertices, disc centres) against the interface
    edges (module doc), two slots per pair keyed by the vertex, the reactions to the edge's
    gridpoints with the weights ``(1 - s, s)``, the tributary lengths by the coverage rule
    (read from ``work.eflag``, written by :func:`node_contacts` in the same step).

    Parameters
    ----------
    P, E : ndarray
        Parameters ``IP_*``; energies ``IE_*`` [J], added to.
    geo : IfaceGeom
        The interface.
    side : GridSide
        Gridpoint coordinates [m] and half-step velocities [m/s].
    bodies, shapes : murus.dem._kdata.Bodies, murus.dem._kdata.Shapes
        The blocks.
    jprops : ndarray (nj, NJ)
        Joint rows.
    c : murus.dem._kdata.Contacts
        The corner pairs and their slots, updated in place.
    work : IfaceWork
        Forces added to ``fg`` [N] and ``fb`` [N, N m]; ``eflag`` read.

    Returns
    -------
    int
        The number of active contacts.

    References
    ----------
    Savalle et al. (2022), eqs. 3-4; Itasca UDEC, Theory and Background.
    """
    gxy = side.gxy
    gvel = side.gvel
    ie = geo.ie
    wv = shapes.wv
    svs = shapes.svs
    svn = shapes.svn
    skind = shapes.skind
    srad = shapes.srad
    sbody = shapes.sbody
    bpos = bodies.bpos
    bvel = bodies.bvel
    bomg = bodies.bomg
    fg = work.fg
    fb = work.fb
    eflag = work.eflag
    pairs = c.pairs
    sid = c.sid
    sf = c.sf
    sbr = c.sbr
    pbond = c.pbond
    dt = P[IP_DT]
    thick = P[IP_THICK]
    reach = P[IP_REACH]
    depth = P[IP_DEPTH]
    shrink = P[IP_SHRINK] > 0.0
    cst = (thick, reach, dt)
    d_slip = 0.0
    d_break = 0.0
    nact = 0
    for k in range(pairs.shape[0]):
        e = pairs[k, 0]
        s = pairs[k, 1]
        g0 = ie[e, 0]
        g1 = ie[e, 1]
        ax = gxy[g0, 0]
        ay = gxy[g0, 1]
        ex = gxy[g1, 0] - ax
        ey = gxy[g1, 1] - ay
        L = math.sqrt(ex * ex + ey * ey)
        tx = ex / L
        ty = ey / L
        nzx = ty  # outward normal (zone on the left of the edge)
        nzy = -tx
        r = srad[s]
        a0 = svs[s]
        na = svn[s]
        # the two contacts of least gap (vertex v, gap g, parameter u, tributary w)
        v0 = -1
        v1 = -1
        gp0 = 0.0
        gp1 = 0.0
        u0 = 0.0
        u1 = 0.0
        w0 = 0.0
        w1 = 0.0
        for j in range(na):
            qx = wv[a0 + j, 0] - ax
            qy = wv[a0 + j, 1] - ay
            u = (qx * tx + qy * ty) / L
            if u < 0.0 or u > 1.0:
                continue
            gap = qx * nzx + qy * nzy - r
            if gap > reach or gap < -depth:
                continue
            if skind[s] == 0:
                w = _corner_trib(wv, a0, na, j, tx, ty, nzx, nzy, eflag)
            else:
                w = 0.0 if eflag[a0, 0] >= 0.0 else 2.0 * r
            if shrink:  # a loaded contact's tributary length may shrink (by more than a
                # part in 1e6: not with the rounding of a block's turn), not grow
                wk = _kept_trib(k, a0 + j, sid, sf, jprops[c.pj[k], J_KN] * thick)
                if wk > 0.0 and w > wk * (1.0 - 1e-6):
                    w = wk
            if w <= 0.0:
                continue
            if v0 < 0 or gap < gp0:
                v1 = v0
                gp1 = gp0
                u1 = u0
                w1 = w0
                v0 = a0 + j
                gp0 = gap
                u0 = u
                w0 = w
            elif v1 < 0 or gap < gp1:
                v1 = a0 + j
                gp1 = gap
                u1 = u
                w1 = w
        s0 = sid[k, 0]
        s1 = sid[k, 1]
        # match by key (the vertex)
        m0 = -1
        m1 = -1
        if v0 >= 0:
            if s0 == v0:
                m0 = 0
            elif s1 == v0:
                m0 = 1
        if v1 >= 0:
            if s0 == v1:
                m1 = 0
            elif s1 == v1:
                m1 = 1
        if s0 >= 0 and m0 != 0 and m1 != 0:
            d_break += _released(k, 0, sf)
        if s1 >= 0 and m0 != 1 and m1 != 1:
            d_break += _released(k, 1, sf)
        nkeep = 0
        if v0 >= 0:
            b = sbody[s]
            jp = c.pj[k]
            pb = pbond[k]
            pmx = (bvel[b, 0], bvel[b, 1], bomg[b], bpos[b, 0], bpos[b, 1])
            # both laws read the old slots before either is written
            cx0 = ax + u0 * ex
            cy0 = ay + u0 * ey
            pm0 = PairMotion((1.0 - u0) * gvel[g0, 0] + u0 * gvel[g1, 0],
                             (1.0 - u0) * gvel[g0, 1] + u0 * gvel[g1, 1], 0.0, cx0, cy0,
                             pmx[0], pmx[1], pmx[2], pmx[3], pmx[4])
            pt0 = SubContact(cx0, cy0, nzx, nzy, gp0, w0)
            ks_t = jprops[jp, J_KS] * thick
            kn_t = jprops[jp, J_KN] * thick
            if m0 >= 0 and sf[k, m0, F_KNA] > 0.0:
                d_break += _carry(k, m0, sf, nzx, nzy, ks_t * w0, kn_t * w0 / sf[k, m0, F_KNA])
            if v1 >= 0 and m1 >= 0 and sf[k, m1, F_KNA] > 0.0:
                d_break += _carry(k, m1, sf, nzx, nzy, ks_t * w1, kn_t * w1 / sf[k, m1, F_KNA])
            (keep0, br0, pb, fn0, fs0, mr0, kna0, ksa0, kra0, ds, dr, db) = _joint_law(
                m0, k, sf, sbr, pb, jprops, jp, False, 0.0, pt0, pm0, cst)
            d_slip += ds
            d_break += db
            cx1 = ax + u1 * ex
            cy1 = ay + u1 * ey
            pm1 = PairMotion((1.0 - u1) * gvel[g0, 0] + u1 * gvel[g1, 0],
                             (1.0 - u1) * gvel[g0, 1] + u1 * gvel[g1, 1], 0.0, cx1, cy1,
                             pmx[0], pmx[1], pmx[2], pmx[3], pmx[4])
            pt1 = SubContact(cx1, cy1, nzx, nzy, gp1, w1)
            keep1 = False
            if v1 >= 0:
                (keep1, br1, pb, fn1, fs1, mr1, kna1, ksa1, kra1, ds, dr, db) = _joint_law(
                    m1, k, sf, sbr, pb, jprops, jp, False, 0.0, pt1, pm1, cst)
                d_slip += ds
                d_break += db
            else:
                br1 = 0
                fn1 = 0.0
                fs1 = 0.0
                mr1 = 0.0
                kna1 = 0.0
                ksa1 = 0.0
                kra1 = 0.0
            pbond[k] = pb
            # a contact formed already pressed: the energy of its spring is gained
            if keep0 and m0 < 0 and fn0 > 0.0 and kna0 > 0.0:
                d_break -= 0.5 * fn0 * fn0 / kna0
            if keep1 and m1 < 0 and fn1 > 0.0 and kna1 > 0.0:
                d_break -= 0.5 * fn1 * fn1 / kna1
            if keep0:
                fx, fy, mb, ma = _store(k, 0, sid, sf, sbr, v0, br0, (fn0, fs0, mr0),
                                        (kna0, ksa0, kra0), pt0, pm0)
                fb[b, 0] += fx
                fb[b, 1] += fy
                fb[b, 2] += mb
                fg[g0, 0] -= (1.0 - u0) * fx
                fg[g0, 1] -= (1.0 - u0) * fy
                fg[g1, 0] -= u0 * fx
                fg[g1, 1] -= u0 * fy
                nkeep = 1
            if keep1:
                fx, fy, mb, ma = _store(k, nkeep, sid, sf, sbr, v1, br1, (fn1, fs1, mr1),
                                        (kna1, ksa1, kra1), pt1, pm1)
                fb[b, 0] += fx
                fb[b, 1] += fy
                fb[b, 2] += mb
                fg[g0, 0] -= (1.0 - u1) * fx
                fg[g0, 1] -= (1.0 - u1) * fy
                fg[g1, 0] -= u1 * fx
                fg[g1, 1] -= u1 * fy
                nkeep += 1
        for o in range(nkeep, 2):
            sid[k, o] = -1
            sbr[k, o] = 0
        nact += nkeep
    E[IE_DSLIP] += d_slip
    E[IE_DBREAK] += d_break
    return nact


@njit(cache=True, error_model="numpy")
def _clear_flags(nodes, shapes, eflag):
    """Reset the edge coverage of the shapes of the node pairs (the only ones set this step)
    to -1 (no gridpoint)."""
    svs = shapes.svs
    svn = shapes.svn
    for k in range(nodes.pairs.shape[0]):
        s = nodes.pairs[k, 1]
        for v in range(svs[s], svs[s] + svn[s]):
            eflag[v, 0] = -1.0
            eflag[v, 1] = -1.0


@njit(cache=True, error_model="numpy")
def step(P, E, C, geo, side, bodies, shapes, jprops, nodes, corners, state, work):
    """One step of the interface: rebuild the candidate pairs when something moved by more
    than half the margin (:func:`moved`, :func:`rebuild`), then the gridpoint contacts
    (:func:`node_contacts`), then the corner contacts (:func:`corner_contacts`); forces
    added to ``work.fg`` [N] and ``work.fb`` [N, N m].

    Parameters
    ----------
    P : ndarray (NIP,)
        Parameters ``IP_*`` (time step [s], thickness [m], margin [m], reach [m], depth [m]).
    E : ndarray (NIE,)
        Energy accumulators ``IE_*`` [J], added to.
    C : ndarray (NIC,) int64
        Counters ``IC_*``.
    geo : IfaceGeom
        The interface.
    side : GridSide or murus.continuum._kdata.Grid
        Gridpoint coordinates [m] and half-step velocities [m/s].
    bodies, shapes : murus.dem._kdata.Bodies, murus.dem._kdata.Shapes
        The blocks (``shapes.wv`` current).
    jprops : ndarray (nj, NJ)
        Joint rows (``J_*`` columns of :mod:`murus.dem.kernels`).
    nodes, corners : murus.dem._kdata.Contacts
        The gridpoint and corner contacts, updated in place.
    state : IfaceState
        Reference positions of the last rebuild.
    work : IfaceWork
        Outputs and scratch arrays.

    Returns
    -------
    tuple of 12 arrays
        The arrays of the node and corner contacts (new ones after a rebuild), as
        :func:`rebuild` returns them.

    References
    ----------
    Savalle et al. (2022), eqs. 3-4; Itasca UDEC, Theory and Background.
    """
    gxy = side.gxy
    if C[IC_NEED_REBUILD] != 0 or moved(geo, gxy, bodies, state, P[IP_MARGIN]):
        # np.int64: a literal 0 would compile another specialisation of rebuild than the
        # int64 of its calls from Python
        t = rebuild(P, E, C, geo, gxy, bodies, shapes, nodes, corners, state, np.int64(0))
        nodes = Contacts(t[0], t[1], t[2], t[3], t[4], t[5])
        corners = Contacts(t[6], t[7], t[8], t[9], t[10], t[11])
    b0 = E[IE_DBREAK]
    nn = node_contacts(P, E, geo, side, bodies, shapes, jprops, nodes, work)
    nc = corner_contacts(P, E, geo, side, bodies, shapes, jprops, corners, work)
    if C[IC_STEP] == 0:  # the contacts of the first step are the initial state, not a gain
        E[IE_DBREAK] = b0
    _clear_flags(nodes, shapes, work.eflag)
    C[IC_NODES] = nn
    C[IC_CORNERS] = nc
    C[IC_STEP] += 1
    return (nodes.pairs, nodes.pj, nodes.pbond, nodes.sid, nodes.sf, nodes.sbr,
            corners.pairs, corners.pj, corners.pbond, corners.sid, corners.sf, corners.sbr)


def stored_energy(nodes, corners) -> float:
    """Elastic energy stored in the interface springs, ``sum Fn² / (2 kn A) + Fs² / (2 ks A)``
    over the active contacts [J].

    Parameters
    ----------
    nodes, corners : murus.dem._kdata.Contacts
        The contact structures of an :class:`Interface`.

    Returns
    -------
    float
        The energy [J].

    References
    ----------
    Savalle et al. (2022), eq. 3 (linear joint springs).
    """
    e = 0.0
    for c in (nodes, corners):
        on = c.sid >= 0
        if not on.any():
            continue
        sf = c.sf[on]
        kn = sf[:, F_KNA]
        ks = sf[:, F_KSA]
        e += float(np.sum(np.where(kn > 0, 0.5 * sf[:, F_FN] ** 2 / np.where(kn > 0, kn, 1.0),
                                   0.0)))
        e += float(np.sum(np.where(ks > 0, 0.5 * sf[:, F_FS] ** 2 / np.where(ks > 0, ks, 1.0),
                                   0.0)))
    return e


# ---- Python front end ------------------------------------------------------------------------

class InterfaceError(MurusError, ValueError):
    """Invalid interface input (``key``: the offending argument)."""


_EMPTY_PAIRS = np.zeros((0, 2), np.int64)


def _empty_contacts():
    return Contacts(_EMPTY_PAIRS.copy(), np.zeros(0, np.int64), np.zeros(0, np.int8),
                    np.zeros((0, 2), np.int64), np.zeros((0, 2, NSF)),
                    np.zeros((0, 2), np.int8))


class Interface:
    """An interface between continuum zones and the blocks of a distinct-element model: the
    kernel data of :func:`step` built from plain arrays, and its state across steps.

    Parameters
    ----------
    grid : object
        The zone side, with attributes ``gxy (ng, 2)`` [m] and ``gvel (ng, 2)`` [m/s] (a
        :class:`murus.continuum.ContinuumModel`); the arrays are used in place (no copy), so
        the interface sees the grid as it moves. When it also has ``boundary_edges()``, the
        edges are checked against it and oriented with their zone on the left.
    edges : array_like (ne, 2) of int
        The interface edges: zone boundary edges (gridpoint pairs), oriented with their zone
        on the left unless ``grid`` can orient them (:meth:`murus.continuum.mesh.Mesh.edges_of`
        gives them so). The interface gridpoints are their ends.
    dem : murus.dem.Model
        The blocks (built on first use); their arrays are used in place.
    joint : murus.dem.Joint, optional
        The joint law of the interface (default: the default joint of ``dem``).
    margin : float, optional
        Broad-phase margin [m] (default: the margin of ``dem``).
    reach : float, optional
        Largest positive gap at which a contact is kept [m] (default ``2 T / kn`` of the
        joint: a bond pulled beyond its tensile strength ``T`` then breaks through the joint law
        and carries its residual tension up to that gap; 0 for a joint without tension).
    depth : float, optional
        Deepest penetration of a block corner behind a zone edge that is still a contact [m]
        (default: a tenth of the shortest interface edge). Interface penetrations are small
        (``F / (kn A)``); the limit keeps a vertex that sits behind a neighbouring zone edge
        (a wall's bed joint just below the top surface of the backfill, when that surface is
        part of the interface) from being taken for a contact with that edge.
    bond_initial : bool
        Contacts present at the first call start bonded (the joint's cohesion and tension), as
        the blocks' (default True).
    corner_share : {"follow", "shrink"}
        How a loaded corner contact's share of a block face follows the coverage rule (module
        doc): "shrink" (default), down only, which gives a loaded corner no energy; "follow",
        up and down, as a contact that forms (:func:`_kept_trib`: a block rocking on a corner
        next to a gridpoint then gains energy at every cycle, the creep of the mock-ups at
        the printed joint stiffness; VALIDATION.md, *The corner rule*).

    Attributes
    ----------
    P, E, C : ndarray
        Parameters ``IP_*``, energies ``IE_*`` [J], counters ``IC_*``.
    geo : IfaceGeom
    state : IfaceState
    work : IfaceWork
    nodes, corners : murus.dem._kdata.Contacts
        Gridpoint contacts (rows: interface gridpoint, shape) and corner contacts (rows:
        interface edge, shape).

    References
    ----------
    Savalle et al. (2022), eqs. 3-4, Figure 11; Itasca UDEC, Theory and Background.
    """

    def __init__(self, grid, edges, dem, joint=None, *, margin: float | None = None,
                 reach: float | None = None, depth: float | None = None,
                 bond_initial: bool = True,
                 corner_share: str = DEFAULT_CORNER_SHARE) -> None:
        from murus.dem import _kdata as dkd
        from murus.dem import kernels as DK
        from murus.dem.materials import Joint

        self.grid = grid
        gxy = grid.gxy
        if gxy.ndim != 2 or gxy.shape[1] != 2 or grid.gvel.shape != gxy.shape:
            raise InterfaceError("grid: gxy and gvel must be (ng, 2) arrays", key=("grid",))
        ng = gxy.shape[0]
        ed = np.asarray(edges)
        if ed.ndim != 2 or ed.shape[1] != 2 or ed.shape[0] == 0 or not np.issubdtype(
                ed.dtype, np.integer):
            raise InterfaceError("edges must be a non-empty (ne, 2) array of gridpoint indices",
                                 key=("edges",))
        ed = ed.astype(np.int64)
        if ed.min() < 0 or ed.max() >= ng:
            raise InterfaceError(f"edges: gridpoint index out of range 0..{ng - 1}",
                                 key=("edges",))
        if hasattr(grid, "boundary_edges"):
            bnd = {(int(a), int(b)) for a, b in grid.boundary_edges()}
            out = []
            for i, (a, b) in enumerate(ed):
                if (int(a), int(b)) in bnd:
                    out.append((a, b))
                elif (int(b), int(a)) in bnd:
                    out.append((b, a))
                else:
                    raise InterfaceError(f"edges: edge {i} ({a}, {b}) is not a boundary edge "
                                         "of a zone", key=("edges", i))
            ed = np.array(out, np.int64)
        L = np.hypot(*(gxy[ed[:, 1]] - gxy[ed[:, 0]]).T)
        if not np.all(L > 0):
            raise InterfaceError("edges: an edge has zero length", key=("edges",))
        dem.build()
        self.dem = dem
        if joint is None:
            joint = Joint.from_row(dem.jprops[0])
        if not isinstance(joint, Joint):
            raise InterfaceError("joint must be a murus.dem.Joint", key=("joint",))
        self.joint = joint
        self.jprops = np.ascontiguousarray(joint.row()[None, :])
        ig = np.unique(ed)
        gloc = np.full(ng, -1, np.int64)
        gloc[ig] = np.arange(ig.size)
        ngroup = int(dem.sgroup.max()) + 1 if dem.sgroup.size else 1
        ends = gloc[ed.ravel()]  # the interface gridpoint of each edge end
        gei = (np.argsort(ends, kind="stable") // 2).astype(np.int64)
        gep = np.zeros(ig.size + 1, np.int64)
        np.cumsum(np.bincount(ends, minlength=ig.size), out=gep[1:])
        self.geo = IfaceGeom(ig, gloc, np.ascontiguousarray(ed), np.zeros(ngroup, np.int64),
                             gep, gei)
        self.P = np.zeros(NIP)
        self.P[IP_THICK] = dem.thickness
        self.P[IP_MARGIN] = float(dem.margin if margin is None else margin)
        self.P[IP_REACH] = float(2.0 * self.jprops[0, J_T] / self.jprops[0, J_KN]
                                 if reach is None else reach)
        self.P[IP_DEPTH] = float(0.1 * L.min() if depth is None else depth)
        if corner_share not in CORNER_SHARES:
            raise InterfaceError(f"corner_share must be one of {', '.join(CORNER_SHARES)}, "
                                 f"got {corner_share!r}", key=("corner_share",))
        self.corner_share = corner_share
        self.P[IP_SHRINK] = float(corner_share == "shrink")
        for name, i in (("margin", IP_MARGIN), ("depth", IP_DEPTH)):
            if not (math.isfinite(self.P[i]) and self.P[i] > 0):
                raise InterfaceError(f"{name} must be positive [m], got {self.P[i]!r}",
                                     key=(name,))
        if not (math.isfinite(self.P[IP_REACH]) and self.P[IP_REACH] >= 0):
            raise InterfaceError(f"reach must be >= 0 [m], got {self.P[IP_REACH]!r}",
                                 key=("reach",))
        self.E = np.zeros(NIE)
        self.C = np.zeros(NIC, np.int64)
        nb = dem.bpos.shape[0]
        self.state = IfaceState(np.zeros((ig.size, 2)), np.zeros((nb, 3)))
        self.work = IfaceWork(np.zeros((ng, 2)), np.zeros((nb, 3)),
                              np.full((dem.wv.shape[0], 2), -1.0))
        self._dkd = dkd
        self._DK = DK
        self.nodes = _empty_contacts()
        self.corners = _empty_contacts()
        self.bodies = dkd.pack(dkd.Bodies, dem)
        self.shapes = dkd.pack(dkd.Shapes, dem)
        DK.world_vertices(dem.bpos, dem.bang, self.shapes)
        t = rebuild(self.P, self.E, self.C, self.geo, gxy, self.bodies, self.shapes,
                    self.nodes, self.corners, self.state, 1 if bond_initial else 0)
        self._set(t)
        self.C[IC_REBUILD] = 0

    @classmethod
    def from_side(cls, grid, mesh, side: str, dem, joint=None, **kw) -> Interface:
        """The interface along a named side of a mesh (:meth:`murus.continuum.mesh.Mesh.side`).

        Parameters
        ----------
        grid : object
            The zone side (``gxy``, ``gvel``), e.g. the :class:`ContinuumModel` of ``mesh``.
        mesh : murus.continuum.mesh.Mesh
            The mesh.
        side : str
            Name of the side (``"backfill.left"``).
        dem : murus.dem.Model
            The blocks.
        joint : murus.dem.Joint, optional
            The joint law.
        **kw
            Further arguments of :class:`Interface`.

        Returns
        -------
        Interface
        """
        return cls(grid, mesh.edges_of(mesh.side(side)), dem, joint, **kw)

    def _set(self, t) -> None:
        self.nodes = Contacts(*t[:6])
        self.corners = Contacts(*t[6:])

    def forces(self, dt: float, *, refresh: bool = True):
        """Interface forces at the current state (one step of the contact law: the shear
        increments use the half-step velocities times ``dt``).

        Parameters
        ----------
        dt : float
            Time step [s] (0: forces from the gaps only, no shear increment).
        refresh : bool
            Recompute the world vertices of the blocks from their positions first (default
            True; a coupled loop that keeps them current passes False).

        Returns
        -------
        fg : ndarray (ng, 2)
            Forces on the gridpoints [N] (for the thickness of the blocks' model).
        fb : ndarray (nb, 3)
            Forces (Fx, Fy) [N] and moments about the centroids [N m] on the bodies.
        """
        if not (math.isfinite(dt) and dt >= 0):
            raise InterfaceError(f"dt must be >= 0 [s], got {dt!r}", key=("dt",))
        dem = self.dem
        if refresh:
            self._DK.world_vertices(dem.bpos, dem.bang, self.shapes)
        self.P[IP_DT] = dt
        self.work.fg[:] = 0.0
        self.work.fb[:] = 0.0
        t = step(self.P, self.E, self.C, self.geo, GridSide(self.grid.gxy, self.grid.gvel),
                 self.bodies, self.shapes, self.jprops, self.nodes, self.corners, self.state,
                 self.work)
        self._set(t)
        return self.work.fg, self.work.fb

    def critical_dt(self, gmass=None) -> float:
        """The interface's part of the stable time step, ``min sqrt(m / k)`` [s] before any
        safety factor (the blocks' form, :func:`murus.dem.engine.stable_dt`, which applies
        ``Model.safety``): over the interface gridpoints, their mass against the stiffness
        ``max(kn, ks) L t`` of their tributary length (whether in contact or not) plus that of
        the active corner contacts on their edges; over the dynamic bodies of the candidate
        pairs, mass and inertia against the stiffness of their active interface contacts, at
        least ``max(kn, ks) t`` times their longest edge (the blocks' floor).

        Parameters
        ----------
        gmass : array_like (ng,), optional
            Gridpoint masses [kg per metre of thickness] (default: ``grid.gmass``).

        Returns
        -------
        float
            The step [s] (``inf`` when nothing limits it).

        References
        ----------
        Itasca UDEC, Theory and Background (time step of deformable blocks in contact).
        """
        gm = np.asarray(self.grid.gmass if gmass is None else gmass, float)
        t = self.P[IP_THICK]
        kmax = float(max(self.jprops[0, J_KN], self.jprops[0, J_KS]))
        gxy = self.grid.gxy
        ig = self.geo.ig
        trib = np.zeros(ig.size)
        ie = self.geo.ie
        h = 0.5 * np.hypot(*(gxy[ie[:, 1]] - gxy[ie[:, 0]]).T)
        np.add.at(trib, self.geo.gloc[ie[:, 0]], h)
        np.add.at(trib, self.geo.gloc[ie[:, 1]], h)
        kg = np.zeros(gxy.shape[0])
        kg[ig] = kmax * t * trib
        c = self.corners
        on = c.sid >= 0
        if on.any():
            k = np.maximum(c.sf[..., F_KNA], c.sf[..., F_KSA])
            for col in (0, 1):
                g = np.repeat(ie[c.pairs[:, 0], col][:, None], 2, 1)[on]
                np.add.at(kg, g, k[on])  # weight <= 1: an upper bound of the share
        dt = np.inf
        sel = ig[kg[ig] > 0]
        if sel.size:
            dt = float(np.sqrt(gm[sel] * t / kg[sel]).min())
        dem = self.dem
        nb = dem.bpos.shape[0]
        Kt = np.zeros(nb)
        Kr = np.zeros(nb)
        for cc in (self.nodes, c):
            on = cc.sid >= 0
            if not on.any():
                continue
            k = np.maximum(cc.sf[..., F_KNA], cc.sf[..., F_KSA])[on]
            b = np.repeat(dem.sbody[cc.pairs[:, 1]][:, None], 2, 1)[on]
            px = cc.sf[..., F_PX][on]
            py = cc.sf[..., F_PY][on]
            np.add.at(Kt, b, k)
            np.add.at(Kr, b, k * ((px - dem.bpos[b, 0]) ** 2 + (py - dem.bpos[b, 1]) ** 2))
        near = np.zeros(nb, bool)
        for cc in (self.nodes, c):
            near[dem.sbody[cc.pairs[:, 1]]] = True
        near &= dem.bkin == 0
        if near.any():
            floor = kmax * t * dem.blen[near]
            dtt = np.sqrt(dem.bmass[near] / np.maximum(Kt[near], floor))
            dtr = np.sqrt(dem.binert[near] / np.maximum(Kr[near], floor * dem.brad[near] ** 2))
            dt = min(dt, float(dtt.min()), float(dtr.min()))
        return dt

    @property
    def energy(self) -> dict:
        """Energies of the interface [J]: ``slip`` and ``break`` dissipation since the start,
        and ``stored`` (elastic energy of the springs now).

        Returns
        -------
        dict
        """
        return {"slip": float(self.E[IE_DSLIP]), "break": float(self.E[IE_DBREAK]),
                "stored": stored_energy(self.nodes, self.corners)}

    def normal_force(self) -> float:
        """Sum of the normal forces of the active contacts [N] (compression positive).

        Returns
        -------
        float
        """
        return float(sum(c.sf[..., F_FN][c.sid >= 0].sum() for c in (self.nodes,
                                                                      self.corners)))

    def shear_force(self) -> float:
        """Sum of the shear forces of the active contacts [N].

        Returns
        -------
        float
        """
        return float(sum(c.sf[..., F_FS][c.sid >= 0].sum() for c in (self.nodes,
                                                                      self.corners)))


def interface_forces(iface: Interface, dt: float, fg=None, fb=None):
    """The interface forces of the current state (:meth:`Interface.forces`), added to ``fg``
    and ``fb`` when given.

    Parameters
    ----------
    iface : Interface
        The interface.
    dt : float
        Time step [s].
    fg : ndarray (ng, 2), optional
        Gridpoint forces to add to [N].
    fb : ndarray (nb, 3), optional
        Body forces and moments to add to [N, N m].

    Returns
    -------
    fg : ndarray (ng, 2)
        Forces on the gridpoints [N].
    fb : ndarray (nb, 3)
        Forces and moments on the bodies [N, N m].

    References
    ----------
    Savalle et al. (2022), eqs. 3-4.
    """
    g, b = iface.forces(dt)
    if fg is None:
        fg = g.copy()
    else:
        fg += g
    if fb is None:
        fb = b.copy()
    else:
        fb += b
    return fg, fb


# numba's cache checks only this file: flush it when the joint law and layouts it compiles in
# (murus.dem.kernels, murus.dem._kdata) change
_guard_cache(globals(), deps=("murus.dem.kernels", "murus.dem._kdata"))
