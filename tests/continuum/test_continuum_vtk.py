"""VTK output of the zones (.vtu of VTK_QUAD cells, .pvd series), parsed back with xml.etree."""

from __future__ import annotations

import xml.etree.ElementTree as ET

import numpy as np
import pytest

from murus._vtkxml import read_base64_array
from murus.continuum.vtk import VTK_QUAD, write_vtu, write_zone_series, zone_cell_data
from murus.dem.vtk import write_series


def _mesh_2x2():
    """3 x 3 gridpoints (row by row from the bottom left), 4 zones counter-clockwise."""
    x, y = np.meshgrid([0.0, 0.5, 1.25], [0.0, 0.4, 1.0])
    xy = np.column_stack([x.ravel(), y.ravel()])
    zones = np.array([[0, 1, 4, 3], [1, 2, 5, 4], [3, 4, 7, 6], [4, 5, 8, 7]])
    return xy, zones


def _array(el, binary, dtype):
    if binary:
        assert el.get("format") == "binary"
        return read_base64_array(el.text, dtype)
    assert el.get("format") == "ascii"
    return np.array(el.text.split(), dtype=dtype)


def _named(section, name):
    (el,) = [a for a in section.findall("DataArray") if a.get("Name") == name]
    return el


@pytest.mark.parametrize("binary", [False, True])
def test_vtu_round_trip(tmp_path, binary):
    xy, zones = _mesh_2x2()
    nz, ng = len(zones), len(xy)
    rng = np.random.default_rng(3)
    stress = rng.normal(size=(nz, 4)) * 1e5
    strain = rng.normal(size=(nz, 3)) * 1e-3
    state = np.array([0, 1, 6, 12], dtype=np.int8)
    disp = rng.normal(size=(ng, 2)) * 1e-3
    vel = rng.normal(size=(ng, 2))
    path = write_vtu(tmp_path / "z.vtu", xy, zones,
                     zone_cell_data(stress, strain, state, material=np.array([1, 1, 2, 2])),
                     {"displacement": disp, "velocity": vel}, z=0.25, binary=binary)
    root = ET.parse(path).getroot()
    assert root.tag == "VTKFile" and root.get("type") == "UnstructuredGrid"
    piece = root.find("UnstructuredGrid/Piece")
    assert piece.get("NumberOfPoints") == str(ng) and piece.get("NumberOfCells") == str(nz)

    pts = piece.find("Points/DataArray")
    assert pts.get("type") == "Float64" and pts.get("NumberOfComponents") == "3"
    p = _array(pts, binary, np.float64).reshape(ng, 3)
    np.testing.assert_array_equal(p[:, :2], xy)  # exact round trip, ASCII and binary
    np.testing.assert_array_equal(p[:, 2], 0.25)

    cells = piece.find("Cells")
    conn = _named(cells, "connectivity")
    off = _named(cells, "offsets")
    types = _named(cells, "types")
    assert conn.get("type") == "Int64" and types.get("type") == "UInt8"
    np.testing.assert_array_equal(_array(conn, binary, np.int64), zones.ravel())
    np.testing.assert_array_equal(_array(off, binary, np.int64), [4, 8, 12, 16])
    np.testing.assert_array_equal(_array(types, binary, np.uint8), [VTK_QUAD] * nz)
    assert VTK_QUAD == 9

    cd = piece.find("CellData")
    s = _named(cd, "stress")
    assert s.get("NumberOfComponents") == "6"
    s6 = _array(s, binary, np.float64).reshape(nz, 6)
    # VTK symmetric tensor order XX, YY, ZZ, XY, YZ, XZ from sxx, syy, sxy, szz
    np.testing.assert_array_equal(s6[:, [0, 1, 3, 2]], stress)
    np.testing.assert_array_equal(s6[:, 4:], 0.0)
    np.testing.assert_allclose(_array(_named(cd, "mean_stress"), binary, np.float64),
                               (stress[:, 0] + stress[:, 1] + stress[:, 3]) / 3, rtol=1e-15)
    e6 = _array(_named(cd, "strain"), binary, np.float64).reshape(nz, 6)
    np.testing.assert_array_equal(e6[:, [0, 1, 3]], strain)
    np.testing.assert_array_equal(e6[:, [2, 4, 5]], 0.0)
    st = _named(cd, "state")
    assert st.get("type") == "Int64"
    np.testing.assert_array_equal(_array(st, binary, np.int64), state)
    np.testing.assert_array_equal(_array(_named(cd, "yielding"), binary, np.int64), [0, 1, 1, 0])
    np.testing.assert_array_equal(_array(_named(cd, "material"), binary, np.int64), [1, 1, 2, 2])

    pd = piece.find("PointData")
    d = _named(pd, "displacement")
    assert d.get("NumberOfComponents") == "3"
    d3 = _array(d, binary, np.float64).reshape(ng, 3)
    np.testing.assert_array_equal(d3[:, :2], disp)
    np.testing.assert_array_equal(d3[:, 2], 0.0)
    v3 = _array(_named(pd, "velocity"), binary, np.float64).reshape(ng, 3)
    np.testing.assert_array_equal(v3[:, :2], vel)


