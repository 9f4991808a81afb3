"""The levels of a stream with regions and tagged faces, side by side, cut
open: pvbatch scripts/render_regions.py OUT.png LEVEL0.vtu LEVEL1.vtu ...

Each .vtu is a level as meshdec writes it (tetrahedra, then the tagged faces
as triangles; cell data `region`: a tetrahedron's region, a triangle's tag).
The tetrahedra are cut by the plane y = the part's middle and coloured by
region; the tagged faces are drawn over them, coloured by tag. Run by
scripts/pictures.sh.
"""
import inspect
import sys

if not hasattr(inspect, "getargspec"):  # Debian 12's ParaView 5.11 on Python 3.11
    inspect.getargspec = inspect.getfullargspec

from paraview.simple import (Clip, ColorBy, CreateView, GetColorTransferFunction, Render, SaveScreenshot, Show,
                             Text, Threshold, XMLUnstructuredGridReader)

out, levels = sys.argv[1], sys.argv[2:]
view = CreateView("RenderView")
view.ViewSize = [400 * len(levels), 420]
view.OrientationAxesVisibility = 0
view.UseColorPaletteForBackground = 0
view.Background = [1, 1, 1]
colours = GetColorTransferFunction("region")
colours.InterpretValuesAsCategories = 1
colours.Annotations = ["1", "aluminium", "2", "steel", "3", "base", "4", "load"]
colours.IndexedColors = [0.75, 0.75, 0.78, 0.35, 0.45, 0.75, 0.85, 0.35, 0.25, 0.95, 0.75, 0.2]
for i, path in enumerate(levels):
    reader = XMLUnstructuredGridReader(FileName=[path])
    reader.UpdatePipeline()
    bounds = reader.GetDataInformation().GetBounds()
    width = bounds[1] - bounds[0]
    cells = Threshold(Input=reader)  # the tetrahedra: regions 1-2
    cells.Scalars = ["CELLS", "region"]
    cells.LowerThreshold, cells.UpperThreshold = 1, 2
    cut = Clip(Input=cells)
    cut.ClipType = "Plane"
    cut.ClipType.Origin = [0, (bounds[2] + bounds[3]) / 2, 0]
    cut.ClipType.Normal = [0, 1, 0]
    faces = Threshold(Input=reader)  # the tagged faces: tags 3-4
    faces.Scalars = ["CELLS", "region"]
    faces.LowerThreshold, faces.UpperThreshold = 3, 4
    for source, edges in ((cut, True), (faces, False)):
        display = Show(source, view)
        display.SetRepresentationType("Surface With Edges" if edges else "Surface")
        display.EdgeColor = [0.25, 0.25, 0.25]
        ColorBy(display, ("CELLS", "region"))
        display.LookupTable = colours
        display.Position = [-i * 1.2 * width, 0, 0]  # the camera looks along -y: +x is to the left
    label = Text(Text=path.rsplit("/", 1)[-1].replace(".vtu", "").replace("_", " "))
    shown = Show(label, view)
    shown.WindowLocation = "Any Location"
    shown.Position = [0.02 + i / len(levels), 0.9]
    shown.FontSize = 14
    shown.Color = [0, 0, 0]
# From the cut's side (the clip keeps y below the middle), a little from
# below and from the loaded end, so that the base and the end show; the row
# of levels fills the picture (a parallel projection).
Render(view)  # the first render resets the camera: set it after
row = (len(levels) - 1) * 1.2 * width + width
centre = [bounds[1] - row / 2, (bounds[2] + bounds[3]) / 2, (bounds[4] + bounds[5]) / 2]
view.CameraFocalPoint = centre
view.CameraPosition = [centre[0] + 0.35 * row, centre[1] + 2 * row, centre[2] - 0.5 * row]
view.CameraViewUp = [0, 0, 1]
view.CameraParallelProjection = 1
view.CameraParallelScale = 1.15 * row / (2 * 400 * len(levels) / 420)
Render(view)
SaveScreenshot(out, view, ImageResolution=[400 * len(levels), 420])
print(out)
