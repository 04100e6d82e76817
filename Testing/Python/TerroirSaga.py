"""Helpers for the tests that compare Terroir with SAGA GIS (TestFlowAccumulationSaga.py): run
`saga_cmd` on a DEM (sink filling, then flow accumulation), read grids as numpy arrays, and
compare two accumulation rasters. Debian's /usr/bin/python3 with osgeo.gdal and numpy.

SAGA tools used (SAGA 8.5.0, Debian package `saga`; ids from `saga_cmd ta_preprocessor` and
`saga_cmd ta_hydrology 0 --help`):
- ta_preprocessor 4 "Fill Sinks (Wang & Liu)": -ELEV, -FILLED, -MINSLOPE (degrees, default 0.1).
- ta_hydrology 0 "Flow Accumulation (Top-Down)": -ELEVATION, -FLOW, -METHOD, -CONVERGENCE (the
  MFD/MTFD exponent, default 1.1), -MFD_CONTOUR (contour-length weights, default off),
  -FLOW_UNIT (0 cells, 1 cell area = m2 on a metric grid; default 1).
saga_cmd reads a GeoTIFF directly and writes a GeoTIFF when the output name ends in .tif
(float32, nodata -99999, same grid as the input).
"""
import math
import os
import shutil
import subprocess
import sys
import time

import numpy as np
from osgeo import gdal

gdal.UseExceptions()

# ta_hydrology 0 METHOD choices (saga_cmd ta_hydrology 0 --help, SAGA 8.5.0).
METHOD_D8 = 0       # Deterministic 8 (O'Callaghan & Mark 1984)
METHOD_DINF = 3     # "Deterministic Infinity": see the warning in TestFlowAccumulationSaga.py
METHOD_MFD = 4      # Multiple Flow Direction (Freeman 1991; slope^p, p = CONVERGENCE)
METHOD_MTFD = 5     # Multiple Triangular Flow Direction (Seibert & McGlynn 2007)

# The checks and their report are the GRASS peer tests' (one implementation for both peers).
from TerroirGrass import check, failures, finish  # noqa: E402,F401 (beside this module)


def require_saga():
    """The `saga_cmd` program, or exit 1: like the GRASS peer tests, this one fails (not skips)
    without its peer (Scripts/setup.sh installs the Debian package saga)."""
    saga = shutil.which("saga_cmd")
    if saga is None:
        print("FAIL: `saga_cmd` (SAGA GIS, Debian package saga) is not on PATH; this peer test "
              "needs it (Scripts/setup.sh installs it).")
        sys.exit(1)
    return saga


def saga_version(saga):
    """The "SAGA Version: x.y.z" line of `saga_cmd --version`, or "unknown"."""
    try:
        out = subprocess.run([saga, "--version"], stdout=subprocess.PIPE,
                             stderr=subprocess.STDOUT, text=True, timeout=60).stdout
    except (OSError, subprocess.SubprocessError):
        return "unknown"
    for line in out.splitlines():
        if "Version" in line:
            return line.split(":", 1)[-1].strip()
    return "unknown"


def min_slope_degrees(dem):
    """The MINSLOPE (degrees) handed to Fill Sinks (Wang & Liu): the gradient that raises a
    filled flat by one float32 step of its highest elevation per cell, and at least 0.001.

    SAGA stores the filled DEM as float32, so a smaller minimum slope rounds to no rise at all
    and leaves the flats flat (where its top-down accumulation then stops); SAGA's default 0.1
    degree also steepens real slopes gentler than 0.1 degree (valley floors, meadows). One
    float32 step per cell only orders the cells of a flat by their distance from its outlet,
    which is what our flat routing does (breadth-first distance to the outlet). Scripts/
    validate_with_saga.sh computes the same value with gdalinfo and awk."""
    ds = gdal.Open(dem)
    band = ds.GetRasterBand(1)
    lo, hi = band.ComputeRasterMinMax(False)
    gt = ds.GetGeoTransform()
    zmax = max(abs(lo), abs(hi), 1.0)
    ulp = 2.0 ** (math.floor(math.log2(zmax)) - 23)
    cell = min(abs(gt[1]), abs(gt[5]))
    return max(0.001, math.degrees(math.atan(ulp / cell)))


