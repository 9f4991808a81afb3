"""dtmesh against the project's own tools: the same streams as meshenc, the same
meshes as meshdec, the same summary as meshinfo; and what a stream's damage
does to it."""
import json
import os
import subprocess
import lzma
import threading
import time
import warnings

import meshio
import numpy as np
import pytest

import dtmesh
from conftest import DATA, ENCODE_ARGS, GOLDEN, read_tetgen, run, tool


def meshdec_level(stream, tmp_path, level=None):
    """meshdec's output as meshio reads it back (VTU: float64 points, the fields in their types)."""
    out = tmp_path / "meshdec.vtu"
    run(tool("meshdec"), stream, "-q", "-o", out, *([] if level is None else ["--level", level]))
    return meshio.read(out)


def assert_same_level(mesh, reference):
    assert mesh.points.dtype == np.float64
    np.testing.assert_array_equal(mesh.points, reference.points)
    if "tetra10" in reference.cells_dict:  # (18.0: a second-order level, meshio's order VTK's)
        tetra10 = reference.cells_dict["tetra10"]
        np.testing.assert_array_equal(mesh.tetrahedra, tetra10[:, :4])
        np.testing.assert_array_equal(mesh.edge_nodes[:, [0, 3, 1, 2, 4, 5]], tetra10[:, 4:])
    else:
        np.testing.assert_array_equal(mesh.tetrahedra, reference.cells_dict["tetra"])
        assert mesh.edge_nodes.shape == (0, 6)
    np.testing.assert_array_equal(mesh.vertex_levels, reference.point_data["level"])
    np.testing.assert_array_equal(mesh.boundary, reference.point_data["boundary"].astype(bool))
    assert sorted(mesh.fields) == sorted(k for k in reference.point_data if k not in ("level", "boundary"))
    for name, values in mesh.fields.items():
        theirs = reference.point_data[name]
        assert values.dtype == theirs.dtype, name
        np.testing.assert_array_equal(values, theirs.reshape(values.shape))


@pytest.mark.parametrize("stream", GOLDEN, ids=lambda p: str(p.relative_to(p.parents[1])))
def test_golden_streams_decode_as_meshdec_decodes_them(stream, tmp_path):
    assert_same_level(dtmesh.decode(stream.read_bytes()), meshdec_level(stream, tmp_path))


def test_a_second_order_level_is_meshios_tetra10(tmp_path):
    # (18.0: the gmsh ball's exact level 0, its edge nodes after its vertices.)
    stream = next(p for p in GOLDEN if p.name == "ball_order2_exact.dtm")
    mesh = dtmesh.decode(stream.read_bytes())
    assert mesh.edge_nodes.shape == (len(mesh.tetrahedra), 6)
    assert (mesh.edge_nodes > mesh.tetrahedra.max()).all() and mesh.edge_nodes.max() == len(mesh.points) - 1
    as_meshio = mesh.to_meshio()
    reference = meshdec_level(stream, tmp_path)
    for kind in ("tetra10", "triangle6"):
        np.testing.assert_array_equal(as_meshio.cells_dict[kind], reference.cells_dict[kind])
    # (And as VTK's 10-node tetrahedra and 6-node triangles, where VTK is.)
    vtk = pytest.importorskip("vtkmodules.vtkCommonDataModel")
    grid = mesh.to_vtk()
    types = [grid.GetCellType(c) for c in range(grid.GetNumberOfCells())]
    assert types == [vtk.VTK_QUADRATIC_TETRA] * len(mesh.tetrahedra) + [vtk.VTK_QUADRATIC_TRIANGLE] * len(mesh.faces)
    assert grid.GetNumberOfPoints() == len(mesh.points)


def test_corpus_streams_decode_as_meshdec_decodes_them_at_every_level(corpus, tmp_path):
    for name, (_, stream) in corpus.items():
        data = stream.read_bytes()
        count = dtmesh.info(data)["level_count"]
        for level in range(count):
            mesh = dtmesh.decode(data, level=level)
            assert (mesh.level, mesh.level_count) == (level, count)
            assert_same_level(mesh, meshdec_level(stream, tmp_path, level))


def test_encode_from_numpy_writes_meshencs_bytes(corpus):
    for name, (node, stream) in corpus.items():
        points, tets, fields = read_tetgen(node)
        encoded = dtmesh.encode(points, tets, fields, box=256, dmax=2)
        assert encoded.bytes == stream.read_bytes(), name


def test_threads_change_no_byte(corpus):
    node, stream = corpus["bunny_10k"]
    points, tets, fields = read_tetgen(node)
    expected = stream.read_bytes()
    for threads in (1, 3):
        assert dtmesh.encode(points, tets, fields, box=256, dmax=2, threads=threads).bytes == expected, threads
    assert dtmesh.threads() >= 1  # the call's setting is gone: the default again
    finest = dtmesh.decode(expected)
    for threads in (1, 3):
        mesh = dtmesh.decode(expected, threads=threads)
        assert np.array_equal(mesh.tetrahedra, finest.tetrahedra), threads
    dtmesh.set_threads(2)
    try:
        assert dtmesh.threads() == 2
        assert dtmesh.encode(points, tets, fields, box=256, dmax=2).bytes == expected
    finally:
        dtmesh.set_threads(None)
    with pytest.raises(ValueError):
        dtmesh.set_threads(0)
    # More than 4 a core of those the process may run on only wait for each
    # other: held to that, as meshenc's --threads.
    dtmesh.set_threads(4096)
    try:
        assert dtmesh.threads() == min(4096, 4 * len(os.sched_getaffinity(0)))
    finally:
        dtmesh.set_threads(None)


def test_encode_options_match_meshencs(corpus, tmp_path):
    node, _ = corpus["torus_10k"]
    points, tets, fields = read_tetgen(node)
    cases = [
        (dict(qbits=12, scale=3.0), ["--qbits", "12", "--scale", "3"]),
        (dict(preset="paper", box=256, dmax=2), ["--preset", "paper", "--box", "256", "--dmax", "2"]),
        (dict(box=100), ["--box", "100"]),
    ]
    for options, arguments in cases:
        stream = tmp_path / "x.dtm"
        run(tool("meshenc"), node, "-q", "-o", stream, *arguments)
        assert dtmesh.encode(points, tets, fields, **options).bytes == stream.read_bytes(), arguments


def test_encode_report_is_meshencs_report(corpus, tmp_path):
    node, _ = corpus["hand_10k"]
    report = tmp_path / "report.json"
    run(tool("meshenc"), node, "-q", "--report", report, *ENCODE_ARGS)
    expected = json.loads(report.read_text())
    got = dtmesh.encode(*read_tetgen(node), box=256, dmax=2).report
    expected.pop("input"), got.pop("input")
    assert got == expected


def test_lossy_field_within_its_bound_and_lossless_fields_exact():
    rng = np.random.default_rng(7)
    points = rng.random((3000, 3))
    fields = {
        "pressure": rng.normal(size=3000),
        "velocity": rng.normal(size=(3000, 3)).astype(np.float32),
        "material": rng.integers(-5, 5, size=3000).astype(np.int8),
        "id": np.arange(3000, dtype=np.uint64),
        "mask": rng.random(3000) < 0.5,
    }
    encoded = dtmesh.encode(points, fields=fields, field_errors={"pressure": 1e-3})
    mesh = dtmesh.decode(encoded.bytes)
    vertex = encoded.vertex_of_input
    assert mesh.fields["pressure"].dtype == np.float64
    assert np.max(np.abs(mesh.fields["pressure"][vertex] - fields["pressure"])) <= 1e-3
    for name in ("velocity", "material", "id"):
        assert mesh.fields[name].dtype == fields[name].dtype
        np.testing.assert_array_equal(mesh.fields[name][vertex], fields[name])
    np.testing.assert_array_equal(mesh.fields["mask"][vertex], fields["mask"].astype(np.uint8))
    assert {f["name"]: f["mode"] for f in encoded.report["fields"]}["pressure"] == "lossy"


