"""Peer comparison of vtkTerroirFlowAccumulation with GRASS GIS r.watershed -s (single flow
direction, D8) on the bundled Sagehen Creek DEM (786 x 720 cells, 10 m, NAD83 / UTM 11N).

Run by CTest with Debian's /usr/bin/python3 (PYTHONPATH = the built terroir package,
TERROIR_DATA_DIR = the bundled data, TERROIR_TEMP_DIR = scratch space). Needs `grass` on PATH
(Debian `grass-core`; GRASS 8.2.1 when this was written): without it the test FAILS, it does not
skip. Exits non-zero on failure. About 2 s on 2 cores (1 s of it the GRASS session).

What is compared
1. Flow directions, cell by cell, away from flats: on the cells whose FILLED elevation (our
   FilledElevation) has a strictly lower 8-neighbour, and not on the edge ring. There both
   methods should take the steepest downslope neighbour (drop over distance, diagonals
   sqrt(2) longer). Elsewhere they legitimately differ: r.watershed does not fill depressions
   (its A* least-cost search routes water out of a depression along the search path) and it
   routes flats its own way, while we fill (Priority-Flood) and route flats breadth-first.
   Asserted: agreement >= AGREE_MIN (0.99). Measured when this was written (GRASS 8.2.1):
   99.85 % of 538,893 compared cells (24,019 flat cells and the 3,008 edge-ring cells left
   out). Of the 799 disagreements, 414 are near-ties (the two slopes on the filled surface
   equal within 1e-4 relative: float rounding decides) and 381 are cells where r.watershed's
   choice is less steep on the filled surface, most of them around depressions (182 of the
   799 are on or next to a cell raised by Priority-Flood), where its least-cost search does
   not follow the filled surface. The threshold leaves room for another GRASS version's tie
   handling while catching a wrong code conversion: rows left north-up (N and S swapped)
   agree on 24.7 %, codes off by one on 0.03 %. On the flat cells (not asserted) the two
   agree on 3.8 % only: r.watershed routes flats along its search path, we breadth-first.
2. Accumulation along the main stem of Sagehen Creek: from the outlet (the cell of largest
   accumulation within one cell of the outlet point of sagehen_outlet_utm11n.geojson) upstream,
   always into the upstream neighbour of largest accumulation, while it drains >= 1 km^2.
   GRASS's accumulation at the same cell (r.watershed -a: absolute cell counts), or the
   largest within one cell where the two channels run side by side, must be within 2 % of
   ours on >= 95 % of the stem's cells, and within 2 % at the outlet. Measured: a stem of 621
   cells; GRASS / ours - 1 has median +0.023 %, max 0.07 %, 100 % of the cells within 2 %;
   at the outlet 275,795 cells (GRASS) against 275,740 (ours, 27.574 km^2). The 2 % bounds
   allow for a few hundred cells moving across a divide with another routing of depressions;
   a lost tributary or a broken accumulation moves the stem by far more.

Conventions
- r.watershed's drainage codes are 1..8 counter-clockwise from NE (1 NE, 2 N, 3 NW, 4 W,
  5 SW, 6 S, 7 SE, 8 E), negative where the flow leaves the region (absolute value = the
  direction), 0 in a depression given by the `depression` map (none here). Ours: 0..7 counter-
  clockwise from E, -1 off the terrain. So ours = |grass| mod 8.
- GRASS rasters come out of r.out.gdal north row first; they are flipped to VTK's south-up
  rows before comparing.
- Edge ring: r.watershed lets an edge cell drain out of the region (negative code) even when
  it has a lower neighbour inside; we drain it inside (our -1 only when there is no lower
  neighbour inside). The outermost ring of cells is therefore excluded from (1).
"""
import json
import os
import shutil
import tempfile
import time

import numpy as np

from osgeo import gdal  # noqa: E402

import TerroirGrass  # noqa: E402 (beside this script)
from TerroirGrass import check  # noqa: E402

t_start = time.time()
grass = TerroirGrass.require_grass()

from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402

import terroir  # noqa: E402
from terroir import vtkTerroirFlowAccumulation  # noqa: E402  (the import users write)

gdal.UseExceptions()

AGREE_MIN = 0.99
STEM_TOL = 0.02
STEM_SHARE_MIN = 0.95
STEM_MIN_CELLS = 10000  # 1 km^2 of 10 m cells

data_dir = os.environ.get("TERROIR_DATA_DIR",
                          os.path.join(os.path.dirname(__file__), "..", "..", "Data"))
folder = os.path.abspath(os.path.join(data_dir, "sagehen_creek_ca"))
dem = os.path.join(folder, "sagehen_dem_utm11n_10m.tif")
temp_root = os.environ.get("TERROIR_TEMP_DIR")
if temp_root:
    os.makedirs(temp_root, exist_ok=True)
