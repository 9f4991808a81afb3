"""dtmesh: progressive compression of tetrahedral volume meshes and their per-vertex data.

A ``.dtm`` stream holds a solid at several levels of detail, each the Delaunay
tetrahedralization of a subset of the finer level's vertices carved to the
input's solid; any prefix of whole layers decodes to a coarser valid mesh.
This package is the C++ library's encoder and decoder with numpy arrays in and
out (the same bytes as the ``meshenc`` tool, the same meshes as ``meshdec``)::

    import numpy as np, dtmesh
    encoded = dtmesh.encode(points, tetrahedra, {"pressure": p}, dmax=0.01)
    open("part.dtm", "wb").write(encoded.bytes)
    mesh = dtmesh.decode(encoded.bytes)            # the finest level
    coarse = dtmesh.decode(encoded.bytes, level=3)  # a coarser one, decoded alone
    mesh.points, mesh.tetrahedra, mesh.fields["pressure"]

    decoder = dtmesh.Decoder()                     # progressive: as bytes arrive
    for chunk in chunks:
        for level in decoder.feed(chunk):
            show(level)

    big = dtmesh.encode(points, tetrahedra, bricks=True)  # bricked: read a part by offset
    box = dtmesh.decode_box("big.dtm", (0, 0, 0, 1, 1, 1))    # the cells meeting a box
    part = dtmesh.decode_piece("big.dtm", rank, ranks)      # one of P pieces of a level

Importing dtmesh registers the ``.dtm`` format with meshio (``meshio.read`` and
``meshio.write``) and, when PyVista is installed, with ``pyvista.read``.
"""
from __future__ import annotations

import contextlib
import json
import os
import threading
import warnings
from dataclasses import dataclass, field
from typing import Any, Dict, Iterator, List, Mapping, Optional, Union

import numpy as np

from . import _dtmesh

__all__ = ["Error", "Mesh", "Encoded", "Decoder", "encode", "decode", "decode_box", "decode_piece", "info",
           "set_threads", "threads", "to_vtk", "to_pyvista", "paraview_plugin"]
__version__ = _dtmesh.version

_threads_asked = 0  # set_threads()'s, 0: the cores the process was given
# Calls with their own threads= share the process's one setting: the last
# to start sets it, and set_threads()'s comes back once none is running.
_threads_lock = threading.Lock()
_calls_with_threads = 0


def _checked_threads(n: Any) -> int:
    if isinstance(n, (bool, np.bool_)) or not isinstance(n, (int, np.integer)) or not 1 <= n <= 4096:
        raise ValueError(f"threads must be an int from 1 to 4096, or None, got {n!r}")
    return int(n)


def set_threads(threads: Optional[int]) -> None:
    """Sets how many threads dtmesh's work uses in this process, as meshenc's
    ``--threads`` does: for a machine shared with other work. None: the cores
    the process may run on (its affinity mask, as taskset or a container
    gives them), the default. Every later call of this process uses it."""
    global _threads_asked
    asked = 0 if threads is None else _checked_threads(threads)
    with _threads_lock:
        _dtmesh.set_threads(asked)  # (the state changes only once the library took it)
        _threads_asked = asked


def threads() -> int:
    """The threads dtmesh's work uses now (set_threads(), else the cores given)."""
    return _dtmesh.threads()


@contextlib.contextmanager
def _threads_for_call(n: Optional[int]) -> Iterator[None]:
    """``threads=`` of one call: set for it; set_threads()'s again once no
    call with its own threads= is running (the setting is the process's)."""
    if n is None:
        yield
        return
    asked = _checked_threads(n)
    global _calls_with_threads
    with _threads_lock:
        _dtmesh.set_threads(asked)
        _calls_with_threads += 1
    try:
        yield
    finally:
        with _threads_lock:
            _calls_with_threads -= 1
            if _calls_with_threads == 0:
                _dtmesh.set_threads(_threads_asked)

#: The ParaView reader plugin installed with the package (the repository's
#: paraview/dtmesh_reader.py): load it in ParaView (Tools > Manage Plugins,
#: or paraview/load_dtmesh.py, which finds it here).
paraview_plugin = os.path.join(os.path.dirname(os.path.abspath(__file__)), "paraview_reader.py")


class Error(Exception):
    """A stream the library refuses (damaged, foreign, hostile) or an input it cannot encode.

    The message is the library's own, as meshdec and meshenc print it: what is
    wrong and where (the level and byte offset of a damaged layer, the field
    and point of a bad value).
    """


_dtmesh.set_error_type(Error)

# The stored types, in the library's order (ScalarType / ValueType).
_INT32_MAX = 2**31 - 1


def _is_int(v: Any) -> bool:
    return isinstance(v, (int, np.integer)) and not isinstance(v, bool)


def _level_arg(level: Optional[int]) -> int:
    """The decoder's level argument (-1: None), or ValueError naming what a level may be."""
    if level is None:
        return -1
    if not _is_int(level) or not 0 <= level <= _INT32_MAX:
        raise ValueError(f"level must be an int from 0 to {_INT32_MAX}, or None; got {level!r}")
    return int(level)


def _max_vertices_arg(max_vertices: int) -> int:
    """The decoder's bound (a uint64: a larger one bounds nothing more)."""
    if not _is_int(max_vertices) or max_vertices < 1:
        raise ValueError(f"max_vertices must be a positive int, got {max_vertices!r}")
    return int(min(max_vertices, 2**64 - 1))


_DTYPES = [np.int8, np.uint8, np.int16, np.uint16, np.int32, np.uint32, np.int64, np.uint64, np.float32, np.float64]
_TYPE_OF = {np.dtype(t): i for i, t in enumerate(_DTYPES)}

Bytes = Union[bytes, bytearray, memoryview]


