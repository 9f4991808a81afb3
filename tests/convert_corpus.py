"""Writes one TetGen model (.node + .ele) in every input format meshenc reads,
with writers that are not ours: VTK's own (python3-paraview, whose Python has VTK) for .vtu and .vtk,
meshio (python3-meshio) for Medit, gmsh, PLY, OFF, OBJ; XYZ by hand.
Coordinates are written so that they read back to the same doubles.

usage: convert_corpus.py MODEL.node OUT_DIR STEM"""
import os
import sys

import meshio
import numpy as np
import vtk
from vtk.util import numpy_support

node_path, out_dir, stem = sys.argv[1], sys.argv[2], sys.argv[3]


def records(path):
    with open(path) as f:
        for line in f:
            line = line.split("#")[0].split()
            if line:
                yield line


rows = records(node_path)
count = int(next(rows)[0])
nodes = [next(rows) for _ in range(count)]
base = int(nodes[0][0])
points = np.array([[float(x) for x in r[1:4]] for r in nodes], dtype=np.float64)
ele_path = node_path[: -len(".node")] + ".ele"
tets = np.zeros((0, 4), dtype=np.int64)
if os.path.exists(ele_path):
    rows = records(ele_path)
    n = int(next(rows)[0])
    tets = np.array([[int(v) - base for v in next(rows)[1:5]] for _ in range(n)], dtype=np.int64)
marker = np.arange(len(points), dtype=np.int32) % 3  # a made-up per-vertex field
out = lambda name: os.path.join(out_dir, stem + name)

# VTK's own writers.
grid = vtk.vtkUnstructuredGrid()
pts = vtk.vtkPoints()
pts.SetData(numpy_support.numpy_to_vtk(points, deep=True))
grid.SetPoints(pts)
for t in tets:
    ids = vtk.vtkIdList()
    for v in t:
        ids.InsertNextId(int(v))
    grid.InsertNextCell(vtk.VTK_TETRA, ids)
arr = numpy_support.numpy_to_vtk(marker, deep=True)
arr.SetName("marker")
grid.GetPointData().AddArray(arr)


def vtu(name, mode, encode=True, compressor="None", header="UInt32", pieces=1):
    w = vtk.vtkXMLUnstructuredGridWriter()
    w.SetFileName(out(name))
    if pieces > 1:
        # Each piece a run of the cells and the points they use (shared
        # ones in several pieces), as a parallel writer's pieces are; made
        # here because VTK's piece extraction writes points as floats.
        split = vtk.vtkProgrammableFilter()
        split.SetInputData(grid)

        def one_piece():
            info = split.GetOutputInformation(0)
            sddp = vtk.vtkStreamingDemandDrivenPipeline
            k, n = info.Get(sddp.UPDATE_PIECE_NUMBER()), info.Get(sddp.UPDATE_NUMBER_OF_PIECES())
            mine = tets[len(tets) * k // n : len(tets) * (k + 1) // n]
            used = np.unique(mine)
            local = {int(v): i for i, v in enumerate(used)}
            piece = vtk.vtkUnstructuredGrid()
            p = vtk.vtkPoints()
            p.SetData(numpy_support.numpy_to_vtk(points[used], deep=True))
            piece.SetPoints(p)
            for t in mine:
                ids = vtk.vtkIdList()
                for v in t:
                    ids.InsertNextId(local[int(v)])
                piece.InsertNextCell(vtk.VTK_TETRA, ids)
            a = numpy_support.numpy_to_vtk(marker[used], deep=True)
            a.SetName("marker")
            piece.GetPointData().AddArray(a)
            split.GetUnstructuredGridOutput().ShallowCopy(piece)

        split.SetExecuteMethod(one_piece)
        w.SetInputConnection(split.GetOutputPort())
        w.SetNumberOfPieces(pieces)
    else:
        w.SetInputData(grid)
    getattr(w, "SetCompressorTypeTo" + compressor)()
    getattr(w, "SetHeaderTypeTo" + header)()
    {"ascii": w.SetDataModeToAscii, "binary": w.SetDataModeToBinary, "appended": w.SetDataModeToAppended}[mode]()
    w.SetEncodeAppendedData(encode)
    assert w.Write() == 1


vtu("_ascii.vtu", "ascii")
vtu("_base64.vtu", "binary")
vtu("_appended_raw.vtu", "appended", encode=False)
vtu("_appended_base64.vtu", "appended", encode=True)
# Compressed, as VTK and ParaView write by default (zlib), and with the
# other compressors VTK offers, in each data mode and header size.
vtu("_zlib.vtu", "binary", compressor="ZLib")
vtu("_lz4_appended_raw.vtu", "appended", encode=False, compressor="LZ4", header="UInt64")
vtu("_lzma_appended_base64.vtu", "appended", encode=True, compressor="LZMA")
vtu("_zlib_3_pieces.vtu", "appended", encode=False, compressor="ZLib", pieces=3)
for name, binary in (("_ascii.vtk", False), ("_binary.vtk", True)):
    w = vtk.vtkUnstructuredGridWriter()
    w.SetFileName(out(name))
    w.SetInputData(grid)
    w.SetFileTypeToBinary() if binary else w.SetFileTypeToASCII()
    assert w.Write() == 1

# meshio's writers.
cells = [("tetra", tets)] if len(tets) else [("vertex", np.arange(len(points)).reshape(-1, 1))]
mesh = meshio.Mesh(points, cells, point_data={"marker": marker})
from meshio.vtk import _vtk_42

_vtk_42.write(out("_42.vtk"), mesh, binary=False)
# meshio's .vtu: zlib by default; lzma on request.
meshio.vtu.write(out("_meshio_zlib.vtu"), mesh)
meshio.vtu.write(out("_meshio_lzma.vtu"), mesh, compression="lzma")
meshio.medit.write(out(".mesh"), meshio.Mesh(points, cells), float_fmt=".17g")
meshio.gmsh.write(out("_22.msh"), mesh, fmt_version="2.2", binary=False, float_fmt=".17g")
meshio.gmsh.write(out("_41.msh"), mesh, fmt_version="4.1", binary=False, float_fmt=".17g")
meshio.gmsh.write(out("_22_binary.msh"), mesh, fmt_version="2.2", binary=True)
meshio.gmsh.write(out("_41_binary.msh"), mesh, fmt_version="4.1", binary=True)
surface = meshio.Mesh(points, [])
meshio.write(out("_binary.ply"), surface, file_format="ply", binary=True)
meshio.write(out("_ascii.ply"), surface, file_format="ply", binary=False)
# OFF, OBJ and XYZ by hand: these writers put too few digits or need faces.
with open(out(".off"), "w") as f:
    f.write("OFF\n%d 0 0\n" % len(points))
    f.writelines("%r %r %r\n" % tuple(map(float, p)) for p in points)
with open(out(".obj"), "w") as f:
    f.writelines("v %r %r %r\n" % tuple(map(float, p)) for p in points)
with open(out(".xyz"), "w") as f:
    f.writelines("%r %r %r\n" % tuple(map(float, p)) for p in points)
