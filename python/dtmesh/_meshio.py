"""The .dtm format in meshio: meshio.read("x.dtm") and meshio.write("x.dtm", mesh).

Reading gives the finest level: its tetrahedra, the stream's fields and the
per-vertex ``level`` and ``boundary`` as point data. Writing encodes the
mesh's points, its tetrahedra (the reference solid) and its point data as
fields, with dtmesh.encode's options as keyword arguments.
"""
import meshio
import numpy as np

from . import decode, encode


def read(filename, level=None):
    return decode(filename, level).to_meshio()


def write(filename, mesh, **options):
    tetrahedra = None
    for block in mesh.cells:
        if block.type == "tetra":
            tetrahedra = block.data if tetrahedra is None else np.vstack([tetrahedra, block.data])
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