@dataclass
class Mesh:
    """One level of detail of a stream, as numpy arrays.

    Attributes:
        points: float64, N x 3, in the input's units (``box`` and ``scale`` set
            only the units the encoder measures in).
        tetrahedra: uint32, M x 4, indices into ``points``, positively oriented,
            in the canonical order (the same arrays on every run).
        fields: the stream's per-vertex fields by name, each in its stored
            dtype, shape (N,) or (N, components).
        level: which level of detail this is (0 = the finest of the stream).
        level_count: how many levels the stream has.
        vertex_levels: int32 per vertex, the coarsest level that contains it.
        boundary: bool per vertex, True on the mesh's boundary surface; empty
            for a part read by :func:`decode_box` from a bricked stream or
            by :func:`decode_piece` (a part's own surface is not the level's).
        regions: int32 per tetrahedron, its region (material) label as the
            input gave it, when the stream has regions; else empty.
        region_names: region label -> name, where the input named them.
        faces: uint32, F x 3, the tagged faces of the level's surface
            (indices into ``points``, outward), when the stream has them.
        face_tags: int32 per face, its tag (a gmsh physical surface, a Medit ref).
        face_tag_names: tag -> name, where the input named them.
        cell_data: the stream's per-cell arrays by name, each in its stored
            dtype, shape (M,) or (M, components): level 0 only (coarser
            levels carry none, and have this empty).
        edge_nodes: int64, M x 6, level 0 of an exact stream of a
            second-order mesh (format 18.0, ``meshenc --exact``): per
            tetrahedron the points on its edges (0,1) (0,2) (0,3) (1,2) (1,3)
            (2,3), -1 where it has none; those points follow the vertices in
            ``points`` (format 21.0, ``--exact --keep-order``: lie among them
            where the input numbered them) (at level 0, with the fields' values there: the
            stream's in format 19.0, in 18.0 their edge's corners' mean).
            Empty (0 x 6) otherwise.
        face_edge_nodes: int64, F x 3, the same for the tagged faces' edges
            (0,1) (1,2) (2,0).
        node_ids: int64 per point, the input file's own id of each node
            (format 22.0, ``meshenc --keep-order`` of a file that numbers
            its nodes otherwise than 1 to n: gmsh node tags, Abaqus node
            numbers, an Exodus node map); empty where the stream has none.
    """

    points: np.ndarray
    tetrahedra: np.ndarray
    fields: Dict[str, np.ndarray] = field(default_factory=dict)
    level: int = 0
    level_count: int = 1
    vertex_levels: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int32))
    boundary: np.ndarray = field(default_factory=lambda: np.zeros(0, bool))
    regions: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int32))
    region_names: Dict[int, str] = field(default_factory=dict)
    faces: np.ndarray = field(default_factory=lambda: np.zeros((0, 3), np.uint32))
    face_tags: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int32))
    face_tag_names: Dict[int, str] = field(default_factory=dict)
    cell_data: Dict[str, np.ndarray] = field(default_factory=dict)
    edge_nodes: np.ndarray = field(default_factory=lambda: np.zeros((0, 6), np.int64))
    face_edge_nodes: np.ndarray = field(default_factory=lambda: np.zeros((0, 3), np.int64))
    node_ids: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))

    def to_meshio(self):
        """This level as a ``meshio.Mesh``: the fields, ``level`` and ``boundary`` as point data;
        the tagged faces as a triangle block; the regions and tags as cell data
        ``gmsh:physical`` (meshio's name, which its gmsh writer keeps), their names as field data
        and each named one as a cell set; the per-cell arrays as cell data (a triangle's row 0)."""
        import meshio

        point_data = dict(self.fields)
        point_data["level"] = self.vertex_levels
        if self.boundary.size:  # (a part read by box or piece has none)
            point_data["boundary"] = self.boundary.astype(np.uint8)
        cells = [("tetra", self.tetrahedra.astype(np.int64))]
        # (A second-order level whose every cell has its edge nodes: tetra10,
        # the nodes in meshio's (VTK's) order.)
        second_order = self.edge_nodes.size > 0 and bool((self.edge_nodes >= 0).all())
        if second_order:
            cells = [("tetra10", np.hstack([cells[0][1], self.edge_nodes[:, [0, 3, 1, 2, 4, 5]]]))]
        cell_data = {}
        field_data = {}
        cell_sets = {}
        if self.regions.size or self.face_tags.size:
            # As gmsh's physical tags: a tetrahedron's region, a face's tag.
            physical = [self.regions if self.regions.size else np.zeros(len(self.tetrahedra), np.int32)]
            if self.face_tags.size:
                if second_order and bool((self.face_edge_nodes >= 0).all()):
                    cells.append(("triangle6", np.hstack([self.faces.astype(np.int64), self.face_edge_nodes])))
                else:
                    cells.append(("triangle", self.faces.astype(np.int64)))
                physical.append(self.face_tags)
            # (gmsh:physical, as meshio names them for every format: a further
            # cell array beside it breaks meshio's own gmsh round trip.)
            cell_data = {"gmsh:physical": physical, "gmsh:geometrical": physical}
            field_data = {name: np.array([label, 3]) for label, name in self.region_names.items()}
            field_data.update({name: np.array([tag, 2]) for tag, name in self.face_tag_names.items()})
            # A named region or tag is also a cell set, as meshio's gmsh reader makes them.
            cell_sets = {}
            for name, (label, _) in field_data.items():
                cell_sets[name] = [np.flatnonzero(block == label) for block in physical]
        for name, values in self.cell_data.items():
            blocks = [values]
            if len(cells) > 1:
                blocks.append(np.zeros((len(self.faces),) + values.shape[1:], values.dtype))
            cell_data[name] = blocks
        # What the decoder makes itself (a box's or a piece's vertex_id too: no
        # stream's field may have that name), which meshio.write("x.dtm")
        # leaves out without a word.
        derived = ["level", "boundary"] + (["vertex_id"] if "vertex_id" in point_data else [])
        return meshio.Mesh(self.points, cells, point_data=point_data, cell_data=cell_data, field_data=field_data,
                           cell_sets=cell_sets, info={"dtmesh_derived": derived})

    def to_vtk(self):
        """This level as a ``vtkUnstructuredGrid`` (see :func:`to_vtk`)."""
        return to_vtk(self)

    def to_pyvista(self):
        """This level as a ``pyvista.UnstructuredGrid`` (see :func:`to_pyvista`)."""
        return to_pyvista(self)