work = tempfile.mkdtemp(prefix="grass_flowacc_", dir=temp_root)

# ---- our filter -------------------------------------------------------------------------------
reader = terroir.vtkTerroirDEMReader()
reader.SetFileName(dem)
f = vtkTerroirFlowAccumulation()
f.SetInputConnection(reader.GetOutputPort())
t0 = time.time()
f.Update()
t_ours = time.time() - t0
out = f.GetOutput()
nx, ny, _ = out.GetDimensions()
check((nx, ny) == (786, 720), "DEM dimensions %s" % ((nx, ny),))
if TerroirGrass.failures:
    TerroirGrass.finish("TestFlowAccumulationGrass")


def point_array(name):
    a = out.GetPointData().GetArray(name)
    check(a is not None, "array %s missing" % name)
    if a is None:
        TerroirGrass.finish("TestFlowAccumulationGrass")
    return vtk_to_numpy(a).reshape(ny, nx)


ours_dir = point_array("FlowDirection").astype(np.int64)
ours_acc = point_array("FlowAccumulation").astype(np.float64)
filled = point_array("FilledElevation").astype(np.float64)
check(f.GetLastBackend() == 1, "ran on backend %d, expected the CPU" % f.GetLastBackend())


# ---- GRASS side -------------------------------------------------------------------------------
def write_grass_script(path):
    lines = [
        "set -e",
        "r.in.gdal -o input='%s' output=dem --quiet" % dem,
        "g.region raster=dem",
        "r.watershed -s -a elevation=dem drainage=drain accumulation=acc --quiet",
        "r.out.gdal -c input=drain output='%s' format=GTiff type=Int16 nodata=-32768 --quiet "
        "--overwrite" % os.path.join(work, "drain.tif"),
        "r.out.gdal -c input=acc output='%s' format=GTiff type=Float64 nodata=-1 --quiet "
        "--overwrite" % os.path.join(work, "acc.tif"),
    ]
    with open(path, "w") as fh:
        fh.write("\n".join(lines) + "\n")


script = os.path.join(work, "grass_flowacc.sh")
write_grass_script(script)
grass_log, grass_rc, t_grass = TerroirGrass.run_session(grass, dem, script, work)
check(grass_rc == 0, "GRASS session failed (exit %s)" % grass_rc)
if grass_rc != 0:
    print(grass_log[-4000:])
    print("scratch kept in", work)
    TerroirGrass.finish("TestFlowAccumulationGrass")

ref_gt = gdal.Open(dem).GetGeoTransform()


def read_grass(name):
    """A GRASS export as a float64 array in VTK order (row 0 = south); NaN for nodata."""
    a, problems = TerroirGrass.read_export(os.path.join(work, name), nx, ny, ref_gt)
    for problem in problems:
        check(False, problem)
    return a


grass_drain = read_grass("drain.tif")
grass_acc = read_grass("acc.tif")
if TerroirGrass.failures:
    print("scratch kept in", work)
    TerroirGrass.finish("TestFlowAccumulationGrass")
check(np.isfinite(grass_drain).all(), "GRASS drainage has NULL cells")
check(np.isfinite(grass_acc).all(), "GRASS accumulation has NULL cells")
check(not (grass_drain == 0).any(), "GRASS drainage has depression cells (0)")
grass_dir = np.abs(np.nan_to_num(grass_drain)).astype(np.int64) % 8  # 8 (E) -> 0

# ---- (1) directions away from flats ------------------------------------------------------------
DI = [1, 1, 0, -1, -1, -1, 0, 1]
DJ = [0, 1, 1, 1, 0, -1, -1, -1]
padded = np.pad(filled, 1, constant_values=np.inf)
has_lower = np.zeros((ny, nx), dtype=bool)
for e in range(8):
    neighbour = padded[1 + DJ[e]:1 + DJ[e] + ny, 1 + DI[e]:1 + DI[e] + nx]
    has_lower |= neighbour < filled
inner = np.zeros((ny, nx), dtype=bool)
inner[1:-1, 1:-1] = True
compared = has_lower & inner
agree = (ours_dir == grass_dir) & compared
n_compared = int(compared.sum())
fraction = agree.sum() / max(1, n_compared)
raised = filled > vtk_to_numpy(out.GetPointData().GetArray("Elevation")).reshape(ny, nx)
flat = inner & ~has_lower
print("Flow directions vs r.watershed -s, away from flats (filled surface has a lower "
      "neighbour), edge ring excluded:")
