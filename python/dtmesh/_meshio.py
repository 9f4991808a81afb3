"""The .dtm format in meshio: meshio.read("x.dtm") and meshio.write("x.dtm", mesh).

Reading gives the finest level: its tetrahedra, the stream's fields and the
per-vertex ``level`` and ``boundary`` as point data. Writing encodes the
mesh's points, its tetrahedra (the reference solid) and its point data as
fields, with dtmesh.encode's options as keyword arguments. The tetrahedra's
regions come from the first cell data array of gmsh:physical, medit:ref,
netgen:index, region, material, MaterialIds, CellEntityIds (meshenc's
default), their names from the field data (gmsh's, Netgen's); the other numeric cell data on the
tetrahedra becomes the stream's cell data, and a cell set that is a named
region's or tag's cells is held by them. A second-order mesh (tetra10,
triangle6) is written as its linear cells, hexahedra, wedges and pyramids
as the tetrahedra that split them (quads as triangles), as meshenc reads
them. What the stream does not hold
(other cell sets, other cells, an array not on every tetrahedron block) is
named in a warning.
"""
import warnings

import meshio
import numpy as np

from . import _dtmesh, decode, encode


def read(filename, level=None):
    return decode(filename, level).to_meshio()


REGION_ARRAYS = ("gmsh:physical", "medit:ref", "netgen:index", "region", "material", "MaterialIds", "CellEntityIds")


# A second-order cell's linear cell and its corner count (meshio's
# second-order cells list their corners first, as gmsh and VTK do).
QUADRATIC = {"tetra10": ("tetra", 4), "triangle6": ("triangle", 3), "hexahedron20": ("hexahedron", 8),
             "hexahedron27": ("hexahedron", 8), "wedge15": ("wedge", 6), "wedge18": ("wedge", 6),
             "pyramid13": ("pyramid", 5), "pyramid14": ("pyramid", 5), "quad8": ("quad", 4), "quad9": ("quad", 4)}
# The linear cells the stream reads: volumes, and faces that may be tagged.
VOLUMES = ("tetra", "hexahedron", "wedge", "pyramid")
KEPT = VOLUMES + ("triangle", "quad")


def _linear(mesh):
    """A second-order mesh as its linear cells, as meshenc reads one: the points that are only nodes
    on the cells' edges (or faces) set aside (with their point data), the rest renumbered; with what
    that leaves out, in words (None for a linear mesh)."""
    # (Without volumes no cell is kept, and every point is the stream's.)
    if not any(block.type in QUADRATIC for block in mesh.cells) or \
            not any(QUADRATIC.get(block.type, (block.type,))[0] in VOLUMES for block in mesh.cells):
        return mesh, None
    points = len(mesh.points)
    corner = np.zeros(points, dtype=bool)
    on_edge = np.zeros(points, dtype=bool)
    blocks = []
    for block in mesh.cells:
        data = np.asarray(block.data)
        if block.type in QUADRATIC:
            kind, corners = QUADRATIC[block.type]
            on_edge[data[:, corners:].reshape(-1)] = True
            block = meshio.CellBlock(kind, data[:, :corners])
        if block.type in KEPT:
            corner[np.asarray(block.data).reshape(-1)] = True
        blocks.append(block)
    keep = ~(on_edge & ~corner)
    if keep.all():  # (every other node some cell's corner: the linear cells, nothing set aside)
        return meshio.Mesh(mesh.points, blocks, point_data=mesh.point_data, cell_data=mesh.cell_data,
                           field_data=mesh.field_data, cell_sets=getattr(mesh, "cell_sets", None),
                           info=mesh.info), None
    index = np.cumsum(keep) - 1
    cells = [meshio.CellBlock(b.type, index[np.asarray(b.data)]) if b.type in KEPT else b for b in blocks]
    linear = meshio.Mesh(mesh.points[keep], cells, point_data={k: np.asarray(v)[keep] for k, v in
                                                               mesh.point_data.items()},
                         cell_data=mesh.cell_data, field_data=mesh.field_data,
                         cell_sets=getattr(mesh, "cell_sets", None), info=mesh.info)
    tetra10 = sum(len(b.data) for b in mesh.cells if b.type == "tetra10")
    others = sum(len(b.data) for b in mesh.cells if b.type in QUADRATIC and QUADRATIC[b.type][0] in VOLUMES[1:])
    elements = ", ".join([f"{tetra10} second-order tetrahedra"] * bool(tetra10) +
                         [f"{others} second-order hexahedra, prisms and pyramids"] * bool(others)) or "faces"
    what = (f"{points - int(keep.sum())} nodes on the edges of second-order elements ({elements}): "
            "the stream holds the linear cells through their corners")
    if mesh.point_data:
        what += ", and the fields' values at their corners only"
    return linear, what


