"""A ParaView reader for .dtm streams (progressive tetrahedral meshes, dtmesh).

Load it once: Tools > Manage Plugins > Load New... and pick this file (tick
"Auto Load" to keep it), or in a pvpython / pvbatch script (on Debian 12's
ParaView 5.11, first `import inspect; inspect.getargspec =
inspect.getfullargspec`: load_dtmesh.py says why):

    from paraview.simple import *
    LoadPlugin("/path/to/paraview/dtmesh_reader.py", ns=globals())
    mesh = OpenDataFile("part.dtm")
    mesh.Level = 3          # a coarser level of detail (0 = the finest)

File > Open then opens .dtm files. The reader shows one level of the stream's
hierarchy as an unstructured grid of tetrahedra, with the stream's per-vertex
fields and, per vertex, `level` (the coarsest level holding it) and
`boundary`; the regions as cell data `region` and level 0's cell arrays as
cell data; the tagged boundary faces as the reader's second output (a
polydata with cell data `face_tag`, on the same points); its Level property runs over the stream's levels (0 = the finest,
as meshdec --level counts them). The stream's figures (meshinfo's) are field
data, in the Information panel.

It needs the Python package dtmesh importable by ParaView's Python (the same
Python 3 as the system's on Debian): install it with pip for that Python, or
put the directory holding it on PYTHONPATH.
"""
import inspect
import json
import sys
import warnings

import numpy as np

# ParaView 5.11's Python algorithms call inspect.getargspec, which Python
# 3.11 removed; they read only its .args, which getfullargspec has too.
if not hasattr(inspect, "getargspec"):
    inspect.getargspec = inspect.getfullargspec

from paraview.util.vtkAlgorithm import VTKPythonAlgorithmBase, smdomain, smhint, smproperty, smproxy  # noqa: E402
from vtkmodules.numpy_interface import dataset_adapter  # noqa: E402
from vtkmodules.vtkCommonCore import vtkStringArray  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkDataObject, vtkPolyData, vtkUnstructuredGrid  # noqa: E402

try:
    import dtmesh
except ImportError as e:  # said when a file is opened, not when the plugin loads
    dtmesh = None
    _import_error = e


@smproxy.reader(name="DtmeshReader", label="dtmesh stream reader", extensions="dtm",
                file_description="dtmesh progressive tetrahedral meshes")
