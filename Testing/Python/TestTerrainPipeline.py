"""Composes terroir.vtkTerroirDEMReader -> vtkTerroirSlope -> vtkTerroirTemperature (and
vtkTerroirSolarIllumination after the slope, and vtkTerroirInfiltration ->
vtkTerroirSoilHumidity after the slope) on the bundled DEM and checks the arrays and a few
values against numpy computations.

Run by CTest with Debian's /usr/bin/python3 (PYTHONPATH = the built terroir package,
TERROIR_DATA_DIR = the bundled data). Exits non-zero on failure.
"""
import math
import os
import sys

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy

import terroir

failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAIL:", message)


data_dir = os.environ.get("TERROIR_DATA_DIR", os.path.join(os.path.dirname(__file__), "..", "..", "Data"))
dem = os.path.join(data_dir, "sagehen_creek_ca", "sagehen_dem_utm11n_10m.tif")

reader = terroir.vtkTerroirDEMReader()
reader.SetFileName(dem)
slope = terroir.vtkTerroirSlope()
slope.SetInputConnection(reader.GetOutputPort())
slope.SetBackendToCPU()
temperature = terroir.vtkTerroirTemperature()
temperature.SetInputConnection(slope.GetOutputPort())
temperature.SetBackendToCPU()
temperature.Update()

out = temperature.GetOutput()
nx, ny, nz = out.GetDimensions()
check(nz == 1 and nx == 786 and ny == 720, "dimensions %s" % ((nx, ny, nz),))
pd = out.GetPointData()
for name in ("Elevation", "Slope", "Aspect", "Normals", "Temperature"):
    check(pd.GetArray(name) is not None, "array %s missing" % name)
if failures:
    sys.exit(1)

z = vtk_to_numpy(pd.GetArray("Elevation")).astype(np.float64).reshape(ny, nx)  # row 0 = south
s = vtk_to_numpy(pd.GetArray("Slope")).reshape(ny, nx)
a = vtk_to_numpy(pd.GetArray("Aspect")).reshape(ny, nx)
n = vtk_to_numpy(pd.GetArray("Normals")).reshape(ny, nx, 3)
t = vtk_to_numpy(pd.GetArray("Temperature")).reshape(ny, nx, 12)
dx, dy, _ = out.GetSpacing()

check(pd.GetArray("Temperature").GetNumberOfComponents() == 12, "Temperature has 12 components")
check(pd.GetArray("Temperature").GetComponentName(0) == "Jan", "first component is Jan")
check(pd.GetArray("Temperature").GetComponentName(11) == "Dec", "last component is Dec")
check(pd.GetArray("Normals").GetNumberOfComponents() == 3, "Normals has 3 components")

# Horn (1981) in numpy on the interior cells (row j+1 is north).
zn, zc, zs = z[2:, :], z[1:-1, :], z[:-2, :]
gx = ((zn[:, 2:] - zn[:, :-2]) + 2.0 * (zc[:, 2:] - zc[:, :-2]) + (zs[:, 2:] - zs[:, :-2])) / (8.0 * dx)
gy = ((zn[:, :-2] - zs[:, :-2]) + 2.0 * (zn[:, 1:-1] - zs[:, 1:-1]) + (zn[:, 2:] - zs[:, 2:])) / (8.0 * dy)
slope_np = np.degrees(np.arctan(np.hypot(gx, gy)))
diff = np.abs(s[1:-1, 1:-1] - slope_np)
check(diff.max() < 1e-3, "slope vs numpy Horn: max diff %g deg" % diff.max())

gamma = terroir.vtkTerroirGeoreference.GetMeridianConvergence(out)
aspect_np = np.mod(np.degrees(np.arctan2(-gx, -gy)) + gamma, 360.0)
steep = slope_np > 1.0
adiff = np.abs((a[1:-1, 1:-1] - aspect_np + 180.0) % 360.0 - 180.0)[steep]
check(adiff.max() < 1e-3, "aspect vs numpy: max diff %g deg" % adiff.max())
check(np.all((a[~np.isnan(a)] >= 0.0) & (a[~np.isnan(a)] < 360.0)), "aspect in [0, 360)")