# Cells read as the tetrahedra (quadrilaterals as the triangles) meshenc's
# readers split them into (tools/formats/cell_split.h), by corner count.
SPLIT = {"hexahedron": "tetra", "wedge": "tetra", "pyramid": "tetra", "quad": "triangle"}
SPLIT_NAMES = {"hexahedron": "hexahedra", "wedge": "prisms", "pyramid": "pyramids"}


def _tetrahedral(mesh):
    """Hexahedra, wedges and pyramids as tetrahedra, quadrilaterals as triangles, each with its
    cell's data and sets, as meshenc reads them; with what that says, in words (None if none)."""
    if not any(block.type in SPLIT for block in mesh.cells):
        return mesh, None
    cells, of_cell = [], []
    for block in mesh.cells:
        if block.type in SPLIT:
            data, cell_of = _dtmesh.split_cells(np.asarray(block.data, dtype=np.int64), np.asarray(mesh.points))
            cells.append(meshio.CellBlock(SPLIT[block.type], data))
            of_cell.append(cell_of)
        else:
            cells.append(block)
            of_cell.append(None)
    spread = lambda arrays: [a if of is None else np.asarray(a)[of] for a, of in zip(arrays, of_cell)]
    cell_data = {name: spread(arrays) if len(arrays) == len(mesh.cells) else arrays
                 for name, arrays in mesh.cell_data.items()}
    cell_sets = {name: [s if of is None else np.flatnonzero(np.isin(of, np.asarray(s)))
                        for s, of in zip(sets, of_cell)] if len(sets) == len(mesh.cells) else sets
                 for name, sets in (getattr(mesh, "cell_sets", None) or {}).items()}
    split = {}
    for block in mesh.cells:
        if block.type in SPLIT_NAMES:
            split[SPLIT_NAMES[block.type]] = split.get(SPLIT_NAMES[block.type], 0) + len(block.data)
    out = meshio.Mesh(mesh.points, cells, point_data=mesh.point_data, cell_data=cell_data,
                      field_data=mesh.field_data, cell_sets=cell_sets, info=mesh.info)
    if not split:
        return out, None
    # (meshenc's order, by corner count.)
    shapes = ", ".join(f"{split[n]} {n}" for n in ("pyramids", "prisms", "hexahedra") if n in split)
    return out, (f"the shapes of its {shapes}: each is read as the tetrahedra that split it "
                 "(its quadrilaterals by their diagonals through their least node)")


def _tetra10_edge_nodes(mesh):
    """With exact=True, a mesh whose volume cells are all tetra10 keeps its edge nodes (format 18.0,
    with the point data there 19.0, as meshenc --exact does): the points that are only such nodes (no
    kept cell's corner), per tetrahedron (the blocks' order) its edges' (0,1) (0,2) (0,3) (1,2) (1,3)
    (2,3) nodes, indices into them, -1 for a node that is some cell's corner, and which of the mesh's
    points they are (a mask); None for any other mesh."""
    volumes = [b for b in mesh.cells if QUADRATIC.get(b.type, (b.type,))[0] in VOLUMES]
    if not volumes or any(b.type != "tetra10" for b in volumes):
        return None
    corner = np.zeros(len(mesh.points), dtype=bool)
    for block in mesh.cells:
        kind, corners = QUADRATIC.get(block.type, (block.type, None))
        if kind in KEPT:
            corner[np.asarray(block.data)[:, :corners].reshape(-1)] = True
    # (meshio's tetra10 lists its edge nodes in VTK's order.)
    nodes = np.vstack([np.asarray(b.data)[:, [4, 6, 7, 5, 8, 9]] for b in volumes])
    aside = np.zeros(len(mesh.points), dtype=bool)
    for block in mesh.cells:
        if block.type in QUADRATIC:
            aside[np.asarray(block.data)[:, QUADRATIC[block.type][1]:].reshape(-1)] = True
    aside &= ~corner
    index = np.cumsum(aside) - 1
    return mesh.points[aside], np.where(aside[nodes], index[nodes], -1), aside