def test_info_is_meshinfos_json(corpus):
    for name, (_, stream) in list(corpus.items())[:2]:
        for stats in (False, True):
            expected = json.loads(run(tool("meshinfo"), stream, "--json", *(["--stats"] if stats else [])))
            got = dtmesh.info(stream.read_bytes(), stats=stats)
            expected.pop("input"), got.pop("input")
            assert got == expected, (name, stats)


def test_progressive_decoder_gives_every_level_as_its_layer_completes(corpus):
    data = corpus["knot1_10k"][1].read_bytes()
    decoder = dtmesh.Decoder()
    seen = []
    for start in range(0, len(data), 4096):
        for mesh in decoder.feed(data[start : start + 4096]):
            seen.append(mesh)
            # A level arrives once its bytes are all in, and not before.
            assert dtmesh.info(data[: start + 4096])["levels"][len(seen) - 1]["complete"]
    decoder.finish()
    assert [m.level for m in seen] == list(range(seen[0].level_count - 1, -1, -1))
    for mesh in seen:
        reference = dtmesh.decode(data, level=mesh.level)
        np.testing.assert_array_equal(mesh.points, reference.points)
        np.testing.assert_array_equal(mesh.tetrahedra, reference.tetrahedra)
    assert decoder.done and decoder.finest_level == 0


def test_every_truncation_ends_in_a_level_or_an_error():
    data = next(p for p in GOLDEN if p.name == "ellipsoid_793.dtm").read_bytes()
    count = dtmesh.info(data)["level_count"]
    decoded = 0
    for end in range(len(data)):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                mesh = dtmesh.decode(data[:end])
            except dtmesh.Error:
                continue
        decoded += 1
        assert 0 < mesh.level < count and len(mesh.tetrahedra) > 0
        assert any("truncated" in str(w.message) for w in caught)
    assert decoded > 0  # every prefix past the base layer decodes