norm = np.sqrt(gx * gx + gy * gy + 1.0)
ndiff = np.abs(n[1:-1, 1:-1, 2] - 1.0 / norm).max()
check(ndiff < 1e-5, "normal z vs numpy: max diff %g" % ndiff)

# Temperature: defaults 2 degC (January) to 20 degC (July), 6.4 degC/km, northern hemisphere.
sea = np.array([2, 5, 8, 11, 14, 17, 20, 17, 14, 11, 8, 5], dtype=np.float64)
t_np = sea[None, None, :] - 6.4 * z[:, :, None] / 1000.0
tdiff = np.abs(t - t_np).max()
check(tdiff < 1e-3, "temperature vs numpy: max diff %g degC" % tdiff)
j, i = np.unravel_index(np.argmax(z), z.shape)
print("highest cell %.1f m: January %.2f degC, July %.2f degC" % (z[j, i], t[j, i, 0], t[j, i, 6]))
check(abs(t[j, i, 6] - (20.0 - 6.4 * z[j, i] / 1000.0)) < 1e-3, "July at the summit")

# Parameters round-trip and the southern hemisphere through Python.
temperature.SetHemisphereToSouth()
temperature.SetLapseRate(5.0)
temperature.Update()
t2 = vtk_to_numpy(temperature.GetOutput().GetPointData().GetArray("Temperature")).reshape(ny, nx, 12)
check(abs(t2[j, i, 0] - (20.0 - 5.0 * z[j, i] / 1000.0)) < 1e-3, "south: January warmest")
check(temperature.GetLastHemisphere() == temperature.South, "LastHemisphere is South")
check(slope.GetLastBackend() == 1, "slope ran on the CPU")

# Solar illumination after slope: an instant in December afternoon (PST), checked with numpy
# from the filter's own field data (the sun position used) and the slope filter's normals:
# SunIncidence = max(0, n . s) on lit cells, 0 in shadow; then the monthly mode.
sun = terroir.vtkTerroirSolarIllumination()
sun.SetInputConnection(slope.GetOutputPort())
sun.SetBackendToCPU()
sun.SetModeToInstant()
sun.SetYear(2025)
sun.SetMonth(12)
sun.SetDay(21)
sun.SetTime(14.0)
sun.SetUTCOffset(-8.0)
sun.Update()
so = sun.GetOutput()
lit = vtk_to_numpy(so.GetPointData().GetArray("Illuminated")).reshape(ny, nx)
inc = vtk_to_numpy(so.GetPointData().GetArray("SunIncidence")).reshape(ny, nx)
month, day, utc, az, el, gaz = so.GetFieldData().GetArray("SunPositions").GetTuple(0)
check(abs(utc - 22.0) < 1e-9 and month == 12 and day == 21, "instant at 22:00 UTC")
check(abs(gaz - (az - gamma)) < 1e-6, "grid azimuth = true azimuth - convergence")
check(150.0 < az < 240.0 and 10.0 < el < 30.0, "a winter afternoon sun: az %.1f el %.1f" % (az, el))
e, g = np.radians(el), np.radians(gaz)
svec = np.array([np.sin(g) * np.cos(e), np.cos(g) * np.cos(e), np.sin(e)])
cos_np = np.maximum(0.0, n @ svec) * lit
idiff = np.abs(inc - cos_np)[1:-1, 1:-1].max()
check(idiff < 1e-5, "SunIncidence vs numpy n.s: max diff %g" % idiff)
shade = 1.0 - lit.mean()
check(0.005 < shade < 0.5, "December afternoon shadow share %.3f" % shade)
print("December 14:00 PST: sun az %.2f el %.2f, %.1f %% of the DEM in shadow" % (az, el, 100 * shade))

