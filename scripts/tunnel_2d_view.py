"""ParaView state for a 2D `demfem tunnel` run: the view of the README picture
(scripts/plot_tunnel_2d.py) as a live ParaView pipeline.

- the continuum coloured by the major principal stress sigma_1 in MPa
  (compression positive, from stress_xx, stress_yy, stress_xy; the layer
  under the grains clipped away), its scale between the 1st and 99th
  percentiles of the cells around the tunnel, rounded out to 5 MPa;
- the grains as disks of their radius, coloured by the displacement the
  excavation caused in mm (this frame minus the frame that ends the in-situ
  phase, grains matched by id; the total displacement when that frame is
  missing), the scale clipped at the 98th percentile of the grains outside
  the opening so that a grain that fell into it does not wash it out;
- cracks red (tensile) and blue (shear), the tunnel outline and the region
  boundary; two colour bars; the last time step.

Use it
  in the ParaView GUI:  DEMFEM_OUTPUT=out/tunnel_2d paraview --script=scripts/tunnel_2d_view.py
                        (or File > Load State... > this file, from the directory
                        that holds out/tunnel_2d; the time slider moves every frame)
  headless, to a PNG:   xvfb-run -a pvbatch scripts/tunnel_2d_view.py OUTPUT_DIR [FILE.png]
                        (FILE.png defaults to OUTPUT_DIR/tunnel_2d_paraview.png)

OUTPUT_DIR is the run's `Problem/output directory`: it reads continuum.pvd,
particles.pvd, cracks.pvd, summary.json and manifest.json. Written for
ParaView 5.11 (Debian 12); docs/tunnel.md, "ParaView".
"""
import json
import math
import os
import sys

from paraview.simple import (Calculator, Clip, ColorBy, Disk, GetActiveViewOrCreate,
                             GetAnimationScene, GetColorTransferFunction, GetScalarBar,
                             Glyph, PVDReader, ProgrammableFilter, Render, SaveScreenshot,
                             Show, servermanager)
from vtkmodules.numpy_interface import dataset_adapter as dsa

BATCH = __name__ == "__main__" and len(sys.argv) > 1
OUT = sys.argv[1] if BATCH else os.environ.get("DEMFEM_OUTPUT", "out/tunnel_2d")


def fail(msg):
    raise SystemExit("tunnel_2d_view.py: " + msg)


def load_json(name):
    path = os.path.join(OUT, name)
    if not os.path.isfile(path):
        fail(f"no {path} (is {OUT} the output directory of a demfem tunnel run?)")
    with open(path) as f:
        return json.load(f)


def percentile(values, q):
    """q-th percentile, linearly interpolated (as scripts/plot_tunnel_2d.py)."""
    values = sorted(values)
    if not values:
        return 0.0
    pos = q / 100.0 * (len(values) - 1)
    i = min(int(pos), len(values) - 2) if len(values) > 1 else 0
    if len(values) == 1:
        return values[0]
    return values[i] + (pos - i) * (values[i + 1] - values[i])


summary = load_json("summary.json")
params = load_json("manifest.json").get("parameters", {})
a = float(params.get("Tunnel", {}).get("radius", "nan"))
if not a > 0:
    fail("manifest.json has no Tunnel/radius")
region = summary.get("dem_region_radius") or float(
    params.get("DEM region", {}).get("radius", "nan"))
window_half = max(4.5 * a, (region if region > 0 else 0) + a)
t_insitu = next((ph.get("time_end_s") for ph in summary.get("phases", [])
                 if ph.get("name") == "in-situ"), None)
for name in ("continuum.pvd", "particles.pvd", "cracks.pvd"):
    if not os.path.isfile(os.path.join(OUT, name)):
        fail(f"no {os.path.join(OUT, name)}: run with Output/interval > 0")

continuum = PVDReader(registrationName="continuum", FileName=os.path.join(OUT, "continuum.pvd"))
particles = PVDReader(registrationName="particles", FileName=os.path.join(OUT, "particles.pvd"))
cracks = PVDReader(registrationName="cracks", FileName=os.path.join(OUT, "cracks.pvd"))