@dataclass
class Encoded:
    """What :func:`encode` made.

    Attributes:
        bytes: the ``.dtm`` stream.
        report: every level's figures, as ``meshenc --report`` writes them
            (vertices, tetrahedra, quality, shape error both ways, bytes per layer, ...).
        vertex_of_input: uint32 per input point, its vertex in level 0 as
            :func:`decode` gives it (points that quantization merged share
            one). With ``keep_order`` that is the point's own index (with
            ``node_numbering``, its place there).
        layer_vertex_of_input: uint32 per input point, its vertex in the
            order the layers bring the vertices (coarsest first), which every
            level decodes in but a ``keep_order`` stream's level 0: a level
            of n vertices holds the points whose entry is below n. Without
            ``keep_order``, the same as ``vertex_of_input``.
    """

    bytes: bytes
    report: Dict[str, Any]
    vertex_of_input: np.ndarray
    layer_vertex_of_input: np.ndarray

    def __len__(self) -> int:
        return len(self.bytes)


def _integers(values: Any, what: str) -> np.ndarray:
    """`values` as int64, refusing what is not whole numbers (a float array of
    indices would otherwise be truncated in silence)."""
    a = np.asarray(values)
    if a.size and not (np.issubdtype(a.dtype, np.integer) or a.dtype == np.bool_):
        if not np.issubdtype(a.dtype, np.floating) or not np.all(np.isfinite(a)) or np.any(a != np.floor(a)):
            raise TypeError(f"{what} must be integers, got {a.dtype} values that are not whole numbers")
    return a.astype(np.int64, copy=False)


def _label_names(names: Optional[Mapping[int, str]], what: str) -> Dict[int, str]:
    """Names by label, checked: a float label would be truncated and None
    stored as "None" in silence."""
    out = {}
    for label, name in (names or {}).items():
        if not _is_int(label) or not -2**31 <= label < 2**31:
            raise TypeError(f"{what}: labels are 32-bit ints, got {label!r}")
        if not isinstance(name, str):
            raise TypeError(f"{what}: names are str, got {name!r} for label {label}")
        out[int(label)] = name
    return out


def _field_in(name: str, values: Any, count: int, what: str = "field"):
    if not isinstance(name, str):
        raise TypeError(f"{what} names are str, got {name!r}")
    a = np.asarray(values)
    if a.dtype == np.bool_:
        a = a.astype(np.uint8)
    if a.dtype.kind in "iuf" and not a.dtype.isnative:  # as VTK's legacy binary files, read by meshio
        a = a.astype(a.dtype.newbyteorder("="))
    if a.dtype == np.float16:  # (stored as float32, the same values: encode() says so)
        a = a.astype(np.float32)
    if a.dtype not in _TYPE_OF:
        raise TypeError(f"{what} {name!r}: dtype {a.dtype} is not one of int8..int64, uint8..uint64, float32, float64")
    if a.ndim not in (1, 2) or a.shape[0] != count:
        raise ValueError(f"{what} {name!r}: shape {a.shape}, expected ({count},) or ({count}, components)")
    components = 1 if a.ndim == 1 else a.shape[1]
    as_double = a.astype(np.float64).reshape(-1)
    if a.dtype.kind in "iu" and a.dtype.itemsize == 8 and a.size:
        with np.errstate(invalid="ignore"):  # (beyond 2^63 after rounding: refused below)
            back = as_double.astype(a.dtype)
        if not np.array_equal(back, a.reshape(-1)):
            raise ValueError(f"field {name!r}: 64-bit integers beyond 2^53 cannot be coded exactly")
    return _dtmesh.FieldIn(name, _TYPE_OF[a.dtype], int(components), as_double)