def test_damaged_and_foreign_bytes_raise_the_librarys_error():
    # Every byte is under a checksum: a flipped bit is refused, or (in a
    # layer's length, which then runs past the end) read as a truncation,
    # never decoded as if whole.
    data = bytearray(GOLDEN[0].read_bytes())
    for bit in range(8 * len(data)):
        flipped = bytearray(data)
        flipped[bit // 8] ^= 1 << (bit % 8)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                dtmesh.decode(bytes(flipped))
            except dtmesh.Error:
                continue
        assert any("truncated" in str(w.message) for w in caught), f"bit {bit % 8} of byte {bit // 8}"
    rng = np.random.default_rng(1)
    for garbage in (b"", b"not a stream at all", bytes(rng.integers(0, 256, 5000, dtype=np.uint8))):
        with pytest.raises(dtmesh.Error):
            dtmesh.decode(garbage)
    with pytest.raises(dtmesh.Error, match="levels 0 to"):
        dtmesh.decode(bytes(data), level=99)


def test_a_file_that_is_not_a_stream_is_named_once(tmp_path):
    # As meshinfo says it: "x.dtm: not a .dtm stream", not "x.dtm: stream: ...".
    path = tmp_path / "notes.dtm"
    path.write_bytes(b"not a stream at all, but long enough to hold a header's bytes" * 4)
    for read in (dtmesh.info, dtmesh.decode):
        with pytest.raises(dtmesh.Error) as caught:
            read(str(path))
        assert str(caught.value).startswith(f"{path}: not a .dtm stream"), str(caught.value)


def test_bad_input_raises_with_the_reason():
    with pytest.raises(dtmesh.Error, match="not in one plane"):
        dtmesh.encode(np.zeros((10, 3)))
    with pytest.raises(ValueError):
        dtmesh.encode(np.zeros((10, 2)))
    with pytest.raises(ValueError, match="names point"):
        dtmesh.encode(np.random.rand(10, 3), np.array([[0, 1, 2, 99]]))
    with pytest.raises(ValueError, match="2\\^53"):
        dtmesh.encode(np.random.rand(10, 3), fields={"big": np.full(10, 2**60 + 1, dtype=np.int64)})
    with pytest.raises(ValueError, match="preset"):
        dtmesh.encode(np.random.rand(10, 3), preset="fast")


def test_meshio_reads_and_writes_dtm(corpus, tmp_path):
    node, stream = corpus["elephant_10k"]
    read = meshio.read(stream)
    finest = dtmesh.decode(stream.read_bytes())
    np.testing.assert_array_equal(read.points, finest.points)
    np.testing.assert_array_equal(read.cells_dict["tetra"], finest.tetrahedra)
    # Written back: the stream's fields, not the derived level and boundary.
    again = tmp_path / "again.dtm"
    meshio.write(again, read, box=256, dmax=2)
    assert [f["name"] for f in dtmesh.info(again)["fields"]] == ["boundary_marker"]
    # A mesh from elsewhere, through meshio: its tetrahedra are the solid.
    points, tets, fields = read_tetgen(node)
    mesh = meshio.Mesh(points, [("tetra", tets)], point_data=fields)
    out = tmp_path / "from_meshio.dtm"
    meshio.write(out, mesh, box=256, dmax=2)
    assert out.read_bytes() == stream.read_bytes()


def test_meshio_write_names_what_the_stream_does_not_hold(corpus, tmp_path):
    points, tets, _ = read_tetgen(corpus["bunny_10k"][0])
    triangles = tets[:5, :3]
    mesh = meshio.Mesh(points, [("tetra", tets), ("triangle", triangles)],
                       cell_data={"stress": [np.ones(len(tets)), np.zeros(5)]},
                       cell_sets={"steel": [np.arange(10), np.array([], dtype=np.int64)]},
                       point_data={"strain": np.ones((len(points), 3, 3))})
    out = tmp_path / "tagged.dtm"
    with pytest.warns(UserWarning) as said:
        meshio.write(out, mesh, box=256, dmax=2)
    lines = [str(w.message) for w in said]
    # A point tensor of two axes: named, as cell data's are (it raised).
    assert any("left out (the stream does not hold it): point data 'strain'" in m for m in lines), lines
    assert any("left out (the stream does not hold it): cells other than tetrahedra (5 triangle)" in m
               for m in lines), lines
    assert any("cell sets 'steel'" in m for m in lines), lines
    # The cell data on the tetrahedra is kept (level 0's cells, all ones).
    assert not any("'stress'" in m for m in lines), lines
    decoded = dtmesh.decode(out)
    assert np.all(decoded.cell_data["stress"] == 1)
    # The mesh itself is encoded all the same: the levels of its tetrahedra alone.
    plain = tmp_path / "plain.dtm"
    meshio.write(plain, meshio.Mesh(points, [("tetra", tets)]), box=256, dmax=2)
    assert np.array_equal(dtmesh.decode(plain).tetrahedra, decoded.tetrahedra)
    # meshio's .vtu of a gmsh mesh joins its groups' names into one array's
    # name, over the 64 bytes a stream holds; MED's field data are lists of
    # names, not [tag, dim]: the one named as left out, the other passed by.
    joined = "-".join(["base", "left_face", "pin_interface", "matrix", "pin", "ball", "gmsh:bounding_entities"])
    odd = meshio.Mesh(points, [("tetra", tets)], cell_data={joined: [np.ones(len(tets), np.int32)],
                                                            "stress": [np.ones(len(tets))]},
                      field_data={"med:nom": [[], []]})
    with pytest.warns(UserWarning) as said:
        meshio.write(tmp_path / "odd.dtm", odd, box=256, dmax=2)
    lines = [str(w.message) for w in said]
    assert any(f"cell data '{joined}'" in m for m in lines), lines
    assert np.all(dtmesh.decode(tmp_path / "odd.dtm").cell_data["stress"] == 1)


def test_cell_data_through_numpy_meshio_and_vtk(corpus, tmp_path):
    """Per-cell arrays: level 0's cells carry them, an input cell its own values bit for bit;
    coarser levels none; meshio and VTK get them as cell data."""
    points, tets, _ = read_tetgen(corpus["bunny_10k"][0])
    centroids = points[tets].mean(axis=1)
    heat = np.sin(centroids[:, 0] / 7).astype(np.float32)
    velocity = np.stack([centroids[:, 1], -centroids[:, 2], np.arange(len(tets))], axis=1)
    zone = (np.arange(len(tets)) % 5).astype(np.int16)
    encoded = dtmesh.encode(points, tets, cell_data={"heat": heat, "velocity": velocity, "zone": zone},
                            box=256, dmax=2)
    info = dtmesh.info(encoded.bytes)
    assert info["version"] == "10.0"
    assert [c["name"] for c in info["cell_fields"]] == ["heat", "velocity", "zone"]
    level0 = dtmesh.decode(encoded.bytes)
    assert level0.cell_data["heat"].dtype == np.float32
    assert level0.cell_data["velocity"].shape == (level0.tetrahedra.shape[0], 3)
    # The third component names the input tetrahedron; an input cell has its own values.
    v = encoded.vertex_of_input
    by_corners = {tuple(sorted(v[t])): i for i, t in enumerate(tets)}
    own = 0
    for k, cell in enumerate(level0.tetrahedra):
        i = by_corners.get(tuple(sorted(cell)))
        if i is None:
            continue
        own += 1
        assert level0.cell_data["velocity"][k, 2] == i
        assert level0.cell_data["heat"][k] == heat[i]
        assert level0.cell_data["zone"][k] == zone[i]
    assert own == encoded.report["cells_from_input"] > 0.9 * len(level0.tetrahedra)
    assert dtmesh.decode(encoded.bytes, 1).cell_data == {}
    with pytest.raises(ValueError, match="cell_data 'zone'"):
        dtmesh.encode(points, tets, cell_data={"zone": zone[:-1]})
    # meshio: cell data, back into a stream with the same values.
    mesh = level0.to_meshio()
    assert mesh.cell_data["heat"][0].dtype == np.float32
    out = tmp_path / "again.dtm"
    meshio.write(out, mesh, box=256, dmax=2)
    again = dtmesh.decode(out)
    assert again.cell_data["heat"].dtype == np.float32
    assert again.cell_data["zone"].shape == (again.tetrahedra.shape[0],)
    assert sorted(set(again.cell_data["zone"].tolist())) == [0, 1, 2, 3, 4]
    grid = level0.to_vtk()
    assert grid.GetCellData().GetArray("velocity").GetNumberOfComponents() == 3


def cells_by_corners(mesh):
    """Each cell of a Mesh, by its corners' coordinates, with its cell data row."""
    out = {}
    for k, cell in enumerate(mesh.tetrahedra):
        key = tuple(sorted(tuple(mesh.points[v]) for v in cell))
        assert key not in out, "a cell twice"
        out[key] = tuple(np.asarray(values[k]).tobytes() for _, values in sorted(mesh.cell_data.items()))
    return out


def test_bricked_streams_read_by_box_and_in_pieces(corpus, tmp_path):
    """bricks=True writes meshenc --bricks' bytes; decode_box gives meshdec --box's cells, read by
    offset from a file; decode_piece's pieces hold every cell of the level once, with its cell data."""
    node, _ = corpus["bunny_10k"]
    points, tets, fields = read_tetgen(node)
    plain = dtmesh.encode(points, tets, fields, box=256, dmax=2, bricks=True, brick_points=256)
    made = tmp_path / "meshenc.dtm"
    run(tool("meshenc"), node, "-q", "-o", made, *ENCODE_ARGS, "--bricks", "--brick-points", "256")
    assert plain.bytes == made.read_bytes()
    # With cell data (format 16.0): each cell's number, so that a cell names its input tetrahedron.
    own = np.arange(len(tets), dtype=np.uint32)
    encoded = dtmesh.encode(points, tets, fields, box=256, dmax=2, bricks=True, brick_points=256,
                            cell_data={"own": own})
    assert dtmesh.info(encoded.bytes)["version"] == "16.0"
    stream = tmp_path / "cells.dtm"
    stream.write_bytes(encoded.bytes)
    whole = dtmesh.decode(stream)
    lo, hi = points.min(axis=0), points.max(axis=0)
    box = tuple(lo + 0.3 * (hi - lo)) + tuple(lo + 0.6 * (hi - lo))
    part = dtmesh.decode_box(stream, box)
    assert 0 < len(part.tetrahedra) < len(whole.tetrahedra)
    out = tmp_path / "box.vtu"
    run(tool("meshdec"), stream, "-q", "--box", *box, "-o", out)
    reference = meshio.read(out)
    np.testing.assert_array_equal(part.points, reference.points)
    np.testing.assert_array_equal(part.tetrahedra, reference.cells_dict["tetra"])
    np.testing.assert_array_equal(part.fields["vertex_id"], reference.point_data["vertex_id"])
    np.testing.assert_array_equal(part.cell_data["own"], reference.cell_data["own"][0])
    assert part.boundary.size == 0  # a box's own surface is not the level's
    assert dtmesh.decode_box(encoded.bytes, box).tetrahedra.shape == part.tetrahedra.shape  # bytes too
    everything = cells_by_corners(whole)
    assert set(cells_by_corners(part).items()) <= set(everything.items())
    pieces = {}
    for k in range(3):
        piece = dtmesh.decode_piece(stream, k, 3)
        for key, values in cells_by_corners(piece).items():
            assert key not in pieces, "a cell in two pieces"
            pieces[key] = values
    assert pieces == everything
    # A part converts as a level does (without boundary: it has none), and
    # meshio writes it back as a stream, its vertex_id (the decoder's) left out.
    assert "boundary" not in piece.to_meshio().point_data
    meshio.write(tmp_path / "piece.dtm", piece.to_meshio())
    assert "vertex_id" not in dtmesh.decode(tmp_path / "piece.dtm").fields
    assert piece.to_vtk().GetNumberOfCells() == len(piece.tetrahedra)
    assert dtmesh.decode_piece(stream, 0, 2, level=1).cell_data == {}  # level 1 has none
    with pytest.raises(ValueError, match="piece"):
        dtmesh.decode_piece(stream, 3, 3)
    # Numbers past what the decoder takes are a ValueError saying the range,
    # not pybind11's TypeError; a bound past a uint64 bounds nothing more.
    for piece, pieces in ((0, 2**40), (2**40, 2**41), (True, 2)):
        with pytest.raises(ValueError, match="pieces 1 to 2147483647"):
            dtmesh.decode_piece(stream, piece, pieces)
    with pytest.raises(ValueError, match="level must be an int from 0 to 2147483647"):
        dtmesh.decode_piece(stream, 0, 2, level=2**40)
    with pytest.raises(ValueError, match="level must be an int from 0 to 2147483647"):
        dtmesh.decode(stream, level=2**40)
    with pytest.raises(ValueError, match="level must be an int from 0 to 2147483647"):
        dtmesh.Decoder(level=2**40)
    assert len(dtmesh.decode_box(stream, (-1e9, -1e9, -1e9, 1e9, 1e9, 1e9), max_vertices=2**70).tetrahedra) > 0
    with pytest.raises(ValueError, match="box"):
        dtmesh.decode_box(stream, (1, 1, 1, 0, 0, 0))
    with pytest.raises(dtmesh.Error, match="bunny_10k.dtm: pieces need a bricked"):  # the file named
        dtmesh.decode_piece(corpus["bunny_10k"][1], 0, 2)
    for bad in (0, -5, 2**33, 2.5):
        with pytest.raises(ValueError, match="brick_points"):
            dtmesh.encode(points, tets, bricks=True, brick_points=bad)
    with pytest.raises(FileNotFoundError):
        dtmesh.decode_box(tmp_path / "absent.dtm", box)
    with pytest.raises(dtmesh.Error, match="level 9"):
        dtmesh.decode_box(stream, box, level=9)
    # A stream that is not bricked: the box cut from the whole level, boundary and all.
    with pytest.raises(dtmesh.Error, match="level 9 asked, the stream has levels 0 to"):
        dtmesh.decode_box(corpus["bunny_10k"][1], box, level=9)
    cut = dtmesh.decode_box(corpus["bunny_10k"][1], box)
    assert len(cut.tetrahedra) > 0 and cut.boundary.size == len(cut.points)
    # A truncated stream: its finest whole level, said.
    with pytest.warns(UserWarning, match="truncated"):
        coarser = dtmesh.decode_box(encoded.bytes[: len(encoded.bytes) - 100], box)
    assert coarser.level == 1


def test_exact_level_zero_is_the_input_cell_for_cell(corpus):
    """exact=True: level 0 is the input's tetrahedra, with the input's numbering (keep_order),
    cell for cell; the cell data on them is each cell's own."""
    points, tets, _ = read_tetgen(corpus["bunny_10k"][0])
    own = np.arange(len(tets), dtype=np.uint32)
    encoded = dtmesh.encode(points, tets, exact=True, keep_order=True, cell_data={"own": own}, box=256, dmax=2)
    assert dtmesh.info(encoded.bytes)["version"] == "23.0"
    assert encoded.report["exact"]["delaunay_cells"] + encoded.report["exact"]["fill_cells"] == len(tets)
    level0 = dtmesh.decode(encoded.bytes)
    assert level0.tetrahedra.shape == tets.shape
    assert sorted(map(tuple, np.sort(level0.tetrahedra, axis=1))) == sorted(map(tuple, np.sort(tets, axis=1)))
    assert (np.sort(level0.tetrahedra, axis=1) == np.sort(tets[level0.cell_data["own"]], axis=1)).all()
    with pytest.raises(dtmesh.Error, match="--qbits"):
        dtmesh.encode(points, tets, exact=True, qbits=6, box=256, dmax=2)


def test_vertex_of_input_names_the_decoded_vertices_with_and_without_keep_order():
    """vertex_of_input maps each point to its vertex in level 0 as decode() gives it: with
    keep_order, its own index; layer_vertex_of_input to the layers' order, which coarser levels use."""
    rng = np.random.default_rng(11)
    points = rng.random((4000, 3))
    for keep_order in (False, True):
        encoded = dtmesh.encode(points, keep_order=keep_order)
        step = dtmesh.info(encoded.bytes)["step"]
        level0 = dtmesh.decode(encoded.bytes)
        assert np.abs(level0.points[encoded.vertex_of_input] - points).max() <= 0.5 * step * (1 + 1e-6)
        coarser = dtmesh.decode(encoded.bytes, level=1)
        held = encoded.layer_vertex_of_input < len(coarser.points)
        assert 0 < held.sum() < len(points)
        at = coarser.points[encoded.layer_vertex_of_input[held]]
        assert np.abs(at - points[held]).max() <= 0.5 * step * (1 + 1e-6)


def test_regions_through_numpy_meshio_and_gmsh(tmp_path):
    """A gmsh part of two materials: its physical volumes are the regions on every level, its
    physical surfaces the tagged faces."""
    msh = tmp_path / "two_materials.msh"
    msh.write_bytes(lzma.open(DATA / "two_materials.msh.xz").read())
    mesh = meshio.read(msh)
    mesh.point_data.clear()  # meshio's gmsh:dim_tags, which meshenc does not read
    out = tmp_path / "two_materials.dtm"
    meshio.write(out, mesh)
    info = dtmesh.info(out)
    assert info["version"] == "9.0"
    assert [(r["label"], r["name"]) for r in info["regions"]] == [(1, "aluminium"), (2, "steel")]
    # meshenc reads the same file to the same stream.
    by_meshenc = tmp_path / "by_meshenc.dtm"
    run(tool("meshenc"), msh, "-q", "-o", by_meshenc)
    assert out.read_bytes() == by_meshenc.read_bytes()
    for level in range(info["level_count"]):
        decoded = dtmesh.decode(out.read_bytes(), level)
        assert decoded.regions.shape == (decoded.tetrahedra.shape[0],)
        assert sorted(set(decoded.regions.tolist())) == [1, 2]
        assert decoded.region_names == {1: "aluminium", 2: "steel"}
    # From numpy, the same labels, the same stream.
    tets = np.vstack([b.data for b in mesh.cells if b.type == "tetra"])
    labels = np.concatenate([mesh.cell_data["gmsh:physical"][i] for i, b in enumerate(mesh.cells)
                             if b.type == "tetra"])
    triangles = np.vstack([b.data for b in mesh.cells if b.type == "triangle"])
    tags = np.concatenate([mesh.cell_data["gmsh:physical"][i] for i, b in enumerate(mesh.cells)
                           if b.type == "triangle"])
    encoded = dtmesh.encode(mesh.points, tets, regions=labels, region_names={1: "aluminium", 2: "steel"},
                            faces=triangles, face_tags=tags, face_tag_names={3: "base", 4: "load"})
    assert encoded.bytes == out.read_bytes()
    assert [(t["label"], t["name"]) for t in info["face_tags"]] == [(3, "base"), (4, "load")]
    finest = dtmesh.decode(out.read_bytes())
    assert sorted(set(finest.face_tags.tolist())) == [3, 4]
    assert finest.faces.shape == (finest.face_tags.shape[0], 3)
    # The stream fed in chunks gives the same faces, row for row, corners in the same turn.
    decoder = dtmesh.Decoder()
    fed = [decoder.feed(out.read_bytes()[k:k + 4000]) for k in range(0, len(out.read_bytes()), 4000)]
    decoder.finish()
    np.testing.assert_array_equal(decoder.mesh().faces, finest.faces)
    np.testing.assert_array_equal([level for chunk in fed for level in chunk][-1].faces, finest.faces)
    # In bricks (17.0): the same tags on every level, and the pieces hold the whole level's tagged
    # faces, each once.
    bricked = dtmesh.encode(mesh.points, tets, regions=labels, region_names={1: "aluminium", 2: "steel"},
                            faces=triangles, face_tags=tags, face_tag_names={3: "base", 4: "load"},
                            bricks=True, brick_points=256)
    assert dtmesh.info(bricked.bytes)["version"] == "17.0"
    whole = dtmesh.decode(bricked.bytes)
    assert whole.face_tag_names == {3: "base", 4: "load"}

    def tagged(level):
        return sorted((tuple(sorted(map(tuple, level.points[f].tolist()))), int(t))
                      for f, t in zip(level.faces, level.face_tags))

    in_pieces = []
    for k in range(3):
        in_pieces += tagged(dtmesh.decode_piece(bricked.bytes, k, 3))
    assert len(in_pieces) > 100 and sorted(in_pieces) == tagged(whole)
    with pytest.raises(ValueError, match="one label per tetrahedron"):
        dtmesh.encode(mesh.points, tets, regions=labels[:-1])
    # Back through meshio's gmsh writer: gmsh's physical groups and names.
    finest = meshio.read(out)
    again = tmp_path / "again.msh"
    meshio.write(again, finest, file_format="gmsh22", binary=False)
    back = meshio.read(again)
    assert sorted(set(np.concatenate(back.cell_data["gmsh:physical"]).tolist())) == [1, 2, 3, 4]
    assert back.field_data["steel"][0] == 2
    # The named regions and tags are meshio's cell sets too, and a round trip keeps them.
    assert sorted(finest.cell_sets) == ["aluminium", "base", "load", "steel"]
    steel = [i for i, b in enumerate(finest.cells) if b.type == "tetra"][0]
    assert len(finest.cell_sets["steel"][steel]) == int((dtmesh.decode(out).regions == 2).sum())
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # nothing of a decoded mesh is left out
        meshio.write(tmp_path / "round.dtm", finest)
    assert dtmesh.decode(tmp_path / "round.dtm").region_names == {1: "aluminium", 2: "steel"}
    # And the VTK grid carries them as cell data.
    level0 = dtmesh.decode(out.read_bytes())
    grid = level0.to_vtk()
    assert grid.GetCellData().GetArray("region").GetNumberOfTuples() == grid.GetNumberOfCells()
    assert grid.GetNumberOfCells() == level0.tetrahedra.shape[0] + level0.faces.shape[0]


NETGEN_VOL = """mesh3d
dimension
3
geomtype
0

# surfnr    bcnr   domin  domout      np      p1      p2      p3
surfaceelements
2
 1 1 1 0 3 1 3 2
 2 7 1 2 3 2 3 4

#  matnr      np      p1      p2      p3      p4
volumeelements
3
1 4 1 2 3 4
2 4 2 3 4 5
2 4 2 4 6 5

edgesegmentsgi2
1
 1 0 1 2 0 0 1 1 1 0 0 0

points
6
 0 0 0
 1 0 0
 0 1 0
 0 0 1
 1 1 1
 1.5 -0.5 1
materials
2
1 aluminium
2 steel

bcnames
2
1\touter
7\tpin

endmesh
"""


def test_meshio_writes_a_second_order_mesh_as_its_linear_cells(tmp_path):
    """The gmsh part made second-order (a node on each edge, tetra10 and triangle6): the stream
    of the linear mesh, the edge nodes named as left out."""
    msh = tmp_path / "two_materials.msh"
    msh.write_bytes(lzma.open(DATA / "two_materials.msh.xz").read())
    mesh = meshio.read(msh)
    mesh.point_data.clear()
    linear = tmp_path / "linear.dtm"
    meshio.write(linear, mesh)
    tets = [b for b in mesh.cells if b.type == "tetra"]
    edges = np.unique(np.sort(np.vstack([b.data[:, pair] for b in tets for pair in
                                         ([0, 1], [1, 2], [0, 2], [0, 3], [1, 3], [2, 3])]), axis=1), axis=0)
    node = {tuple(e): len(mesh.points) + i for i, e in enumerate(edges.tolist())}
    points = np.vstack([mesh.points, (mesh.points[edges[:, 0]] + mesh.points[edges[:, 1]]) / 2])
    def quadratic(block):
        if block.type == "tetra":
            pairs, kind = ((0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)), "tetra10"
        elif block.type == "triangle":
            pairs, kind = ((0, 1), (1, 2), (0, 2)), "triangle6"
        else:
            return block
        mids = [[node[tuple(sorted((c[a], c[b])))] for a, b in pairs] for c in block.data.tolist()]
        return meshio.CellBlock(kind, np.hstack([block.data, np.array(mids)]))
    second = meshio.Mesh(points, [quadratic(b) for b in mesh.cells], cell_data=mesh.cell_data,
                         field_data=mesh.field_data)
    out = tmp_path / "second.dtm"
    with pytest.warns(UserWarning, match=f"left out.*{len(edges)} nodes on the edges of second-order elements "
                                         f"\\({sum(len(b.data) for b in tets)} second-order tetrahedra\\)"):
        meshio.write(out, second)
    assert out.read_bytes() == linear.read_bytes()


def test_meshio_writes_a_second_order_mesh_exactly_as_meshenc_does(tmp_path):
    """A gmsh ball of tetra10 (its surface's nodes on the sphere): meshio.write with exact=True keeps
    the edge nodes (format 20.0), meshenc --exact's bytes for the same .msh; decoded, its to_meshio()
    is the input's tetra10 within half a grid step; without exact a warning names them."""
    geo = tmp_path / "ball.geo"
    geo.write_text('SetFactory("OpenCASCADE");\nSphere(1) = {0, 0, 0, 1};\nMesh.MeshSizeMax = 0.5;\n'
                   'Physical Volume("ball", 1) = {1};\n')
    msh = tmp_path / "ball.msh"
    run("gmsh", geo, "-3", "-order", "2", "-format", "msh41", "-o", msh)
    mesh = meshio.read(msh)
    mesh.point_data.clear()  # meshio's gmsh:dim_tags, which meshenc does not read
    ours, theirs = tmp_path / "ours.dtm", tmp_path / "theirs.dtm"
    meshio.write(ours, mesh, exact=True)
    run(tool("meshenc"), msh, "-q", "--exact", "-o", theirs)
    assert ours.read_bytes() == theirs.read_bytes()
    decoded = dtmesh.decode(ours.read_bytes())
    info = dtmesh.info(ours.read_bytes())
    assert info["version"] == "23.0" and decoded.edge_nodes.shape == (len(mesh.cells_dict["tetra10"]), 6)
    back = decoded.to_meshio()
    t, u = mesh.cells_dict["tetra10"], back.cells_dict["tetra10"]
    nearest = {i: int(np.argmin(np.abs(mesh.points - back.points[i]).max(axis=1))) for i in np.unique(u[:, :4])}
    want = {frozenset((c[a], c[b])): mesh.points[c[4 + k]]
            for c in t for k, (a, b) in enumerate([(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)])}
    worst = max(np.abs(back.points[c[4 + k]] - want[frozenset((nearest[c[a]], nearest[c[b]]))]).max()
                for c in u for k, (a, b) in enumerate([(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)]))
    assert worst <= 0.5 * info["step"] * (1 + 1e-6)
    with pytest.warns(UserWarning, match="nodes on the edges of second-order elements"):
        meshio.write(tmp_path / "linear.dtm", mesh)


def test_a_second_order_mesh_keeps_gmshs_numbering_of_all_its_nodes(tmp_path):
    """The ball with exact=True and keep_order=True: meshenc --exact --keep-order's bytes (format
    21.0, the edge nodes where gmsh numbered them among the vertices); decoded, its to_meshio() has
    the input's nodes in the input's order, within half a grid step, and the same tetra10."""
    geo = tmp_path / "ball.geo"
    geo.write_text('SetFactory("OpenCASCADE");\nSphere(1) = {0, 0, 0, 1};\nMesh.MeshSizeMax = 0.5;\n'
                   'Physical Volume("ball", 1) = {1};\n')
    msh = tmp_path / "ball.msh"
    run("gmsh", geo, "-3", "-order", "2", "-format", "msh41", "-o", msh)
    mesh = meshio.read(msh)
    mesh.point_data.clear()
    ours, theirs = tmp_path / "ours.dtm", tmp_path / "theirs.dtm"
    meshio.write(ours, mesh, exact=True, keep_order=True)
    run(tool("meshenc"), msh, "-q", "--exact", "--keep-order", "-o", theirs)
    assert ours.read_bytes() == theirs.read_bytes()
    info = dtmesh.info(ours.read_bytes())
    assert info["version"] == "23.0"
    back = dtmesh.decode(ours.read_bytes()).to_meshio()
    assert back.points.shape == mesh.points.shape
    assert np.abs(back.points - mesh.points).max() <= 0.5 * info["step"] * (1 + 1e-6)
    def cells(m):  # each tetra10 as its corners and its edges' nodes, by number
        pairs = [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)]  # (meshio's order, VTK's)
        return {(frozenset(c[:4]), frozenset((frozenset((c[a], c[b])), c[4 + k]) for k, (a, b) in enumerate(pairs)))
                for c in np.asarray(m.cells_dict["tetra10"]).tolist()}
    assert cells(back) == cells(mesh)


