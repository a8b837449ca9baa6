# A result in ParaView as `radiosity render` shows it: opens the result's XDMF sidecar, colours
# the surfaces by B itself (the smooth radiosity as red, green and blue, not through a colour
# map), exposed as the renderer exposes (the 97th percentile of the luminance, area-weighted over
# the patches, shown at 0.85, then sRGB), seen from the renderer's default camera (looking along
# +z at the centre of the scene from just far enough to see all of it, up +y, 40 degrees), and
# saves a PNG picture. B is light leaving the surface: no shading, and back faces are culled, so a
# camera outside a closed room looks in, as in the renderer.
#
# Usage (installed as share/radiosity/paraview_picture.py):
#   pvpython paraview_picture.py RESULT.xmf|RESULT.h5 PICTURE.png [--width 512] [--height 512]
#       [--exposure STOPS] [--eye x,y,z] [--look-at x,y,z] [--up x,y,z] [--fov DEGREES]
# RESULT.h5 stands for the RESULT.xmf beside it (`radiosity xdmf RESULT.h5` writes one for a
# result of an older version). pvbatch runs it alike; Debian's ParaView needs an X display, so on
# a machine without one: xvfb-run -a -s -noreset pvbatch paraview_picture.py ... The options are the
# renderer's (`radiosity render --help`). From ParaView's Python shell or a script of your own:
#   sys.path.insert(0, PREFIX + "/share/radiosity"); import paraview_picture
#   paraview_picture.show_as_rendered(reader, view)  # an opened sidecar, in a render view
#   paraview_picture.place_camera(view, reader.GetDataInformation().GetBounds(), width / height)
import argparse
import builtins  # (ParaView's filters run `from ...numpy_interface.algorithms import *` in the
import math      # script's namespace: its max, min, abs and all shadow Python's there)
import os
import sys

import numpy

import paraview.simple
from paraview import servermanager
from paraview.simple import (ColorBy, CreateView, ProgrammableFilter, Render, SaveScreenshot,
                             Show, Xdmf3ReaderS)
from vtkmodules.numpy_interface import dataset_adapter as dsa

# The renderer's exposure (render/render.cpp): this luminance percentile is shown at this value.
EXPOSURE_PERCENTILE, EXPOSURE_TARGET = 0.97, 0.85
LUMINANCE_WEIGHTS = (0.2126, 0.7152, 0.0722)  # core/channels.h
FIT_MARGIN = 1.05  # render/camera.cpp: a little black around the scene


def array_named(names, base):
    """The array `base`, with or without the unit the sidecar adds ("area [mm^2]"); None."""
    for name in names:
        if name == base or name.startswith(base + " ["):
            return name
    return None


def sidecar_of(path):
    """The absolute path of the XDMF sidecar for RESULT.xmf or RESULT.h5. Absolute, because
    ParaView 5.11's XDMF 3 reader looks for the .h5 of a sidecar opened by a bare file name
    ("r.xmf") as "r.xmfr.h5" and aborts."""
    root, extension = os.path.splitext(path)
    xmf = root + ".xmf" if extension.lower() == ".h5" else path
    if not os.path.isfile(xmf):
        if extension.lower() == ".h5":
            sys.exit("%s: no sidecar %s beside it; write one with: radiosity xdmf %s"
                     % (path, xmf, path))
        sys.exit("%s: no such file" % xmf)
    return os.path.abspath(xmf)


def exposure_scale(data, exposure_stops):
    """The factor that shows the 97th percentile of the patches' luminance, area-weighted, at
    0.85, times 2^stops: the renderer's automatic exposure, over the surfaces rather than the
    pixels (hidden patches apart)."""
    cells = data.CellData
    b = numpy.asarray(cells[array_named(cells.keys(), "radiosity")], dtype=float)
    b = b.reshape(len(b), -1)  # [n, 3], or [n, 1] for a thermal run's one channel
    y = b[:, 0] if b.shape[1] == 1 else b[:, :3] @ numpy.array(LUMINANCE_WEIGHTS)
    area = numpy.asarray(cells[array_named(cells.keys(), "area")], dtype=float)
    if "hidden" in cells.keys():
        keep = numpy.asarray(cells["hidden"]) == 0
        y, area = y[keep], area[keep]
    reference = 0.0
    if len(y) and area.sum() > 0:
        order = numpy.argsort(y)
        below = numpy.cumsum(area[order]) / area.sum()
        at = builtins.min(numpy.searchsorted(below, EXPOSURE_PERCENTILE), len(y) - 1)
        reference = y[order][at]
    if not reference > 0 and len(y):
        reference = y.max()  # a mostly black scene: expose for its brightest patch
    scale = EXPOSURE_TARGET / reference if reference > 0 else 1.0
    return scale * 2.0 ** exposure_stops


# Run by ProgrammableFilter on ParaView's side: the displayed colour, sRGB of min(B·scale, 1), one
# channel shown grey. NAME, ASSOCIATION and SCALE are filled in.
COLOUR_SCRIPT = """
import numpy
attributes = inputs[0].%(association)s
b = numpy.asarray(attributes[%(name)r], dtype=float).reshape(len(attributes[%(name)r]), -1)
if b.shape[1] == 1:
    b = numpy.repeat(b, 3, axis=1)
x = numpy.clip(b[:, :3] * %(scale).17g, 0.0, 1.0)
shown = numpy.where(x <= 0.0031308, 12.92 * x, 1.055 * x ** (1 / 2.4) - 0.055)
output.%(association)s.append(shown, "colour_as_rendered")
"""


