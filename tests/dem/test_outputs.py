"""Outputs of the 2D distinct-element model: VTK XML files, ParaView collections, figures."""

import xml.etree.ElementTree as ET

import numpy as np
import pytest

from murus.dem.vtk import (
    PvdWriter,
    read_base64_array,
    write_contacts_vtp,
    write_series,
    write_vtp,
)

SQUARE = np.array([[0.0, 0.0], [0.4, 0.0], [0.4, 0.2], [0.0, 0.2]])
TRIANGLE = np.array([[0.5, 0.0], [0.9, 0.0], [0.7, 0.3]])
CENTRES = np.array([[1.2, 0.1], [1.5, 0.3]])
RADII = np.array([0.1, 0.05])
# one value per cell: 2 polygons first, then 2 discs
CELL_DATA = {
    "body_id": np.array([0, 1, 2, 3]),
    "disp": np.array([0.1, 1.0 / 3.0, 2.5e-7, 0.0]),
    "disp_vec": np.array([[0.1, 0.0], [0.2, -0.1], [1e-9, 3.0], [0.0, 0.0]]),
}


def _values(el):
    if el.get("format") == "binary":
        dtype = {"Float64": "<f8", "Int64": "<i8"}[el.get("type")]
        return read_base64_array(el.text, dtype)
    conv = float if el.get("type") == "Float64" else int
    return np.array([conv(v) for v in el.text.split()])


def _parse(path):
    root = ET.parse(path).getroot()
    assert root.tag == "VTKFile"
    assert root.attrib == {"type": "PolyData", "version": "0.1", "byte_order": "LittleEndian"}
    piece = root.find("PolyData/Piece")
    pts = piece.find("Points/DataArray")
    assert pts.get("type") == "Float64" and pts.get("NumberOfComponents") == "3"
    out = {
        "piece": {k: int(v) for k, v in piece.attrib.items()},
        "points": _values(pts).reshape(-1, 3),
    }
    for section in ("CellData", "PointData"):
        arrays = {}
        for el in piece.findall(f"{section}/DataArray"):
            a = _values(el)
            k = int(el.get("NumberOfComponents"))
            arrays[el.get("Name")] = (el.get("type"), a if k == 1 else a.reshape(-1, k))
        out[section] = arrays
    for cells in ("Polys", "Verts"):
        el = piece.find(cells)
        if el is not None:
            byname = {d.get("Name"): d for d in el.findall("DataArray")}
            assert byname["connectivity"].get("type") == "Int64"
            assert byname["offsets"].get("type") == "Int64"
            out[cells] = (_values(byname["connectivity"]), _values(byname["offsets"]))
    return out


@pytest.mark.parametrize("binary", [False, True])
def test_blocks_round_trip(tmp_path, binary):
    path = write_vtp(tmp_path / "b.vtp", [SQUARE, TRIANGLE], (CENTRES, RADII), CELL_DATA,
                     disc_resolution=12, z=0.5, binary=binary)
    f = _parse(path)
    n_points = 4 + 3 + 2 * 12
    assert f["piece"] == {"NumberOfPoints": n_points, "NumberOfVerts": 0, "NumberOfLines": 0,
                          "NumberOfStrips": 0, "NumberOfPolys": 4}
    conn, offsets = f["Polys"]
    assert offsets.tolist() == [4, 7, 19, 31]
    assert conn.tolist() == list(range(n_points))
    pts = f["points"]
    assert np.array_equal(pts[:4, :2], SQUARE) and np.array_equal(pts[4:7, :2], TRIANGLE)
    assert np.all(pts[:, 2] == 0.5)
    # discs: regular 12-gons on the circle, first vertex at angle 0
    for i, (c, r) in enumerate(zip(CENTRES, RADII, strict=True)):
        ring = pts[7 + 12 * i : 7 + 12 * (i + 1), :2]
        np.testing.assert_allclose(np.hypot(*(ring - c).T), r, rtol=1e-14)
        np.testing.assert_allclose(ring[0], c + [r, 0.0], rtol=1e-14)
    cd = f["CellData"]
    assert list(cd) == ["body_id", "disp", "disp_vec"]
    assert cd["body_id"][0] == "Int64" and cd["body_id"][1].tolist() == [0, 1, 2, 3]
    assert cd["disp"][0] == "Float64" and np.array_equal(cd["disp"][1], CELL_DATA["disp"])
    vec = cd["disp_vec"][1]
    assert vec.shape == (4, 3)
    assert np.array_equal(vec[:, :2], CELL_DATA["disp_vec"]) and np.all(vec[:, 2] == 0)