def test_a_files_own_node_ids_come_back_as_node_ids(tmp_path):
    """An Abaqus deck numbering its nodes from an offset, encoded by meshenc --keep-order (format 22.0):
    dtmesh.decode gives each point the deck's node number as node_ids, in the deck's order."""
    points, tets, _ = read_tetgen(DATA / "torus_288.node")
    ids = np.arange(len(points)) * 3 + 5001
    deck = tmp_path / "torus.inp"
    deck.write_text("*NODE\n" + "".join(f"{i}, {p[0]!r}, {p[1]!r}, {p[2]!r}\n" for i, p in zip(ids, points)) +
                    "*ELEMENT, TYPE=C3D4\n" + "".join(f"{k + 1}, " + ", ".join(str(ids[v]) for v in t) + "\n"
                                                    for k, t in enumerate(tets)))
    stream = tmp_path / "torus.dtm"
    run(tool("meshenc"), deck, "-q", "--keep-order", "--box", "256", "--dmax", "2", "-o", stream)
    mesh = dtmesh.decode(stream.read_bytes())
    np.testing.assert_array_equal(mesh.node_ids, ids)
    assert np.abs(mesh.points - points).max() < 1e-3 * np.ptp(points, axis=0).max()
    assert dtmesh.decode(stream.read_bytes(), level=1).node_ids.size == 0


