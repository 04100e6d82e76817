#!/usr/bin/python3
"""Rivers from rain, scored against the mapped USGS rivers (NHD flowlines).

Pipeline: vtkTerroirDEMReader -> vtkTerroirVectorRasterizer (the NHD flowlines onto the DEM
grid, array `Reference`) -> vtkTerroirVectorRasterizer (the watershed polygon, array `Area`)
-> vtkTerroirWaterFlow (100 mm of rain on every cell runs downhill: `Discharge`, m3) and
vtkTerroirFlowAccumulation (the classic D8 baseline: `FlowAccumulation`, cells).

The scoring is the rule of `terroir validate` (Documentation/validation.md), written here with
numpy on the arrays that vtkmodules.numpy_interface.dataset_adapter exposes: river cells are the
crests of the flow measure (a local maximum across one of the four axes through the cell) at or
above the threshold that makes them as many as the reference cells inside the watershed;
precision, recall and F1 within 30 m and 60 m. The result is the same as `terroir validate
--mode pulse --max-iterations 150` (the example's test checks it). A map of the comparison at
60 m is saved. (This is Long (2016)'s single pulse; `terroir validate` and `terroir run` use the
river-forming mode, SetModeToRivers(): Documentation/validation.md.)

Run under an X display (or xvfb-run -a):
  PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 \
      Examples/Python/RiversFromRain.py --data Data --out example-output
The simulation stops after 150 iterations here (a few seconds); --iterations 10000 lets the
Long (2016)'s stop rule end it (371 iterations, F1@60 0.657 as in validation.md).
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
parser.add_argument("--out", default="example-output", help="folder for the PNG")
parser.add_argument("--iterations", type=int, default=150,
                    help="most water-flow iterations (default 150; 10000 for the full run)")
args = parser.parse_args()
os.makedirs(args.out, exist_ok=True)
sagehen = os.path.join(args.data, "sagehen_creek_ca")

reader = terroir.vtkTerroirDEMReader()
reader.SetFileName(os.path.join(sagehen, "sagehen_dem_utm11n_10m.tif"))
reference = terroir.vtkTerroirVectorRasterizer()  # lines: the cells of their path
reference.SetInputConnection(reader.GetOutputPort())
reference.SetFileName(os.path.join(sagehen, "sagehen_nhd_flowlines_utm11n.geojson"))
reference.SetOutputArrayName("Reference")
area = terroir.vtkTerroirVectorRasterizer()  # polygons: the cells whose centre is inside
area.SetInputConnection(reference.GetOutputPort())
area.SetFileName(os.path.join(sagehen, "sagehen_watershed_utm11n.geojson"))
area.SetOutputArrayName("Area")

flow = terroir.vtkTerroirWaterFlow()
flow.SetInputConnection(area.GetOutputPort())
flow.SetWaterSourceToConstant()
flow.SetInitialWater(100.0)  # mm of rain on every cell
flow.SetMaximumIterations(args.iterations)
d8 = terroir.vtkTerroirFlowAccumulation()
d8.SetInputConnection(flow.GetOutputPort())
d8.Update()
terrain = d8.GetOutput()
if terrain.GetNumberOfPoints() == 0:
    sys.exit("RiversFromRain: the pipeline failed (see the error above)")
fields = terrain.GetFieldData()
print(f"water flow: {int(fields.GetArray('WaterFlowIterations').GetValue(0))} iterations "
      f"({fields.GetAbstractArray('WaterFlowStopReason').GetValue(0)})")

# numpy views of the arrays, as (rows, columns) grids; row 0 is the south edge.
nx, ny, _ = terrain.GetDimensions()
dx, dy, _ = terrain.GetSpacing()
points = dsa.WrapDataObject(terrain).PointData
ref = np.asarray(points["Reference"]).reshape(ny, nx) > 0
inside = np.asarray(points["Area"]).reshape(ny, nx) > 0


def shifted(grid, dj, di, fill):
    """grid[j + dj, i + di] at every (j, i); `fill` where that falls off the grid."""
    out = np.full_like(grid, fill)
    out[max(-dj, 0):ny - max(dj, 0), max(-di, 0):nx - max(di, 0)] = \
        grid[max(dj, 0):ny + min(dj, 0), max(di, 0):nx + min(di, 0)]
    return out


def crests(value):
    """The value on channel cells (a maximum across one of the four axes), NaN elsewhere."""
    channel = np.zeros(value.shape, bool)
    for dj, di in ((0, 1), (1, 0), (1, 1), (1, -1)):
        # NaN (no neighbour) compares false, so the grid's edge makes no crest.
        channel |= (value >= shifted(value, dj, di, np.nan)) & \
            (value >= shifted(value, -dj, -di, np.nan))
    return np.where(channel, value, np.nan)


def length_matching_threshold(value, k):
    """The threshold t whose count of values >= t is closest to k (the larger t on a tie)."""
    values = value[inside & np.isfinite(value)]
    if k == 0 or values.size == 0:
        return np.inf
    if k >= values.size:
        return values.min()
    v = np.partition(values, values.size - k)[values.size - k]  # the k-th largest
    at_least = np.count_nonzero(values >= v)
    larger = values[values > v]
    if k - larger.size <= at_least - k:
        return larger.min() if larger.size else np.inf
    return v


def near(mask, tolerance):
    """Cells with a cell of `mask` within `tolerance` metres (centre to centre)."""
    out = np.zeros_like(mask)
    reach = int(tolerance // min(dx, dy)) + 1
    for dj in range(-reach, reach + 1):
        for di in range(-reach, reach + 1):
            if (di * dx) ** 2 + (dj * dy) ** 2 <= tolerance ** 2 * (1 + 2e-9):
                out |= shifted(mask, dj, di, False)
    return out


reference_cells = ref & inside
print(f"reference: {np.count_nonzero(reference_cells)} river cells inside the watershed")
print("method       threshold    P@30   R@30  F1@30    P@60   R@60  F1@60")
comparison = None
for name, measure in (("waterflow", "Discharge"), ("D8", "FlowAccumulation")):
    crest = crests(np.asarray(points[measure], dtype=np.float64).reshape(ny, nx))
    threshold = length_matching_threshold(crest, np.count_nonzero(reference_cells))
    with np.errstate(invalid="ignore"):
        simulated = inside & (crest >= threshold)
    scores = []
    for tolerance in (30.0, 60.0):
        sim_hit = simulated & near(reference_cells, tolerance)
        ref_hit = reference_cells & near(simulated, tolerance)
        p = np.count_nonzero(sim_hit) / max(np.count_nonzero(simulated), 1)
        r = np.count_nonzero(ref_hit) / max(np.count_nonzero(reference_cells), 1)
        scores += [p, r, 2 * p * r / (p + r) if p + r > 0 else 0.0]
    print(f"{name:<10} {threshold:11.3f}  " + "  ".join(
        " ".join(f"{s:6.4f}" for s in scores[i:i + 3]) for i in (0, 3)))
    if name == "waterflow":
        # Classes of the RiverComparison overlay: 1 mapped only, 2 model only, 3 both.
        comparison = np.where(ref_hit | sim_hit, 3, np.where(reference_cells, 1,
                                                             np.where(simulated, 2, 0)))

# Back to VTK: a numpy array becomes a point array of the terrain, then an overlay.
picture = dsa.WrapDataObject(terrain)
picture.PointData.append(comparison.astype(np.uint8).ravel(), "RiverComparison")
view = terroir.vtkTerroirOverlayView()
view.SetInputData(terrain)
view.SetArrayName("RiverComparison")
view.SetPreset("RiverComparison")
view.SetTitle("Rivers within 60 m")
view.SetWidth(400)
view.SetHeight(400)
if not view.WritePNG(os.path.join(args.out, "rivers_comparison.png")):
    sys.exit(f"RiversFromRain: {view.GetLastError()}")
print("wrote rivers_comparison.png")
