"""Composes terroir.vtkTerroirDEMReader -> vtkTerroirFloodFill on the bundled DEM: a seed in
Independence Lake (world coordinates, the overloads of AddSeedPoint) must wet exactly the cells
an independent breadth-first fill in Python wets, and FillDepressions must find the same lake.

Run by CTest with Debian's /usr/bin/python3 (PYTHONPATH = the built terroir package,
TERROIR_DATA_DIR = the bundled data). Exits non-zero on failure.
"""
import collections
import os
import sys

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkDataArray

import terroir

failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAIL:", message)


data_dir = os.environ.get("TERROIR_DATA_DIR",
                          os.path.join(os.path.dirname(__file__), "..", "..", "Data"))
dem = os.path.join(data_dir, "sagehen_creek_ca", "sagehen_dem_utm11n_10m.tif")

reader = terroir.vtkTerroirDEMReader()
reader.SetFileName(dem)
fill = terroir.vtkTerroirFloodFill()
fill.SetInputConnection(reader.GetOutputPort())
fill.AddSeedPoint(215365, 4371215)  # cell (138, 474), on the lake's flat
fill.Update()
out = fill.GetOutput()
nx, ny, _ = out.GetDimensions()
z = vtk_to_numpy(out.GetPointData().GetArray("Elevation")).reshape(ny, nx)  # row 0 = south
body_name = terroir.vtkTerroirFloodFill.WaterBodyName()
ids = vtk_to_numpy(out.GetPointData().GetArray(body_name)).reshape(ny, nx)
depth = vtk_to_numpy(out.GetPointData().GetArray("WaterDepth")).reshape(ny, nx)
units = out.GetPointData().GetArray("WaterDepth").GetInformation().Get(vtkDataArray.UNITS_LABEL())
check(units == "m", "WaterDepth units %r" % units)

# Independent fill: breadth-first over 8-neighbours with z <= level (float32 compared as double).
level = float(z[474, 138])
wet = np.zeros((ny, nx), bool)
wet[474, 138] = True
queue = collections.deque([(474, 138)])
while queue:
    j, i = queue.popleft()
    for dj in (-1, 0, 1):
        for di in (-1, 0, 1):
            jj, ii = j + dj, i + di
            if 0 <= jj < ny and 0 <= ii < nx and not wet[jj, ii] and float(z[jj, ii]) <= level:
                wet[jj, ii] = True
                queue.append((jj, ii))
check(np.array_equal(ids == 1, wet), "seed fill differs from the Python fill in %d cells"
      % int(np.sum((ids == 1) != wet)))
check(wet.sum() >= 10000, "lake has %d cells" % wet.sum())
check(np.allclose(depth[wet], level - z[wet].astype(np.float64), atol=1e-6), "depths")
cells = out.GetFieldData().GetArray("WaterBodyCells").GetValue(0)
check(cells == wet.sum(), "WaterBodyCells %s" % cells)
check(abs(out.GetFieldData().GetArray("WaterBodyLevel").GetValue(0) - 2117.8) < 0.01, "level")

# The explicit-level overload and FillDepressions.
fill.RemoveAllSeeds()
fill.AddSeedPoint(215365, 4371215, level)
fill.Update()
check(fill.GetOutput().GetFieldData().GetArray("WaterBodyCells").GetValue(0) == wet.sum(),
      "AddSeedPoint(x, y, level)")
fill.SetModeToFillDepressions()
fill.Update()
bodies = vtk_to_numpy(fill.GetOutput().GetPointData().GetArray("WaterBody")).reshape(ny, nx)
lake = np.bincount(bodies[wet]).argmax()
check(lake > 0 and np.sum(bodies[wet] == lake) >= 0.95 * wet.sum(), "FillDepressions lake")
check(fill.GetOutput().GetFieldData().GetAbstractArray("FloodFillMode").GetValue(0)
      == "FillDepressions", "FloodFillMode")

if failures:
    sys.exit(1)
print("ok: lake of %d cells at %.3f m" % (wet.sum(), level))