def test_a_second_order_meshs_point_data_is_kept_at_its_edge_nodes(tmp_path):
    """The ball with point data at every node (a simulation's results on tetra10): meshio.write with
    exact=True keeps the values at the edge nodes too (format 19.0), meshenc --exact's bytes for the
    same .vtu; decoded, to_meshio() gives every node its own values, bit for bit, or within a lossy
    field's bound; encode(edge_fields=) refuses values that are not a field's."""
    geo = tmp_path / "ball.geo"
    geo.write_text('SetFactory("OpenCASCADE");\nSphere(1) = {0, 0, 0, 1};\nMesh.MeshSizeMax = 0.5;\n')
    msh = tmp_path / "ball.msh"
    run("gmsh", geo, "-3", "-order", "2", "-format", "msh41", "-o", msh)
    read = meshio.read(msh)
    p = read.points
    data = {"temperature": np.sin(2 * p[:, 0]) + p[:, 1] * p[:, 2], "id": np.arange(len(p), dtype=np.int32),
            "velocity": np.stack([p[:, 0] ** 2, np.cos(p[:, 1]), p[:, 2]], axis=1).astype(np.float32)}
    mesh = meshio.Mesh(p, [b for b in read.cells if b.type == "tetra10"], point_data=data)
    vtu = tmp_path / "ball.vtu"
    mesh.write(vtu)
    ours, theirs = tmp_path / "ours.dtm", tmp_path / "theirs.dtm"
    meshio.write(ours, mesh, exact=True, field_errors={"velocity": 1e-3})
    run(tool("meshenc"), vtu, "-q", "--exact", "--field-error", "velocity=1e-3", "-o", theirs)
    assert ours.read_bytes() == theirs.read_bytes()
    assert dtmesh.info(ours.read_bytes())["version"] == "23.0"
    back = dtmesh.decode(ours.read_bytes()).to_meshio()
    assert len(back.points) == len(p)
    index = np.array([int(np.argmin(np.abs(p - q).max(axis=1))) for q in back.points])
    np.testing.assert_array_equal(back.point_data["temperature"], data["temperature"][index])
    np.testing.assert_array_equal(back.point_data["id"], data["id"][index])
    assert np.abs(back.point_data["velocity"] - data["velocity"][index]).max() <= 1e-3 * (1 + 1e-6)
    tets = np.asarray(mesh.cells_dict["tetra10"])
    with pytest.raises(ValueError, match="not a field"):
        dtmesh.encode(p, tets[:, :4], {"id": data["id"]}, exact=True, edge_points=p, edge_nodes=tets[:, 4:] * 0 - 1,
                      edge_fields={"other": data["id"]})


