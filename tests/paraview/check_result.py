# Opens a result's XDMF sidecar in ParaView (run by pvbatch), as a user would, renders the smooth
# radiosity (the sidecar's point data) as colour and checks the picture: for builtin:cornell the
# wall on the left of the picture is red and the one on the right green.
# Usage: pvbatch check_result.py RESULT.xmf PICTURE.png PATCHES
import sys

import numpy

from paraview import servermanager
from paraview.simple import (Calculator, ColorBy, CreateView, Render, SaveScreenshot, Show,
                             Xdmf3ReaderS)
from vtkmodules.numpy_interface import dataset_adapter as dsa
from vtkmodules.vtkIOImage import vtkPNGReader


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


xmf, png, patches = sys.argv[1], sys.argv[2], int(sys.argv[3])
reader = Xdmf3ReaderS(FileName=[xmf])
reader.UpdatePipeline()
data = dsa.WrapDataObject(servermanager.Fetch(reader))
if data.GetNumberOfCells() != patches:
    fail("ParaView reads %d cells, the result has %d patches" % (data.GetNumberOfCells(), patches))
for name in ("radiosity", "irradiance", "emission", "reflectance", "area", "source_face"):
    if name not in data.CellData.keys():
        fail("no cell array " + name + " (has " + ", ".join(data.CellData.keys()) + ")")
if "radiosity_smooth" not in data.PointData.keys():
    fail("no point array radiosity_smooth")

# Colours straight from B (not a colour map), scaled so that the brighter walls are near white
# (the 95th percentile of the patches that do not emit; brighter ones clip).
radiosity, emission = data.CellData["radiosity"], data.CellData["emission"]
reflecting = radiosity[emission.max(axis=1) == 0].max(axis=1)
scale = float(numpy.percentile(reflecting, 95)) if len(reflecting) else 1.0
shown = Calculator(Input=reader, AttributeType="Point Data", ResultArrayName="shown",
                   Function="iHat*min(radiosity_smooth_X/%.17g,1)+jHat*min(radiosity_smooth_Y/%.17g,1)"
                            "+kHat*min(radiosity_smooth_Z/%.17g,1)" % (scale, scale, scale))
view = CreateView("RenderView")
view.ViewSize = [480, 480]
view.OrientationAxesVisibility = 0
view.UseColorPaletteForBackground = 0
view.Background = [0, 0, 0]
display = Show(shown, view)
ColorBy(display, ("POINTS", "shown"))
display.MapScalars = 0  # the values are the colours
display.Interpolation = "Flat"
display.Ambient, display.Diffuse = 1.0, 0.0  # B is the light leaving the surface: no shading
# The classic Cornell camera: in front of the open side, looking in along +z.
(x0, x1, y0, y1, z0, z1) = shown.GetDataInformation().GetBounds()
centre = [(x0 + x1) / 2, (y0 + y1) / 2, (z0 + z1) / 2]
view.CameraPosition = [centre[0], centre[1], z0 - 1.4 * (z1 - z0)]
view.CameraFocalPoint = centre
view.CameraViewUp = [0, 1, 0]
view.CameraViewAngle = 39.3
Render(view)
SaveScreenshot(png, view, ImageResolution=[480, 480])

image = vtkPNGReader()
image.SetFileName(png)
image.Update()
pixels = image.GetOutput()


def colour(x, y):
    return [pixels.GetScalarComponentAsDouble(x, y, 0, c) for c in range(3)]


# Along the middle row, the first lit pixels from each side are the side walls' (the background
# is black, whatever the framing).
row = [colour(x, 240) for x in range(480)]
lit = [x for x in range(480) if sum(row[x]) > 60]
if not lit:
    fail("the picture is black along its middle row")
left, right = row[min(lit[0] + 10, 479)], row[max(lit[-1] - 10, 0)]
print("left wall pixel %s, right wall pixel %s" % (left, right))
if not (left[0] > 2 * left[1] and left[0] > 2 * left[2] and left[0] > 40):
    fail("the left wall is not red: %s" % left)
if not (right[1] > 1.5 * right[0] and right[1] > 1.5 * right[2] and right[1] > 40):
    fail("the right wall is not green: %s" % right)
print("PASS: ParaView opened %s and shows the Cornell walls red and green" % xmf)