def test_zones_share_their_gridpoints(tmp_path):
    """One point per gridpoint (not per zone corner): the centre gridpoint 4 is in all four
    zones."""
    xy, zones = _mesh_2x2()
    root = ET.parse(write_vtu(tmp_path / "z.vtu", xy, zones)).getroot()
    conn = _array(_named(root.find("UnstructuredGrid/Piece/Cells"), "connectivity"), False,
                  np.int64)
    assert np.count_nonzero(conn == 4) == 4
    assert root.find("UnstructuredGrid/Piece").get("NumberOfPoints") == "9"


@pytest.mark.parametrize("kwargs,message", [
    (dict(xy=np.zeros((3, 3))), "expected (ng, 2)"),
    (dict(zones=np.array([[0, 1, 4, 9]])), "outside 0..8"),
    (dict(zones=np.array([[0, 1, 1, 3]])), "repeats a gridpoint"),
    (dict(zones=np.zeros((2, 3), dtype=int)), "expected (nz, 4)"),
    (dict(zones=np.zeros((1, 4))), "integer gridpoint indices"),
    (dict(cell_data={"s": np.zeros(3)}), "3 values for 4 zones"),
    (dict(point_data={"u": np.full((9, 2), np.nan)}), "non-finite"),
])
def test_bad_input_writes_nothing(tmp_path, kwargs, message):
    xy, zones = _mesh_2x2()
    args = dict(xy=xy, zones=zones) | kwargs
    with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)")):
        write_vtu(tmp_path / "z.vtu", **args)
    assert list(tmp_path.iterdir()) == []


def test_zone_cell_data_checks():
    with pytest.raises(ValueError, match="expected"):
        zone_cell_data(stress=np.zeros((4, 3)))
    with pytest.raises(ValueError, match="0..15"):
        zone_cell_data(state=np.array([16]))
    with pytest.raises(ValueError, match="clashes"):
        zone_cell_data(state=np.array([1]), yielding=np.array([0]))
    e = zone_cell_data(strain=np.ones((2, 4)))["strain"]
    np.testing.assert_array_equal(e, [[1, 1, 1, 1, 0, 0]] * 2)


def test_zone_series_beside_the_blocks(tmp_path):
    """zones_NNNN.vtu + zones.pvd in the folder of the blocks' series: neither writer touches
    the other's files nor a stranger's; a shorter re-run removes its own extra frame."""
    xy, zones = _mesh_2x2()
    out = tmp_path / "vtk"
    out.mkdir()
    (out / "notes.txt").write_text("mine")
    square = [np.array([[2.0, 0], [3, 0], [3, 1], [2, 1]])]
    write_series(out, [(0.0, {"polygons": square}), (0.1, {"polygons": square})])

    def frames(n):
        for i in range(n):
            yield 0.1 * i, {"xy": xy + 0.01 * i, "zones": zones,
                            "cell_data": zone_cell_data(state=np.full(4, i, dtype=np.int8)),
                            "point_data": {"displacement": np.full((9, 2), 0.01 * i)}}

    pvd = write_zone_series(out, frames(3))
    assert pvd == out / "zones.pvd"
    names = sorted(p.name for p in out.iterdir())
    assert names == ["frame_0000.vtp", "frame_0001.vtp", "notes.txt", "series.pvd",
                     "zones.pvd", "zones_0000.vtu", "zones_0001.vtu", "zones_0002.vtu"]
    ds = ET.parse(pvd).getroot().findall("Collection/DataSet")
    assert [d.get("file") for d in ds] == ["zones_0000.vtu", "zones_0001.vtu", "zones_0002.vtu"]
    np.testing.assert_allclose([float(d.get("timestep")) for d in ds], [0.0, 0.1, 0.2])
    p = ET.parse(out / "zones_0002.vtu").getroot().find("UnstructuredGrid/Piece/Points/DataArray")
    np.testing.assert_array_equal(np.array(p.text.split(), float).reshape(9, 3)[:, :2],
                                  xy + 0.02)

    write_zone_series(out, frames(2))
    names = sorted(p.name for p in out.iterdir())
    assert "zones_0002.vtu" not in names and "notes.txt" in names and "frame_0001.vtp" in names
    assert (out / "notes.txt").read_text() == "mine"


def test_zone_series_bad_frame_changes_nothing(tmp_path):
    xy, zones = _mesh_2x2()
    out = tmp_path / "vtk"
    good = {"xy": xy, "zones": zones}
    write_zone_series(out, [(0.0, good)])
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    bad = {"xy": xy, "zones": zones, "cell_data": {"s": np.zeros(2)}}
    with pytest.raises(ValueError, match=r"frame 1: cell_data 's' has 2 values for 4 zones"):
        write_zone_series(out, [(0.0, good), (0.1, bad)])
    with pytest.raises(ValueError, match="frame 1: .*times must increase"):
        write_zone_series(out, [(0.0, good), (0.0, good)])
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["vtk"]
