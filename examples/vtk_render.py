#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Render one frame of `tumble export` with VTK's Python (no ParaView needed), as ParaView's
Glyph filter would: a sphere of the particle's radius at each point, coloured by body, the
ground square and, with --walls, the walls see-through. docs/export.md; Debian: apt-get install
python3-vtk9 (an X display or Xvfb: xvfb-run -a python3 examples/vtk_render.py …).

usage: vtk_render.py FRAME.vtp [GROUND.vtp] [--walls WALLS.vtp] -o OUT.png [--size 1200x800]
"""
import argparse

from vtkmodules.vtkCommonColor import vtkNamedColors
from vtkmodules.vtkFiltersCore import vtkGlyph3D
from vtkmodules.vtkFiltersSources import vtkSphereSource
from vtkmodules.vtkIOImage import vtkPNGWriter
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
from vtkmodules.vtkRenderingCore import (vtkActor, vtkPolyDataMapper, vtkRenderer, vtkRenderWindow,
                                         vtkWindowToImageFilter)
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401  (the OpenGL back end)

ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
ap.add_argument("frame")
ap.add_argument("ground", nargs="?")
ap.add_argument("--walls", help="the frame's walls (NAME_walls.vtp or NAME_walls_K.vtp), drawn see-through")
ap.add_argument("-o", "--output", required=True)
ap.add_argument("--size", default="1200x800")
a = ap.parse_args()
w, h = (int(v) for v in a.size.split("x"))


def read(path):
    r = vtkXMLPolyDataReader()
    r.SetFileName(path)
    r.Update()
    return r.GetOutput()


frame = read(a.frame)
frame.GetPointData().SetActiveScalars("radius")
sphere = vtkSphereSource()
sphere.SetRadius(1.0)
sphere.SetThetaResolution(16)
sphere.SetPhiResolution(12)
glyph = vtkGlyph3D()
glyph.SetInputData(frame)
glyph.SetSourceConnection(sphere.GetOutputPort())
glyph.SetScaleModeToScaleByScalar()  # radius
glyph.SetColorModeToColorByScalar()
glyph.SetScaleFactor(1.0)
glyph.Update()
glyphs = glyph.GetOutput()
# Colour by body: the glyphs copy the point data, so map "body" through a lookup table.
glyphs.GetPointData().SetActiveScalars("body")
mapper = vtkPolyDataMapper()
mapper.SetInputData(glyphs)
mapper.SetScalarModeToUsePointFieldData()
mapper.SelectColorArray("body")
nbody = frame.GetPointData().GetArray("body").GetRange()
mapper.SetScalarRange(nbody)
lut = mapper.GetLookupTable()
lut.SetHueRange(0.0, 0.9)
lut.SetNumberOfTableValues(64)
lut.Build()
actor = vtkActor()
actor.SetMapper(mapper)

ren = vtkRenderer()
ren.AddActor(actor)
colors = vtkNamedColors()
if a.ground:
    gm = vtkPolyDataMapper()
    gm.SetInputData(read(a.ground))
    ga = vtkActor()
    ga.SetMapper(gm)
    ga.GetProperty().SetColor(colors.GetColor3d("LightGrey"))
    ren.AddActor(ga)
if a.walls:
    wm = vtkPolyDataMapper()
    wm.SetInputData(read(a.walls))
    wm.ScalarVisibilityOff()
    wa = vtkActor()
    wa.SetMapper(wm)
    wa.GetProperty().SetColor(colors.GetColor3d("SteelBlue"))
    wa.GetProperty().SetOpacity(0.25)
    ren.AddActor(wa)
ren.SetBackground(colors.GetColor3d("White"))
# From the side and above: the camera looks at the particles' centre from the -y side.
x0, x1, y0, y1, z0, z1 = frame.GetBounds()
c = ((x0 + x1) / 2, (y0 + y1) / 2, (z0 + z1) / 2)
d = max(x1 - x0, y1 - y0, z1 - z0)
cam = ren.GetActiveCamera()
cam.SetFocalPoint(*c)
cam.SetPosition(c[0] + 0.7 * d, c[1] - 1.3 * d, c[2] + 0.9 * d)
cam.SetViewUp(0, 0, 1)
ren.ResetCameraClippingRange()

win = vtkRenderWindow()
win.SetOffScreenRendering(1)
win.AddRenderer(ren)
win.SetSize(w, h)
win.Render()
grab = vtkWindowToImageFilter()
grab.SetInput(win)
grab.Update()
png = vtkPNGWriter()
png.SetFileName(a.output)
png.SetInputConnection(grab.GetOutputPort())
png.Write()
print(f"vtk_render: {frame.GetNumberOfPoints()} particles to {a.output}")
