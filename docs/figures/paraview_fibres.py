"""ParaView screenshot of a fibresim VTK series: each fibre a
capped tube of radius D/2 around its VTK_LINE, coloured by speed, the box
as an outline; beside it (right half) the same tubes, translucent, with an
arrow per fibre from ParaView's 3D Glyphs oriented by the `quaternion`
array (Orientation Mode: Quaternion, components w, x, y, z): the arrow
source points along x, the fibre axis in the body frame, so each arrow must
lie along its tube.

    xvfb-run -a pvbatch docs/figures/paraview_fibres.py OUT_DIR PNG [TIME]

OUT_DIR holds fibres.pvd and box.vtp (`fibresim run ... --vtk-every N`);
TIME (s) picks the frame nearest to it (default: the last).
"""
import sys

from paraview.simple import (CellCenters, CellDatatoPointData, Calculator, ColorBy, CreateView, GetScalarBar,
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

# Glyphs at the fibre centres, oriented by the quaternion [w, x, y, z].
centres = CellCenters(Input=series, VertexCells=1)


def view(width, focus, scale):
    v = CreateView("RenderView")
    v.ViewSize = [width, 700]
    v.OrientationAxesVisibility = 0
    v.Background = [1, 1, 1]
    v.UseColorPaletteForBackground = 0
    v.ViewTime = t
    v.CameraFocalPoint = focus
    v.CameraPosition = [focus[0] + 0.8, focus[1] - 2.4, focus[2] + 0.6]
    v.CameraViewUp = [0, 0, 1]
    v.CameraParallelProjection = 1
    v.CameraParallelScale = scale
    return v


layout = CreateLayout("fibres")
left = view(700, [0.5, 0.5, 0.45], 0.75)
AssignViewToLayout(view=left, layout=layout, hint=0)
d = Show(tubes, left)
ColorBy(d, ("CELLS", "speed"))
lut = GetColorTransferFunction("speed")
lut.ApplyPreset("Viridis (matplotlib)", True)
lut.RescaleTransferFunction(0.0, 5.0)
d.SetScalarBarVisibility(left, True)
bar = GetScalarBar(lut, left)
bar.Title = "speed"
bar.ComponentTitle = "(m/s)"
bar.TitleColor = bar.LabelColor = [0.1, 0.1, 0.1]
b = Show(box, left)
b.Representation = "Wireframe"
b.AmbientColor = b.DiffuseColor = [0.3, 0.3, 0.3]

layout.SplitHorizontal(0, 0.5)
# Right: closer, at the fibres' centroid (the 3D Glyphs view).
series.UpdatePipeline(t)
b0 = series.GetDataInformation().GetBounds()
right = view(700, [(b0[0] + b0[1]) / 2, (b0[2] + b0[3]) / 2, (b0[4] + b0[5]) / 2], 0.4)
AssignViewToLayout(view=right, layout=layout, hint=2)
t2 = Show(tubes, right)
ColorBy(t2, ("CELLS", "speed"))
t2.Opacity = 0.35
g = Show(centres, right)
g.SetRepresentationType("3D Glyphs")
g.GlyphType = "Arrow"
g.Orient = 1
g.OrientationMode = "Quaternion"
g.SelectOrientationVectors = "quaternion"
g.Scaling = 1
g.ScaleFactor = 0.03  # the arrow source is 1 long along x: 3 cm, a bit over L
g.AmbientColor = g.DiffuseColor = [0.85, 0.1, 0.1]
g.ColorArrayName = ["POINTS", ""]
b2 = Show(box, right)
b2.Representation = "Wireframe"
b2.AmbientColor = b2.DiffuseColor = [0.3, 0.3, 0.3]
Render(left)
Render(right)
SaveScreenshot(png, layout, ImageResolution=[1400, 700])
print(f"{png}: t = {t} s of {len(times)} frames")
