#!/usr/bin/python3
"""Terroir outputs as numpy arrays: area per slope class and July temperature per zone.

Pipeline: vtkTerroirDEMReader -> vtkTerroirSlope -> vtkTerroirTemperature -> vtkTerroirKMeans
(4 zones on slope and temperature), on the whole bundled DEM. Then
vtkmodules.numpy_interface.dataset_adapter (dsa) wraps the output: every point array is a numpy
array without a copy (a monthly array has the shape (cells, 12)), and numpy does the rest:
- the area of each slope class (gentle < 10 deg, moderate 10-20, steep 20-30, very steep > 30),
  from the cell size;
- the mean July temperature and the highest cell of each zone, next to the mean that the zone
  table of vtkTerroirKMeans reports (they must agree);
- a new point array computed with numpy (growing degree-days above 5 degC over the year) goes
  back into the VTK data set, where any VTK or Terroir filter, writer or view can use it.

Run (no display needed):
  PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 \
      Examples/Python/NumpyZoneStatistics.py --data Data
"""
import argparse
import os
import sys

import numpy as np
from vtkmodules.numpy_interface import dataset_adapter as dsa

import terroir

repository_data = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "Data")
parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--data", default=os.environ.get("TERROIR_DATA_DIR", repository_data),
                    help="bundled data folder (default: $TERROIR_DATA_DIR, else Data/)")
args = parser.parse_args()

reader = terroir.vtkTerroirDEMReader()
reader.SetFileName(os.path.join(args.data, "sagehen_creek_ca", "sagehen_dem_utm11n_10m.tif"))
slope = terroir.vtkTerroirSlope()
slope.SetInputConnection(reader.GetOutputPort())
temperature = terroir.vtkTerroirTemperature()
temperature.SetInputConnection(slope.GetOutputPort())
zones = terroir.vtkTerroirKMeans()
zones.SetInputConnection(temperature.GetOutputPort())
zones.SetNumberOfClusters(4)
zones.AddFeature("Slope", 1.0)
zones.AddFeature("Temperature", 1.0)
zones.Update()
if zones.GetOutput().GetNumberOfPoints() == 0:
    sys.exit("NumpyZoneStatistics: the pipeline failed (see the error above)")

terrain = dsa.WrapDataObject(zones.GetOutput())
slope_deg = terrain.PointData["Slope"]  # shape (cells,)
july = terrain.PointData["Temperature"][:, 6]  # shape (cells, 12): July is column 6
zone = terrain.PointData["ClusterId"]  # -1 where a cell takes no part
elevation = terrain.PointData["Elevation"]
dx, dy, _ = zones.GetOutput().GetSpacing()
cell_ha = dx * dy / 1e4
print(f"{slope_deg.shape[0]} cells of {cell_ha:.2f} ha; "
      f"Temperature {terrain.PointData['Temperature'].shape}")

print("slope class        area_ha  share_%")
edges = [0.0, 10.0, 20.0, 30.0, 90.0]
names = ["gentle < 10", "moderate 10-20", "steep 20-30", "very steep > 30"]
valid = np.isfinite(slope_deg)
counts, _ = np.histogram(slope_deg[valid], bins=edges)
for name, count in zip(names, counts):
    print(f"{name:<16} {count * cell_ha:9.2f}  {100.0 * count / valid.sum():7.3f}")
print(f"total            {counts.sum() * cell_ha:9.2f}  {100.0 * counts.sum() / valid.sum():7.3f}")

table = zones.GetClusterTable()
print("zone  cells  numpy_T_jul_C  table_T_jul_C  highest_m")
for k in range(table.GetNumberOfRows()):
    members = zone == k
    print(f"{k:4d} {np.count_nonzero(members):6d}  {july[members].mean(dtype=np.float64):13.4f}  "
          f"{table.GetValueByName(k, 'Temperature_Jul').ToDouble():13.4f}  "
          f"{elevation[members].max():9.2f}")

# numpy back into VTK: degree-days above 5 degC, with each month counted as 30.4 days.
monthly = terrain.PointData["Temperature"]
degree_days = (np.clip(monthly - 5.0, 0.0, None) * 30.4).sum(axis=1).astype(np.float32)
terrain.PointData.append(degree_days, "GrowingDegreeDays")
vtk_array = zones.GetOutput().GetPointData().GetArray("GrowingDegreeDays")  # a vtkFloatArray
low, high = vtk_array.GetRange()
print(f"growing degree-days (vtkFloatArray): min {low:.2f} max {high:.2f} degC day")
