"""Prints what an independent reader sees in a mesh file, as text for the
tests to compare: points (Python repr, the shortest round-trip form), cells,
point data.  usage: dump_mesh.py meshio|vtk FILE"""
import sys

reader, path = sys.argv[1], sys.argv[2]
if reader == "meshio":
    import meshio

    m = meshio.read(path)
    points = m.points
    blocks = [(b.type, b.data) for b in m.cells]
    point_data = dict(m.point_data)
else:
    import vtk
    from vtk.util import numpy_support as ns

    r = vtk.vtkUnstructuredGridReader() if path.endswith(".vtk") else vtk.vtkXMLUnstructuredGridReader()
    errors = []
    r.AddObserver("ErrorEvent", lambda obj, ev: errors.append(ev))
    r.SetFileName(path)
    r.Update()
    g = r.GetOutput()
    if errors or g is None or g.GetPoints() is None:
        sys.exit("VTK could not read " + path)
    points = ns.vtk_to_numpy(g.GetPoints().GetData())
    conn = ns.vtk_to_numpy(g.GetCells().GetConnectivityArray())
    types = ns.vtk_to_numpy(g.GetCellTypesArray())
    if len(types) and not (types == vtk.VTK_TETRA).all():
        sys.exit("cells other than VTK_TETRA")
    blocks = [("tetra", conn.reshape(-1, 4))] if len(types) else []
    pd = g.GetPointData()
    point_data = {pd.GetArrayName(i): ns.vtk_to_numpy(pd.GetArray(i)) for i in range(pd.GetNumberOfArrays())}

print("points", len(points))
for p in points:
    print(*(repr(float(x)) for x in p[:3]))
for kind, data in blocks:
    print("cells", kind, len(data))
    for c in data:
        print(*(int(v) for v in c))
for name in sorted(point_data):
    d = point_data[name].reshape(len(points), -1)
    print("pointdata", name, len(d))
    print(*(repr(float(v[0])) for v in d))
print("end")
