#!/usr/bin/python3
"""Command-line contract of `terroir`: outputs, one-line errors, no partial output, overwrite.

Run by CTest with /usr/bin/python3 (env TERROIR_BIN_DIR, TERROIR_DATA_DIR, TERROIR_TEMP_DIR).
Expected values come from GDAL (python3-gdal) reading the written files and from gdaldem.
The PNGs of `terroir run` need an X display (VTK 9.1 renders through X; `xvfb-run -a`): without
DISPLAY the run gets --no-png and the PNGs are not checked (a message says so), unless
TERROIR_REQUIRE_GPU=1, which fails the test instead.
"""
import json
import re
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import unittest

import numpy as np
from osgeo import gdal

gdal.UseExceptions()
BIN = os.path.join(os.environ.get("TERROIR_BIN_DIR", "build/bin"), "terroir")
DATA = os.environ.get("TERROIR_DATA_DIR", "Data")
DEM = os.path.join(DATA, "sagehen_creek_ca", "sagehen_dem_utm11n_10m.tif")
TEMP = os.environ.get("TERROIR_TEMP_DIR", tempfile.gettempdir())


def read_band(path, band=1):
    """Band `band` of a raster as an array (the dataset stays open while the band is read)."""
    ds = gdal.Open(path)
    return ds.GetRasterBand(band).ReadAsArray()


def read_vti(path):
    """Every point array of a .vti (VTK's reader), as numpy arrays by name."""
    import vtk
    from vtk.util.numpy_support import vtk_to_numpy
    reader = vtk.vtkXMLImageDataReader()
    reader.SetFileName(path)
    reader.Update()
    pd = reader.GetOutput().GetPointData()
    return {pd.GetArrayName(k): vtk_to_numpy(pd.GetArray(k)) for k in range(pd.GetNumberOfArrays())}


def terroir(*args, env=None):
    e = dict(os.environ)
    e.update(env or {})
    return subprocess.run([BIN, *args], capture_output=True, text=True, env=e, timeout=600)