def encode(
    points: Any,
    tetrahedra: Any = None,
    fields: Optional[Mapping[str, Any]] = None,
    *,
    qbits: int = 14,
    box: Optional[float] = None,
    scale: Optional[float] = None,
    dmax: Optional[float] = None,
    preset: str = "codec",
    field_errors: Optional[Mapping[str, float]] = None,
    threads: Optional[int] = None,
    regions: Any = None,
    region_names: Optional[Mapping[int, str]] = None,
    faces: Any = None,
    face_tags: Any = None,
    face_tag_names: Optional[Mapping[int, str]] = None,
    cell_data: Optional[Mapping[str, Any]] = None,
    keep_order: bool = False,
    exact: bool = False,
    bricks: bool = False,
    brick_points: Optional[int] = None,
    edge_points: Any = None,
    edge_nodes: Any = None,
    edge_fields: Optional[Mapping[str, Any]] = None,
    node_numbering: Any = None,
) -> Encoded:
    """Encodes a volume point set, and its tetrahedra when it has them, into a ``.dtm`` stream.

    The options are meshenc's, with its names and defaults; for the same points
    and options the stream is byte for byte the one meshenc writes.

    Args:
        points: N x 3 coordinates (any float or int dtype).
        tetrahedra: M x 4 indices into ``points``, or None. When given they are
            the reference solid: every level keeps the Delaunay cells inside it,
            and its boundary is held within ``dmax`` of theirs.
        fields: per-vertex values by name, each (N,) or (N, components) of
            int8..int64, uint8..uint64, float32, float64 (bool as uint8); coded
            losslessly unless named in ``field_errors``. Their order is the
            stream's.
        qbits: quantization bits per axis, 1 to 24.
        box: measure as if the points' largest extent were this (excludes
            ``scale``): the units of ``dmax`` and the report. The stream keeps
            the input's units.
        scale: measure in the coordinates times this.
        dmax: boundary tolerance in (scaled) input units; default 0.5% of the largest extent.
        preset: "codec" (levels carved to the input's solid, about half the
            vertices each) or "paper" (the seed paper's hierarchy).
        field_errors: float field name -> E: every decoded value within E of its own.
        regions: one integer label per tetrahedron (its material: a gmsh
            physical volume, a Medit ref), or None. Every level's cells then
            carry the label of the input region holding their centroid, at
            most 255 distinct labels (the codec preset only).
        region_names: label -> name, kept in the stream with the labels.
        faces, face_tags: F x 3 indices into ``points`` (the input's tagged
            triangles: boundary conditions' patches) and one tag each; every
            level's surface faces then carry the tag of their patch.
        face_tag_names: tag -> name.
        cell_data: per-tetrahedron arrays by name (element results, material
            properties), each (M,) or (M, components) of the dtypes of
            ``fields``, lossless unless named in ``field_errors``. Level 0's
            cells carry them: a cell that is one of ``tetrahedra`` its own
            values, another those of the tetrahedron holding its centroid;
            coarser levels carry none (the codec preset only).
        keep_order: decode level 0's vertices in the order of ``points``
            (meshenc's ``--keep-order``; the order is coded, about log2(N)
            bits a vertex for a random one); every point must quantize to
            its own grid point.
        exact: decode level 0 as ``tetrahedra`` themselves, cell for cell
            (meshenc's ``--exact``; the cells that are not Delaunay cells are
            coded beside the levels, 0.3-0.75 bits a vertex on gmsh and
            Netgen meshes); every point must quantize to its own grid point
            and every cell stay a tetrahedron there (the error names the
            ``qbits`` that would do).
        bricks: bricked layers (meshenc's ``--bricks``): each layer's points
            and corrections in one chunk per octree brick, so that
            :func:`decode_box` and :func:`decode_piece` read only the chunks
            around a part; the levels are built in blocks, in less memory
            (the codec preset only; not with ``exact`` or ``keep_order``).
        brick_points: with ``bricks``, each layer's bricks hold about this
            many of its new points, 2048 by default (smaller: a part reads
            fewer bytes, the stream grows).
        edge_points, edge_nodes: a second-order mesh's nodes on the
            tetrahedra's edges, not among ``points``: K x 3 positions, and per
            tetrahedron M x 6 indices into them, its edges (0,1) (0,2) (0,3)
            (1,2) (1,3) (2,3), -1 for none. Kept with ``exact`` (format 18.0:
            :attr:`Mesh.edge_nodes` gives them back, each within half a grid
            step); without it the stream holds the linear cells (a warning
            says so).
        edge_fields: with ``edge_points``, fields' values there by name,
            each (K,) or (K, components) of its field's dtype (format 19.0:
            :attr:`Mesh.fields` give them back at the edge nodes, as at the
            vertices); a field without them gets its edge's corners' mean.
        node_numbering: with ``keep_order``, ``exact`` and ``edge_nodes``,
            the file's numbering of the points and edge points together, an
            (N + K,) array: entry k is the file's node k, i < N the point i
            (ascending among the entries), N + j the edge point j (format
            21.0: the decoded mesh's points then come in this order, the
            edge nodes among the vertices; about 8 bits an edge node for a
            mesher's numbering). None: the edge nodes after the vertices.
        threads: threads to use for this call (meshenc's ``--threads``); None:
            :func:`set_threads`'s, by default the cores the process may run on.
            The stream is the same for any number.

    Returns:
        :class:`Encoded`, with the stream and the report.

    Raises:
        Error: points that cannot make a tetrahedral mesh (fewer than 4
            distinct, all coplanar), or a field that cannot be coded as asked.
        ValueError, TypeError: arguments of the wrong shape, type or range.
    """
    if not _is_int(qbits) or not 1 <= qbits <= 24:
        raise ValueError(f"qbits must be an int from 1 to 24 (meshenc's --qbits), got {qbits!r}")
    if brick_points is not None and not bricks:
        raise ValueError("brick_points sizes the bricks: give bricks=True too")
    brick_points = 2048 if brick_points is None else brick_points
    if not _is_int(brick_points) or not 1 <= brick_points <= 2**32:
        raise ValueError(f"brick_points must be an int from 1 to 2**32 (meshenc's --brick-points), got {brick_points!r}")
    p = np.ascontiguousarray(np.asarray(points, dtype=np.float64))
    if p.ndim != 2 or p.shape[1] != 3:
        raise ValueError(f"points must be N x 3, got shape {p.shape}")
    t = None
    if tetrahedra is not None:
        t = np.ascontiguousarray(_integers(tetrahedra, "tetrahedra"))
    r = None
    if regions is not None:
        if t is None:
            raise ValueError("regions label tetrahedra: give the tetrahedra too")
        r = _integers(regions, "regions")
        if r.ndim != 1:
            raise ValueError(f"regions must be one label a tetrahedron, a 1-D array, got shape {r.shape}")
        r = np.ascontiguousarray(r)
    names = _label_names(region_names, "region_names")
    f = ft = None
    if faces is not None:
        if t is None:
            raise ValueError("tagged faces bound tetrahedra: give the tetrahedra too")
        f = np.ascontiguousarray(_integers(faces, "faces"))
        ft = _integers(face_tags if face_tags is not None else np.zeros(0, np.int64), "face_tags")
        if ft.ndim != 1:
            raise ValueError(f"face_tags must be one tag a face, a 1-D array, got shape {ft.shape}")
        ft = np.ascontiguousarray(ft)
    elif face_tags is not None or face_tag_names:
        raise ValueError("face_tags and face_tag_names tag faces: give the faces too")
    if region_names and regions is None:
        raise ValueError("region_names name regions: give the regions too")
    face_names = _label_names(face_tag_names, "face_tag_names")
    # (A name whose label no cell or face has would be dropped in silence.)
    for what, named, labels in (("region_names", names, r), ("face_tag_names", face_names, ft)):
        absent = sorted(set(named) - set(np.unique(labels).tolist())) if named and labels is not None else []
        if absent:
            raise ValueError(f"{what} name labels that no {'tetrahedron' if what == 'region_names' else 'face'} "
                             f"has: {absent}")
    # A face listed again keeps its first tag, as meshenc's readers keep it;
    # a tag name that only such faces had goes with them, said.
    if f is not None and f.ndim == 2 and f.shape[1] == 3 and len(f) == len(ft) and len(f):
        _, first = np.unique(np.sort(f, axis=1), axis=0, return_index=True)
        if len(first) < len(f):
            first.sort()
            warnings.warn(f"left out (the stream does not hold it): {len(f) - len(first)} faces tagged a second time "
                          "(each keeps its first tag)", stacklevel=2)
            f, ft = np.ascontiguousarray(f[first]), np.ascontiguousarray(ft[first])
            for tag in sorted(set(face_names) - set(np.unique(ft).tolist())):
                warnings.warn(f"left out (the stream does not hold it): the name {face_names.pop(tag)!r} of face tag "
                              f"{tag}, which no face has but those tagged a second time", stacklevel=2)
    # (The decoder makes these arrays itself: a field or cell array of the
    # name would be hidden behind them.)
    for name in fields or {}:
        if name in ("level", "boundary", "vertex_id"):
            raise ValueError(f"fields: {name!r} is the name of an array the decoder makes (each vertex's "
                             f"{'level' if name == 'level' else 'place on the boundary' if name == 'boundary' else 'number'}): "
                             "give the field another name")
    for name in cell_data or {}:
        if name in ("region", "gmsh:physical"):
            raise ValueError(f"cell_data: {name!r} is the name the decoded mesh gives its regions: give the array "
                             "another name, or pass it as regions=")
    for what, arrays in (("field", fields), ("cell_data", cell_data), ("edge_fields", edge_fields)):
        for name, values in (arrays or {}).items():
            if getattr(values, "dtype", None) == np.float16:
                warnings.warn(f"{what} {name!r}: float16 values are stored as float32 (the same values)",
                              stacklevel=2)
    field_list = [_field_in(name, values, p.shape[0]) for name, values in (fields or {}).items()]
    if cell_data and t is None:
        raise ValueError("cell_data belongs to tetrahedra: give the tetrahedra too")
    cell_list = [_field_in(name, values, t.shape[0] if t is not None and t.ndim == 2 else 0, "cell_data")
                 for name, values in (cell_data or {}).items()]
    ep = en = None
    if edge_points is not None and edge_nodes is None:
        raise ValueError("edge_points are placed on the tetrahedra's edges by edge_nodes: give edge_nodes too")
    if edge_nodes is not None:
        if t is None:
            raise ValueError("edge_nodes lie on tetrahedra's edges: give the tetrahedra too")
        ep = np.ascontiguousarray(np.asarray(edge_points if edge_points is not None else np.zeros((0, 3)),
                                             dtype=np.float64))
        if ep.size and not np.all(np.isfinite(ep)):
            raise ValueError("edge_points must be finite: a NaN or infinite coordinate has no place on the grid")
        en = np.ascontiguousarray(_integers(edge_nodes, "edge_nodes"))
        if en.size and en.min() < -1:
            raise ValueError(f"edge_nodes are indices into edge_points or -1 for none, got {int(en.min())}")
        if not exact:
            warnings.warn("left out (the stream does not hold it): the nodes on the tetrahedra's edges: "
                          "only exact=True keeps them; the stream holds the linear cells", stacklevel=2)
    edge_list = []
    if edge_fields:
        if en is None:
            raise ValueError("edge_fields are values at edge_points: give edge_points and edge_nodes too")
        for name, values in edge_fields.items():
            if name not in (fields or {}):
                raise ValueError(f"edge_fields {name!r}: not a field of fields")
            field_dtype = np.asarray(fields[name]).dtype
            if np.asarray(values).dtype != field_dtype:
                raise TypeError(f"edge_fields {name!r}: dtype {np.asarray(values).dtype}, its field's is {field_dtype}")
            edge_list.append(_field_in(name, values, ep.shape[0], "edge_fields"))
    numbering = None
    if node_numbering is not None:
        if not (keep_order and exact and en is not None):
            raise ValueError("node_numbering places edge_nodes among points: give keep_order=True, exact=True "
                             "and edge_nodes too")
        numbering = np.asarray(node_numbering)
        if numbering.ndim != 1 or not np.issubdtype(numbering.dtype, np.integer):
            raise TypeError(f"node_numbering must be a 1-D array of integers, got {numbering.dtype} "
                            f"of shape {numbering.shape}")
        numbering = np.ascontiguousarray(numbering, dtype=np.int64)
    with _threads_for_call(threads):
        stream, report, vertex_of_input = _dtmesh.encode(
            p, t, r, names, f, ft, face_names, field_list, cell_list, int(qbits), box, scale, dmax, preset,
            dict(field_errors or {}), bool(keep_order), bool(exact), bool(bricks), int(brick_points), ep, en,
            edge_list, numbering)
    # With keep_order, level 0 comes in the points' own order (and with a
    # node_numbering, point i where the numbering names it).
    level0_vertex = vertex_of_input
    if keep_order:
        level0_vertex = np.arange(p.shape[0], dtype=np.uint32)
        if numbering is not None:
            place = np.empty(numbering.shape[0], dtype=np.uint32)
            place[numbering] = np.arange(numbering.shape[0], dtype=np.uint32)
            level0_vertex = place[: p.shape[0]]
    encoded = Encoded(stream, json.loads(report), level0_vertex, vertex_of_input)
    for name in encoded.report.get("names_cut", []):
        warnings.warn(f"the name {name!r} is longer than a stream holds (64 bytes): its beginning is kept",
                      stacklevel=2)
    if encoded.report.get("merged_points_with_other_values"):
        warnings.warn(f"{encoded.report['merged_points_with_other_values']} vertices merged points with different "
                      "field values: each keeps its first point's (a larger qbits keeps the points apart)",
                      stacklevel=2)
    # (Tagged faces no level can carry, said as meshenc says them.)
    if f is not None and len(f) and t is not None:
        inside = _dtmesh.faces_inside(t, r if r is not None else np.zeros(0, np.int64), f)
        if inside:
            warnings.warn(f"left out (the stream does not hold it): {inside}", stacklevel=2)
    if encoded.report.get("edge_nodes_dropped"):
        warnings.warn("left out (the stream does not hold it): the nodes on level 0's edges: the exact cells "
                      "fell back to format 11.0's coding, which holds none" +
                      (", and the fields' values there" if fields else ""), stacklevel=2)
    return encoded


