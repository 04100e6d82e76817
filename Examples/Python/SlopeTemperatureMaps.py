#!/usr/bin/python3
"""Slope and July temperature maps of a DEM, saved as PNG.

Pipeline: vtkTerroirDEMReader -> vtkTerroirSlope -> vtkTerroirTemperature, then two
vtkTerroirOverlayView pictures (a top-down slope map and a 3-D relief coloured by the July
temperature) and a few numbers on stdout.

Run (rendering needs an X display; on a machine without one, prefix xvfb-run -a):
  PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 \
      Examples/Python/SlopeTemperatureMaps.py --data Data --out example-output
Uses the whole bundled Sagehen Creek DEM (786 x 720 cells of 10 m); any DEM that GDAL reads
works: change the file name below.
"""
import argparse
import os
import sys

from vtkmodules.numpy_interface import algorithms as algs
from vtkmodules.numpy_interface import dataset_adapter as dsa

import terroir

repository_data = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "Data")
parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--data", default=os.environ.get("TERROIR_DATA_DIR", repository_data),
                    help="bundled data folder (default: $TERROIR_DATA_DIR, else Data/)")
parser.add_argument("--out", default="example-output", help="folder for the PNGs")
args = parser.parse_args()
os.makedirs(args.out, exist_ok=True)

# Read the DEM: elevation in metres, georeference in field data.
reader = terroir.vtkTerroirDEMReader()
reader.SetFileName(os.path.join(args.data, "sagehen_creek_ca", "sagehen_dem_utm11n_10m.tif"))

# Slope (degrees), aspect and normals, as `gdaldem slope` computes them.
slope = terroir.vtkTerroirSlope()
slope.SetInputConnection(reader.GetOutputPort())

# Monthly temperature: 2 degC in January and 20 degC in July at sea level, 6.4 degC/km cooler
# with height (the filter's defaults, spelled out here to show the knobs).
temperature = terroir.vtkTerroirTemperature()
temperature.SetInputConnection(slope.GetOutputPort())
temperature.SetSeaLevelTemperatureColdest(2.0)
temperature.SetSeaLevelTemperatureWarmest(20.0)
temperature.SetLapseRate(6.4)
temperature.Update()
terrain = temperature.GetOutput()
if terrain.GetNumberOfPoints() == 0:
    sys.exit("SlopeTemperatureMaps: the pipeline failed (see the error above)")
nx, ny, _ = terrain.GetDimensions()
points = dsa.WrapDataObject(terrain).PointData  # arrays as numpy views, no copy
july = points["Temperature"][:, 6]  # components are Jan..Dec
print(f"grid: {nx} x {ny} cells of {terrain.GetSpacing()[0]:.1f} m")
elevation = points["Elevation"]
print(f"elevation: min {algs.min(elevation):.2f} max {algs.max(elevation):.2f} m")
print(f"slope: mean {algs.mean(points['Slope']):.3f} max {algs.max(points['Slope']):.3f} deg")
print(f"july temperature: min {algs.min(july):.3f} mean {algs.mean(july):.3f} "
      f"max {algs.max(july):.3f} degC")


def save(array, component, mode, title, name):
    """One overlay picture, 400 x 400 pixels, legend on the right."""
    view = terroir.vtkTerroirOverlayView()
    view.SetInputData(terrain)
    view.SetArrayName(array)
    view.SetArrayComponent(component)
    view.SetMode(mode)
    view.SetTitle(title)
    view.SetWidth(400)
    view.SetHeight(400)
    path = os.path.join(args.out, name)
    if not view.WritePNG(path):
        sys.exit(f"SlopeTemperatureMaps: {view.GetLastError()}")
    print(f"wrote {name}")


save("Slope", 0, terroir.vtkTerroirOverlayView.Map, "Slope", "slope_map.png")
save("Temperature", 6, terroir.vtkTerroirOverlayView.Relief, "July temperature",
     "temperature_july_relief.png")