def write(filename, mesh, **options):
    edge = _tetra10_edge_nodes(mesh) if options.get("exact") else None
    point_data = mesh.point_data
    mesh, set_aside = _linear(mesh)
    edge_fields = {}
    if edge is not None and set_aside is not None:
        # (Kept, with the point data's values there.)
        options["edge_points"], options["edge_nodes"], aside = edge
        if options.get("keep_order"):
            # (The file's numbering of the corners and edge nodes together.)
            numbering = np.empty(len(aside), dtype=np.int64)
            numbering[~aside] = np.arange(int((~aside).sum()))
            numbering[aside] = int((~aside).sum()) + np.arange(int(aside.sum()))
            options["node_numbering"] = numbering
        edge_fields = {name: np.asarray(values)[aside] for name, values in point_data.items()}
        set_aside = None
    mesh, split = _tetrahedral(mesh)
    tetrahedra = None
    others = {}
    tetra_blocks = []
    for i, block in enumerate(mesh.cells):
        if block.type == "tetra":
            tetrahedra = block.data if tetrahedra is None else np.vstack([tetrahedra, block.data])
            tetra_blocks.append(i)
        else:
            others[block.type] = others.get(block.type, 0) + len(block.data)
    triangle_blocks = [i for i, block in enumerate(mesh.cells) if block.type == "triangle"]
    # The regions: an integer cell array of a known name, on the tetrahedra;
    # the same array on the triangles is their tags (gmsh's physical groups).
    # (region_array=NAME, as meshenc's --region-array: that array, for a
    # file whose regions have another name, such as FEniCS's XDMF files.)
    region_array = None
    names = REGION_ARRAYS
    if "region_array" in options:
        chosen = options.pop("region_array")
        arrays = mesh.cell_data.get(chosen)
        if arrays is None or not tetra_blocks or not all(
                np.asarray(arrays[i]).dtype.kind in "iu" for i in tetra_blocks):
            raise ValueError(f"{filename}: region_array {chosen!r} is not an integer cell array on the tetrahedra "
                             f"(the mesh has {sorted(mesh.cell_data)})")
        names = (chosen,)
    if tetra_blocks and "regions" not in options:
        for name in names:
            arrays = mesh.cell_data.get(name)
            if arrays is not None and all(np.asarray(arrays[i]).dtype.kind in "iu" for i in tetra_blocks):
                region_array = name
                options["regions"] = np.concatenate([np.asarray(arrays[i]).reshape(-1) for i in tetra_blocks])
                options.setdefault("region_names", {int(v[0]): k for k, v in _tag_names(mesh) if int(v[1]) == 3})
                if triangle_blocks and "faces" not in options:
                    options["faces"] = np.vstack([mesh.cells[i].data for i in triangle_blocks])
                    options["face_tags"] = np.concatenate([np.asarray(arrays[i]).reshape(-1) for i in triangle_blocks])
                    options.setdefault("face_tag_names", {int(v[0]): k for k, v in _tag_names(mesh)
                                                          if int(v[1]) == 2})
                    others.pop("triangle", None)
                break
    # What the stream does not hold yet is named, as meshenc names it:
    # nothing of a user's mesh is left out without a word.
    left_out = [what for what in (split, set_aside) if what]
    # A physical group's name without cells or faces of its label (gmsh
    # lists every group): named, not given to encode(), which refuses it.
    for what, labels_of in (("region_names", "regions"), ("face_tag_names", "face_tags")):
        if options.get(what) and options.get(labels_of) is not None:
            present = set(np.unique(np.asarray(options[labels_of])).tolist())
            unheld = {label: name for label, name in options[what].items() if label not in present}
            if unheld:
                options[what] = {label: name for label, name in options[what].items() if label in present}
                left_out.append(f"the names of {'regions' if what == 'region_names' else 'face tags'} without "
                                f"{'cells' if what == 'region_names' else 'faces'}: " +
                                ", ".join(f"{label} '{name}'" for label, name in sorted(unheld.items())))
    if others:
        left_out.append("cells other than tetrahedra (" + ", ".join(f"{n} {t}" for t, n in others.items()) + ")")
    # Copies of the regions (a decoded mesh gives them under several names) are kept with them.
    def same_as_regions(name):
        arrays = mesh.cell_data[name]
        return region_array is not None and len(arrays) == len(mesh.cells) and all(
            np.array_equal(np.asarray(arrays[i]).reshape(-1), np.asarray(mesh.cell_data[region_array][i]).reshape(-1))
            for i in range(len(mesh.cells)))

    other_cell_data = [name for name in mesh.cell_data if name != region_array and not same_as_regions(name)]
    # Per-cell arrays on the tetrahedra: the stream's cell data (but gmsh's
    # geometrical entity tags, which meshenc does not read from a .msh
    # either: the same file gives the same stream both ways).
    cell_data = {}
    for name in other_cell_data:
        if name == "gmsh:geometrical":
            continue
        arrays = mesh.cell_data[name]
        blocks = [np.asarray(arrays[i]) for i in tetra_blocks] if len(arrays) == len(mesh.cells) else []
        # (A name over 64 bytes, which a stream cannot hold, is named below:
        # meshio's .vtu of a gmsh mesh joins its groups' names into one.)
        if (blocks and all(b.dtype.kind in "iufb" and b.ndim in (1, 2) for b in blocks) and
                len(name.encode("utf-8", "surrogatepass")) <= 64):
            cell_data[name] = np.concatenate(blocks)
    unkept = [name for name in other_cell_data if name not in cell_data and name != "gmsh:geometrical"]
    if "gmsh:geometrical" in other_cell_data:
        left_out.append("cell data 'gmsh:geometrical' (gmsh's geometrical entity of each element)")
    if unkept:
        left_out.append("cell data " + ", ".join(f"'{name}'" for name in unkept))
    if cell_data and "cell_data" not in options:
        options["cell_data"] = _kept_aside(filename, cell_data, ("region",))
    # A cell set that is a named region's or tag's cells (meshio's gmsh
    # reader makes one a physical group) is held by the regions and tags;
    # gmsh's bounding entities are its geometry's bookkeeping.
    def held(name, sets):
        label = dict(_tag_names(mesh)).get(name)
        if region_array is None or label is None or len(sets) != len(mesh.cells):
            return False
        physical = mesh.cell_data[region_array]
        return all(np.array_equal(np.sort(np.asarray(sets[i]).reshape(-1)),
                                  np.flatnonzero(np.asarray(physical[i]).reshape(-1) == int(label[0])))
                   for i in range(len(mesh.cells)))
    unheld = [name for name, sets in (getattr(mesh, "cell_sets", None) or {}).items()
              if name != "gmsh:bounding_entities" and not held(name, sets)]
    if unheld:
        left_out.append("cell sets " + ", ".join(f"'{name}'" for name in unheld))
    if "gmsh:bounding_entities" in (getattr(mesh, "cell_sets", None) or {}):
        left_out.append("cell set 'gmsh:bounding_entities' (gmsh's geometrical entities)")
    for what in left_out:
        warnings.warn(f"{filename}: left out (the stream does not hold it): {what}", stacklevel=2)
    # A decoded mesh names the point data the stream makes itself (level,
    # boundary): they are not stored as fields. A mesh from elsewhere keeps
    # every array it has.
    derived = list(mesh.info.get("dtmesh_derived", []) if isinstance(mesh.info, dict) else [])
    # A file meshdec wrote (its .vtu, .msh, ...) read by meshio carries those
    # arrays too: level with boundary or vertex_id, whole non-negative
    # numbers, are meshdec's own, as meshenc takes them; gmsh's node entities
    # (meshio's gmsh:dim_tags) meshenc does not read either.
    def meshdecs(name):
        a = np.asarray(mesh.point_data[name])
        return (name in ("level", "boundary", "vertex_id") and a.ndim == 1 and a.size > 0 and
                np.issubdtype(a.dtype, np.number) and bool(np.all((a >= 0) & (a == np.floor(a)))) and
                (name != "boundary" or bool(np.all(a <= 1))))
    names = [n for n in mesh.point_data if n not in derived]
    if "level" in names and meshdecs("level") and any(n in names and meshdecs(n) for n in ("boundary", "vertex_id")):
        own = [n for n in ("level", "boundary", "vertex_id") if n in names and meshdecs(n)]
        warnings.warn(f"{filename}: left out (the stream does not hold it): the point arrays " +
                      ", ".join(f"'{n}'" for n in own) + " (meshdec's own: the decoder makes them again)",
                      stacklevel=2)
        derived += own
    if "gmsh:dim_tags" in mesh.point_data and "gmsh:dim_tags" not in derived:
        warnings.warn(f"{filename}: left out (the stream does not hold it): point data 'gmsh:dim_tags' "
                      "(gmsh's entity of each node)", stacklevel=2)
        derived.append("gmsh:dim_tags")
    unheld_points = list(getattr(mesh, "point_sets", None) or {})
    if unheld_points:
        warnings.warn(f"{filename}: left out (the stream does not hold it): point sets " +
                      ", ".join(f"'{n}'" for n in unheld_points), stacklevel=2)
    region_like = set(options.get("region_names", {}).values()) | set(options.get("face_tag_names", {}).values())
    other_field_data = [n for n in (mesh.field_data or {}) if n not in region_like]
    if other_field_data:
        warnings.warn(f"{filename}: left out (the stream does not hold it): field data " +
                      ", ".join(f"'{n}'" for n in other_field_data) + " (not a region's or tag's name)",
                      stacklevel=2)
    # Point arrays the stream cannot hold as they are (a tensor of more than
    # one axis per point, complex numbers, strings): named, as cell data's are.
    unkept_points = [name for name, values in mesh.point_data.items() if name not in derived and
                     not (np.asarray(values).dtype.kind in "iufb" and np.asarray(values).ndim in (1, 2) and
                          len(name.encode("utf-8", "surrogatepass")) <= 64)]
    if unkept_points:
        warnings.warn(f"{filename}: left out (the stream does not hold it): point data " +
                      ", ".join(f"'{n}'" for n in unkept_points), stacklevel=2)
        derived += unkept_points
    fields = _kept_aside(filename, {name: values for name, values in mesh.point_data.items() if name not in derived},
                         ("level", "boundary", "vertex_id"))
    if edge_fields and "edge_fields" not in options:
        kept_as = {name: name + " (input)" if name in ("level", "boundary", "vertex_id") else name
                   for name in edge_fields}
        options["edge_fields"] = {kept_as[name]: values for name, values in edge_fields.items()
                                  if kept_as[name] in fields}
    encoded = encode(mesh.points, tetrahedra, fields, **options)
    with open(filename, "wb") as f:
        f.write(encoded.bytes)


def _tag_names(mesh):
    """The field data entries that name a tag as gmsh's reader makes them: name -> [tag, dimension].

    Other formats put other things there (MED its family names, as lists):
    those are not names of tags.
    """
    out = []
    for name, value in (mesh.field_data or {}).items():
        try:
            v = np.asarray(value)
        except ValueError:
            continue
        if (v.ndim == 1 and v.size >= 2 and v.dtype.kind in "iuf" and bool(np.all(np.isfinite(v))) and
                bool(np.all(v == np.floor(v)))):
            out.append((name, v))
    return out


def _kept_aside(filename, arrays, taken):
    """The file's own arrays under a name meshdec gives its own (a water
    level, say) kept under another name, as meshenc keeps them, and said."""
    out = {}
    for name, values in arrays.items():
        if name in taken:
            warnings.warn(f"{filename}: the array '{name}' is kept as '{name} (input)' (meshdec writes its own "
                          f"'{name}')", stacklevel=3)
            name += " (input)"
        out[name] = values
    return out


def register():
    meshio.register_format("dtmesh", [".dtm"], read, {"dtmesh": write})