def _arrays_of(arrays, n: int) -> Dict[str, np.ndarray]:
    out = {}
    for name, type_index, components, raw in arrays:
        a = np.frombuffer(raw, dtype=np.dtype(_DTYPES[type_index]).newbyteorder("<")).astype(
            _DTYPES[type_index], copy=True)
        out[name] = a if components == 1 else a.reshape(n, components)
    return out


def _mesh_of(d: Dict[str, Any]) -> Mesh:
    fields = _arrays_of(d["fields"], d["points"].shape[0])
    return Mesh(points=d["points"], tetrahedra=d["tetrahedra"], fields=fields, level=d["level"],
                cell_data=_arrays_of(d["cell_data"], d["tetrahedra"].shape[0]),
                level_count=d["level_count"], vertex_levels=d["vertex_levels"],
                boundary=d["boundary"].astype(bool), regions=d["regions"],
                region_names=dict(d["region_names"]), faces=d["faces"], face_tags=d["face_tags"],
                face_tag_names=dict(d["face_tag_names"]), edge_nodes=d["edge_nodes"],
                face_edge_nodes=d["face_edge_nodes"], node_ids=d["node_ids"])


def _as_bytes(data: Union[Bytes, str, os.PathLike]) -> bytes:
    if isinstance(data, (str, os.PathLike)):
        with open(data, "rb") as f:
            return f.read()
    if not isinstance(data, (bytes, bytearray, memoryview)):
        raise TypeError(f"a stream is bytes, bytearray, memoryview or a file's path, got {type(data).__name__}")
    return bytes(data)


