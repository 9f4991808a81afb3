"""The .dtm format in meshio: meshio.read("x.dtm") and meshio.write("x.dtm", mesh).

Reading gives the finest level: its tetrahedra, the stream's fields and the
per-vertex ``level`` and ``boundary`` as point data. Writing encodes the
mesh's points, its tetrahedra (the reference solid) and its point data as
fields, with dtmesh.encode's options as keyword arguments; what the stream
does not hold yet (cell data, cell sets, other cells) is named in a warning.
"""
import warnings

import meshio
import numpy as np

from . import decode, encode


def read(filename, level=None):
    return decode(filename, level).to_meshio()


def write(filename, mesh, **options):
    tetrahedra = None
    others = {}
    for block in mesh.cells:
        if block.type == "tetra":
            tetrahedra = block.data if tetrahedra is None else np.vstack([tetrahedra, block.data])
        else:
            others[block.type] = others.get(block.type, 0) + len(block.data)
    # What the stream does not hold yet is named, as meshenc names it:
    # nothing of a user's mesh is left out without a word.
    left_out = []
    if others:
        left_out.append("cells other than tetrahedra (" + ", ".join(f"{n} {t}" for t, n in others.items()) + ")")
    if mesh.cell_data:
        left_out.append("cell data " + ", ".join(f"'{name}'" for name in mesh.cell_data))
    if getattr(mesh, "cell_sets", None):
        left_out.append("cell sets " + ", ".join(f"'{name}'" for name in mesh.cell_sets))
    for what in left_out:
        warnings.warn(f"{filename}: left out (the stream does not hold it): {what}", stacklevel=2)
    # A decoded mesh names the point data the stream makes itself (level,
    # boundary): they are not stored as fields. A mesh from elsewhere keeps
    # every array it has.
    derived = mesh.info.get("dtmesh_derived", []) if isinstance(mesh.info, dict) else []
    fields = {name: values for name, values in mesh.point_data.items() if name not in derived}
    encoded = encode(mesh.points, tetrahedra, fields, **options)
    with open(filename, "wb") as f:
        f.write(encoded.bytes)


def register():
    meshio.register_format("dtmesh", [".dtm"], read, {"dtmesh": write})
