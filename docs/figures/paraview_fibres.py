"""ParaView screenshot of a fibresim VTK series (issue 11): each fibre a
capped tube of radius D/2 around its VTK_LINE, coloured by speed, the box
as an outline, and beside it (right half) the same frame drawn by ParaView's
3D Glyphs from the quaternion, which must coincide with the tubes.

    xvfb-run -a pvbatch docs/figures/paraview_fibres.py OUT_DIR PNG [TIME]

OUT_DIR holds fibres.pvd and box.vtp (`fibresim run ... --vtk-every N`);
TIME (s) picks the frame nearest to it (default: the last).
"""
import sys

from paraview.simple import (CellCenters, CellDatatoPointData, Calculator, ColorBy, CreateView,
                             GetColorTransferFunction, Glyph, PVDReader, Render, SaveScreenshot, Show,
                             Tube, XMLPolyDataReader, AssignViewToLayout, CreateLayout)

out, png = sys.argv[1], sys.argv[2]
series = PVDReader(FileName=f"{out}/fibres.pvd")
times = list(series.TimestepValues) or [0.0]
t = times[-1] if len(sys.argv) < 4 else min(times, key=lambda x: abs(x - float(sys.argv[3])))

# Exact cylinders: radius = diameter / 2 as point data, then a capped tube.
radius = Calculator(Input=series, AttributeType="Cell Data", ResultArrayName="radius", Function="diameter/2")
points = CellDatatoPointData(Input=radius, PassCellData=1)
tubes = Tube(Input=points, Scalars=["POINTS", "radius"], VaryRadius="By Absolute Scalar", Capping=1,
             NumberofSides=32)
box = XMLPolyDataReader(FileName=[f"{out}/box.vtp"])

# The same fibres as 3D Glyphs at their centres, oriented by the quaternion
# [w, x, y, z]: a unit cylinder (axis y in VTK) turned onto body x and
# scaled to L x D x D before the quaternion rotates it.
centres = CellCenters(Input=series, VertexCells=1)


def view(width):
    v = CreateView("RenderView")
    v.ViewSize = [width, 700]
    v.OrientationAxesVisibility = 0
    v.Background = [1, 1, 1]
    v.UseColorPaletteForBackground = 0
    v.ViewTime = t
    v.CameraPosition = [1.3, -1.9, 1.1]
    v.CameraFocalPoint = [0.5, 0.5, 0.4]
    v.CameraViewUp = [0, 0, 1]
    v.CameraParallelProjection = 1
    v.CameraParallelScale = 0.62
    return v


layout = CreateLayout("fibres")
left = view(700)
AssignViewToLayout(view=left, layout=layout, hint=0)
d = Show(tubes, left)
ColorBy(d, ("CELLS", "speed"))
lut = GetColorTransferFunction("speed")
lut.ApplyPreset("Viridis (matplotlib)", True)
lut.RescaleTransferFunction(0.0, 5.0)
d.SetScalarBarVisibility(left, True)
bar = lut.GetScalarBar(left) if hasattr(lut, "GetScalarBar") else None
b = Show(box, left)
b.Representation = "Wireframe"
b.AmbientColor = b.DiffuseColor = [0.3, 0.3, 0.3]

layout.SplitHorizontal(0, 0.5)
right = view(700)
AssignViewToLayout(view=right, layout=layout, hint=2)
g = Show(centres, right)
g.SetRepresentationType("3D Glyphs")
g.GlyphType = "Cylinder"
g.GlyphType.Resolution = 32
g.Orient = 1
g.OrientationMode = "Quaternion"
g.SelectOrientationVectors = "quaternion"
g.Scaling = 0
g.GlyphTransform.Rotate = [0.0, 0.0, -90.0]
g.GlyphTransform.Scale = [0.01, 0.025, 0.01]  # test case 1's fibre: D across, L along the cylinder's y
ColorBy(g, ("POINTS", "speed"))
b2 = Show(box, right)
b2.Representation = "Wireframe"
b2.AmbientColor = b2.DiffuseColor = [0.3, 0.3, 0.3]
Render(left)
Render(right)
SaveScreenshot(png, layout, ImageResolution=[1400, 700])
print(f"{png}: t = {t} s of {len(times)} frames")
