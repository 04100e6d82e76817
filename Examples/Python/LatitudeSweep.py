#!/usr/bin/python3
"""A parameter sweep: the same valley moved from the equator to 60 degrees north.

Pipeline: vtkTerroirDEMReader -> vtkExtractVOI (200 x 200 cells) ->
vtkTerroirSolarIllumination (daily mode, 21 December), run once per latitude from 0 to 60
degrees in steps of 10 (the longitude stays the terrain's). Each step prints the mean hours of
direct sun and the mean clear-sky insolation and writes one map; the horizon map of the terrain
is computed once and reused by every step, since only the sun moves.

Run under an X display (or xvfb-run -a):
  PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 \
      Examples/Python/LatitudeSweep.py --data Data --out example-output
For a finer sweep pass --step 5 (or 1); for the whole DEM drop the vtkExtractVOI stage.
"""
import argparse
import os
import sys

from vtkmodules.numpy_interface import algorithms as algs
from vtkmodules.numpy_interface import dataset_adapter as dsa
from vtkmodules.vtkImagingCore import vtkExtractVOI

import terroir

repository_data = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "Data")
parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--data", default=os.environ.get("TERROIR_DATA_DIR", repository_data),
                    help="bundled data folder (default: $TERROIR_DATA_DIR, else Data/)")
parser.add_argument("--out", default="example-output", help="folder for the PNGs")
parser.add_argument("--step", type=int, default=10, help="latitude step, degrees (default 10)")
args = parser.parse_args()
os.makedirs(args.out, exist_ok=True)

reader = terroir.vtkTerroirDEMReader()
reader.SetFileName(os.path.join(args.data, "sagehen_creek_ca", "sagehen_dem_utm11n_10m.tif"))
crop = vtkExtractVOI()
crop.SetInputConnection(reader.GetOutputPort())
crop.SetVOI(380, 579, 250, 449, 0, 0)

sun = terroir.vtkTerroirSolarIllumination()
sun.SetInputConnection(crop.GetOutputPort())
sun.SetModeToDaily()
sun.SetYear(2025)
sun.SetMonth(12)
sun.SetDay(21)

view = terroir.vtkTerroirOverlayView()
view.SetArrayName("IlluminationHours")
view.SetUseCustomRange(True)
view.SetRange(0.0, 12.0)  # one scale for every step, so the pictures compare
view.SetWidth(300)
view.SetHeight(300)

print("latitude  mean_sun_h  mean_insolation_kWh/m2")
for latitude in range(0, 61, args.step):
    sun.SetLatitude(float(latitude))
    sun.Update()
    terrain = sun.GetOutput()
    if terrain.GetNumberOfPoints() == 0:
        sys.exit("LatitudeSweep: the illumination stage failed (see the error above)")
    points = dsa.WrapDataObject(terrain).PointData
    print(f"{latitude:8d}  {algs.mean(points['IlluminationHours']):10.4f}  "
          f"{algs.mean(points['Insolation']) / 1000.0:10.4f}")
    view.SetInputData(terrain)
    view.SetTitle(f"21 December, {latitude} N")
    name = f"sweep_lat{latitude:02d}.png"
    if not view.WritePNG(os.path.join(args.out, name)):
        sys.exit(f"LatitudeSweep: {view.GetLastError()}")
    print(f"wrote {name}")
