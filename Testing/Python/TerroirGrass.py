"""Helpers shared by the tests that compare Terroir with GRASS GIS (TestGrassPeer.py,
TestFlowAccumulationGrass.py): one throwaway GRASS session, and reading its GeoTIFF exports."""
import os
import shutil
import subprocess
import sys
import time

import numpy as np
from osgeo import gdal

failures = []


def check(condition, message):
    """Records a failed check (the test goes on, and finish() reports them all)."""
    if not condition:
        failures.append(message)
        print("FAIL:", message)


def finish(name):
    """Exits 1 when a check failed, else prints "<name>: OK" and exits 0."""
    if failures:
        print("%d failure(s)" % len(failures))
        sys.exit(1)
    print("%s: OK" % name)
    sys.exit(0)


def require_grass():
    """The `grass` program, or exit 1: the peer tests fail (not skip) without it."""
    grass = shutil.which("grass")
    if grass is None:
        print("FAIL: `grass` (GRASS GIS, Debian package grass-core) is not on PATH; this peer "
              "test needs it (CI installs grass-core).")
        sys.exit(1)
    return grass


def run_session(grass, dem, script, work, timeout=600):
    """Runs `bash script` in a temporary GRASS location made from `dem`, with a private HOME and
    no inherited GRASS variables. Returns (log, exit status or "timeout", seconds)."""
    home = os.path.join(work, "home")
    os.makedirs(home, exist_ok=True)
    env = {k: v for k, v in os.environ.items()
           if not (k.startswith("GRASS") or k.startswith("GIS"))}
    env.update(HOME=home, TMPDIR=work, LC_ALL="C", GRASS_VERBOSE="0")
    t0 = time.time()
    try:
        proc = subprocess.run([grass, "--tmp-location", dem, "--exec", "bash", script], env=env,
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                              timeout=timeout)
        log, rc = proc.stdout, proc.returncode
    except subprocess.TimeoutExpired as e:
        log, rc = str(e.output), "timeout"
    return log, rc, time.time() - t0


def read_export(path, nx, ny, ref_gt):
    """A GRASS export as a float64 array in VTK order (row 0 = south), NaN for nodata, and the
    list of problems found (size or geotransform different from the DEM's)."""
    ds = gdal.Open(path)
    problems = []
    if ds.RasterXSize != nx or ds.RasterYSize != ny:
        problems.append("%s size %dx%d" % (path, ds.RasterXSize, ds.RasterYSize))
    if not np.allclose(ds.GetGeoTransform(), ref_gt):
        problems.append("%s geotransform %s != DEM %s" % (path, ds.GetGeoTransform(), ref_gt))
    band = ds.GetRasterBand(1)
    a = band.ReadAsArray().astype(np.float64)
    nodata = band.GetNoDataValue()
    if nodata is not None:
        a[a == nodata] = np.nan
    return a[::-1].copy(), problems  # GDAL rows are north-up; VTK's are south-up