scene = GetAnimationScene()
scene.UpdateAnimationUsingDataTimeSteps()
times = list(particles.TimestepValues) if particles.TimestepValues else [0.0]
scene.AnimationTime = times[-1]

# sigma_1, compression positive: -(mean) + radius of Mohr's circle, in MPa.
sigma1 = Calculator(registrationName="sigma_1", Input=continuum)
sigma1.ResultArrayName = "sigma_1_MPa"
sigma1.Function = ("(-(stress_xx+stress_yy)/2+sqrt(((stress_xx-stress_yy)/2)^2"
                   "+stress_xy^2))/1e6")
rock = sigma1
if region > 0:
    # The overlap layer under the grains is not the rock's answer: hidden.
    rock = Clip(registrationName="outside the region", Input=sigma1)
    rock.ClipType = "Cylinder"
    rock.ClipType.Axis = [0, 0, 1]
    rock.ClipType.Radius = region
    rock.Crinkleclip = 0  # cut at the region radius, where the grains end
    rock.Invert = 0

# Excavation displacement: this frame minus the in-situ phase's last frame,
# matched by grain id (grains in the opening are removed in between).
excavation = ProgrammableFilter(registrationName="excavation displacement",
                                Input=particles)
excavation.Script = f"""
import numpy as np
from vtkmodules.numpy_interface import dataset_adapter as dsa
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
import xml.etree.ElementTree as ET, os
out = self.GetOutput()
out.ShallowCopy(self.GetInput())
pd = dsa.WrapDataObject(out)
u = np.array(pd.PointData['displacement'])
ref_time = {t_insitu!r}
ref_file = None
if ref_time is not None:
    for ds in ET.parse({os.path.join(OUT, 'particles.pvd')!r}).getroot().iter('DataSet'):
        t = float(ds.get('timestep'))
        if abs(t - ref_time) <= 1e-9 * abs(ref_time):
            ref_file = os.path.join({OUT!r}, ds.get('file'))
            break
if ref_file is not None:
    r = vtkXMLPolyDataReader(); r.SetFileName(ref_file); r.Update()
    ref = dsa.WrapDataObject(r.GetOutput())
    ref_id = np.array(ref.PointData['id']).astype(np.int64)
    order = np.argsort(ref_id)
    ids = np.array(pd.PointData['id']).astype(np.int64)
    k = np.clip(np.searchsorted(ref_id[order], ids), 0, len(order) - 1)
    found = ref_id[order][k] == ids
    u = u - np.where(found[:, None], np.array(ref.PointData['displacement'])[order][k], 0.0)
pd.PointData.append(1e3 * u, 'excavation_displacement_mm')
"""
grains = Glyph(registrationName="grains", Input=excavation, GlyphType="Sphere")
grains.ScaleArray = ["POINTS", "radius"]
grains.ScaleFactor = 2.0  # the sphere source has diameter 1
grains.GlyphMode = "All Points"
grains.GlyphType.ThetaResolution = 24
grains.GlyphType.PhiResolution = 12

tunnel = Disk(registrationName="tunnel outline", InnerRadius=0.99 * a, OuterRadius=a,
              CircumferentialResolution=256)
boundary = Disk(registrationName="region boundary", InnerRadius=region - 0.005 * a,
                OuterRadius=region, CircumferentialResolution=256) if region > 0 else None

view = GetActiveViewOrCreate("RenderView")
view.OrientationAxesVisibility = 0
view.ViewSize = [1000, 1100]  # fonts are sized for this; the screenshot keeps it
view.Background = [1, 1, 1]
try:
    view.UseColorPaletteForBackground = 0
except AttributeError:
    pass

# Colour scales from this frame's data, as the SVG's.
rock.UpdatePipeline(times[-1])
excavation.UpdatePipeline(times[-1])
rock_data = dsa.WrapDataObject(servermanager.Fetch(rock))
s1 = [float(v) for v, p in zip(rock_data.PointData["sigma_1_MPa"], rock_data.Points)
      if abs(float(p[0])) <= window_half and abs(float(p[1])) <= window_half]