sun.SetModeToMonthly()
sun.SetTimeStep(30.0)
sun.Update()
hours = vtk_to_numpy(sun.GetOutput().GetPointData().GetArray("IlluminationHours")).reshape(ny, nx, 12)
ins = vtk_to_numpy(sun.GetOutput().GetPointData().GetArray("Insolation")).reshape(ny, nx, 12)
check(np.all((hours >= 0.0) & (hours <= 24.0)), "hours within a day")
check(np.all(ins >= 0.0), "insolation not negative")
check(hours[:, :, 5].mean() > hours[:, :, 11].mean() + 3.0, "June has more sun than December")
# South-facing slopes get more December energy than north-facing ones (northern hemisphere).
south = (a > 135.0) & (a < 225.0) & (s > 15.0)
north = ((a < 45.0) | (a > 315.0)) & (s > 15.0)
check(ins[:, :, 11][south].mean() > 1.5 * ins[:, :, 11][north].mean(),
      "December insolation: south-facing %.0f vs north-facing %.0f Wh/m2"
      % (ins[:, :, 11][south].mean(), ins[:, :, 11][north].mean()))

# Soil water: reader -> slope -> infiltration (loam everywhere, a clay patch painted from a
# mask array, no infiltration on slopes over 30 degrees) -> soil humidity, against numpy.
patch = np.zeros((ny, nx), dtype=np.uint8)
patch[100:200, 300:500] = 1
from vtkmodules.util.numpy_support import numpy_to_vtk
with_patch = terroir.vtkTerroirSlope()
with_patch.SetInputConnection(reader.GetOutputPort())
with_patch.SetBackendToCPU()
with_patch.Update()
terrain = with_patch.GetOutput()
mask = numpy_to_vtk(patch.ravel(), deep=True)
mask.SetName("ClayPatch")
terrain.GetPointData().AddArray(mask)
infiltration = terroir.vtkTerroirInfiltration()
infiltration.SetInputData(terrain)
infiltration.AddFill(15.0)
infiltration.AddPaintMaskArray("ClayPatch", 3.0)
infiltration.AddSlopeRule(30.0)
humidity = terroir.vtkTerroirSoilHumidity()
humidity.SetInputConnection(infiltration.GetOutputPort())
humidity.SetBackendToCPU()
rain = [150, 140, 110, 60, 35, 15, 5, 5, 15, 50, 110, 145]
intensity = [2.5, 2.5, 2, 1.5, 3, 6, 10, 10, 5, 2, 2, 2.5]
humidity.SetPrecipitation(rain)
humidity.SetPrecipitationIntensity(intensity)
humidity.Update()
hp = humidity.GetOutput().GetPointData()
rate = vtk_to_numpy(hp.GetArray("InfiltrationRate")).reshape(ny, nx)
expected_rate = np.where(s > 30.0, 0.0, np.where(patch == 1, 3.0, 15.0))
check(np.array_equal(rate, expected_rate), "InfiltrationRate = fill, clay patch, slope rule")
sh = vtk_to_numpy(hp.GetArray("SoilHumidity")).reshape(ny, nx, 12)
swh = vtk_to_numpy(hp.GetArray("WeightedSoilHumidity")).reshape(ny, nx, 12)
sw = vtk_to_numpy(hp.GetArray("StandingWater")).reshape(ny, nx, 12)
q = np.array(rain, dtype=np.float64)
ri = np.array(intensity, dtype=np.float64)
sh_np = np.minimum(rate[:, :, None] / ri[None, None, :], 1.0) * q[None, None, :]
check(np.abs(sh - sh_np).max() < 1e-4, "SoilHumidity vs numpy: %g" % np.abs(sh - sh_np).max())
swh_np = sh_np / 2 + np.roll(sh_np, 1, axis=2) / 3 + np.roll(sh_np, 2, axis=2) / 6
check(np.abs(swh - swh_np).max() < 1e-4, "WeightedSoilHumidity vs numpy (periodic year)")
check(np.abs(sw - (q[None, None, :] - sh_np)).max() < 1e-4, "StandingWater = rain - absorbed")
print("soil water: July absorbed %.2f mm on clay, %.2f mm on loam; %.1f %% of cells are cliffs"
      % (sh[150, 400, 6] if rate[150, 400] == 3.0 else float("nan"),
         sh[:, :, 6][rate == 15.0].mean(), 100.0 * (rate == 0.0).mean()))

if failures:
    print("%d failure(s)" % len(failures))
    sys.exit(1)
print("TestTerrainPipeline: OK")
