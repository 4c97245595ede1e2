"""Mesh of the backfill of a retaining wall: the back of the wall inclined 10 deg from the
vertical, the ground level for 1 m behind the wall then sloped up at 20 deg, zones graded finer
towards the wall, on a foundation layer that also runs under the wall; saved as a PNG.

    python examples/continuum/mesh_backfill.py [OUT_DIR]      (default out/continuum)

The backfill is a pentagon whose four corners are found automatically (the break of slope is not
a corner: the top side is a polyline with a gridpoint at the break); the foundation is two
rectangles, one under the wall and one under the backfill with the same zones and grading along
the shared side, and the three regions are merged into one conforming mesh
(:mod:`murus.continuum.mesh`).
"""

import math
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402

from murus.continuum.mesh import merge, polygon_corners, polygon_region, rectangle  # noqa: E402

H = 3.0                 # height of the wall back [m]
BACK_DEG = 10.0         # inclination of the wall back from the vertical [deg]
LEVEL = 1.0             # level ground behind the top of the wall [m]
SLOPE_DEG = 20.0        # slope of the ground beyond [deg]
LENGTH = 9.0            # extent of the backfill from the heel [m]
WALL_BASE = 1.5         # width of the wall base in front of the heel [m]
FOUNDATION = 2.0        # depth of the foundation layer [m]
NX, NY, GRADING = 24, 10, 1.06   # zones along and across the backfill, growth away from the wall


def backfill_vertices() -> list[tuple[float, float]]:
    """Vertices of the backfill [m], counter-clockwise from the heel of the wall back."""
    top = (H * math.tan(math.radians(BACK_DEG)), H)
    brk = (top[0] + LEVEL, H)
    far = (LENGTH, H + (LENGTH - brk[0]) * math.tan(math.radians(SLOPE_DEG)))
    return [(0.0, 0.0), (LENGTH, 0.0), far, brk, top]


def build():
    """The merged mesh of the backfill and its foundation.

    Returns
    -------
    murus.continuum.mesh.Mesh
        Regions ``backfill``, ``foundation`` (under the backfill) and ``under_wall``.
    """
    verts = backfill_vertices()
    print("corners of the backfill (vertex indices):", polygon_corners(verts))
    backfill = polygon_region(verts, nx=NX, ny=NY, grading=(GRADING, 1.0), name="backfill")
    foundation = rectangle(0.0, -FOUNDATION, LENGTH, FOUNDATION, nx=NX, ny=4,
                           grading=(GRADING, 1.0), name="foundation")
    under_wall = rectangle(-WALL_BASE, -FOUNDATION, WALL_BASE, FOUNDATION, nx=4, ny=4,
                           name="under_wall")
    return merge([under_wall, foundation, backfill])


def plot(mesh, path: Path) -> None:
    """Draw the zones coloured by region, the wall back and the ground surface; save a PNG.

    Parameters
    ----------
    mesh : murus.continuum.mesh.Mesh
        The mesh.
    path : pathlib.Path
        PNG file to write.
    """
    fig, ax = plt.subplots(figsize=(10, 5))
    colours = plt.get_cmap("Pastel1").colors
    ax.add_collection(PolyCollection(mesh.xy[mesh.zones], facecolors=[
        colours[r % len(colours)] for r in mesh.region], edgecolors="0.3", linewidths=0.4))
    for name, style in (("backfill.left", "r-"), ("backfill.top", "g-")):
        p = mesh.xy[mesh.side(name)]
        ax.plot(p[:, 0], p[:, 1], style, lw=2, label=name)
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(mesh.quality().summary(), fontsize=8)
    ax.legend(loc="lower right", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(out: Path) -> None:
    out.mkdir(parents=True, exist_ok=True)
    mesh = build()
    print(mesh.quality().summary())
    plot(mesh, out / "mesh_backfill.png")
    print("wrote", out / "mesh_backfill.png")


if __name__ == "__main__":
    main(Path(sys.argv[1] if len(sys.argv) > 1 else "out/continuum"))