lo = 5 * math.floor(percentile(s1, 1) / 5)
hi = 5 * math.ceil(percentile(s1, 99) / 5)
hi = hi if hi > lo else lo + 5
grain_data = dsa.WrapDataObject(servermanager.Fetch(excavation))
pts = grain_data.Points
umag = [math.sqrt(float(x) ** 2 + float(y) ** 2 + float(z) ** 2)
        for (x, y, z) in grain_data.PointData["excavation_displacement_mm"]]
outside = [m for m, p in zip(umag, pts) if math.hypot(float(p[0]), float(p[1])) >= a]
umax = percentile(outside, 98) or max(umag + [1e-12])


def colour_bar(display, lut, title, x):
    """A horizontal colour bar of lut at x (fraction of the view's width)."""
    display.SetScalarBarVisibility(view, True)
    bar = GetScalarBar(lut, view)
    bar.Title, bar.ComponentTitle = title, ""
    bar.TitleColor = bar.LabelColor = [0, 0, 0]
    bar.WindowLocation, bar.Orientation = "Any Location", "Horizontal"
    bar.Position, bar.ScalarBarLength, bar.ScalarBarThickness = [x, 0.03], 0.4, 14
    bar.TitleFontSize, bar.LabelFontSize = 16, 14
    bar.RangeLabelFormat = "%-#.3g"


def fixed_scale(name, preset, lo, hi, invert=False):
    """The colour map of array name, preset colours, fixed range [lo, hi]."""
    lut = GetColorTransferFunction(name)
    lut.ApplyPreset(preset, True)
    if invert:
        lut.InvertTransferFunction()
    lut.RescaleTransferFunction(lo, hi)
    lut.AutomaticRescaleRangeMode = "Never"
    return lut


rock_display = Show(rock, view)
ColorBy(rock_display, ("POINTS", "sigma_1_MPa"))
colour_bar(rock_display, fixed_scale("sigma_1_MPa", "Viridis (matplotlib)", lo, hi),
           "continuum sigma_1 [MPa], compression +", 0.05)

grain_display = Show(grains, view)
grain_display.Ambient, grain_display.Diffuse = 1.0, 0.0  # flat disks, as in the plane
ColorBy(grain_display, ("POINTS", "excavation_displacement_mm", "Magnitude"))
u_lut = fixed_scale("excavation_displacement_mm", "Grayscale", 0.0, umax, invert=True)
u_lut.VectorMode = "Magnitude"
colour_bar(grain_display, u_lut, "grain displacement by the excavation [mm]", 0.55)

crack_display = Show(cracks, view)
ColorBy(crack_display, ("CELLS", "mode"))
mode_lut = GetColorTransferFunction("mode")
mode_lut.InterpretValuesAsCategories = 1
mode_lut.Annotations = ["0", "tensile", "1", "shear"]
mode_lut.IndexedColors = [0.84, 0.15, 0.16, 0.12, 0.31, 0.84]
crack_display.LineWidth = 3.0
crack_display.SetScalarBarVisibility(view, False)
# Cracks and outlines above the disks (the disks' top is at z = max radius).
crack_display.Position = [0, 0, 1.0]

for outline in [tunnel] + ([boundary] if boundary else []):
    d = Show(outline, view)
    d.ColorArrayName = ["POINTS", ""]
    d.AmbientColor = d.DiffuseColor = [0, 0, 0]
    d.Position = [0, 0, 1.0]

Render(view)  # the first render resets the camera: set it afterwards
view.InteractionMode = "2D"
view.CameraPosition = [0, 0, 100]
view.CameraFocalPoint = [0, 0, 0]
view.CameraViewUp = [0, 1, 0]
view.CameraParallelProjection = 1
view.CameraParallelScale = 1.1 * window_half
Render(view)

if BATCH:
    png = sys.argv[2] if len(sys.argv) > 2 else os.path.join(OUT, "tunnel_2d_paraview.png")
    SaveScreenshot(png, view, ImageResolution=[1000, 1100])
    print(f"tunnel_2d_view.py: wrote {png} (sigma_1 {lo:g} .. {hi:g} MPa, "
          f"displacement 0 .. {umax:.3g} mm, {len(umag)} grains)")