@contextlib.contextmanager
def _named(data: Any) -> Iterator[None]:
    """A stream given by its path: the library's errors name the file, as meshdec's do."""
    try:
        yield
    except Error as e:
        if isinstance(data, (str, os.PathLike)) and not str(e).startswith(os.fspath(data)):
            # (The library names bytes "stream": the path names them here.)
            message = str(e)
            message = message[len("stream: "):] if message.startswith("stream: ") else message
            raise Error(f"{os.fspath(data)}: {message}") from None
        raise


class Decoder:
    """Decodes a stream as its bytes arrive: each level as soon as its layer is complete.

    ::

        decoder = dtmesh.Decoder()
        for chunk in response.iter_content(65536):
            for mesh in decoder.feed(chunk):
                print(mesh.level, len(mesh.points))
        decoder.finish()

    Args:
        level: stop after this level (0 = the finest); None decodes every level.
        max_vertices: refuse a stream claiming more vertices than this (the
            decoder never allocates what a stream merely claims).
    """

    def __init__(self, level: Optional[int] = None, max_vertices: int = _dtmesh.default_max_vertices):
        self._decoder = _dtmesh.Decoder(_level_arg(level), _max_vertices_arg(max_vertices))
        self._level = level
        self._finished = False

    def feed(self, chunk: Bytes) -> List[Mesh]:
        """Takes the next bytes (at once); returns each level they completed, coarsest first.

        Raises:
            Error: the stream is damaged or foreign (the levels decoded before stand), or its
                header has no level as fine as the one asked for (said once the header is in).
            ValueError: after :meth:`finish`.
        """
        if self._finished:
            raise ValueError("feed() after finish(): the input has ended (a new Decoder reads another stream)")
        if not isinstance(chunk, (bytes, bytearray, memoryview)):
            raise TypeError(f"feed() takes the stream's bytes (bytes, bytearray, memoryview), got "
                            f"{type(chunk).__name__}: decode() reads a file by its path")
        return [_mesh_of(d) for d in self._decoder.feed(_as_bytes(chunk), True)]

    def finish(self) -> None:
        """Says the input has ended: warns if it stopped before the last level asked for.

        Raises:
            Error: the stream is damaged, or has no level as fine as the
                one asked for (as :func:`decode` says).
        """
        if self._finished:
            return
        self._finished = True
        count = self._decoder.level_count()
        if self._level is not None and 0 < count <= self._level:
            raise Error(f"level {self._level} asked, the stream has levels 0 to {count - 1}")
        truncated = self._decoder.finish()
        if truncated is not None:
            warnings.warn(f"truncated stream: {truncated}; the finest whole level is {self.finest_level}",
                          stacklevel=2)

    @property
    def done(self) -> bool:
        """Every level asked for is decoded."""
        return self._decoder.done()

    @property
    def finest_level(self) -> int:
        """The finest level decoded so far; -1 before the first."""
        return self._decoder.finest_level()

    @property
    def level_count(self) -> int:
        """How many levels the stream has; -1 before its header."""
        return self._decoder.level_count()

    def mesh(self) -> Mesh:
        """The finest level decoded so far."""
        return _mesh_of(self._decoder.mesh())