def test_meshio_writes_prisms_and_hexahedra_as_meshenc_reads_them(tmp_path):
    """A boundary layer of prisms under tetrahedra, and a block of hexahedra with tagged quads, made
    by gmsh: meshio.write gives meshenc's bytes for the same .msh, with exact=True too (the cells
    split into the very same tetrahedra, each with its cell's region), and names the shapes."""
    geo = tmp_path / "hybrid.geo"
    geo.write_text("""
Point(1) = {0, 0, 0, 0.25}; Point(2) = {1, 0, 0, 0.25}; Point(3) = {1, 1, 0, 0.25}; Point(4) = {0, 1, 0, 0.25};
Point(5) = {2, 0, 0, 0.25}; Point(6) = {2, 1, 0, 0.25};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1}; Line(5) = {2, 5}; Line(6) = {5, 6};
Line(7) = {6, 3};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Curve Loop(2) = {5, 6, 7, -2}; Plane Surface(2) = {2};
Transfinite Curve{2, 5, 6, 7} = 5; Transfinite Surface{2}; Recombine Surface{2};
layer[] = Extrude {0, 0, 0.2} { Surface{1}; Layers{2}; Recombine; };
core[] = Extrude {0, 0, 0.5} { Surface{layer[0]}; };
block[] = Extrude {0, 0, 0.2} { Surface{2}; Layers{2}; Recombine; };
Physical Volume("layer", 1) = {layer[1]};
Physical Volume("core", 2) = {core[1]};
Physical Volume("block", 3) = {block[1]};
Physical Surface("bottom", 4) = {1, 2};
""")
    msh = tmp_path / "hybrid.msh"
    run("gmsh", geo, "-3", "-format", "msh41", "-o", msh)
    mesh = meshio.read(msh)
    mesh.point_data.clear()  # meshio's gmsh:dim_tags, which meshenc does not read
    kinds = {block.type for block in mesh.cells}
    assert {"wedge", "hexahedron", "quad", "tetra"} <= kinds, kinds
    out = tmp_path / "hybrid.dtm"
    with pytest.warns(UserWarning, match=r"left out.*the shapes of its [0-9]+ prisms, [0-9]+ hexahedra: each is read "
                                         r"as the tetrahedra that split it"):
        meshio.write(out, mesh)
    by_meshenc = tmp_path / "by_meshenc.dtm"
    run(tool("meshenc"), msh, "-q", "-o", by_meshenc)
    assert out.read_bytes() == by_meshenc.read_bytes()
    assert [(r["label"], r["name"]) for r in dtmesh.info(out)["regions"]] == [(1, "layer"), (2, "core"), (3, "block")]
    exact, exact_by_meshenc = tmp_path / "exact.dtm", tmp_path / "exact_by_meshenc.dtm"
    with pytest.warns(UserWarning, match="the shapes of its"):
        meshio.write(exact, mesh, exact=True)
    run(tool("meshenc"), msh, "-q", "--exact", "-o", exact_by_meshenc)
    assert exact.read_bytes() == exact_by_meshenc.read_bytes()
    # Made second-order (wedge18, hexahedron27, quad9, tetra10): the linear mesh's bytes.
    second = tmp_path / "second.msh"
    run("gmsh", geo, "-3", "-order", "2", "-format", "msh41", "-o", second)
    mesh2 = meshio.read(second)
    mesh2.point_data.clear()
    assert {"wedge18", "hexahedron27", "tetra10"} <= {block.type for block in mesh2.cells}
    out2 = tmp_path / "second.dtm"
    with pytest.warns(UserWarning, match=r"second-order tetrahedra, [0-9]+ second-order hexahedra, prisms and pyramids"):
        meshio.write(out2, mesh2)
    assert out2.read_bytes() == out.read_bytes()


def test_netgen_vol_through_meshio_is_meshencs_stream(tmp_path):
    """Netgen's .vol as meshio reads it (netgen:index, names in its field data): the materials are
    the regions and the boundary conditions the tagged faces, with their names, the bytes meshenc
    writes from the file itself."""
    vol = tmp_path / "part.vol"
    vol.write_text(NETGEN_VOL)
    out = tmp_path / "part.dtm"
    with pytest.warns(UserWarning, match="left out.*line"):
        meshio.write(out, meshio.read(vol))
    info = dtmesh.info(out)
    assert [(r["label"], r["name"]) for r in info["regions"]] == [(1, "aluminium"), (2, "steel")]
    assert [(t["label"], t["name"]) for t in info["face_tags"]] == [(1, "outer"), (7, "pin")]
    by_meshenc = tmp_path / "by_meshenc.dtm"
    run(tool("meshenc"), vol, "-q", "-o", by_meshenc)
    assert out.read_bytes() == by_meshenc.read_bytes()


