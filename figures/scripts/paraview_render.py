"""Renders the last frame of a dem2d run's VTK output with ParaView: grains as their true
outlines (light grey, with their rims), contacts as lines between the centroids coloured by the
normal contact force (force chains, over the full range of forces), walls in black; a colour bar; white background. Above it,
the whole pile; below, a close-up of its middle at the bottom (a sixth of the width).

    xvfb-run -a pvpython figures/scripts/paraview_render.py RUN_DIR OUT.png

RUN_DIR holds run.pvd (from `dem2d run CASE --vtk`). Needs ParaView (Debian: paraview; 5.11
here) and, without a display, a virtual one (Debian: xvfb, for xvfb-run). The user guide's picture
(docs/src/tutorials/paraview.md) is made by the commands in that tutorial.
"""

import sys
import xml.etree.ElementTree as ET
from os.path import join

from paraview.simple import (AssignViewToLayout, ColorBy, CreateLayout, CreateRenderView,
                             GetAnimationScene, GetColorTransferFunction, GetScalarBar,
                             GetTimeKeeper, PVDReader, SaveScreenshot, Show, Threshold)

run, out = sys.argv[1], sys.argv[2]
pvd = join(run, "run.pvd")
last_time = float(ET.parse(pvd).getroot().findall("./Collection/DataSet")[-1].get("timestep"))
reader = PVDReader(FileName=pvd)
scene = GetAnimationScene()
scene.UpdateAnimationUsingDataTimeSteps()
scene.AnimationTime = last_time
GetTimeKeeper().Time = last_time
reader.UpdatePipeline(last_time)


def kind(k):
    return Threshold(Input=reader, Scalars=["CELLS", "kind"], LowerThreshold=k - 0.5,
                     UpperThreshold=k + 0.5, ThresholdMethod="Between")


bodies, contacts, walls = kind(0), kind(1), kind(2)
for f in (bodies, contacts, walls):
    f.UpdatePipeline(last_time)
fn = contacts.CellData["normal_force"].GetRange()
bounds = bodies.GetDataInformation().GetBounds()
(x0, x1, y0, y1) = bounds[:4]

force = GetColorTransferFunction("normal_force")
force.ApplyPreset("Turbo", True)


def view(size, centre, half_height):
    v = CreateRenderView()
    v.ViewTime = last_time
    v.ViewSize = size
    v.Background = [1, 1, 1]
    v.OrientationAxesVisibility = 0
    v.CameraParallelProjection = 1
    v.UseColorPaletteForBackground = 0
    b = Show(bodies, v)
    b.SetRepresentationType("Surface With Edges")
    ColorBy(b, None)
    b.DiffuseColor = b.AmbientColor = [0.88, 0.88, 0.88]
    b.EdgeColor = [0.45, 0.45, 0.45]
    c = Show(contacts, v)
    ColorBy(c, ("CELLS", "normal_force"))
    c.LineWidth = 2
    w = Show(walls, v)
    ColorBy(w, None)
    w.DiffuseColor = w.AmbientColor = [0, 0, 0]
    w.LineWidth = 3
    v.CameraPosition = [centre[0], centre[1], 100]
    v.CameraFocalPoint = [centre[0], centre[1], 0]
    v.CameraViewUp = [0, 1, 0]
    v.CameraParallelScale = half_height
    return v, c


W = 1600
width, height = x1 - x0, y1 - y0
# The whole pile, with room above it for the colour bar.
view_h = max(1.5 * height, 1.5 * width * 160 / W)
top_h = int(W * view_h / (width * 1.04))
full, full_c = view([W, top_h], ((x0 + x1) / 2, y0 - 0.03 * height + view_h / 2), view_h / 2)
bar = GetScalarBar(force, full)
bar.Title = "normal contact force (dyn per cm of thickness)"
bar.ComponentTitle = ""
bar.TitleColor = bar.LabelColor = [0, 0, 0]
bar.TitleFontSize = 16
bar.LabelFontSize = 14
bar.Orientation = "Horizontal"
bar.WindowLocation = "Any Location"
bar.Position = [0.30, 0.72]
bar.ScalarBarLength = 0.4
bar.RangeLabelFormat = "%-#.3g"
full_c.SetScalarBarVisibility(full, True)
# A close-up: a sixth of the width, from the floor up, at the middle.
zw = width / 6
zoom_h = 600
half = zw * zoom_h / W / 2
zoom, _ = view([W, zoom_h], ((x0 + x1) / 2, y0 + half), half)

layout = CreateLayout("pile")
layout.SplitVertical(0, top_h / (top_h + zoom_h))
AssignViewToLayout(view=full, layout=layout, hint=1)
AssignViewToLayout(view=zoom, layout=layout, hint=2)
SaveScreenshot(out, layout, ImageResolution=[W, top_h + zoom_h], TransparentBackground=0)
print(f"{out}: t = {last_time} s, {bodies.GetDataInformation().GetNumberOfCells()} grains, "
      f"{contacts.GetDataInformation().GetNumberOfCells()} contacts, largest normal force {fn[1]:.4g}")