def decode(data: Union[Bytes, str, os.PathLike], level: Optional[int] = None, *,
           threads: Optional[int] = None, max_vertices: int = _dtmesh.default_max_vertices) -> Mesh:
    """Decodes a stream (bytes, or a file's path) to one level of detail.

    Args:
        data: the ``.dtm`` stream, whole or any prefix of it.
        level: the level to decode (0 = the finest); None: the finest present.
        threads: threads to use for this call (meshdec's ``--threads``); None:
            :func:`set_threads`'s, by default the cores the process may run on.
        max_vertices: refuse a stream that claims more vertices (meshdec's
            ``--max-vertices``).

    Returns:
        :class:`Mesh`. A truncated stream gives its finest whole level, with a
        ``warnings.warn`` saying where it stopped.

    Raises:
        Error: the stream is damaged or foreign, holds no whole level, or has
            no such level.
    """
    decoder = _dtmesh.Decoder(_level_arg(level), _max_vertices_arg(max_vertices))
    with _threads_for_call(threads), _named(data):
        decoder.feed(_as_bytes(data), False)
        truncated = decoder.finish()
        count = decoder.level_count()
        if level is not None and count >= 0 and level >= count:
            raise Error(f"level {level} asked, the stream has levels 0 to {count - 1}")
        if decoder.finest_level() < 0:
            raise Error(truncated or "the stream holds no whole level")
        # (A level asked for that a truncated stream does not reach is an
        # error, as meshdec --level says, not a coarser level in its place.)
        if level is not None and decoder.finest_level() > level:
            raise Error(f"level {level} asked, but {truncated}")
        if truncated is not None:
            warnings.warn(f"truncated stream: {truncated}; decoding level {decoder.finest_level()}",
                          stacklevel=2)
        return _mesh_of(decoder.mesh())


def _part_source(data: Union[Bytes, str, os.PathLike]):
    # A path is read by offset (only the bytes a part needs); bytes as they are.
    if isinstance(data, (str, os.PathLike)):
        path = os.fsdecode(data)
        if os.path.isdir(path):
            raise IsADirectoryError(f"{path}: is a folder, not a stream")
        if not os.path.isfile(path):
            raise FileNotFoundError(f"{path}: no such file")
        return path
    return bytes(data)


def _part_mesh(d: Dict[str, Any]) -> Mesh:
    if "truncated" in d:
        warnings.warn(f"truncated stream: {d['truncated']}; decoding level {d['level']}", stacklevel=3)
    return _mesh_of(d)


def decode_box(data: Union[Bytes, str, os.PathLike], box: Any, level: Optional[int] = None, *,
               max_vertices: int = _dtmesh.default_max_vertices, threads: Optional[int] = None) -> Mesh:
    """The cells of one level that meet a box, as ``meshdec --box`` writes them.

    From a bricked stream (``encode(..., bricks=True)``, ``meshenc --bricks``)
    only the chunks around the box are read, by offset when ``data`` is a
    path: a part of a stream far larger than memory. The cells are exactly
    the whole level's that meet the box (a cell meets it when the bounding
    box of its corners does), with their regions, their tagged faces (each
    with the cell the level's surface takes it from: the kept one, at an
    interface the lower region's), the vertices' fields, level and number in
    the whole level (field ``vertex_id``) and, at level 0, the cells'
    ``cell_data``; ``boundary`` is empty (the box's own surface is not the
    level's). A stream that is not bricked is decoded whole and
    the box cut from it, with everything it carries.

    Args:
        data: the stream's path (read by offset), or its bytes.
        box: (x0, y0, z0, x1, y1, z1) in the input's units, bounds included.
        level: 0 = the finest; None: the finest whole level (of a truncated
            stream, with a warning).
        max_vertices: refuse a stream claiming more vertices than this.
        threads: threads to use for this call; None: :func:`set_threads`'s.

    Raises:
        Error: the stream is damaged, foreign or too short for the level.
        ValueError: a box that is not six numbers with x0 <= x1, y0 <= y1, z0 <= z1.
    """
    b = tuple(float(v) for v in np.asarray(box, dtype=np.float64).reshape(-1))
    if len(b) != 6 or not all(np.isfinite(b)) or b[0] > b[3] or b[1] > b[4] or b[2] > b[5]:
        raise ValueError(f"box must be (x0, y0, z0, x1, y1, z1), finite, with each low corner at most its high one; got {box!r}")
    level_arg, bound = _level_arg(level), _max_vertices_arg(max_vertices)
    with _threads_for_call(threads):
        d = _dtmesh.decode_part(_part_source(data), b, 0, 1, level_arg, bound)
    return _part_mesh(d)


def decode_piece(data: Union[Bytes, str, os.PathLike], piece: int, pieces: int, level: Optional[int] = None, *,
                 max_vertices: int = _dtmesh.default_max_vertices, threads: Optional[int] = None) -> Mesh:
    """Piece ``piece`` of ``pieces`` of one level of a bricked stream, as ``mpirun meshdec -o X.pvtu``
    gives each rank its own.

    The pieces are contiguous ranges of the level's bricks holding about as
    many of its points each; every cell of the level is in exactly one
    piece, with the arrays :func:`decode_box` gives. Each reads only the
    chunks around its bricks (by offset when ``data`` is a path), so that P
    processes together hold the level once.

    Args:
        data: the stream's path (read by offset), or its bytes.
        piece: 0 to ``pieces`` - 1.
        pieces: how many pieces the level is cut into.
        level: 0 = the finest; None: the finest whole level (of a truncated
            stream, with a warning).
        max_vertices: refuse a stream claiming more vertices than this.
        threads: threads to use for this call; None: :func:`set_threads`'s.

    Raises:
        Error: the stream is not bricked, is damaged, or is too short for the level.
        ValueError: no such piece.
    """
    if not (_is_int(pieces) and 1 <= pieces <= _INT32_MAX and _is_int(piece) and 0 <= piece < pieces):
        raise ValueError(f"piece must be 0 to pieces - 1 and pieces 1 to {_INT32_MAX}; got piece {piece!r} of {pieces!r}")
    level_arg, bound = _level_arg(level), _max_vertices_arg(max_vertices)
    with _threads_for_call(threads):
        d = _dtmesh.decode_part(_part_source(data), None, int(piece), int(pieces), level_arg, bound)
    return _part_mesh(d)


