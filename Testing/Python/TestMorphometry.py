"""Composes terroir.vtkTerroirDEMReader -> vtkTerroirMorphometry on the bundled DEM and checks
the channel network against a plain-Python re-implementation written from the definitions in
Documentation/TerrainGeneration.md (not from the C++): Strahler orders cell by cell, N_w and L_w
per order, R_b and R_l, the longest flow paths and Hack's h and C (numpy.polyfit), from the
FlowDirection and ContributingArea of vtkTerroirFlowAccumulation at the same threshold.

Run by CTest with Debian's /usr/bin/python3 (PYTHONPATH = the built terroir package,
TERROIR_DATA_DIR = the bundled data). Exits non-zero on failure. About 3 s.
"""
import collections
import math
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
morph = terroir.vtkTerroirMorphometry()
morph.SetInputConnection(reader.GetOutputPort())
morph.Update()
out = morph.GetOutput()
flow = terroir.vtkTerroirFlowAccumulation()
flow.SetInputConnection(reader.GetOutputPort())
flow.SetRiverThreshold(morph.GetChannelArea())
flow.Update()
nx, ny, _ = out.GetDimensions()
dx, dy, _ = out.GetSpacing()
fd = out.GetFieldData()


def field(name):
    a = fd.GetArray(name)
    check(a is not None, "field array %s missing" % name)
    return [a.GetComponent(k, 0) for k in range(a.GetNumberOfTuples())] if a else [math.nan]


order = vtk_to_numpy(out.GetPointData().GetArray("StrahlerOrder")).astype(np.int64)
length = vtk_to_numpy(out.GetPointData().GetArray("FlowLength")).astype(np.float64)
check(out.GetPointData().GetArray("FlowLength").GetInformation().Get(
    vtkDataArray.UNITS_LABEL()) == "m", "FlowLength units")
direction = vtk_to_numpy(flow.GetOutput().GetPointData().GetArray("FlowDirection")).astype(int)
area = vtk_to_numpy(flow.GetOutput().GetPointData().GetArray("ContributingArea"))
channel = area >= morph.GetChannelArea()

# ---- the network again, in Python: Kahn's order over every cell -------------------------------
DI = [1, 1, 0, -1, -1, -1, 0, 1]
DJ = [0, 1, 1, 1, 0, -1, -1, -1]
n = nx * ny
target = np.full(n, -1, dtype=np.int64)
step = np.zeros(n)
for k in np.nonzero(direction >= 0)[0]:
    d = direction[k]
    i, j = k % nx, k // nx
    target[k] = (i + DI[d]) + nx * (j + DJ[d])
    step[k] = math.hypot(DI[d] * dx, DJ[d] * dy)
indegree = np.bincount(target[target >= 0], minlength=n)
inflow_orders = collections.defaultdict(list)
my_order = np.zeros(n, dtype=np.int64)
my_length = np.zeros(n)
starts = collections.Counter()
lengths = collections.Counter()
queue = collections.deque(np.nonzero((indegree == 0) & (direction != -2))[0].tolist())
left = indegree.copy()
while queue:
    k = queue.popleft()
    if channel[k]:
        ins = inflow_orders[k]
        top = max(ins) if ins else 0
        w = 1 if not ins else (top + 1 if ins.count(top) >= 2 else top)
        my_order[k] = w
        if not ins or ins.count(top) >= 2:
            starts[w] += 1
        lengths[w] += step[k]
    t = target[k]
    if t >= 0:
        if my_order[k] > 0:
            inflow_orders[t].append(my_order[k])
        my_length[t] = max(my_length[t], my_length[k] + step[k])
        left[t] -= 1
        if left[t] == 0:
            queue.append(t)

wrong = int(np.sum(order != my_order))
print("Strahler orders: %d of %d channel cells differ" % (wrong, int(channel.sum())))
check(wrong == 0, "%d cells have another Strahler order" % wrong)
valid = direction != -2
worst = float(np.max(np.abs(length[valid] - my_length[valid])))
# FlowLength is float32: 1e-6 of the longest path (about 1 cm) covers its rounding.
check(worst <= 1e-6 * float(my_length.max()), "FlowLength differs by up to %g m" % worst)
omega = int(my_order.max())
counts = field("HortonStreamCount")
means = field("HortonMeanLength")
check(len(counts) == omega, "%d orders, expected %d" % (len(counts), omega))
for w in range(1, omega + 1):
    print("order %d: N %d (ours %d), mean length %.3f m (ours %.3f)"
          % (w, starts[w], counts[w - 1], lengths[w] / starts[w], means[w - 1]))
    check(counts[w - 1] == starts[w], "N_%d %d vs %d" % (w, counts[w - 1], starts[w]))
    check(abs(means[w - 1] - lengths[w] / starts[w]) <= 1e-6 * means[w - 1],
          "mean L_%d %.6f vs %.6f" % (w, means[w - 1], lengths[w] / starts[w]))
ws = np.arange(1, omega)
rb = 10 ** -np.polyfit(ws, np.log10([starts[w] for w in ws]), 1)[0]
rl = 10 ** np.polyfit(ws, np.log10([lengths[w] / starts[w] for w in ws]), 1)[0]
print("R_b %.6f (ours %.6f), R_l %.6f (ours %.6f)"
      % (rb, field("BifurcationRatio")[0], rl, field("LengthRatio")[0]))
check(abs(field("BifurcationRatio")[0] - rb) <= 1e-9 * rb, "R_b")
check(abs(field("LengthRatio")[0] - rl) <= 1e-9 * rl, "R_l")
sel = channel & (my_length > 0)
h, logc = np.polyfit(np.log10(area[sel] / 1e6), np.log10(my_length[sel] / 1e3), 1)
print("Hack h %.6f (ours %.6f), C %.6f (ours %.6f) over %d channel cells"
      % (h, field("HackExponent")[0], 10 ** logc, field("HackCoefficient")[0], int(sel.sum())))
check(abs(field("HackExponent")[0] - h) <= 1e-6, "Hack h")
check(abs(field("HackCoefficient")[0] - 10 ** logc) <= 1e-6 * 10 ** logc, "Hack C")
channel_length = float(step[channel].sum())
check(abs(field("ChannelLength")[0] - channel_length) <= 1e-6 * channel_length, "channel length")

if failures:
    print("%d failure(s)" % len(failures))
    sys.exit(1)
print("TestMorphometry: OK")