print("  compared %d cells of %d (%d flat cells, %d edge-ring cells left out), agree %d = "
      "%.4f %%" % (n_compared, nx * ny, int(flat.sum()), int((~inner).sum()), int(agree.sum()),
                   100.0 * fraction))
disagree = compared & ~agree
# Where do disagreements sit? Next to a cell raised by the filling, or a near-tie.
near_raised = np.zeros((ny, nx), dtype=bool)
rp = np.pad(raised, 1, constant_values=False)
for e in range(8):
    near_raised |= rp[1 + DJ[e]:1 + DJ[e] + ny, 1 + DI[e]:1 + DI[e] + nx]
near_raised |= raised
print("  disagreements: %d, of which %d on or next to a cell raised by Priority-Flood"
      % (int(disagree.sum()), int((disagree & near_raised).sum())))
# Agreement on the flat cells too (not asserted: the methods differ there by design).
flat_agree = ((ours_dir == grass_dir) & flat).sum() / max(1, flat.sum())
print("  (flat cells, not asserted: agree %.2f %%)" % (100.0 * flat_agree))
check(fraction >= AGREE_MIN, "direction agreement %.4f < %.2f" % (fraction, AGREE_MIN))

# ---- (2) accumulation along the main stem ----------------------------------------------
with open(os.path.join(folder, "sagehen_outlet_utm11n.geojson")) as fh:
    ox, oy = json.load(fh)["features"][0]["geometry"]["coordinates"][:2]
ox0, oy0, _ = out.GetOrigin()
dx, dy, _ = out.GetSpacing()
oi, oj = int(round((ox - ox0) / dx)), int(round((oy - oy0) / dy))
window = ours_acc[oj - 1:oj + 2, oi - 1:oi + 2]
wj, wi = np.unravel_index(np.argmax(window), window.shape)
ci, cj = oi - 1 + wi, oj - 1 + wj
stem = []
while ours_acc[cj, ci] >= STEM_MIN_CELLS:
    stem.append((ci, cj))
    best = None
    for e in range(8):
        ui, uj = ci - DI[e], cj - DJ[e]  # the neighbour that drains here with code e
        if 0 <= ui < nx and 0 <= uj < ny and ours_dir[uj, ui] == e:
            if best is None or ours_acc[uj, ui] > ours_acc[best[1], best[0]]:
                best = (ui, uj)
    if best is None:
        break
    ci, cj = best
check(len(stem) > 100, "main stem of only %d cells" % len(stem))
gp = np.pad(grass_acc, 1, constant_values=0.0)
rel = []
for (i, j) in stem:
    g = grass_acc[j, i]
    if abs(g / ours_acc[j, i] - 1.0) > STEM_TOL:  # channels side by side: the best within 1 cell
        g = gp[j:j + 3, i:i + 3].flat[np.argmin(np.abs(gp[j:j + 3, i:i + 3] - ours_acc[j, i]))]
    rel.append(g / ours_acc[j, i] - 1.0)
rel = np.array(rel)
within = np.abs(rel) <= STEM_TOL
i0, j0 = stem[0]
print()
print("Accumulation along the main stem (%d cells from the outlet (%d, %d) up to %d cells "
      "drained):" % (len(stem), i0, j0, STEM_MIN_CELLS))
print("  outlet: ours %d cells = %.3f km2, GRASS %d cells (%+.3f %%)"
      % (ours_acc[j0, i0], ours_acc[j0, i0] * dx * dy / 1e6, grass_acc[j0, i0],
         100.0 * (grass_acc[j0, i0] / ours_acc[j0, i0] - 1.0)))
print("  GRASS / ours - 1: median %+.4f %%, p95 |.| %.3f %%, max |.| %.2f %%; within %.0f %%: "
      "%.2f %% of the stem" % (100.0 * np.median(rel), 100.0 * np.percentile(np.abs(rel), 95),
                               100.0 * np.abs(rel).max(), 100.0 * STEM_TOL,
                               100.0 * within.mean()))
check(abs(grass_acc[j0, i0] / ours_acc[j0, i0] - 1.0) <= STEM_TOL,
      "outlet accumulation: GRASS %d, ours %d" % (grass_acc[j0, i0], ours_acc[j0, i0]))
check(within.mean() >= STEM_SHARE_MIN, "only %.2f %% of the main stem within %.0f %%"
      % (100.0 * within.mean(), 100.0 * STEM_TOL))

print()
print("time: terroir %.2f s, GRASS session %.1f s, total %.1f s"
      % (t_ours, t_grass, time.time() - t_start))
if TerroirGrass.failures:
    print("scratch kept in", work)
else:
    shutil.rmtree(work, ignore_errors=True)
TerroirGrass.finish("TestFlowAccumulationGrass")