def run(saga, args, log):
    """Runs `saga_cmd -f=q args...`; appends its output to `log` (a list). Returns the exit
    status and the seconds it took."""
    t0 = time.time()
    proc = subprocess.run([saga, "-f=q", *[str(a) for a in args]], stdout=subprocess.PIPE,
                          stderr=subprocess.STDOUT, text=True, timeout=600,
                          env=dict(os.environ, LC_ALL="C"))
    log.append("$ saga_cmd " + " ".join(str(a) for a in args) + "\n" + proc.stdout)
    return proc.returncode, time.time() - t0


def fill_and_accumulate(saga, dem, work, methods, convergence=1.1, min_slope=None):
    """Fill Sinks (Wang & Liu) on `dem`, then Flow Accumulation (Top-Down) with each METHOD in
    `methods` (cell area units, no contour-length weights), all written as GeoTIFFs in `work`.
    Returns ({method: path}, {step: seconds}, log text, min slope used); the dict of paths is
    empty if a step failed (the log says why)."""
    if min_slope is None:
        min_slope = min_slope_degrees(dem)
    log, seconds, paths = [], {}, {}
    filled = os.path.join(work, "saga_filled.tif")
    rc, seconds["fill"] = run(saga, ["ta_preprocessor", 4, "-ELEV", dem, "-FILLED", filled,
                                     "-MINSLOPE", "%.6g" % min_slope], log)
    if rc != 0 or not os.path.exists(filled):
        return {}, seconds, "\n".join(log), min_slope
    for method in methods:
        out = os.path.join(work, "saga_acc_%d.tif" % method)
        rc, seconds["method %d" % method] = run(
            saga, ["ta_hydrology", 0, "-ELEVATION", filled, "-FLOW", out, "-METHOD", method,
                   "-CONVERGENCE", convergence, "-MFD_CONTOUR", 0, "-FLOW_UNIT", 1], log)
        if rc != 0 or not os.path.exists(out):
            return {}, seconds, "\n".join(log), min_slope
        paths[method] = out
    return paths, seconds, "\n".join(log), min_slope


def read_grid(path, like=None):
    """A single-band raster as float64, GDAL order (row 0 = north), NaN for nodata; and the
    problems found when `like` (a path) is given and the grid differs from it."""
    ds = gdal.Open(path)
    band = ds.GetRasterBand(1)
    a = band.ReadAsArray().astype(np.float64)
    nodata = band.GetNoDataValue()
    if nodata is not None and not math.isnan(nodata):
        a[a == nodata] = np.nan
    problems = []
    if like is not None:
        ref = gdal.Open(like)
        if (ds.RasterXSize, ds.RasterYSize) != (ref.RasterXSize, ref.RasterYSize):
            problems.append("%s is %dx%d, %s %dx%d" % (path, ds.RasterXSize, ds.RasterYSize,
                                                       like, ref.RasterXSize, ref.RasterYSize))
        elif not np.allclose(ds.GetGeoTransform(), ref.GetGeoTransform()):
            problems.append("%s geotransform %s != %s" % (path, ds.GetGeoTransform(),
                                                          ref.GetGeoTransform()))
    return a, problems


def ranks(values):
    """Ranks 0..n-1 of `values`, tied values sharing their mean rank (for Spearman's rho)."""
    order = np.argsort(values, kind="stable")
    sorted_values = values[order]
    first = np.r_[True, sorted_values[1:] != sorted_values[:-1]]
    group = np.cumsum(first) - 1
    starts = np.flatnonzero(first)
    ends = np.r_[starts[1:], len(values)]
    mean_rank = (starts + ends - 1) / 2.0
    out = np.empty(len(values))
    out[order] = mean_rank[group]
    return out


def spearman(a, b):
    """Spearman's rank correlation of two 1-D arrays (Pearson's r of their ranks)."""
    return float(np.corrcoef(ranks(a), ranks(b))[0, 1])


def compare(ours, peer, cells):
    """Statistics of peer / ours - 1 over the boolean mask `cells`: n, median and 90th percentile
    of |relative difference|, share within 5 %, Spearman's rho."""
    o, p = ours[cells], peer[cells]
    rel = np.abs(p / o - 1.0)
    return {"n": int(cells.sum()), "median": float(np.median(rel)),
            "p90": float(np.percentile(rel, 90)), "within5": float((rel <= 0.05).mean()),
            "spearman": spearman(o, p)}
