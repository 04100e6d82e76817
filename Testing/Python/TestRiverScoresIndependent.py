#!/usr/bin/python3
"""The river scores of `terroir validate`, recomputed by code that shares nothing with it.

`terroir validate` scores every method with the project's own library (RiverValidation.h:
channel cells, the length-matching threshold, the distance matching). This test re-derives the
scores of two rows from the definitions in Documentation/validation.md with GDAL, numpy and
SciPy only:

- reference cells: the NHD flowlines burnt onto the DEM grid (gdal.RasterizeLayer defaults),
  inside the watershed polygon (burnt the same way) and where the DEM has data;
- the measure of a method, written by other commands (`terroir waterflow --mode rivers` to a
  .vti for the simulation's RiverStrength; `terroir flowacc` for D8's ContributingArea, which
  ranks cells as the row's FlowAccumulation does: every cell is 100 m^2);
- channel cells: a local maximum (>=) of the measure across one of the four axes through the
  cell, both neighbours inside the grid and not NaN;
- the threshold: the value t at which as many channel cells inside the area have a measure
  >= t as there are reference cells (on a tie, the count nearer to the reference's, then the
  larger t);
- a cell matches when a cell of the other kind inside the area lies within the tolerance
  (Euclidean distance between cell centres, metres, by scipy.ndimage.distance_transform_edt);
  precision, recall and F1 from those counts.

The counts must equal the program's exactly, and the simulation's F1 at 60 m must stay at the
level validation.md reports (0.820; floor 0.81), so a regression in the model or in the scoring
library fails here even when the two would still agree with each other.
"""
import json
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np
from osgeo import gdal
from scipy import ndimage
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOXML import vtkXMLImageDataReader

gdal.UseExceptions()

DATA = os.environ.get("TERROIR_DATA_DIR",
                      os.path.join(os.path.dirname(__file__), "..", "..", "Data"))
BIN = os.path.join(os.environ.get("TERROIR_BIN_DIR", "build/bin"), "terroir")
TEMP = os.environ.get("TERROIR_TEMP_DIR", tempfile.gettempdir())
SAGEHEN = os.path.join(DATA, "sagehen_creek_ca")
# validation.md's F1 at 60 m on Sagehen, minus 0.01 (measured 0.821, 0.782, 0.792, 0.786,
# 0.795, 0.798, 0.818, 0.831).
F1_FLOORS = {
    "terroir waterflow rivers": 0.811, "D8": 0.772, "D8 A*S": 0.782, "MFD": 0.776,
    "MFD A*S": 0.785, "MFD-md": 0.788, "D-infinity": 0.808, "D-infinity A*S": 0.821,
}
DEM = os.path.join(SAGEHEN, "sagehen_dem_utm11n_10m.tif")
LINES = os.path.join(SAGEHEN, "sagehen_nhd_flowlines_utm11n.geojson")
AREA = os.path.join(SAGEHEN, "sagehen_watershed_utm11n.geojson")

# The peer tests' check helpers, and TestValidateJson's burning of vector files onto the grid
# (GDAL's rasterisation: not the project's code either).
from TerroirGrass import check, failures  # noqa: E402 (beside this script)
from TestValidateJson import burn, valid_cells  # noqa: E402


def channel_cells(value):
    """Cells >= both neighbours along one of the axes E-W, N-S, NE-SW, NW-SE (rows and columns
    as stored; the axes are symmetric, so the north-up order of GDAL does not matter)."""
    v = np.asarray(value, dtype=np.float64)
    ny, nx = v.shape
    padded = np.full((ny + 2, nx + 2), np.nan)
    padded[1:-1, 1:-1] = v
    centre = padded[1:-1, 1:-1]
    crest = np.zeros(v.shape, dtype=bool)
    for (a0, a1), (b0, b1) in (((0, -1), (0, 1)), ((-1, 0), (1, 0)), ((-1, -1), (1, 1)),
                               ((-1, 1), (1, -1))):
        na = padded[1 + a0:ny + 1 + a0, 1 + a1:nx + 1 + a1]
        nb = padded[1 + b0:ny + 1 + b0, 1 + b1:nx + 1 + b1]
        with np.errstate(invalid="ignore"):
            crest |= (centre >= na) & (centre >= nb)  # NaN compares False
    return crest & np.isfinite(v)


def length_matching_threshold(values, k):
    """t with count(values >= t) = k, or the nearest count (ties: the larger t)."""
    s = np.sort(values)[::-1]
    if k <= 0 or s.size == 0:
        return np.inf
    if s.size <= k:
        return s[-1]
    v = s[k - 1]
    at = int(np.sum(s >= v))
    if at == k:
        return v
    above = s[s > v]
    if above.size == 0:
        return v if at - k < k else np.inf
    t_above = above.min()
    count_above = int(np.sum(s >= t_above))
    return t_above if abs(count_above - k) <= abs(at - k) else v