def test_exodus_through_meshio(corpus, tmp_path):
    """Exodus II (a simulation's mesh) goes through meshio's reader (python3-netcdf4)."""
    pytest.importorskip("netCDF4", reason="apt-get install python3-netcdf4 (scripts/setup.sh --all)")
    points, tets, _ = read_tetgen(corpus["torus_10k"][0])
    exodus = tmp_path / "part.e"
    meshio.write(exodus, meshio.Mesh(points, [("tetra", tets)]), file_format="exodus")
    via_exodus, direct = tmp_path / "via_exodus.dtm", tmp_path / "direct.dtm"
    meshio.write(via_exodus, meshio.read(exodus), box=256, dmax=2)
    meshio.write(direct, meshio.Mesh(points, [("tetra", tets)]), box=256, dmax=2)
    assert via_exodus.read_bytes() == direct.read_bytes()


def test_xdmf_as_fenics_users_convert_gmsh_meshes(tmp_path):
    """XDMF with HDF5, FEniCS's and dolfinx's mesh files, made as their tutorials convert a gmsh mesh
    (meshio, the physical volumes as a cell array "name_to_read"), goes through meshio's reader
    (python3-h5py): region_array= takes that array as the regions (the stream of the .msh itself,
    whose names XDMF does not hold); decoded, to_meshio() writes XDMF again, which meshio reads."""
    pytest.importorskip("h5py", reason="apt-get install python3-h5py (scripts/setup.sh --all)")
    msh = tmp_path / "two_materials.msh"
    msh.write_bytes(lzma.open(DATA / "two_materials.msh.xz").read())
    gmsh_mesh = meshio.read(msh)
    tetra = gmsh_mesh.get_cells_type("tetra")
    labels = gmsh_mesh.get_cell_data("gmsh:physical", "tetra")
    xdmf = tmp_path / "mesh.xdmf"
    meshio.write(xdmf, meshio.Mesh(gmsh_mesh.points, [("tetra", tetra)], cell_data={"name_to_read": [labels]}))
    via_xdmf, direct = tmp_path / "via_xdmf.dtm", tmp_path / "direct.dtm"
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # nothing of the XDMF left out
        meshio.write(via_xdmf, meshio.read(xdmf), region_array="name_to_read", box=256, dmax=2)
    meshio.write(direct, meshio.Mesh(gmsh_mesh.points, [("tetra", tetra)], cell_data={"region": [labels]}),
                 box=256, dmax=2)
    assert via_xdmf.read_bytes() == direct.read_bytes()
    assert len(dtmesh.info(via_xdmf)["regions"]) == 2
    with pytest.raises(ValueError, match="region_array 'nothing'"):
        meshio.write(tmp_path / "x.dtm", meshio.read(xdmf), region_array="nothing")
    level = dtmesh.decode(via_xdmf.read_bytes())
    back = tmp_path / "back.xdmf"
    meshio.write(back, level.to_meshio())
    again = meshio.read(back)
    assert len(again.points) == len(level.points)
    assert np.array_equal(again.get_cells_type("tetra"), level.tetrahedra)
    assert np.array_equal(again.get_cell_data("gmsh:physical", "tetra"), level.regions)


def test_vtk_grid_has_the_level_and_its_point_data(corpus):
    mesh = dtmesh.decode(corpus["fandisk_11k"][1].read_bytes(), level=1)
    grid = dtmesh.to_vtk(mesh)
    assert grid.GetNumberOfPoints() == len(mesh.points)
    assert grid.GetNumberOfCells() == len(mesh.tetrahedra)
    ids = grid.GetCell(5).GetPointIds()
    assert [ids.GetId(i) for i in range(4)] == list(mesh.tetrahedra[5])
    names = {grid.GetPointData().GetArrayName(i) for i in range(grid.GetPointData().GetNumberOfArrays())}
    assert names == {"boundary_marker", "level", "boundary"}


def test_meshio_reads_meshdecs_surfaces_with_their_types(tmp_path):
    # An MRI's uint16 values on a level's surface, as .ply (uint16, not
    # ushort: meshio reads only that name) and .off. (meshio reads no name
    # of int16.)
    stream = tmp_path / "mri.dtm"
    run(tool("meshenc"), DATA / "fields" / "mri_s0.nrrd", "--threshold", "150", "-q", "-o", stream)
    level = dtmesh.decode(stream.read_bytes(), level=2)
    for ext in ("ply", "off"):
        run(tool("meshdec"), stream, "--level", "2", "-q", "-o", tmp_path / f"s.{ext}")
        m = meshio.read(tmp_path / f"s.{ext}")
        assert len(m.cells_dict["triangle"]) > 0
        assert set(map(tuple, m.points)) <= set(map(tuple, level.points)), ext
    m = meshio.read(tmp_path / "s.ply")
    assert m.point_data["value"].dtype == np.uint16
    assert m.point_data["level"].dtype == np.int32
    values = {tuple(p): v for p, v in zip(level.points, level.fields["value"])}
    assert all(values[tuple(p)] == v for p, v in zip(m.points, m.point_data["value"]))
    levels = {tuple(p): v for p, v in zip(level.points, level.vertex_levels)}
    assert all(levels[tuple(p)] == v for p, v in zip(m.points, m.point_data["level"]))


def test_encoding_and_decoding_release_the_gil():
    # While one thread is inside a long library call, Python code runs in
    # another at a good share of its own pace; were the GIL held through the
    # call, it would not run at all until the call returned.
    def count_until(event):
        ticks, start = 0, time.perf_counter()
        while not event.is_set():
            ticks += 1
        return ticks / (time.perf_counter() - start)

    alone = threading.Event()
    threading.Timer(0.3, alone.set).start()
    pace_alone = count_until(alone)
    points = np.random.default_rng(3).random((60000, 3))
    encoded = []
    for call in (lambda: encoded.append(dtmesh.encode(points).bytes), lambda: dtmesh.decode(encoded[0])):
        started, done = threading.Event(), threading.Event()

        def work():
            started.set()
            call()
            done.set()

        worker = threading.Thread(target=work)
        worker.start()
        started.wait()
        pace_meanwhile = count_until(done)
        worker.join()
        assert pace_meanwhile > 0.15 * pace_alone, (pace_meanwhile, pace_alone)


