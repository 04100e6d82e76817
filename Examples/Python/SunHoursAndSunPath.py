#!/usr/bin/python3
"""Monthly hours of direct sun in a valley, and a plot of the sun's path.

Pipeline: vtkTerroirDEMReader -> vtkExtractVOI (the Sagehen Creek valley, 256 x 256 cells) ->
vtkTerroirSolarIllumination (monthly mode: the 15th of every month, 10-minute steps, cast
shadows from the terrain). Prints each month's mean, minimum and maximum hours of sun and
mean clear-sky insolation, writes a map of the December sun hours and plots the sun's
elevation against its azimuth for three days with VTK's charts (vtkChartXY).

Run under an X display (or xvfb-run -a):
  PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 \
      Examples/Python/SunHoursAndSunPath.py --data Data --out example-output
The crop keeps the run short (about a second). For the whole DEM drop the vtkExtractVOI stage
(about 1.5 s more per run on two cores); shadows cast from outside a crop are not seen.
"""
import argparse
import os
import sys

from vtkmodules.numpy_interface import algorithms as algs
from vtkmodules.numpy_interface import dataset_adapter as dsa
from vtkmodules.vtkChartsCore import vtkAxis, vtkChart, vtkChartXY
from vtkmodules.vtkCommonCore import vtkFloatArray
from vtkmodules.vtkCommonDataModel import vtkTable
from vtkmodules.vtkImagingCore import vtkExtractVOI
from vtkmodules.vtkIOImage import vtkPNGWriter
from vtkmodules.vtkRenderingCore import vtkWindowToImageFilter
from vtkmodules.vtkViewsContext2D import vtkContextView
import vtkmodules.vtkRenderingContextOpenGL2  # noqa: F401 (the charts' OpenGL back end)

import terroir

repository_data = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "Data")
parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--data", default=os.environ.get("TERROIR_DATA_DIR", repository_data),
                    help="bundled data folder (default: $TERROIR_DATA_DIR, else Data/)")
parser.add_argument("--out", default="example-output", help="folder for the PNGs")
args = parser.parse_args()
os.makedirs(args.out, exist_ok=True)
if not os.environ.get("DISPLAY"):
    # VTK 9.1 aborts the process when a window cannot reach an X display: check first.
    sys.exit("SunHoursAndSunPath: no X display (DISPLAY unset); run under xvfb-run -a")

reader = terroir.vtkTerroirDEMReader()
reader.SetFileName(os.path.join(args.data, "sagehen_creek_ca", "sagehen_dem_utm11n_10m.tif"))

# The valley of Sagehen Creek: columns 330..585, rows 230..485 (row 0 is the south edge).
valley = vtkExtractVOI()
valley.SetInputConnection(reader.GetOutputPort())
valley.SetVOI(330, 585, 230, 485, 0, 0)

sun = terroir.vtkTerroirSolarIllumination()
sun.SetInputConnection(valley.GetOutputPort())
sun.SetModeToMonthly()  # IlluminationHours and Insolation, 12 components (Jan..Dec)
sun.SetYear(2025)
sun.SetMonthlyDay(15)
sun.SetTimeStep(10.0)  # minutes
sun.Update()
terrain = sun.GetOutput()
if terrain.GetNumberOfPoints() == 0:
    sys.exit("SunHoursAndSunPath: the illumination stage failed (see the error above)")

points = dsa.WrapDataObject(terrain).PointData
hours = points["IlluminationHours"]  # shape (cells, 12)
insolation = points["Insolation"]  # Wh/m2 per day
frame = terrain.GetFieldData().GetArray("SolarFrame")  # latitude, longitude, grid north
print(f"valley: {terrain.GetDimensions()[0]} x {terrain.GetDimensions()[1]} cells, "
      f"latitude {frame.GetComponent(0, 0):.4f}, longitude {frame.GetComponent(0, 1):.4f}")
print("month  mean_h  min_h  max_h  insolation_kWh/m2")
months = ["Jan", "Feb", "Mar", "Apr", "May", "Jun", "Jul", "Aug", "Sep", "Oct", "Nov", "Dec"]
for m, name in enumerate(months):
    print(f"{name}    {algs.mean(hours[:, m]):6.3f} {algs.min(hours[:, m]):6.3f} "
          f"{algs.max(hours[:, m]):6.3f}  {algs.mean(insolation[:, m]) / 1000.0:6.3f}")

# Map of the December hours of sun on a fixed 0-10 h scale.
view = terroir.vtkTerroirOverlayView()
view.SetInputData(terrain)
view.SetArrayName("IlluminationHours")
view.SetArrayComponent(11)
view.SetUseCustomRange(True)
view.SetRange(0.0, 10.0)
view.SetTitle("Hours of sun, 15 December")
view.SetWidth(400)
view.SetHeight(400)
if not view.WritePNG(os.path.join(args.out, "sun_hours_december.png")):
    sys.exit(f"SunHoursAndSunPath: {view.GetLastError()}")
print("wrote sun_hours_december.png")

# The sun's path: field data SunPositions holds one tuple per time step (Month, Day, UTCHours,
# Azimuth, Elevation, GridAzimuth), azimuth clockwise from true north, degrees.
positions = terrain.GetFieldData().GetArray("SunPositions")
chart = vtkChartXY()
chart.SetShowLegend(True)
for axis, title, low, high in ((vtkAxis.LEFT, "Sun elevation (degrees)", 0.0, 80.0),
                               (vtkAxis.BOTTOM, "Azimuth from north (degrees)", 45.0, 315.0)):
    chart.GetAxis(axis).SetTitle(title)
    chart.GetAxis(axis).SetRange(low, high)
    chart.GetAxis(axis).SetBehavior(vtkAxis.FIXED)  # keep these ranges
colours = {6: (220, 50, 32), 3: (0, 114, 178), 12: (90, 90, 90)}
for month, label in ((6, "15 June"), (3, "15 March"), (12, "15 December")):
    table = vtkTable()
    azimuth = vtkFloatArray()
    azimuth.SetName("Azimuth")
    elevation = vtkFloatArray()
    elevation.SetName(label)
    for t in range(positions.GetNumberOfTuples()):
        if positions.GetComponent(t, 0) == month and positions.GetComponent(t, 4) > 0.0:
            azimuth.InsertNextValue(positions.GetComponent(t, 3))
            elevation.InsertNextValue(positions.GetComponent(t, 4))
    table.AddColumn(azimuth)
    table.AddColumn(elevation)
    print(f"sun path {label}: {azimuth.GetNumberOfTuples()} steps above the horizon, "
          f"highest {elevation.GetRange()[1]:.3f} deg")
    line = chart.AddPlot(vtkChart.LINE)
    line.SetInputData(table, 0, 1)
    line.SetColor(*colours[month], 255)
    line.SetWidth(2.0)

chartView = vtkContextView()
chartView.GetScene().AddItem(chart)
chartView.GetRenderer().SetBackground(1.0, 1.0, 1.0)
window = chartView.GetRenderWindow()
window.SetSize(480, 360)
window.SetMultiSamples(0)
window.OffScreenRenderingOn()
window.Render()
grab = vtkWindowToImageFilter()
grab.SetInput(window)
grab.ReadFrontBufferOff()
png = vtkPNGWriter()
png.SetInputConnection(grab.GetOutputPort())
png.SetFileName(os.path.join(args.out, "sun_path.png"))
png.Write()
if png.GetErrorCode():
    sys.exit(f"SunHoursAndSunPath: cannot write {args.out}/sun_path.png")
print("wrote sun_path.png")