def test_closing_vertex_dropped_and_polygons_only(tmp_path):
    closed = np.vstack([SQUARE, SQUARE[:1]])
    f = _parse(write_vtp(tmp_path / "p.vtp", [closed], cell_data={"h": [2.0]}))
    assert f["piece"]["NumberOfPoints"] == 4 and f["piece"]["NumberOfPolys"] == 1
    assert f["Polys"][1].tolist() == [4]
    assert f["CellData"]["h"][1].tolist() == [2.0]


@pytest.mark.parametrize("binary", [False, True])
def test_contacts_round_trip(tmp_path, binary):
    rows = np.array([[0.2, 0.2, 1500.0, -12.5, 0.0, 1.0],
                     [0.45, 0.1, 733.25, 0.1, -1.0, 0.0],
                     [1.1, 0.0, 0.0, 0.0, 0.6, 0.8]])
    f = _parse(write_contacts_vtp(tmp_path / "c.vtp", rows, point_data={"id": [7, 8, 9]},
                                  binary=binary))
    assert f["piece"]["NumberOfPoints"] == 3 and f["piece"]["NumberOfVerts"] == 3
    assert f["piece"]["NumberOfPolys"] == 0
    conn, offsets = f["Verts"]
    assert conn.tolist() == [0, 1, 2] and offsets.tolist() == [1, 2, 3]
    assert np.array_equal(f["points"], np.column_stack([rows[:, :2], np.zeros(3)]))
    pd = f["PointData"]
    assert np.array_equal(pd["normal_force"][1], rows[:, 2])
    assert np.array_equal(pd["shear_force"][1], rows[:, 3])
    assert np.array_equal(pd["normal"][1], np.column_stack([rows[:, 4:], np.zeros(3)]))
    assert pd["id"][1].tolist() == [7, 8, 9]


def test_no_contacts_gives_valid_empty_file(tmp_path):
    f = _parse(write_contacts_vtp(tmp_path / "c.vtp", np.zeros((0, 6))))
    assert f["piece"]["NumberOfPoints"] == 0 and f["piece"]["NumberOfVerts"] == 0
    assert f["points"].shape == (0, 3)


def _pvd(path):
    root = ET.parse(path).getroot()
    assert root.get("type") == "Collection" and root.get("version") == "0.1"
    return [(float(d.get("timestep")), d.get("file")) for d in root.findall("Collection/DataSet")]


def test_pvd_writer(tmp_path):
    with PvdWriter(tmp_path / "run.pvd") as pvd:
        pvd.add(0.0, "frame_0000.vtp")
        pvd.add(0.1, tmp_path / "sub" / "frame_0001.vtp")  # absolute: stored relative
        pvd.add(0.25, "frame_0002.vtp")
        assert not (tmp_path / "run.pvd").exists()  # written on close only
    assert _pvd(tmp_path / "run.pvd") == [
        (0.0, "frame_0000.vtp"), (0.1, "sub/frame_0001.vtp"), (0.25, "frame_0002.vtp")]
    assert [p.name for p in tmp_path.iterdir()] == ["run.pvd"]  # no temporary left
    with pytest.raises(ValueError, match="closed"):
        pvd.add(0.3, "late.vtp")


def test_pvd_not_written_when_the_block_fails(tmp_path):
    with pytest.raises(RuntimeError), PvdWriter(tmp_path / "run.pvd") as pvd:
        pvd.add(0.0, "a.vtp")
        raise RuntimeError("engine failed")
    assert list(tmp_path.iterdir()) == []


def test_pvd_times_must_increase(tmp_path):
    pvd = PvdWriter(tmp_path / "run.pvd")
    pvd.add(0.2, "a.vtp")
    with pytest.raises(ValueError, match="frame 1 has time 0.2 s, not after"):
        pvd.add(0.2, "b.vtp")
    with pytest.raises(ValueError, match="non-finite"):
        pvd.add(float("nan"), "b.vtp")


def test_write_series(tmp_path):
    contacts = np.array([[0.2, 0.2, 100.0, 1.0, 0.0, 1.0]])
    frames = (
        (0.01 * i, {"polygons": [SQUARE + [0.01 * i, 0.0], TRIANGLE], "discs": (CENTRES, RADII),
                    "cell_data": {"disp": np.full(4, 0.01 * i)},
                    **({"contacts": contacts} if i != 1 else {})})
        for i in range(3)
    )
    out = tmp_path / "series"
    (out).mkdir()
    (out / "frame_0007.vtp").write_text("stale")  # from an earlier, longer series
    (out / "notes.txt").write_text("keep me")
    assert write_series(out, frames, disc_resolution=6, binary=True) == out / "series.pvd"
    assert _pvd(out / "series.pvd") == [(0.0, "frame_0000.vtp"), (0.01, "frame_0001.vtp"),
                                        (0.02, "frame_0002.vtp")]
    assert _pvd(out / "contacts.pvd") == [(0.0, "contacts_0000.vtp"), (0.01, "contacts_0001.vtp"),
                                          (0.02, "contacts_0002.vtp")]
    assert sorted(p.name for p in out.iterdir()) == [
        "contacts.pvd", "contacts_0000.vtp", "contacts_0001.vtp", "contacts_0002.vtp",
        "frame_0000.vtp", "frame_0001.vtp", "frame_0002.vtp", "notes.txt", "series.pvd"]
    f2 = _parse(out / "frame_0002.vtp")
    assert f2["piece"]["NumberOfPolys"] == 4 and f2["piece"]["NumberOfPoints"] == 7 + 12
    np.testing.assert_array_equal(f2["points"][0, :2], [0.02, 0.0])
    assert f2["CellData"]["disp"][1].tolist() == [0.02] * 4
    assert _parse(out / "contacts_0001.vtp")["piece"]["NumberOfVerts"] == 0
    assert [p.name for p in tmp_path.iterdir()] == ["series"]  # temporary folder removed