def scores(reference, simulated, area, dx, dy, tolerance):
    ref = reference & area
    sim = simulated & area
    # Distance from every cell to the nearest cell of each kind (inside the area), metres.
    to_ref = ndimage.distance_transform_edt(~ref, sampling=(dy, dx))
    to_sim = ndimage.distance_transform_edt(~sim, sampling=(dy, dx))
    limit = tolerance * (1.0 + 1e-9)
    sim_hits = int(np.sum(sim & (to_ref <= limit)))
    ref_hits = int(np.sum(ref & (to_sim <= limit)))
    p = sim_hits / sim.sum() if sim.sum() else 0.0
    r = ref_hits / ref.sum() if ref.sum() else 0.0
    f1 = 2 * p * r / (p + r) if p + r > 0 else 0.0
    return {"simulated_cells": int(sim.sum()), "reference_cells": int(ref.sum()),
            "simulated_hits": sim_hits, "reference_hits": ref_hits, "precision": p,
            "recall": r, "f1": f1}


def score_measure(measure, reference, area, dx, dy):
    crest = channel_cells(measure)
    inside = crest & area
    t = length_matching_threshold(measure[inside], int((reference & area).sum()))
    with np.errstate(invalid="ignore"):
        simulated = inside & (measure >= t)
    return t, [scores(reference, simulated, area, dx, dy, tol) for tol in (30.0, 60.0)]


def run(*args):
    r = subprocess.run([BIN] + list(args), capture_output=True, text=True, timeout=900)
    check(r.returncode == 0, "terroir %s failed: %s" % (args[0], r.stderr))
    return r


def read_vti_array(path, name):
    reader = vtkXMLImageDataReader()
    reader.SetFileName(path)
    reader.Update()
    image = reader.GetOutput()
    nx, ny, _ = image.GetDimensions()
    a = vtk_to_numpy(image.GetPointData().GetArray(name)).astype(np.float64)
    return a.reshape(ny, nx)[::-1, :]  # VTK rows south first -> north-up like GDAL


def main():
    os.makedirs(TEMP, exist_ok=True)
    work = tempfile.mkdtemp(prefix="scores-independent-", dir=TEMP)
    try:
        scores_json = os.path.join(work, "scores.json")
        run("validate", "--json", scores_json, "--backend", "cpu")
        run("waterflow", DEM, os.path.join(work, "flow.vti"), "--mode", "rivers",
            "--backend", "cpu")
        run("flowacc", DEM, os.path.join(work, "acc.tif"))
        if failures:
            return 1
        with open(scores_json) as f:
            program = json.load(f)
        ds = gdal.Open(DEM)
        valid = valid_cells(ds)
        gt = ds.GetGeoTransform()
        dx, dy = abs(gt[1]), abs(gt[5])
        reference = burn(LINES, ds) & valid
        area = burn(AREA, ds) & valid
        strength = read_vti_array(os.path.join(work, "flow.vti"), "RiverStrength")
        acc_ds = gdal.Open(os.path.join(work, "acc.tif"))
        accumulation = acc_ds.GetRasterBand(1).ReadAsArray().astype(np.float64)
        rows = {m["name"]: m for m in program["methods"]}
        for name, measure in (("terroir waterflow rivers", strength), ("D8", accumulation)):
            t, mine = score_measure(measure, reference, area, dx, dy)
            theirs = rows[name]["scores"]
            for a, b in zip(mine, theirs):
                for key in ("simulated_cells", "reference_cells", "simulated_hits",
                            "reference_hits"):
                    check(a[key] == b[key], "%s @%g m: %s %d here, %d by terroir validate"
                          % (name, b["tolerance_m"], key, a[key], b[key]))
                check(abs(a["f1"] - b["f1"]) <= 1e-12, "%s @%g m: F1 %.6f here, %.6f by terroir"
                      " validate" % (name, b["tolerance_m"], a["f1"], b["f1"]))
            print("%-26s threshold %-12.6g F1@30 %.4f  F1@60 %.4f (P %.4f, R %.4f)"
                  % (name, t, mine[0]["f1"], mine[1]["f1"], mine[1]["precision"],
                     mine[1]["recall"]))
            if name == "terroir waterflow rivers":
                check(mine[1]["f1"] >= 0.81, "the simulation's F1 at 60 m fell to %.4f (0.820 in "
                      "validation.md)" % mine[1]["f1"])
            else:
                check(mine[1]["f1"] >= 0.77, "D8's F1 at 60 m fell to %.4f (0.782)"
                      % mine[1]["f1"])
        # Every method's F1 at 60 m on Sagehen stays within 0.01 of what validation.md reports
        # (the floors are those values minus 0.01): a regression in any baseline fails here.
        for name, floor in F1_FLOORS.items():
            check(name in rows, "terroir validate has no method %r" % name)
            if name in rows:
                f1 = rows[name]["scores"][1]["f1"]
                check(rows[name]["scores"][1]["tolerance_m"] == 60.0, "%s: not at 60 m" % name)
                check(f1 >= floor, "%s: F1 at 60 m %.4f, below its floor %.3f" % (name, f1, floor))
    finally:
        shutil.rmtree(work, ignore_errors=True)
    if failures:
        print("%d failure(s)" % len(failures))
        return 1
    print("TestRiverScoresIndependent: OK")
    return 0


if __name__ == "__main__":
    sys.exit(main())
