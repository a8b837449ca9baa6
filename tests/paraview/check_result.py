# Checks, in ParaView (run by pvbatch), what a user meets: a result's XDMF sidecar as ParaView
# reads it, and the picture paraview_picture.py made of it, against the renderer's.
#  - The first point array, what ParaView colours by after Apply, is luminance_tonemapped, and it
#    displays well: Y / (Y + m) for one midpoint m, its median mid-scale (the light, ~200 times
#    the typical wall, squeezes the walls of a linear scale of B or Y into its bottom 2 %).
#  - B's channels as arrays named for them equal B's components; units in names ("area [mm^2]":
#    builtin:cornell is in mm); the labels as field data ("group 5: red wall").
#  - The picture: the wall on the left red, the one on the right green, not one colour, and
#    close to `radiosity render`'s picture of the same result from the same default camera.
# Usage: pvbatch check_result.py RESULT.xmf PICTURE.png RENDERED.png PATCHES
import builtins  # (ParaView's numpy algorithms shadow max and min in a script's namespace)
import sys

import numpy

from paraview import servermanager
from paraview.simple import CreateView, Show, Xdmf3ReaderS
from vtkmodules.numpy_interface import dataset_adapter as dsa
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOImage import vtkPNGReader

failures = []


def fail(message):
    print("FAIL: " + message)
    failures.append(message)


xmf, picture, rendered, patches = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])
reader = Xdmf3ReaderS(FileName=[xmf])
reader.UpdatePipeline()
data = dsa.WrapDataObject(servermanager.Fetch(reader))
points, cells, field = data.PointData, data.CellData, data.FieldData
print("point arrays: " + ", ".join(points.keys()))
print("cell arrays: " + ", ".join(cells.keys()))
print("field data: " + ", ".join(field.keys()))
if data.GetNumberOfCells() != patches:
    fail("ParaView reads %d cells, the result has %d patches" % (data.GetNumberOfCells(), patches))

# What ParaView shows first.
expected = ["luminance_tonemapped", "radiosity_smooth", "radiosity_smooth_red",
            "radiosity_smooth_green", "radiosity_smooth_blue"]
if list(points.keys()) != expected:
    fail("point arrays %s, expected %s" % (list(points.keys()), expected))
display = Show(reader, CreateView("RenderView"))
if list(display.ColorArrayName) != ["POINTS", "luminance_tonemapped"]:
    fail("ParaView colours by %s, not luminance_tonemapped" % list(display.ColorArrayName))
if "luminance_tonemapped" in points.keys() and "radiosity_smooth" in points.keys():
    shown = numpy.asarray(points["luminance_tonemapped"])
    b = numpy.asarray(points["radiosity_smooth"])
    y = b @ numpy.array([0.2126, 0.7152, 0.0722])
    if not (shown.min() >= 0 and shown.max() < 1):
        fail("luminance_tonemapped outside [0, 1): %g to %g" % (shown.min(), shown.max()))
    lit = shown > 0
    midpoints = y[lit] * (1 - shown[lit]) / shown[lit]
    spread = midpoints.max() / midpoints.min() - 1
    print("luminance_tonemapped: midpoint %.6g (spread %.2g), median %.3f; linear Y's median at "
          "%.2g of its range" % (numpy.median(midpoints), spread, numpy.median(shown),
                                 numpy.median(y) / y.max()))
    if not spread < 1e-9:
        fail("luminance_tonemapped is not Y / (Y + m) for one m: m varies by %g" % spread)
    if not 0.25 < numpy.median(shown) < 0.75:
        fail("luminance_tonemapped's median %g is not mid-scale" % numpy.median(shown))

# B's channels apart, named for them.
for attributes, name in ((points, "radiosity_smooth"), (cells, "radiosity")):
    for c, channel in enumerate(("red", "green", "blue")):
        part = name + "_" + channel
        if part not in attributes.keys():
            fail("no array " + part)
        elif not numpy.array_equal(numpy.asarray(attributes[part]).ravel(),
                                   numpy.asarray(attributes[name])[:, c]):
            fail("%s is not component %d of %s" % (part, c, name))
for name in ("radiosity", "irradiance", "emission", "reflectance", "area [mm^2]", "group"):
    if name not in cells.keys():
        fail("no cell array " + name)
labels = {name.split(": ", 1)[1]: int(numpy.asarray(field[name]).ravel()[0])
          for name in field.keys() if name.startswith("group ")}
if "group" in cells.keys():
    groups = builtins.max(numpy.asarray(cells["group"])) + 1
    if sorted(labels.values()) != list(range(groups)):
        fail("field data names labels %s, the patches have %d" % (sorted(labels.values()), groups))
for wall in ("red wall", "green wall"):
    if wall not in labels:
        fail("no field data names the label " + wall)


def load(path):
    image = vtkPNGReader()
    image.SetFileName(path)
    image.Update()
    width, height, _ = image.GetOutput().GetDimensions()
    pixels = vtk_to_numpy(image.GetOutput().GetPointData().GetScalars())
    return pixels.reshape(height, width, -1)[::-1, :, :3].astype(float)  # top row first


# The picture: along the middle row, the first lit pixels from each side are the side walls'
# (the background is black, whatever the framing).
image = load(picture)
height, width, _ = image.shape
row = image[height // 2]
lit = numpy.nonzero(row.sum(axis=1) > 60)[0]
if len(lit) == 0:
    fail("the picture is black along its middle row")
else:
    left = row[builtins.min(lit[0] + 10, width - 1)]
    right = row[builtins.max(lit[-1] - 10, 0)]
    print("left wall pixel %s, right wall pixel %s" % (left, right))
    # (sRGB brings channels closer: the green wall's linear G/R of 2.5 shows as about 1.4.)
    if not (left[0] > 1.5 * left[1] and left[0] > 1.5 * left[2] and left[0] > 80):
        fail("the left wall is not red: %s" % left)
    if not (right[1] > 1.25 * right[0] and right[1] > 1.5 * right[2] and right[1] > 80):
        fail("the right wall is not green: %s" % right)
colours = len(numpy.unique(image.reshape(-1, 3), axis=0))
if colours < 1000:
    fail("the picture has %d colours: not a picture of the box" % colours)
reference = load(rendered)
if reference.shape != image.shape:
    fail("the picture is %s, the renderer's %s" % (image.shape, reference.shape))
else:
    difference = numpy.abs(image - reference).max(axis=2)
    print("against the renderer's picture: mean difference %.1f of 255, %.2f %% of pixels off by "
          "more than 64" % (difference.mean(), 100 * (difference > 64).mean()))
    if not (difference.mean() < 16 and (difference > 64).mean() < 0.03):
        fail("the picture is not the renderer's")

if failures:
    sys.exit(1)
print("PASS: ParaView opened %s (luminance_tonemapped first, B's channels and the labels named) "
      "and paraview_picture.py shows the Cornell walls red and green, as the renderer does" % xmf)