def show_as_rendered(source, view, exposure_stops=0.0):
    """Shows `source` (an opened result) in `view` coloured by B as the renderer shows it: the
    smooth radiosity where the result has it (else B per patch), exposed and sRGB-encoded, with
    MapScalars off (the values are the colours), no shading, back faces culled. Returns the
    filter that computes the colours."""
    data = dsa.WrapDataObject(servermanager.Fetch(source))
    smooth = array_named(data.PointData.keys(), "radiosity_smooth")
    name = smooth or array_named(data.CellData.keys(), "radiosity")
    if name is None:
        raise RuntimeError("no radiosity in the data: not a result's sidecar")
    association = "PointData" if smooth else "CellData"
    colours = ProgrammableFilter(Input=source)
    colours.Script = COLOUR_SCRIPT % {"association": association, "name": name,
                                      "scale": exposure_scale(data, exposure_stops)}
    view.OrientationAxesVisibility = 0
    view.UseColorPaletteForBackground = 0
    view.Background = [0, 0, 0]
    display = Show(colours, view)
    ColorBy(display, ("POINTS" if smooth else "CELLS", "colour_as_rendered"))
    display.MapScalars = 0  # the values are the colours
    display.SetScalarBarVisibility(view, False)
    display.Ambient, display.Diffuse, display.Specular = 1.0, 0.0, 0.0  # B is light: no shading
    display.BackfaceRepresentation = "Cull Backface"  # see-through back faces, as the renderer
    return colours


def place_camera(view, bounds, aspect, fov=40.0, eye=None, look_at=None, up=(0.0, 1.0, 0.0)):
    """The renderer's camera (render/camera.cpp): looking at `look_at` (the centre of `bounds`,
    ParaView's (x0, x1, y0, y1, z0, z1)) from `eye`, by default from −z along +z, just far
    enough back that every corner of the bounds fits the vertical field of view `fov` (degrees)
    and its horizontal counterpart for width/height `aspect`, with a 5 % margin. (paraview.simple's
    first Render() resets the camera: call paraview.simple._DisableFirstRenderCameraReset()
    before it, as ParaView's traces do, or save with SaveScreenshot alone.)"""
    lo = numpy.array(bounds[0::2], dtype=float)
    hi = numpy.array(bounds[1::2], dtype=float)
    target = numpy.array(look_at, dtype=float) if look_at is not None else 0.5 * (lo + hi)
    if eye is None:
        forward = numpy.array([0.0, 0.0, 1.0])
        right = numpy.cross(forward, up)
        right /= numpy.linalg.norm(right)
        camera_up = numpy.cross(right, forward)
        tan_half = math.tan(math.radians(fov) / 2)
        distance = 0.0
        for corner in range(8):
            p = numpy.where([corner & 1, corner & 2, corner & 4], hi, lo)
            q = p - target
            x, y, z = builtins.abs(q @ right), builtins.abs(q @ camera_up), q @ forward
            distance = builtins.max(distance, FIT_MARGIN * y / tan_half - z,
                                    FIT_MARGIN * x / (tan_half * aspect) - z)
        distance = builtins.max(distance, 1e-3 * numpy.linalg.norm(hi - lo))
        if not distance > 0:
            distance = 1.0
        eye = target - distance * forward
    view.CameraPosition = list(map(float, eye))
    view.CameraFocalPoint = list(map(float, target))
    view.CameraViewUp = list(map(float, up))
    view.CameraViewAngle = fov  # vertical, as the renderer's


def three_numbers(text):
    values = [float(v) for v in text.split(",")]
    if len(values) != 3 or not builtins.all(math.isfinite(v) for v in values):
        raise argparse.ArgumentTypeError("expected x,y,z, got %r" % text)
    return values


def main(argv):
    parser = argparse.ArgumentParser(
        prog="paraview_picture.py",
        description="A radiosity result in ParaView as `radiosity render` shows it, saved as PNG.")
    parser.add_argument("result", help="RESULT.xmf, or RESULT.h5 with its RESULT.xmf beside it")
    parser.add_argument("picture", help="the PNG to write")
    parser.add_argument("--width", type=int, default=512)
    parser.add_argument("--height", type=int, default=512)
    parser.add_argument("--exposure", type=float, default=0.0,
                        help="stops added to the automatic exposure")
    parser.add_argument("--eye", type=three_numbers)
    parser.add_argument("--look-at", type=three_numbers)
    parser.add_argument("--up", type=three_numbers, default=[0.0, 1.0, 0.0])
    parser.add_argument("--fov", type=float, default=40.0, help="vertical field of view, degrees")
    args = parser.parse_args(argv)
    if not (0 < args.width <= 16384 and 0 < args.height <= 16384):
        parser.error("--width and --height must be in 1..16384")
    if not 0 < args.fov < 180:
        parser.error("--fov must be in (0, 180) degrees")

    paraview.simple._DisableFirstRenderCameraReset()  # (as ParaView's traces do) our camera stays
    reader = Xdmf3ReaderS(FileName=[sidecar_of(args.result)])
    reader.UpdatePipeline()
    view = CreateView("RenderView")
    view.ViewSize = [args.width, args.height]
    show_as_rendered(reader, view, args.exposure)
    place_camera(view, reader.GetDataInformation().GetBounds(), args.width / args.height,
                 args.fov, args.eye, args.look_at, args.up)
    Render(view)
    SaveScreenshot(args.picture, view, ImageResolution=[args.width, args.height])
    print("wrote " + args.picture)


if __name__ == "__main__":
    main(sys.argv[1:])