def test_write_series_bad_frame_writes_nothing(tmp_path):
    frames = [(0.0, {"polygons": [SQUARE]}), (0.1, {"polygons": [SQUARE[:2]]})]
    with pytest.raises(ValueError, match="^frame 1: polygon 0 has 2 vertices"):
        write_series(tmp_path / "s", frames)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"polygons": [SQUARE, SQUARE, SQUARE, SQUARE[:2]]},
         "polygon 3 has 2 vertices; a polygon needs at least 3"),
        ({"polygons": [SQUARE[:, :1]]}, r"polygon 0 has shape \(4, 1\)"),
        ({"polygons": [SQUARE * np.nan]}, "polygon 0 has non-finite coordinates"),
        ({"polygons": [SQUARE], "discs": (CENTRES, RADII[:1])}, "disc radii have shape"),
        ({"polygons": [SQUARE], "discs": (CENTRES, [0.1, -0.1])}, "disc 1 has radius -0.1"),
        ({"polygons": [SQUARE] * 6, "discs": (CENTRES, RADII), "cell_data": {"disp": np.ones(7)}},
         r"cell_data 'disp' has 7 values for 8 cells \(6 polygons \+ 2 discs\)"),
        ({"polygons": [SQUARE], "cell_data": {"d": [np.inf]}}, "cell_data 'd' has non-finite"),
        ({"polygons": [SQUARE], "cell_data": {"d": ["a"]}}, "cell_data 'd' has dtype"),
        ({"polygons": [SQUARE], "disc_resolution": 2}, "disc_resolution is 2"),
    ],
)
def test_bad_input(tmp_path, kwargs, message):
    with pytest.raises(ValueError, match=message) as err:
        write_vtp(tmp_path / "bad.vtp", **kwargs)
    assert "\n" not in str(err.value)
    assert list(tmp_path.iterdir()) == []  # nothing written


def test_bad_contacts(tmp_path):
    with pytest.raises(ValueError, match=r"contact rows have shape \(2, 5\)"):
        write_contacts_vtp(tmp_path / "c.vtp", np.zeros((2, 5)))
    with pytest.raises(ValueError, match="point_data 'id' has 1 values for 2 contacts"):
        write_contacts_vtp(tmp_path / "c.vtp", np.zeros((2, 6)), point_data={"id": [1]})
    assert list(tmp_path.iterdir()) == []


def test_plot_blocks_and_history():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from murus.dem.plots import plot_blocks, plot_history

    values = np.array([0.002, 0.010, -0.001, 0.004])
    ax = plot_blocks([SQUARE, TRIANGLE], (CENTRES, RADII), values)
    polys, discs = ax.collections
    assert len(polys.get_paths()) == 2 and len(discs.get_paths()) == 2
    cbar = polys.colorbar
    assert cbar is not None and cbar.ax.get_ylabel() == "displacement [m]"
    assert (cbar.norm.vmin, cbar.norm.vmax) == (values.min(), values.max())
    assert discs.norm is polys.norm  # one colour scale for polygons and discs
    assert ax.get_aspect() == 1.0
    x0, x1 = ax.get_xlim()
    assert x0 <= 0.0 and x1 >= 1.55  # autoscaled to include the discs
    with pytest.raises(ValueError, match=r"expected \(4,\)"):
        plot_blocks([SQUARE, TRIANGLE], (CENTRES, RADII), values[:3])

    ax2 = plot_blocks([SQUARE], show_edges=False)
    assert len(ax2.collections) == 1 and ax2.collections[0].colorbar is None

    t = np.linspace(0.0, 1.0, 11)
    ax3 = plot_history(t, {"top [m]": t**2, "base [m]": -t})
    assert [line.get_label() for line in ax3.get_lines()] == ["top [m]", "base [m]"]
    with pytest.raises(ValueError, match="series 'x' has shape"):
        plot_history(t, {"x": t[:5]})
    plt.close("all")