def test_bad_arguments_are_refused_not_truncated_and_leave_no_state(tmp_path):
    """Indices that are not whole numbers, a field under a name the decoder gives its own arrays, a
    failed set_threads, a Decoder fed after finish(), a truncated stream asked for a level it does
    not reach: each refused, naming the problem (a path's file too)."""
    points, tets, _ = read_tetgen(DATA / "torus_288.node")
    with pytest.raises(TypeError, match="tetrahedra must be integers"):
        dtmesh.encode(points, tets + 0.5)
    with pytest.raises(ValueError, match="regions must be one label a tetrahedron"):
        dtmesh.encode(points, tets, regions=np.zeros((len(tets) // 2, 2), np.int32))
    with pytest.raises(ValueError, match="'level' is the name of an array the decoder makes"):
        dtmesh.encode(points, tets, {"level": np.zeros(len(points))})
    before = dtmesh.threads()
    with pytest.raises(ValueError, match="threads must be an int from 1 to 4096"):
        dtmesh.set_threads(2**40)
    assert dtmesh.threads() == before
    stream = dtmesh.encode(points, tets, box=256, dmax=2).bytes
    decoder = dtmesh.Decoder()
    decoder.feed(stream)
    decoder.finish()
    with pytest.raises(ValueError, match="after finish"):
        decoder.feed(stream)
    cut = stream[: len(stream) * 3 // 4]
    with pytest.warns(UserWarning):
        assert dtmesh.decode(cut).level > 0
    with pytest.raises(dtmesh.Error, match="level 0 asked, but"):
        dtmesh.decode(cut, 0)
    damaged = tmp_path / "damaged.dtm"
    damaged.write_bytes(stream[:40] + bytes([stream[40] ^ 0xFF]) + stream[41:])
    with pytest.raises(dtmesh.Error, match="damaged.dtm: "):
        dtmesh.decode(damaged)
    with pytest.raises(TypeError, match="a stream is bytes"):
        dtmesh.decode(5)
    # A float or text where an int is asked; a name whose label nothing has;
    # a path fed to a Decoder (decode() reads files); a bound on the vertices.
    with pytest.raises(ValueError, match="qbits must be an int"):
        dtmesh.encode(points, tets, qbits=2.7)
    with pytest.raises(ValueError, match="brick_points must be an int"):
        dtmesh.encode(points, tets, bricks=True, brick_points=True)
    with pytest.raises(ValueError, match=r"region_names name labels that no tetrahedron has: \[9\]"):
        dtmesh.encode(points, tets, regions=np.ones(len(tets), np.int32), region_names={1: "steel", 9: "typo"})
    with pytest.raises(TypeError, match="feed.. takes the stream's bytes"):
        dtmesh.Decoder().feed(str(damaged))
    with pytest.raises(dtmesh.Error, match="vertices"):
        dtmesh.decode(stream, max_vertices=10)


def test_what_a_user_passes_is_taken_as_meshenc_takes_it_or_said(tmp_path):
    """A review as a user, 2026-12-07: big-endian arrays (meshio's reading of a legacy .vtk) are
    taken; a point array 'level' of the user's own is kept under another name, as meshenc keeps
    it; merged points' values, faces tagged twice and names cut to 64 bytes are said; edge nodes
    are checked as the tetrahedra are; threads= from several threads leaves set_threads()'s; a
    Decoder asked for a level the stream lacks says so."""
    points, tets, _ = read_tetgen(DATA / "torus_288.node")
    value = np.linspace(0, 1, len(points))
    native = dtmesh.encode(points, tets, {"t": value}).bytes
    assert dtmesh.encode(points, tets, {"t": value.astype(">f8")}).bytes == native
    vtu = tmp_path / "own_level.vtu"
    meshio.write(vtu, meshio.Mesh(points, [("tetra", tets)], point_data={"level": value}))
    ours, theirs = tmp_path / "ours.dtm", tmp_path / "theirs.dtm"
    with pytest.warns(UserWarning, match="'level' is kept as 'level .input.'"):
        meshio.write(ours, meshio.read(vtu))
    run(tool("meshenc"), vtu, "-q", "-o", theirs)
    assert ours.read_bytes() == theirs.read_bytes()
    crowded = np.vstack([points, points[:5] + 1e-12])
    with pytest.warns(UserWarning, match="5 vertices merged points with different field values"):
        dtmesh.encode(crowded, tets, {"t": np.arange(len(crowded), dtype=np.float64)})
    regions = np.ones(len(tets), np.int32)
    face = tets[:1, :3]
    with pytest.warns(UserWarning, match="1 faces tagged a second time"):
        dtmesh.encode(points, tets, regions=regions, faces=np.vstack([face, face]), face_tags=[3, 4],
                      face_tag_names={3: "wall", 4: "inlet"})
    name = "x" + "\u00e4" * 40  # 81 bytes: cut between two characters
    with pytest.warns(UserWarning, match="longer than a stream holds"):
        stream = dtmesh.encode(points, tets, regions=regions, region_names={1: name}).bytes
    assert dtmesh.decode(stream).region_names[1] == name[:32]  # x and 31 two-byte characters
    with pytest.raises(TypeError, match="edge_nodes must be integers"):
        dtmesh.encode(points, tets, exact=True, edge_points=np.zeros((1, 3)), edge_nodes=np.full((len(tets), 6), 0.5))
    with pytest.raises(ValueError, match="edge_points must be finite"):
        dtmesh.encode(points, tets, exact=True, edge_points=np.full((1, 3), np.nan),
                      edge_nodes=np.full((len(tets), 6), -1))
    with pytest.raises(ValueError, match="brick_points sizes the bricks"):
        dtmesh.encode(points, tets, brick_points=100)
    with pytest.raises(TypeError, match="labels are 32-bit ints"):
        dtmesh.encode(points, tets, regions=regions, region_names={1.5: "a"})
    before = dtmesh.threads()
    calls = [threading.Thread(target=dtmesh.decode, args=(native,), kwargs={"threads": n}) for n in (1, 3, 1, 3)]
    for call in calls:
        call.start()
    for call in calls:
        call.join()
    assert dtmesh.threads() == before
    levels = dtmesh.info(native)["level_count"]
    # (Said once the header is in, not after every level is decoded.)
    decoder = dtmesh.Decoder(level=levels + 3)
    with pytest.raises(dtmesh.Error, match=f"level {levels + 3} asked, the stream has levels 0 to {levels - 1}"):
        decoder.feed(native[:100])


def test_meshio_write_gives_meshencs_stream_of_gmsh_and_meshdec_files(tmp_path):
    """meshio's reading of a gmsh file (with its gmsh:dim_tags) and of meshdec's own .vtu (with its
    level and boundary) writes the stream meshenc makes of the same file, the arrays it leaves out
    named."""
    msh = tmp_path / "two_materials.msh"
    msh.write_bytes(lzma.open(DATA / "two_materials.msh.xz").read())
    ours, theirs = tmp_path / "ours.dtm", tmp_path / "theirs.dtm"
    with pytest.warns(UserWarning, match="gmsh:dim_tags"):
        meshio.write(ours, meshio.read(msh))
    run(tool("meshenc"), msh, "-q", "-o", theirs)
    assert ours.read_bytes() == theirs.read_bytes()
    vtu = tmp_path / "decoded.vtu"
    run(tool("meshdec"), theirs, "-q", "-o", vtu)
    again, again_meshenc = tmp_path / "again.dtm", tmp_path / "again_meshenc.dtm"
    with pytest.warns(UserWarning, match="'level', 'boundary' .meshdec's own"):
        meshio.write(again, meshio.read(vtu))
    run(tool("meshenc"), vtu, "-q", "-o", again_meshenc)
    assert again.read_bytes() == again_meshenc.read_bytes()


def test_tagged_faces_no_level_can_carry_are_named(tmp_path):
    """Tagged triangles inside one region (a crack's, say) are no face of any level's surface: encode()
    and meshenc say so (--strict refuses the file), where before they were dropped in silence."""
    points, tets, _ = read_tetgen(DATA / "torus_288.node")
    seen = {}
    for t in tets:
        for f in ((t[0], t[1], t[2]), (t[0], t[1], t[3]), (t[0], t[2], t[3]), (t[1], t[2], t[3])):
            key = tuple(sorted(int(v) for v in f))
            seen[key] = seen.get(key, 0) + 1
    inner = np.array([f for f, n in seen.items() if n == 2][:5])
    with pytest.warns(UserWarning, match="5 of the 5 tagged triangles, inside a region"):
        dtmesh.encode(points, tets, faces=inner, face_tags=[7] * 5, box=256, dmax=2)
    msh = tmp_path / "crack.msh"
    meshio.write(msh, meshio.Mesh(points, [("tetra", tets), ("triangle", inner)],
                                  cell_data={"gmsh:physical": [np.ones(len(tets), np.int32), np.full(5, 7, np.int32)],
                                             "gmsh:geometrical": [np.ones(len(tets), np.int32), np.full(5, 7, np.int32)]}),
                 file_format="gmsh22", binary=False)
    said = subprocess.run([tool("meshenc"), msh, "--strict", "-o", tmp_path / "crack.dtm"], capture_output=True,
                          text=True)
    assert said.returncode != 0 and "5 of the 5 tagged triangles, inside a region" in said.stderr, said.stderr
    assert not (tmp_path / "crack.dtm").exists()