def info(data: Union[Bytes, str, os.PathLike], stats: bool = False) -> Dict[str, Any]:
    """What a stream holds, as ``meshinfo --json`` gives it (``--stats`` with ``stats=True``).

    Read from the headers (checksums verified, no mesh rebuilt); with
    ``stats`` every level is decoded and its tetrahedra and quality added.
    """
    with _named(data):
        return json.loads(_dtmesh.info(_as_bytes(data), bool(stats)))


def to_vtk(mesh: Mesh, faces: bool = True):
    """A level as a ``vtkUnstructuredGrid``: its fields, ``level`` and ``boundary`` as point data.

    The regions are cell data ``region``, level 0's cell arrays cell data.
    With ``faces``, the tagged faces follow the tetrahedra as triangles, as
    in meshdec's .vtu: their tag in ``region``, their row of the cell arrays
    0, which a filter averaging cell data to the points would take in.
    ``faces=False``: the tetrahedra alone (the ParaView reader's first
    output; it gives the faces as its second).

    Uses whatever VTK the interpreter has (``vtkmodules``: VTK's wheel,
    Debian's python3-vtk9, or ParaView's own inside pvpython).
    """
    from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import VTK_TETRA, vtkCellArray, vtkUnstructuredGrid

    grid = vtkUnstructuredGrid()
    points = vtkPoints()
    points.SetData(numpy_to_vtk(np.ascontiguousarray(mesh.points), deep=True))
    grid.SetPoints(points)
    m = mesh.tetrahedra.shape[0]
    # (A second-order level whose every cell has its edge nodes: 10-node
    # tetrahedra, VTK's node order, and 6-node tagged triangles.)
    second_order = mesh.edge_nodes.size > 0 and bool((mesh.edge_nodes >= 0).all())
    corners = mesh.tetrahedra.astype(np.int64)
    if second_order:
        corners = np.hstack([corners, mesh.edge_nodes[:, [0, 3, 1, 2, 4, 5]]])
    width = corners.shape[1] if m else 4
    offsets = numpy_to_vtkIdTypeArray(np.arange(0, width * m + 1, width, dtype=np.int64), deep=True)
    connectivity = numpy_to_vtkIdTypeArray(np.ascontiguousarray(corners.reshape(-1)), deep=True)
    cells = vtkCellArray()
    cells.SetData(offsets, connectivity)
    grid.SetCells(24 if second_order else VTK_TETRA, cells)  # (24: VTK_QUADRATIC_TETRA)
    arrays = dict(mesh.fields)
    arrays["level"] = mesh.vertex_levels
    if mesh.boundary.size:  # (a part read by box or piece has none)
        arrays["boundary"] = mesh.boundary.astype(np.uint8)
    for name, values in arrays.items():
        a = numpy_to_vtk(np.ascontiguousarray(values), deep=True)
        a.SetName(name)
        grid.GetPointData().AddArray(a)
    with_faces = faces and mesh.face_tags.size > 0
    if with_faces:
        # The tagged faces after the tetrahedra, as meshdec's .vtu has them.
        from vtkmodules.vtkCommonDataModel import VTK_TRIANGLE
        faces = mesh.faces.astype(np.int64)
        if second_order and bool((mesh.face_edge_nodes >= 0).all()):
            faces = np.hstack([faces, mesh.face_edge_nodes])
        for face in faces:
            grid.InsertNextCell(VTK_TRIANGLE if len(face) == 3 else 22, len(face), [int(v) for v in face])
    if mesh.regions.size or with_faces:
        # As gmsh's physical tags: a tetrahedron's region, a face's tag.
        regions = mesh.regions if mesh.regions.size else np.zeros(m, np.int32)
        tags = mesh.face_tags if with_faces else mesh.face_tags[:0]
        a = numpy_to_vtk(np.ascontiguousarray(np.concatenate([regions, tags]).astype(np.int32)), deep=True)
        a.SetName("region")
        grid.GetCellData().AddArray(a)
        grid.GetCellData().SetActiveScalars("region")
    for name, values in mesh.cell_data.items():
        # A tagged face's row 0.
        rows = len(mesh.face_tags) if with_faces else 0
        padded = np.concatenate([values, np.zeros((rows,) + values.shape[1:], values.dtype)])
        a = numpy_to_vtk(np.ascontiguousarray(padded), deep=True)
        a.SetName(name)
        grid.GetCellData().AddArray(a)
    return grid


def to_pyvista(mesh: Mesh):
    """A level as a ``pyvista.UnstructuredGrid`` (PyVista must be installed)."""
    import pyvista

    return pyvista.wrap(to_vtk(mesh))


def _register_readers() -> None:
    try:
        from . import _meshio

        _meshio.register()
    except ImportError:
        pass  # meshio is optional
    try:
        import pyvista
    except ImportError:
        return
    if hasattr(pyvista, "register_reader"):
        pyvista.register_reader(".dtm", lambda path, **kwargs: to_pyvista(decode(path, kwargs.get("level"))))


_register_readers()
