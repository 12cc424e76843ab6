#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Render one frame of `tumble export` with VTK's Python (no ParaView needed), as ParaView's
Glyph filter would: a sphere of the particle's radius at each point, coloured by body, the
ground square and, with --walls, the walls see-through; with --contacts (tumble export --contacts)
the force chains: each contact a tube between the two centres, its radius by the normal force,
coloured by it in compression and purple in tension (cohesion), the spheres then faint.
docs/export.md; Debian: apt-get install python3-vtk9 (an X display or Xvfb: xvfb-run -a python3
examples/vtk_render.py …).

usage: vtk_render.py FRAME.vtp [GROUND.vtp] [--walls WALLS.vtp] [--contacts CONTACTS.vtp] [--view iso|side] -o OUT.png
                    [--size 1200x800]
"""
import argparse

from vtkmodules.vtkCommonColor import vtkNamedColors
from vtkmodules.vtkFiltersCore import vtkGlyph3D, vtkTubeFilter
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
ap.add_argument("--contacts", help="the frame's contacts (NAME_contacts_K.vtp of tumble export --contacts): force chains")
ap.add_argument("--view", choices=("iso", "side"), default="iso",
                help="iso: from the side and above (default); side: along +y, level (a slab, a column's wall)")
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
if a.contacts:
    # Tubes of radius up to a third of the mean particle radius, by the normal force (its square
    # root: the tube's cross-section grows with the force): contacts in compression coloured by
    # the force (blue weak, red strong), those in tension (fn < 0: cohesion) purple.
    chains = read(a.contacts)
    force = chains.GetCellData().GetArray("normal_magnitude")
    fmax = max(force.GetRange()[1], 1e-30) if force is not None else 1.0
    from vtkmodules.vtkCommonCore import vtkFloatArray
    from vtkmodules.vtkCommonDataModel import vtkDataObject
    from vtkmodules.vtkFiltersCore import vtkCellDataToPointData, vtkThreshold
    from vtkmodules.vtkFiltersGeometry import vtkGeometryFilter
    rmean = sum(frame.GetPointData().GetArray("radius").GetRange()) / 2

    def part(tension):
        """The contacts in tension (fn < 0) or in compression, as lines with the point scalar 'size'."""
        if chains.GetCellData().GetArray("fn") is None:  # (every contact drawn as compressed)
            if tension:
                return None
            lines = chains
        else:
            keep = vtkThreshold()
            keep.SetInputData(chains)
            keep.SetInputArrayToProcess(0, 0, 0, vtkDataObject.FIELD_ASSOCIATION_CELLS, "fn")
            if tension:
                keep.SetThresholdFunction(vtkThreshold.THRESHOLD_LOWER)
                keep.SetLowerThreshold(-1e-30)  # fn <= -1e-30
            else:
                keep.SetThresholdFunction(vtkThreshold.THRESHOLD_UPPER)
                keep.SetUpperThreshold(0.0)  # fn >= 0
            geometry = vtkGeometryFilter()
            geometry.SetInputConnection(keep.GetOutputPort())
            geometry.Update()
            lines = geometry.GetOutput()
        if lines.GetNumberOfCells() == 0:
            return None
        to_points = vtkCellDataToPointData()
        to_points.SetInputData(lines)
        to_points.Update()
        lines = to_points.GetOutput()
        root = vtkFloatArray()
        root.SetName("size")
        src = lines.GetPointData().GetArray("normal_magnitude")
        for k in range(lines.GetNumberOfPoints()):
            root.InsertNextValue((src.GetValue(k) / fmax) ** 0.5 if src is not None else 1.0)
        lines.GetPointData().AddArray(root)
        lines.GetPointData().SetActiveScalars("size")
        return lines

    for tension in (False, True):
        lines = part(tension)
        if lines is None:
            continue
        tube = vtkTubeFilter()
        tube.SetInputData(lines)
        tube.SetRadius(0.02 * rmean)
        tube.SetRadiusFactor(15.0)  # up to 0.3 of the radius
        tube.SetVaryRadiusToVaryRadiusByScalar()
        tube.SetNumberOfSides(8)
        tm = vtkPolyDataMapper()
        tm.SetInputConnection(tube.GetOutputPort())
        ta = vtkActor()
        ta.SetMapper(tm)
        if tension:
            tm.ScalarVisibilityOff()
            ta.GetProperty().SetColor(0.55, 0.1, 0.75)
        else:
            tm.SetScalarModeToUsePointFieldData()
            tm.SelectColorArray("size")
            tm.SetScalarRange(0.0, 1.0)
            tl = tm.GetLookupTable()
            tl.SetHueRange(0.66, 0.0)  # blue (weak) to red (strong)
            tl.Build()
        ren.AddActor(ta)
    actor.GetProperty().SetOpacity(0.12)
    mapper.ScalarVisibilityOff()
    actor.GetProperty().SetColor(0.6, 0.6, 0.6)
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
if a.view == "side":
    cam.SetPosition(c[0], c[1] - 2.2 * d, c[2])
else:
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
print(f"vtk_render: {frame.GetNumberOfPoints()} particles{' and their contacts' if a.contacts else ''} to {a.output}")