class DtmeshReader(VTKPythonAlgorithmBase):
    def __init__(self):
        VTKPythonAlgorithmBase.__init__(self, nInputPorts=0, nOutputPorts=2, outputType="vtkUnstructuredGrid")
        self._filename = None
        self._level = 0
        self._bytes = None
        self._info = None
        self._count = None  # a damaged stream's level count, from its header
        self._meshes = {}  # level -> dtmesh.Mesh, decoded once each

    def FillOutputPortInformation(self, port, info):
        # Port 0: the level's mesh; port 1: its tagged boundary faces alone.
        info.Set(vtkDataObject.DATA_TYPE_NAME(), "vtkUnstructuredGrid" if port == 0 else "vtkPolyData")
        return 1

    def _say(self, message):
        # ParaView's Output Messages window shows standard error.
        print(f"dtmesh reader: {self._filename}: {message}", file=sys.stderr)

    def _stream(self):
        if self._bytes is None and self._filename:
            if dtmesh is None:
                raise RuntimeError(f"the dtmesh Python package is not importable here: {_import_error}")
            with open(self._filename, "rb") as f:
                self._bytes = f.read()
            try:
                self._info = dtmesh.info(self._bytes)
            except dtmesh.Error as e:
                # A damaged stream: the levels before the damage are shown
                # (_decode), the damage said once here.
                self._info = None
                self._say(e)
        return self._bytes

    def _level_count(self):
        if self._info is not None:
            return self._info["level_count"]
        if self._count is None:  # (read from the header once: the stream is damaged)
            decoder = dtmesh.Decoder()
            try:
                decoder.feed(self._bytes[:4096])  # (the header's 56 bytes give it)
            except dtmesh.Error:
                pass
            self._count = max(1, decoder.level_count)
        return self._count


    def _decode(self, level):
        """The level's mesh; where the stream is cut or damaged before it, the
        finest whole level before that, said; None when there is none."""
        try:
            with warnings.catch_warnings(record=True) as said:
                warnings.simplefilter("always")
                mesh = dtmesh.decode(self._bytes, level)
            for w in said:
                self._say(w.message)
            return mesh
        except dtmesh.Error as e:
            if self._info is not None:
                self._say(e)
        # Fed as a viewer would: the levels complete before the cut or the
        # damage stand.
        decoder = dtmesh.Decoder()
        try:
            decoder.feed(self._bytes)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                decoder.finish()
        except dtmesh.Error:
            pass
        if decoder.finest_level < 0:
            self._say("no whole level to show")
            return None
        try:
            mesh = decoder.mesh()
        except dtmesh.Error as e:  # (damage in a section read only for the mesh)
            self._say(f"level {decoder.finest_level}: {e}")
            return None
        self._say(f"showing level {decoder.finest_level}, the finest whole level")
        return mesh

    @smproperty.stringvector(name="FileName")
    @smdomain.filelist()
    @smhint.filechooser(extensions="dtm", file_description="dtmesh progressive tetrahedral meshes")
    def SetFileName(self, name):
        if name != self._filename:
            self._filename = name
            self._bytes, self._info, self._meshes, self._count = None, None, {}, None
            self.Modified()

    @smproperty.intvector(name="LevelRange", information_only="1")
    def GetLevelRange(self):
        if self._stream() is None:
            return (0, 0)
        return (0, max(0, self._level_count() - 1))

    # default_mode="min": a range domain's default is its middle unless
    # told, and File > Open showed a middle level, not the finest.
    @smproperty.intvector(name="Level", default_values=0)
    @smdomain.xml("""<IntRangeDomain name="range" default_mode="min">
                       <RequiredProperties><Property name="LevelRange" function="RangeInfo"/></RequiredProperties>
                     </IntRangeDomain>
                     <Documentation>The level of detail shown: 0 is the finest, the largest the coarsest.</Documentation>""")
    def SetLevel(self, level):
        if level != self._level:
            self._level = level
            self.Modified()

    def RequestData(self, request, in_info, out_info):
        if self._stream() is None:
            return 1
        level = min(max(0, int(self._level)), self._level_count() - 1)
        if level not in self._meshes:
            # A stream cut or damaged before the level: its finest whole
            # level, shown as what it is (dtm_level).
            self._meshes[level] = self._decode(level)
        mesh = self._meshes[level]
        if mesh is None:
            return 1
        level = mesh.level
        output = vtkUnstructuredGrid.GetData(out_info, 0)
        # The tetrahedra alone: the tagged faces are the second output (among
        # the cells, a filter such as Cell Data to Point Data would average
        # their rows of the cell arrays in, and their tags into `region`).
        output.ShallowCopy(dtmesh.to_vtk(mesh, faces=False))
        # The stream's figures, for the Information panel.
        fields = dataset_adapter.WrapDataObject(output).FieldData
        fields.append(np.array([level]), "dtm_level")
        fields.append(np.array([self._level_count()]), "dtm_level_count")
        if self._info is None:  # (damaged: meshinfo's figures are not known)
            return self._faces(mesh, output, out_info)
        fields.append(np.array([self._info["bytes"]]), "dtm_stream_bytes")
        fields.append(np.array([self._info["bits_per_vertex"]]), "dtm_bits_per_vertex")
        layers = [row for row in self._info["levels"] if row["level"] >= level]
        fields.append(np.array([sum(row["layer_bytes"] for row in layers)]), "dtm_layer_bytes_to_this_level")
        summary = vtkStringArray()
        summary.SetName("dtm_info")
        summary.InsertNextValue(json.dumps(self._info))
        output.GetFieldData().AddArray(summary)
        return self._faces(mesh, output, out_info)

    def _faces(self, mesh, output, out_info):
        # The tagged faces on their own (the second output): triangles with
        # their tag as cell data `face_tag`, on the level's points.
        faces = vtkPolyData.GetData(out_info, 1)
        faces.Initialize()
        faces.SetPoints(output.GetPoints())
        from vtkmodules.util.numpy_support import numpy_to_vtk
        from vtkmodules.vtkCommonDataModel import vtkCellArray
        triangles = vtkCellArray()
        for face in mesh.faces:
            triangles.InsertNextCell(3, [int(v) for v in face])
        faces.SetPolys(triangles)
        tags = numpy_to_vtk(np.ascontiguousarray(mesh.face_tags.astype(np.int32)), deep=True)
        tags.SetName("face_tag")
        faces.GetCellData().AddArray(tags)
        faces.GetCellData().SetActiveScalars("face_tag")
        return 1