class TerroirCommandLine(unittest.TestCase):
    def setUp(self):
        self.work = tempfile.mkdtemp(prefix="cli-", dir=TEMP)

    def tearDown(self):
        shutil.rmtree(self.work, ignore_errors=True)

    def test_help_on_every_command(self):
        for cmd in ([], ["run"], ["slope"], ["temperature"], ["illumination"], ["kmeans"], ["bench"],
                    ["info"], ["fractal"]):
            r = terroir(*cmd, "--help")
            self.assertEqual(r.returncode, 0, (cmd, r.stderr))
            self.assertIn("Usage", r.stdout + r.stderr)

    def test_run_writes_every_output_and_report(self):
        out = os.path.join(self.work, "out")
        args = ["run", "--out", out, "--backend", "cpu"]
        if not os.environ.get("DISPLAY"):
            if os.environ.get("TERROIR_REQUIRE_GPU") == "1":
                self.fail("TERROIR_REQUIRE_GPU=1 but DISPLAY is unset: the PNGs cannot be checked")
            print("no X display: run with --no-png, the PNGs are not checked", file=sys.stderr)
            args.append("--no-png")
        r = terroir(*args)
        self.assertEqual(r.returncode, 0, r.stderr)
        expected = ["terrain.vti", "slope.tif", "aspect.tif", "temperature.tif", "illumination.tif",
                    "insolation.tif", "infiltration.tif", "humidity.tif", "weighted_humidity.tif",
                    "standing_water.tif", "lakes.tif", "rivers.tif", "discharge.tif",
                    "clusters.tif", "clusters.csv",
                    "clusters.json", "report.md", "report.json"]
        if os.environ.get("DISPLAY"):
            expected += ["slope.png", "temperature_jan.png", "temperature_jul.png",
                         "illumination_dec.png", "illumination_jun.png", "insolation_dec.png",
                         "insolation_jun.png", "humidity_jan.png", "humidity_jul.png", "lakes.png",
                         "rivers.png", "rivers_relief.png", "validation.png", "clusters.png"]
        for name in expected:
            path = os.path.join(out, name)
            self.assertTrue(os.path.getsize(path) > 0, name)
        # No temporary files are left behind.
        self.assertEqual(sorted(os.listdir(out)), sorted(expected))
        with open(os.path.join(out, "report.json")) as f:
            report = json.load(f)
        self.assertEqual(report["grid"]["nx"], 786)
        self.assertEqual(report["grid"]["ny"], 720)
        self.assertAlmostEqual(report["georeference"]["center_lat"], 39.43, delta=0.05)
        self.assertEqual(report["stages"]["slope"]["backend"], "CPU")
        # The slope GeoTIFF keeps the input's georeference and agrees with gdaldem.
        src = gdal.Open(DEM)
        slope = gdal.Open(os.path.join(out, "slope.tif"))
        self.assertEqual(slope.RasterXSize, src.RasterXSize)
        np.testing.assert_allclose(slope.GetGeoTransform(), src.GetGeoTransform())
        ref = gdal.DEMProcessing(os.path.join(self.work, "ref.tif"), DEM, "slope", computeEdges=True)
        a = slope.GetRasterBand(1).ReadAsArray().astype(np.float64)
        b = ref.GetRasterBand(1).ReadAsArray().astype(np.float64)
        self.assertLess(np.nanmax(np.abs(a - b)), 0.01)
        # Temperature: 12 bands; July colder than January nowhere (northern hemisphere defaults).
        temp = gdal.Open(os.path.join(out, "temperature.tif"))
        self.assertEqual(temp.RasterCount, 12)
        jan = temp.GetRasterBand(1).ReadAsArray()
        jul = temp.GetRasterBand(7).ReadAsArray()
        self.assertTrue(np.all(jul > jan))
        # Monthly illumination: 12 bands each; more sun in June than in December on average,
        # and the report gives the stage's time with the horizon map's share of it.
        stage = report["stages"]["illumination"]
        self.assertGreater(stage["seconds"], 0)
        self.assertGreater(stage["horizon_map_seconds"], 0)
        self.assertLess(stage["horizon_map_seconds"], stage["seconds"])
        self.assertEqual(stage["horizon_sectors"], 64)
        self.assertIn("IlluminationHours", report["arrays"])
        self.assertEqual(report["arrays"]["Insolation"]["units"], "Wh/m2")
        with open(os.path.join(out, "report.md")) as f:
            self.assertIn("horizon map of 64 sectors built in", f.read())
        hours = gdal.Open(os.path.join(out, "illumination.tif"))
        energy = gdal.Open(os.path.join(out, "insolation.tif"))
        self.assertEqual((hours.RasterCount, energy.RasterCount), (12, 12))
        for ds in (hours, energy):
            dec = ds.GetRasterBand(12).ReadAsArray().astype(np.float64)
            jun = ds.GetRasterBand(6).ReadAsArray().astype(np.float64)
            self.assertGreater(jun.mean(), 1.3 * dec.mean())
        self.assertLessEqual(hours.GetRasterBand(6).ReadAsArray().max(), 24.0)
        # Soil water with the defaults: 15 mm/h, 0 on slopes over 30 degrees; absorbed plus
        # standing water is the month's rain (60 mm in January); lakes: Independence Lake.
        rates = gdal.Open(os.path.join(out, "infiltration.tif")).ReadAsArray()
        self.assertEqual(set(np.unique(rates)), {0.0, 15.0})
        np.testing.assert_array_equal(rates == 0.0, a > 30.0)
        sh = gdal.Open(os.path.join(out, "humidity.tif"))
        sw = gdal.Open(os.path.join(out, "standing_water.tif"))
        self.assertEqual((sh.RasterCount, sw.RasterCount), (12, 12))
        total = sh.GetRasterBand(1).ReadAsArray() + sw.GetRasterBand(1).ReadAsArray()
        np.testing.assert_allclose(total, 60.0, atol=1e-4)
        self.assertGreaterEqual(report["stages"]["lakes"]["water_bodies"], 1)
        depth = gdal.Open(os.path.join(out, "lakes.tif")).ReadAsArray()
        self.assertTrue(np.all(depth >= 0.0))
        # Rivers (river-forming water flow): the river mask holds the report's river cells, each
        # carrying the rain (0.3 mm/h) of at least 0.1 km2; the outflow balanced the rain; the
        # rivers score against the bundled NHD lines (validation.md: F1 0.820 within 60 m).
        rs = report["stages"]["rivers"]
        self.assertEqual(rs["stop_reason"], "Balanced")
        # The coarse-to-fine start: 786 x 720 averaged to 393 x 360 and 197 x 180 (a 128-cell
        # side is the coarsest), coarsest first; the grid settled 100 iterations at least.
        levels = rs["warm_start_levels"]
        self.assertEqual([(l["nx"], l["ny"]) for l in levels], [(197, 180), (393, 360)])
        self.assertGreaterEqual(levels[1]["iterations"], 100)
        self.assertGreaterEqual(rs["iterations"], 100)
        rivers = gdal.Open(os.path.join(out, "rivers.tif")).ReadAsArray()
        rate = gdal.Open(os.path.join(out, "discharge.tif")).ReadAsArray().astype(np.float64)
        self.assertEqual(int((rivers == 1).sum()), rs["river_cells"])
        self.assertEqual(set(np.unique(rivers)), {0, 1})
        least = 1e5 * 0.3e-3 / 3600.0
        self.assertTrue(np.all(rate[rivers == 1] >= least * (1 - 1e-6)))
        # No cell carries more than the rain on the whole grid.
        self.assertLessEqual(np.nanmax(rate), 786 * 720 * 100.0 * 0.3e-3 / 3600.0)
        self.assertGreaterEqual(rs["lakes"], 1)
        v = rs["validation"]["scores"][1]
        self.assertEqual(v["tolerance_m"], 60.0)
        self.assertGreaterEqual(v["f1"], 0.81)
        # Ecological zones, K = 5 on the four resources: the zone raster, the table's counts
        # and its mean slopes agree with what GDAL reads from clusters.tif and slope.tif.
        ids = gdal.Open(os.path.join(out, "clusters.tif")).ReadAsArray()
        with open(os.path.join(out, "clusters.json")) as f:
            zones = json.load(f)
        self.assertEqual(report["clusters"]["iterations"], zones["iterations"])
        self.assertEqual(zones["collapsed_arrays"], ["Temperature"])
        band = src.GetRasterBand(1)  # src (the DEM) stays open while its band is read
        heights = band.ReadAsArray().astype(np.float64)
        valid = np.isfinite(heights)
        if band.GetNoDataValue() is not None:
            valid &= heights != band.GetNoDataValue()
        self.assertEqual(len(zones["clusters"]), 5)
        self.assertTrue(np.all(ids[~valid] == -1))
        self.assertAlmostEqual(sum(z["Share"] for z in zones["clusters"]), 1.0, places=12)
        for z in zones["clusters"]:
            members = ids == z["ClusterId"]
            self.assertEqual(int(members.sum()), z["Cells"])
            self.assertAlmostEqual(z["Cells"] / valid.sum(), z["Share"], places=12)
            self.assertAlmostEqual(float(a[members].mean()), z["Slope"], delta=1e-4)
        with open(os.path.join(out, "clusters.csv")) as f:
            header = f.readline().strip().split(",")
        self.assertEqual(header[:5], ["ClusterId", "Color", "Cells", "Share", "Slope"])
        self.assertEqual(len(header), 4 + 1 + 12 * 3)
        self.assertIn("Temperature_Jul", header)
        with open(os.path.join(out, "report.md")) as f:
            self.assertIn("Ecological zones (k-means, K = 5", f.read())
        # Where writing goes: every output but the two reports (written after the stage), once,
        # by kind; the files' seconds add up to the writing's busy seconds, the kinds' to
        # theirs; what the run waited for after computing is part of its wall time.
        write = report["stages"]["write"]
        written = [f["file"] for f in write["files"]]
        self.assertEqual(sorted(written),
                         sorted(n for n in expected if n not in ("report.md", "report.json")))
        kinds = {"vti": ".vti", "geotiff": ".tif", "png": ".png", "text": (".csv", ".json")}
        for f in write["files"]:
            self.assertTrue(f["file"].endswith(kinds[f["kind"]]), f)
            self.assertGreater(f["seconds"], 0.0)
        self.assertAlmostEqual(sum(f["seconds"] for f in write["files"]), write["busy_seconds"],
                               places=9)
        for kind, seconds in write["seconds_by_kind"].items():
            self.assertAlmostEqual(
                seconds, sum(f["seconds"] for f in write["files"] if f["kind"] == kind), places=9)
        self.assertGreaterEqual(write["seconds"], 0.0)
        self.assertLess(write["seconds"], report["wall_seconds"])
        compute = sum(report["stages"][s]["seconds"] for s in
                      ("read", "slope", "temperature", "illumination", "infiltration", "humidity",
                       "lakes", "rivers", "clusters"))
        self.assertLessEqual(compute + write["seconds"], report["wall_seconds"] * (1 + 1e-9))
        # terrain.vti (LZ4, raw appended) holds the same slope as slope.tif, north row last.
        slope_vti = read_vti(os.path.join(out, "terrain.vti"))["Slope"].reshape(720, 786)
        np.testing.assert_array_equal(slope_vti[::-1], slope.GetRasterBand(1).ReadAsArray())

    def test_run_writes_the_outputs_asked_for_in_the_layout_asked_for(self):
        # --outputs takes a stage (slope: slope.tif, aspect.tif), files (one named twice) and a
        # kind; the reports always come. The GeoTIFFs: DEFLATE, 256 x 256 tiles, overviews 2 and
        # 4 (720 / 2 >= 256).
        out = os.path.join(self.work, "some")
        r = terroir("run", "--out", out, "--no-png", "--backend", "cpu", "--outputs",
                    "slope,slope.tif,clusters.csv,vti", "--vti-compression", "zlib",
                    "--tiff-compression", "deflate", "--tiff-layout", "tiles", "--tiff-threads",
                    "2", "--tiff-overviews")
        self.assertEqual(r.returncode, 0, r.stderr)
        expected = ["slope.tif", "aspect.tif", "clusters.csv", "terrain.vti", "report.md",
                    "report.json"]
        self.assertEqual(sorted(os.listdir(out)), sorted(expected))
        with open(os.path.join(out, "report.json")) as f:
            report = json.load(f)
        self.assertEqual(sorted(os.path.basename(p) for p in report["outputs"]), sorted(expected))
        self.assertEqual(sorted(f["file"] for f in report["stages"]["write"]["files"]),
                         sorted(n for n in expected if not n.startswith("report")))
        ds = gdal.Open(os.path.join(out, "slope.tif"))
        self.assertEqual(ds.GetMetadata("IMAGE_STRUCTURE")["COMPRESSION"], "DEFLATE")
        band = ds.GetRasterBand(1)
        self.assertEqual(band.GetBlockSize(), [256, 256])
        self.assertEqual(band.GetOverviewCount(), 2)
        # The same slope whatever the layout: as gdaldem computes it, as terrain.vti holds it.
        ref = gdal.DEMProcessing(os.path.join(self.work, "ref.tif"), DEM, "slope",
                                 computeEdges=True)
        a = band.ReadAsArray().astype(np.float64)
        self.assertLess(np.nanmax(np.abs(a - ref.GetRasterBand(1).ReadAsArray())), 0.01)
        zlib = read_vti(os.path.join(out, "terrain.vti"))
        np.testing.assert_array_equal(zlib["Slope"].reshape(720, 786)[::-1], band.ReadAsArray())
        # terrain.vti with each compressor: the same bytes in every array.
        for compressor in ("lz4", "none"):
            other = os.path.join(self.work, "vti-" + compressor)
            r = terroir("run", "--out", other, "--no-png", "--backend", "cpu", "--outputs", "vti",
                        "--vti-compression", compressor)
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertEqual(sorted(os.listdir(other)), ["report.json", "report.md", "terrain.vti"])
            arrays = read_vti(os.path.join(other, "terrain.vti"))
            self.assertEqual(sorted(arrays), sorted(zlib))
            for name, values in zlib.items():
                self.assertEqual(arrays[name].tobytes(), values.tobytes(), name)
        # --no-vti drops terrain.vti even when --outputs names it.
        none = os.path.join(self.work, "none")
        r = terroir("run", "--out", none, "--no-png", "--no-vti", "--outputs", "vti,tables")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(sorted(os.listdir(none)),
                         ["clusters.csv", "clusters.json", "report.json", "report.md"])
        # A name that is no file, stage or kind: one line, exit 1, nothing written.
        bad = os.path.join(self.work, "bad")
        r = terroir("run", "--out", bad, "--no-png", "--outputs", "slope,rivres")
        self.assertEqual(r.returncode, 1)
        self.assertIn("--outputs: 'rivres' is not a file, stage or kind of this run", r.stderr)
        self.assertEqual(len(r.stderr.strip().splitlines()), 1, r.stderr)
        self.assertEqual(os.listdir(bad), [])

    def test_run_interrupted_leaves_the_folder_as_it_was(self):
        # Every output goes into place at the end of the run: while it runs the folder holds
        # only hidden temporaries, also of the files already written (slope.tif, aspect.tif,
        # then temperature.tif: three at once). SIGTERM then leaves no output and no temporary.
        out = os.path.join(self.work, "stopped")
        os.makedirs(out)
        proc = subprocess.Popen([BIN, "run", "--out", out, "--no-png", "--backend", "cpu"],
                                stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        hidden, shown = [], []
        while proc.poll() is None and len(hidden) < 3 and not shown:
            names = os.listdir(out)
            hidden = [n for n in names if n.startswith(".")]
            shown += [n for n in names if not n.startswith(".")]
        proc.terminate()
        _, err = proc.communicate(timeout=60)
        self.assertEqual(shown, [], "outputs in place before the run ended")
        self.assertEqual(len(hidden), 3, "the run ended before three files were written: " +
                         err.decode())
        self.assertEqual(proc.returncode, -signal.SIGTERM, err.decode())
        self.assertEqual(os.listdir(out), [], "seen while running: %s" % hidden)

    def test_soil_water_and_lake_commands(self):
        rates = os.path.join(self.work, "rates.tif")
        watershed = os.path.join(os.path.dirname(DEM), "sagehen_watershed_utm11n.geojson")
        r = terroir("infiltration", DEM, rates, "--fill", "15", "--paint-polygons",
                    watershed + "=4", "--slope-rule", "30")
        self.assertEqual(r.returncode, 0, r.stderr)
        rate = gdal.Open(rates).ReadAsArray()
        mask = gdal.Open(os.path.join(os.path.dirname(DEM),
                                      "sagehen_watershed_mask_utm11n_10m.tif")).ReadAsArray()
        slope_ds = gdal.DEMProcessing(os.path.join(self.work, "s.tif"), DEM, "slope",
                                      computeEdges=True)
        slope = slope_ds.ReadAsArray()
        # The shipped watershed mask was burnt by gdal_rasterize from the same polygon.
        expected = np.where(slope > 30.0, 0.0, np.where(mask == 1, 4.0, 15.0))
        self.assertLess(np.mean(rate != expected), 1e-3)
        h, w = (os.path.join(self.work, n) for n in ("h.tif", "w.tif"))
        r = terroir("humidity", DEM, h, "--infiltration", rates, "--weighted", w, "--precip",
                    "10,20,30,40,50,60,70,80,90,100,110,120", "--intensity", "8,8,8,8,8,8,8,8,8,8,8,8")
        self.assertEqual(r.returncode, 0, r.stderr)
        sh = gdal.Open(h)
        self.assertEqual(sh.RasterCount, 12)
        for m in (0, 6, 11):
            got = sh.GetRasterBand(m + 1).ReadAsArray()
            np.testing.assert_allclose(got, np.minimum(rate / 8.0, 1.0) * 10.0 * (m + 1), atol=1e-4)
        lake = os.path.join(self.work, "lake.tif")
        r = terroir("floodfill", DEM, lake, "--seed", "215375,4371215")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("2117.80", r.stdout)
        ids = os.path.join(self.work, "ids.tif")
        r = terroir("floodfill", DEM, os.path.join(self.work, "lakes.tif"), "--fill-depressions",
                    "--ids", ids)
        self.assertEqual(r.returncode, 0, r.stderr)
        body = gdal.Open(ids).ReadAsArray()
        self.assertGreaterEqual(np.count_nonzero(body), 23000)  # Independence Lake and more

    def test_kmeans_command(self):
        # A bare DEM: Slope and Temperature are computed first (a note says so). Weight 4 on
        # the only feature gives the same zones and 4 times the within-cluster sum of squares
        # (the distance is sum w (x - y)^2).
        one, four = os.path.join(self.work, "one.tif"), os.path.join(self.work, "four.vti")
        csv, js = os.path.join(self.work, "z.csv"), os.path.join(self.work, "z.json")
        r = terroir("kmeans", DEM, one, "-k", "3", "--features", "Slope", "--csv", csv,
                    "--json", js, "--backend", "cpu")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("has no resource arrays", r.stdout)
        self.assertIn("K = 3", r.stdout)
        r = terroir("kmeans", DEM, four, "-k", "3", "--features", "Slope:4", "--backend", "cpu",
                    "--json", os.path.join(self.work, "four.json"))
        self.assertEqual(r.returncode, 0, r.stderr)
        with open(js) as f:
            a = json.load(f)
        with open(os.path.join(self.work, "four.json")) as f:
            b = json.load(f)
        self.assertEqual([z["Cells"] for z in a["clusters"]], [z["Cells"] for z in b["clusters"]])
        self.assertAlmostEqual(b["within_cluster_sum_of_squares"],
                               4.0 * a["within_cluster_sum_of_squares"],
                               delta=1e-5 * b["within_cluster_sum_of_squares"])
        # The .vti it wrote is a terrain with Slope and Temperature: read back as the input,
        # it gives the zones of the first run (same arrays, same features) without computing
        # them again.
        again = os.path.join(self.work, "again.json")
        r = terroir("kmeans", four, os.path.join(self.work, "again.tif"), "-k", "3",
                    "--features", "Slope", "--json", again, "--backend", "cpu")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertNotIn("has no resource arrays", r.stdout)
        with open(again) as f:
            c = json.load(f)
        self.assertEqual([z["Cells"] for z in a["clusters"]], [z["Cells"] for z in c["clusters"]])
        # A file named .vti that is not one: one line naming it, exit 1, no output.
        bad = os.path.join(self.work, "bad.vti")
        with open(bad, "w") as f:
            f.write("not xml\n")
        out = os.path.join(self.work, "never.tif")
        r = terroir("kmeans", bad, out, "-k", "3")
        self.assertEqual(r.returncode, 1, r.stderr)
        self.assertIn(bad, r.stderr)
        self.assertEqual(len(r.stderr.strip().splitlines()), 1, r.stderr)
        self.assertFalse(os.path.exists(out))
        with open(csv) as f:
            rows = [line.strip().split(",") for line in f]
        self.assertEqual(rows[0], ["ClusterId", "Color", "Cells", "Share", "Slope", "Temperature_Jan",
                                   "Temperature_Feb", "Temperature_Mar", "Temperature_Apr",
                                   "Temperature_May", "Temperature_Jun", "Temperature_Jul",
                                   "Temperature_Aug", "Temperature_Sep", "Temperature_Oct",
                                   "Temperature_Nov", "Temperature_Dec"][:5])
        self.assertEqual(len(rows), 4)
        ids = gdal.Open(one).ReadAsArray()
        self.assertEqual(sorted(np.unique(ids[ids >= 0]).tolist()), [0, 1, 2])
        self.assertEqual([int((ids == k).sum()) for k in range(3)],
                         [int(row[2]) for row in rows[1:]])
        # Zones ordered as their diagonal seeds; mean slopes are the members' mean.
        slope = gdal.DEMProcessing(os.path.join(self.work, "s.tif"), DEM, "slope",
                                   computeEdges=True).ReadAsArray().astype(np.float64)
        for row in rows[1:]:
            members = ids == int(row[0])
            self.assertAlmostEqual(float(slope[members].mean()), float(row[4]), delta=0.01)

    def test_morphometry_command(self):
        # The bundled DEM: the printed table, --json that parses and agrees with the table,
        # --csv equal to the JSON's per-order table, OUT .tif with the StrahlerOrder band.
        js, csv = os.path.join(self.work, "m.json"), os.path.join(self.work, "h.csv")
        tif = os.path.join(self.work, "order.tif")
        r = terroir("morphometry", DEM, tif, "--json", js, "--csv", csv)
        self.assertEqual(r.returncode, 0, r.stderr)
        with open(js) as f:
            m = json.load(f)
        self.assertEqual(m["valid_cells"], 786 * 720)
        self.assertIn("hypsometric integral      %.4f" % m["hypsometric_integral"], r.stdout)
        self.assertAlmostEqual(m["drainage"]["channel_area_m2"], 1e5)
        self.assertEqual(sum(m["slope_deg"]["histogram"]), m["valid_cells"])
        self.assertEqual(len(m["slope_deg"]["histogram"]), 18)
        orders = m["horton"]["orders"]
        self.assertEqual([o["order"] for o in orders], list(range(1, len(orders) + 1)))
        self.assertEqual(m["horton"]["orders_fitted"], [1, len(orders) - 1])
        self.assertAlmostEqual(sum(o["total_length_m"] for o in orders) / 1e3,
                               m["drainage"]["channel_length_km"], places=6)
        with open(csv) as f:
            rows = [line.strip().split(",") for line in f]
        self.assertEqual(rows[0], ["order", "streams", "mean_length_m", "total_length_m"])
        self.assertEqual([int(x[1]) for x in rows[1:]], [o["streams"] for o in orders])
        order = read_band(tif)
        self.assertEqual(int((order > 0).sum()), m["drainage"]["channel_cells"])
        self.assertEqual(int(order.max()), len(orders))
        # A larger threshold: fewer channel cells, a lower drainage density; --depression-depth
        # 1 km: no cell is that deep.
        r = terroir("morphometry", DEM, "--json", os.path.join(self.work, "big.json"),
                    "--channel-area", "1e6", "--depression-depth", "1000")
        self.assertEqual(r.returncode, 0, r.stderr)
        with open(os.path.join(self.work, "big.json")) as f:
            big = json.load(f)
        self.assertLess(big["drainage"]["drainage_density_km_per_km2"],
                        m["drainage"]["drainage_density_km_per_km2"])
        self.assertEqual(big["closed_depressions"]["cells"], 0)
        self.assertEqual(big["closed_depressions"]["depth_threshold_m"], 1000)
        # Without outputs it only prints; an existing --json is kept without --overwrite.
        before = os.path.getmtime(js)
        r = terroir("morphometry", DEM, "--json", js)
        self.assertEqual(r.returncode, 1)
        self.assertEqual(r.stderr.strip().splitlines()[-1],
                         "terroir: error: %s: exists; pass --overwrite to replace it" % js)
        self.assertEqual(os.path.getmtime(js), before)
        r = terroir("morphometry", DEM)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("Horton R_b / R_l", r.stdout)

    def test_erosion_command(self):
        # The bundled DEM, 20 steps: the printed volumes; OUT .tif is the bed after them, which
        # differs from the DEM where water ran (a film of 5 cm on Weiss's capacity erodes), and
        # whose sum moved by less than what was eroded; bad options are one line, exit 2.
        tif = os.path.join(self.work, "eroded.tif")
        r = terroir("erosion", DEM, tif, "--steps", "20", "--capacity-depth", "0.5")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertRegex(r.stdout, r"erosion: 20 steps; eroded [0-9.e+]+ m3, deposited")
        eroded = float(r.stdout.split("eroded ")[1].split(" m3")[0])
        before, after = read_band(DEM), read_band(tif)
        self.assertEqual(after.shape, before.shape)
        self.assertGreater(float(np.abs(after - before).max()), 0.01)
        self.assertLess(float((before - after).sum()) * 100.0, eroded)  # 10 m cells: 100 m2
        # Dunn's weather: water evaporates (raised for effect) and the line says how much.
        r = terroir("erosion", DEM, os.path.join(self.work, "w.tif"), "--steps", "5",
                    "--weather", "--evaporation-scale", "1e5")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertRegex(r.stdout, r"weather: evaporated [0-9.e+]+ m3 from the water")
        self.assertGreater(float(r.stdout.split("weather: evaporated ")[1].split(" ")[0]), 0.0)
        for bad in (["--sea", "high"], ["--steps", "-1"], ["--talus", "90"],
                    ["--wind-strength", "-1"]):
            r = terroir("erosion", DEM, os.path.join(self.work, "x.tif"), *bad)
            self.assertEqual(r.returncode, 2, bad)  # a usage error
            self.assertEqual(len(r.stderr.strip().splitlines()), 1, r.stderr)
            self.assertFalse(os.path.exists(os.path.join(self.work, "x.tif")))

    def test_plants_command(self):
        # Zones of a 64 x 48 grid of 10 m cells written as a ClusterId GeoTIFF (west half zone
        # 0, east half zone 1, a no-data column): a hard-core pattern (5 m) at 0.01 plants per
        # m2 puts about 0.01 x 15200 m2 in each zone, no two plants of a zone closer than 5 m,
        # and none in the no-data column; the same from an exemplar CSV whose points lie on
        # its bounds (the window); a bad exemplar row is one line naming the file and the line.
        import vtk
        from osgeo import gdal_array
        from vtk.util.numpy_support import vtk_to_numpy
        zones = np.zeros((48, 64), dtype=np.float32)
        zones[:, 32:] = 1.0
        zones[:, 0] = np.nan
        tif = os.path.join(self.work, "zones.tif")
        ds = gdal_array.SaveArray(zones, tif, format="GTiff")
        ds.SetGeoTransform((500000.0, 10.0, 0.0, 4300000.0, 0.0, -10.0))
        ds = None
        out = os.path.join(self.work, "plants.csv")
        r = terroir("plants", tif, out, "--seed", "3")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertRegex(r.stdout, r"plants: [0-9]+ plants in 2 zones \(hard core\)")
        rows = np.loadtxt(out, delimiter=",", skiprows=1, ndmin=2)
        with open(out) as f:
            self.assertEqual(f.readline().strip(), "x,y,z,species,cluster_id")
        for zone, cells in ((0, 31 * 48), (1, 32 * 48)):
            mine = rows[rows[:, 4] == zone]
            self.assertAlmostEqual(len(mine) / (0.01 * cells * 100.0), 1.0, delta=0.15)
            d = np.hypot(mine[:, None, 0] - mine[None, :, 0], mine[:, None, 1] - mine[None, :, 1])
            np.fill_diagonal(d, np.inf)
            self.assertGreaterEqual(d.min(), 5.0 - 1e-9)
        self.assertGreater(rows[:, 0].min(), 500000.0 + 10.0)  # the no-data column stays empty
        exemplar = os.path.join(self.work, "exemplar.csv")
        with open(exemplar, "w") as f:
            f.write("x,y,species\n" + "".join("%d,%d,%d\n" % (8 * (k % 8), 8 * (k // 8), k % 2)
                                              for k in range(64)))
        vtp = os.path.join(self.work, "plants.vtp")
        r = terroir("plants", tif, vtp, "--exemplar", exemplar)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("(learned from", r.stdout)
        reader = vtk.vtkXMLPolyDataReader()
        reader.SetFileName(vtp)
        reader.Update()
        species = vtk_to_numpy(reader.GetOutput().GetPointData().GetArray("Species"))
        self.assertEqual(set(species.tolist()), {0, 1})
        with open(exemplar, "a") as f:
            f.write("3,4,99\n")
        r = terroir("plants", tif, os.path.join(self.work, "x.vtp"), "--exemplar", exemplar)
        self.assertEqual(r.returncode, 1)
        self.assertEqual(r.stderr.strip().splitlines()[-1], "terroir: error: " + exemplar +
                         ": line 66: species '99' is not a whole number in 0..63")
        self.assertFalse(os.path.exists(os.path.join(self.work, "x.vtp")))
        r = terroir("plants", tif, os.path.join(self.work, "x.vtp"), "--exemplar-window",
                    "0", "1", "0", "1")
        self.assertEqual(r.returncode, 2)

    def test_existing_outputs_are_kept_without_overwrite(self):
        out = os.path.join(self.work, "slope.tif")
        with open(out, "w") as f:
            f.write("precious")
        r = terroir("slope", DEM, out)
        self.assertEqual(r.returncode, 1)
        self.assertIn("--overwrite", r.stderr)
        with open(out) as f:
            self.assertEqual(f.read(), "precious")
        r = terroir("slope", DEM, out, "--overwrite")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(gdal.Open(out).RasterCount, 1)

    def test_bad_input_is_one_line_error_and_no_output(self):
        bad = os.path.join(self.work, "broken.tif")
        with open(bad, "wb") as f:
            f.write(b"II*\x00this is not a tiff")
        out = os.path.join(self.work, "o.tif")
        for path in (bad, os.path.join(self.work, "missing.tif")):
            r = terroir("slope", path, out)
            self.assertEqual(r.returncode, 1)
            lines = [l for l in r.stderr.splitlines() if l.strip()]
            self.assertEqual(len(lines), 1, r.stderr)
            self.assertTrue(lines[0].startswith("terroir: error: "), lines[0])
            self.assertIn(os.path.basename(path), lines[0])
            self.assertFalse(os.path.exists(out))
        self.assertEqual(sorted(os.listdir(self.work)), ["broken.tif"])

    def test_network_paths_refused_by_default(self):
        r = terroir("info", "/vsicurl/https://example.com/dem.tif")
        self.assertEqual(r.returncode, 1)
        self.assertIn("vsicurl", r.stderr)

    def test_progress_is_plain_lines_when_not_a_terminal(self):
        out = os.path.join(self.work, "s.tif")
        r = terroir("slope", DEM, out)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertNotIn("\r", r.stderr)
        self.assertIn("slope: 100%", r.stderr)

    def test_temperature_command_monthly_values(self):
        out = os.path.join(self.work, "t.tif")
        monthly = ",".join(str(v) for v in range(12))
        r = terroir("temperature", DEM, out, "--monthly", monthly, "--lapse-rate", "5")
        self.assertEqual(r.returncode, 0, r.stderr)
        dem = gdal.Open(DEM)
        z = dem.GetRasterBand(1).ReadAsArray().astype(np.float64)
        t = gdal.Open(out)
        for m in (0, 6, 11):
            got = t.GetRasterBand(m + 1).ReadAsArray().astype(np.float64)
            np.testing.assert_allclose(got, m - 5.0 * z / 1000.0, atol=1e-3)
        # A bad command line is a usage error (exit status 2), found before any work is done.
        r = terroir("temperature", DEM, os.path.join(self.work, "u.tif"), "--monthly", "1,2,3")
        self.assertEqual(r.returncode, 2)
        self.assertEqual(r.stderr, "terroir: error: --monthly: expected 12 values, got 3\n")

    def test_generate_island_from_options_and_a_params_file(self):
        """`terroir generate island`: the same seed gives the same bytes, a --params file gives
        what the same options give and an option on the command line wins over it; the .vti
        keeps every array, the sea is below 0 m and the highest cell at --max-height; a bad
        key is a usage error naming the file."""
        a, b, c = (os.path.join(self.work, n) for n in ("a.tif", "b.tif", "c.vti"))
        r = terroir("generate", "island", a, "--seed", "5", "--width", "96", "--height", "80",
                    "--regions", "200", "--max-height", "700")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertRegex(r.stdout, r"island 96 x 80, seed 5: land [0-9.]+ %")
        params = os.path.join(self.work, "island.json")
        with open(params, "w") as f:
            json.dump({"seed": 5, "width": 96, "height": 80, "regions": 200, "max_height": 700,
                       "rivers": 3}, f)
        r = terroir("generate", "island", b, "--params", params, "--rivers", "0")
        self.assertEqual(r.returncode, 0, r.stderr)
        za, zb = read_band(a), read_band(b)
        np.testing.assert_array_equal(za, zb)
        self.assertEqual(float(za.max()), 700.0)
        self.assertLess(float(za[0, 0]), 0.0)  # the map's corner is sea
        r = terroir("generate", "island", c, "--params", params)
        self.assertEqual(r.returncode, 0, r.stderr)
        arrays = read_vti(c)
        for name in ("Elevation", "Biome", "Moisture", "River", "WaterClass", "RegionId"):
            self.assertIn(name, arrays)
        self.assertEqual(int(np.count_nonzero(arrays["WaterClass"] == 2)) > 0, True)
        # Placed in a projected CRS: a georeferenced GeoTIFF, and the rivers as GeoJSON lines in
        # that CRS, each running downhill between two cells of the generated River map.
        e, lines = os.path.join(self.work, "e.tif"), os.path.join(self.work, "rivers.geojson")
        r = terroir("generate", "island", e, "--params", params, "--crs", "EPSG:32631",
                    "--origin", "600000,4100000", "--river-lines", lines)
        self.assertEqual(r.returncode, 0, r.stderr)
        ds = gdal.Open(e)
        gt = ds.GetGeoTransform()
        self.assertEqual(gt, (600000 - 15.0, 30.0, 0.0, 4100000 + 79.5 * 30.0, 0.0, -30.0))
        self.assertIn("32631", ds.GetSpatialRef().GetAuthorityCode(None))
        z = ds.GetRasterBand(1).ReadAsArray()  # row 0 north
        with open(lines) as f:
            collection = json.load(f)
        self.assertEqual(collection["crs"]["properties"]["name"], "EPSG:32631")
        self.assertGreater(len(collection["features"]), 0)
        for feature in collection["features"]:
            (x0, y0), (x1, y1) = feature["geometry"]["coordinates"]
            rows = [int((gt[3] - y) // 30.0) for y in (y0, y1)]
            cols = [int((x - gt[0]) // 30.0) for x in (x0, x1)]
            self.assertLessEqual(z[rows[1], cols[1]], z[rows[0], cols[0]] + 1e-3)
            self.assertGreater(feature["properties"]["river_flow"], 0)
        with open(params, "w") as f:
            json.dump({"seed": 5, "hieght": 80}, f)
        r = terroir("generate", "island", os.path.join(self.work, "d.tif"), "--params", params)
        self.assertEqual(r.returncode, 2)
        self.assertEqual(r.stderr.strip(),
                         "terroir: error: %s: unknown parameter 'hieght'" % params)
        self.assertFalse(os.path.exists(os.path.join(self.work, "d.tif")))

    def test_the_placeholder_climate_is_announced(self):
        """Issue 24 item 7: a run on the default climate (the filters' illustrative year) says
        so once on stderr after it worked, with the values; any climate option silences it;
        a command that fails prints its one error line and no note."""
        out = os.path.join(self.work, "t.tif")
        r = terroir("temperature", DEM, out)
        self.assertEqual(r.returncode, 0, r.stderr)
        notes = [line for line in r.stderr.splitlines() if line.startswith("terroir: note:")]
        self.assertEqual(notes, [
            "terroir: note: the temperatures come from a placeholder climate (sea level 2 \u00b0C "
            "in the coldest month, 20 \u00b0C in the warmest, 6.4 \u00b0C/km), not this site's: "
            "give --coldest/--warmest, --monthly or --climate FILE"])
        r = terroir("temperature", DEM, os.path.join(self.work, "t2.tif"), "--coldest", "-3")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertNotIn("note:", r.stderr)
        r = terroir("humidity", DEM, os.path.join(self.work, "h.tif"))
        self.assertEqual(r.returncode, 0, r.stderr)
        notes = [line for line in r.stderr.splitlines() if line.startswith("terroir: note:")]
        self.assertEqual(len(notes), 1, r.stderr)
        self.assertTrue(notes[0].startswith("terroir: note: the precipitation comes from a "
                                            "placeholder climate ("), notes[0])
        r = terroir("humidity", DEM, os.path.join(self.work, "h2.tif"),
                    "--precip", ",".join(["50"] * 12), "--intensity", ",".join(["2"] * 12))
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertNotIn("note:", r.stderr)
        r = terroir("temperature", DEM, out)  # exists: fails, one line
        self.assertEqual(r.returncode, 1)
        self.assertEqual(len(r.stderr.splitlines()), 1, r.stderr)
        self.assertIn("error", r.stderr)

    def test_temperature_from_a_climate_file(self):
        # The same 12 sea-level temperatures from a CSV climate table and from --monthly give
        # the same raster; a table without temperature_c is refused before any work.
        monthly = [-2, -1.5, 1, 4, 8, 12, 16, 15.5, 12, 7, 2, -1]
        names = ["Jan", "Feb", "Mar", "Apr", "May", "Jun", "Jul", "Aug", "Sep", "Oct", "Nov", "Dec"]
        climate = os.path.join(self.work, "climate.csv")
        with open(climate, "w") as f:
            f.write("month,temperature_c\n")
            for name, t in reversed(list(zip(names, monthly))):
                f.write(f"{name},{t}\n")
        a, b = os.path.join(self.work, "a.tif"), os.path.join(self.work, "b.tif")
        r = terroir("temperature", DEM, a, "--climate", climate)
        self.assertEqual(r.returncode, 0, r.stderr)
        r = terroir("temperature", DEM, b, "--monthly", ",".join(str(t) for t in monthly))
        self.assertEqual(r.returncode, 0, r.stderr)
        da, db = gdal.Open(a), gdal.Open(b)  # keep the datasets alive while their bands are read
        for band in (1, 7, 12):
            np.testing.assert_array_equal(da.GetRasterBand(band).ReadAsArray(),
                                          db.GetRasterBand(band).ReadAsArray())
        rain = os.path.join(self.work, "rain.json")
        with open(rain, "w") as f:
            json.dump({"precipitation_mm": [50] * 12, "intensity_mm_per_h": [2] * 12}, f)
        out = os.path.join(self.work, "c.tif")
        r = terroir("temperature", DEM, out, "--climate", rain)
        self.assertEqual(r.returncode, 1)
        self.assertEqual(r.stderr, f"terroir: error: {rain}: no temperature_c values "
                                   "(needed by the temperature model)\n")
        self.assertFalse(os.path.exists(out))

    def test_fractal_is_seeded_and_bench_reports_every_stage(self):
        a, b, c = (os.path.join(self.work, n) for n in ("a.tif", "b.tif", "c.tif"))
        for path, seed in ((a, "3"), (b, "3"), (c, "4")):
            r = terroir("fractal", path, "--size", "96", "--seed", seed, "--spacing", "5")
            self.assertEqual(r.returncode, 0, r.stderr)
        ds = [gdal.Open(p) for p in (a, b, c)]
        za, zb, zc = (d.GetRasterBand(1).ReadAsArray() for d in ds)
        self.assertEqual(za.shape, (96, 96))
        self.assertEqual(ds[0].GetGeoTransform()[1], 5.0)
        np.testing.assert_array_equal(za, zb)
        self.assertGreater(np.max(np.abs(za - zc)), 1.0)
        r = terroir("bench", "--size", "64", "--repeat", "1", "--backends", "cpu",
                    "--json", os.path.join(self.work, "bench.json"))
        self.assertEqual(r.returncode, 0, r.stderr)
        with open(os.path.join(self.work, "bench.json")) as f:
            bench = json.load(f)
        stages = [x["stage"] for x in bench["results"]]
        self.assertEqual(stages, ["slope", "temperature", "horizon", "instant", "instant-raymarch",
                                  "monthly", "infiltration", "humidity", "humidity-all",
                                  "floodfill", "depressions", "flowacc", "waterflow", "kmeans",
                                  "morphometry"])
        self.assertTrue(all(x["seconds"] > 0 for x in bench["results"]))
        self.assertTrue(all(x["mcells"] == 64 * 64 / 1e6 for x in bench["results"]))
        rows = {x["stage"]: x for x in bench["results"]}
        self.assertEqual(rows["instant"]["horizon_map_seconds"], 0)  # the map came from the cache
        self.assertGreater(rows["monthly"]["horizon_map_seconds"], 0)
        self.assertEqual(rows["monthly"]["sun_steps"], 12 * 144)
        self.assertIn("instant-raymarch", r.stdout)
        # --stages picks stages, and runs them in the fixed order.
        r = terroir("bench", "--size", "32", "--repeat", "1", "--backends", "cpu", "--stages",
                    "monthly,horizon", "--json", os.path.join(self.work, "some.json"))
        self.assertEqual(r.returncode, 0, r.stderr)
        with open(os.path.join(self.work, "some.json")) as f:
            some = json.load(f)
        self.assertEqual([x["stage"] for x in some["results"]], ["horizon", "monthly"])
        self.assertEqual(some["stages"], ["horizon", "monthly"])
        self.assertNotIn("slope", r.stdout)
        # --bandwidth with the waterflow stage: the kernel's time per iteration and its share
        # of the copy bandwidth at 36 bytes per cell, recomputed here from the reported numbers.
        r = terroir("bench", "--size", "64", "--repeat", "1", "--backends", "cpu", "--stages",
                    "waterflow", "--bandwidth", "--json", os.path.join(self.work, "bw.json"))
        self.assertEqual(r.returncode, 0, r.stderr)
        with open(os.path.join(self.work, "bw.json")) as f:
            bw = json.load(f)
        ms = bw["waterflow_kernel_ms_per_iteration"]
        self.assertGreater(ms, 0)
        self.assertGreater(bw["copy_bandwidth_GBps"], 0)
        self.assertAlmostEqual(bw["waterflow_kernel_fraction_of_bandwidth"],
                               36 * 64 * 64 / (ms * 1e-3) / (bw["copy_bandwidth_GBps"] * 1e9),
                               delta=1e-9)
        self.assertIn("water-flow kernel (per iteration, run to the automatic stop)", r.stdout)
        r = terroir("bench", "--stages", "shadows")
        self.assertEqual(r.returncode, 2)
        self.assertEqual(r.stderr, "terroir: error: --stages: 'shadows' is not one of slope, "
                                   "temperature, horizon, instant, monthly, infiltration, humidity, floodfill, "
                                   "depressions, flowacc, waterflow, kmeans, morphometry\n")

    def flat_dem(self, name="flat.tif"):
        """A flat 60 x 50 GeoTIFF at 1900 m near Sagehen Creek (UTM 11N, about 39.5 N)."""
        path = os.path.join(self.work, name)
        ds = gdal.GetDriverByName("GTiff").Create(path, 60, 50, 1, gdal.GDT_Float32)
        ds.SetGeoTransform((734000, 10, 0, 4376000, 0, -10))
        ds.SetProjection("EPSG:32611")
        ds.GetRasterBand(1).WriteArray(np.full((50, 60), 1900, np.float32))
        ds = None
        return path

    def test_illumination_daily_on_flat_ground_is_the_day_length(self):
        # Nothing casts a shadow on flat ground: every cell has the sun for the whole day.
        # NOAA's calculator gives 14 h 53 min between sunrise and sunset at 39.5 N on the June
        # solstice, and 9 h 27 min at 39.5 S (its winter); the filter counts 10-minute steps.
        dem = self.flat_dem()
        north = os.path.join(self.work, "north.tif")
        r = terroir("illumination", dem, north, "--mode", "daily", "--date", "2025-06-21")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("illumination: 100%", r.stderr)
        ds = gdal.Open(north)
        self.assertEqual(ds.RasterCount, 1)
        self.assertEqual(ds.RasterXSize, 60)
        np.testing.assert_allclose(ds.GetRasterBand(1).ReadAsArray(), 14 + 53 / 60, atol=1 / 6)
        south = os.path.join(self.work, "south.tif")
        energy = os.path.join(self.work, "energy.tif")
        r = terroir("illumination", dem, south, "--mode", "daily", "--date", "2025-06-21",
                    "--lat", "-39.5", "--insolation", energy)
        self.assertEqual(r.returncode, 0, r.stderr)
        np.testing.assert_allclose(read_band(south),
                                   9 + 27 / 60, atol=1 / 6)
        # Less sun in winter, and a clearer sky lets more of it through.
        winter = read_band(energy)
        r = terroir("illumination", dem, os.path.join(self.work, "n2.tif"), "--mode", "daily",
                    "--date", "2025-06-21", "--insolation", os.path.join(self.work, "e2.tif"))
        self.assertEqual(r.returncode, 0, r.stderr)
        summer = read_band(os.path.join(self.work, "e2.tif"))
        self.assertGreater(summer.min(), 2 * winter.max())
        r = terroir("illumination", dem, os.path.join(self.work, "n3.tif"), "--mode", "daily",
                    "--date", "2025-06-21", "--transmittance", "0.9", "--insolation",
                    os.path.join(self.work, "e3.tif"))
        self.assertEqual(r.returncode, 0, r.stderr)
        clear = read_band(os.path.join(self.work, "e3.tif"))
        self.assertGreater(clear.min(), summer.max())

    def test_illumination_instant_with_a_fixed_sun(self):
        # --sun AZ,EL: on flat ground everything is lit when the sun is up, with cos(incidence)
        # = sin(elevation), and nothing when it is below the horizon.
        dem = self.flat_dem()
        lit, cos = os.path.join(self.work, "lit.tif"), os.path.join(self.work, "cos.tif")
        r = terroir("illumination", dem, lit, "--mode", "instant", "--sun", "200,30",
                    "--incidence", cos)
        self.assertEqual(r.returncode, 0, r.stderr)
        np.testing.assert_array_equal(read_band(lit), 1)
        np.testing.assert_allclose(read_band(cos), 0.5, atol=1e-5)
        r = terroir("illumination", dem, lit, "--mode", "instant", "--sun", "200,-5", "--overwrite")
        self.assertEqual(r.returncode, 0, r.stderr)
        np.testing.assert_array_equal(read_band(lit), 0)

    def test_illumination_instant_shadows_on_the_bundled_dem(self):
        # 2025-12-21 16:00 PST: the sun is low (6 deg) in the south-west. Slopes facing
        # north-east (aspect from gdaldem) are in shadow, slopes facing it mostly lit; the
        # ray-marching method agrees with the horizon map on nearly every cell.
        common = ["--mode", "instant", "--date", "2025-12-21", "--time", "16:00",
                  "--utc-offset", "-8"]
        out, march = os.path.join(self.work, "shadow.tif"), os.path.join(self.work, "march.tif")
        r = terroir("illumination", DEM, out, *common, "--backend", "cpu")
        self.assertEqual(r.returncode, 0, r.stderr)
        r = terroir("illumination", DEM, march, *common, "--method", "raymarch")
        self.assertEqual(r.returncode, 0, r.stderr)
        lit = read_band(out)
        self.assertEqual(set(np.unique(lit)), {0.0, 1.0})
        marched = read_band(march)
        self.assertGreater(np.mean(lit == marched), 0.99)
        for name in ("aspect", "slope"):
            gdal.DEMProcessing(os.path.join(self.work, name + ".tif"), DEM, name,
                               computeEdges=True)
        aspect = read_band(os.path.join(self.work, "aspect.tif"))
        slope = read_band(os.path.join(self.work, "slope.tif"))
        steep = slope > 10
        facing_away = steep & ((aspect - 8) % 360 < 90)   # north-east: 8..98 deg
        facing_sun = steep & ((aspect - 188) % 360 < 90)  # south-west: 188..278 deg
        self.assertLess(lit[facing_away].mean(), 0.02)
        self.assertGreater(lit[facing_sun].mean(), 0.8)

    def test_illumination_vti_and_monthly_defaults(self):
        from vtkmodules.vtkIOXML import vtkXMLImageDataReader
        out = os.path.join(self.work, "all.vti")
        r = terroir("illumination", DEM, out, "--step", "30", "--day", "21")
        self.assertEqual(r.returncode, 0, r.stderr)
        reader = vtkXMLImageDataReader()
        reader.SetFileName(out)
        reader.Update()
        pd = reader.GetOutput().GetPointData()
        for name in ("Elevation", "IlluminationHours", "Insolation"):
            self.assertIsNotNone(pd.GetArray(name), name)
        self.assertEqual(pd.GetArray("IlluminationHours").GetNumberOfComponents(), 12)
        self.assertEqual(pd.GetArray("IlluminationHours").GetComponentName(11), "Dec")
        sun = reader.GetOutput().GetFieldData().GetArray("SunPositions")
        self.assertEqual(sun.GetNumberOfTuples(), 12 * 48)
        self.assertEqual(sun.GetComponent(0, 1), 21)  # the day of each month asked for

    def test_illumination_errors_are_one_line_and_leave_nothing(self):
        out = os.path.join(self.work, "i.tif")
        ter = os.path.join(DATA, "sagehen_creek_ca", "sagehen_dem_utm11n_10m.ter")
        # No georeference and no --lat/--lon: the filter's error, exit status 1.
        r = terroir("illumination", ter, out)
        self.assertEqual(r.returncode, 1)
        lines = [l for l in r.stderr.splitlines() if l.strip() and not l.endswith("%")]
        self.assertEqual(lines, [f"terroir: error: {ter}: the terrain has no georeference: set "
                                 "Latitude and Longitude (and Orientation, the bearing of grid "
                                 "north)"])
        self.assertEqual(os.listdir(self.work), [])
        # With them, the same file works.
        r = terroir("illumination", ter, out, "--lat", "39.43", "--lon", "-120.24", "--step",
                    "60")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(gdal.Open(out).RasterCount, 12)
        # Bad command lines: exit status 2 before the DEM is read (it does not even exist).
        missing = os.path.join(self.work, "missing.tif")
        for args, message in (
                (["--lat", "91"], "--lat: 91 is outside [-90, 90] (see terroir --help)"),
                (["--mode", "daily", "--date", "2025-02-29"], "--date: 2025-02-29 does not exist"),
                (["--step", "0"], "--step: 0 is outside [1, 1440] (see terroir --help)"),
                (["--mode", "instant"], "--mode instant needs --time HH:MM (or --sun AZ,EL)")):
            r = terroir("illumination", missing, os.path.join(self.work, "o.tif"), *args)
            self.assertEqual(r.returncode, 2, args)
            self.assertEqual(r.stderr, f"terroir: error: {message}\n")
        self.assertEqual(os.listdir(self.work), ["i.tif"])
        # An existing output is kept without --overwrite.
        r = terroir("illumination", DEM, out, "--step", "60")
        self.assertEqual(r.returncode, 1)
        self.assertEqual(r.stderr, f"terroir: error: {out}: exists; pass --overwrite to replace it\n")

    def test_run_without_georeference_skips_illumination(self):
        ter = os.path.join(DATA, "sagehen_creek_ca", "sagehen_dem_utm11n_10m.ter")
        out = os.path.join(self.work, "out")
        r = terroir("run", ter, "--out", out, "--no-png", "--backend", "cpu")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn(f"terroir: warning: {ter}: illumination skipped (the DEM has no "
                      "georeference; pass --lat and --lon)", r.stderr)
        self.assertNotIn("illumination.tif", os.listdir(out))
        with open(os.path.join(out, "report.json")) as f:
            report = json.load(f)
        self.assertIn("skipped", report["stages"]["illumination"])
        self.assertNotIn("IlluminationHours", report["arrays"])

    def test_z_unit_scales_heights_of_a_dem_without_unit_metadata(self):
        # The Shellmound DEM is in feet but says nothing; GDAL gives its exact minimum.
        dem = os.path.join(DATA, "shellmound_ms", "meras_100m_dem.tif")
        ds = gdal.Open(dem)  # the band lives only as long as its dataset
        stats = ds.GetRasterBand(1).ComputeRasterMinMax(False)[0]
        ranges = {}
        for unit in ("auto", "ft", "us-ft"):
            r = terroir("info", dem, "--z-unit", unit)
            self.assertEqual(r.returncode, 0, r.stderr)
            m = re.search(r"elevation \(m\): min (\S+),", r.stdout)
            ranges[unit] = float(m.group(1))
        # `info` prints 10 significant digits of float32 heights.
        self.assertAlmostEqual(ranges["auto"], stats, delta=1e-5)
        self.assertAlmostEqual(ranges["ft"], stats * 0.3048, delta=1e-5)
        self.assertAlmostEqual(ranges["us-ft"], stats * 1200.0 / 3937.0, delta=1e-5)

    def test_terragen_input(self):
        ter = os.path.join(DATA, "sagehen_creek_ca", "sagehen_dem_utm11n_10m.ter")
        r = terroir("info", ter)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("786 x 720", r.stdout)


if __name__ == "__main__":
    unittest.main(verbosity=2)
