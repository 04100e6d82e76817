#!/usr/bin/python3
"""Command-line contract of `terroir`: outputs, one-line errors, no partial output, overwrite.

Run by CTest with /usr/bin/python3 (env TERROIR_BIN_DIR, TERROIR_DATA_DIR, TERROIR_TEMP_DIR).
Expected values come from GDAL (python3-gdal) reading the written files and from gdaldem.
"""
import json
import os
import shutil
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
        for cmd in ([], ["run"], ["slope"], ["temperature"], ["bench"], ["info"], ["fractal"]):
            r = terroir(*cmd, "--help")
            self.assertEqual(r.returncode, 0, (cmd, r.stderr))
            self.assertIn("Usage", r.stdout + r.stderr)

    def test_run_writes_every_output_and_report(self):
        out = os.path.join(self.work, "out")
        args = ["run", "--out", out, "--backend", "cpu"]
        if not os.environ.get("DISPLAY"):
            args.append("--no-png")
        r = terroir(*args)
        self.assertEqual(r.returncode, 0, r.stderr)
        expected = ["terrain.vti", "slope.tif", "aspect.tif", "temperature.tif", "report.md", "report.json"]
        if os.environ.get("DISPLAY"):
            expected += ["slope.png", "temperature_jan.png", "temperature_jul.png"]
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
        stages = sorted(x["stage"] for x in bench["results"])
        self.assertEqual(stages, ["slope", "temperature"])
        self.assertTrue(all(x["seconds"] > 0 for x in bench["results"]))

    def test_terragen_input(self):
        ter = os.path.join(DATA, "sagehen_creek_ca", "sagehen_dem_utm11n_10m.ter")
        r = terroir("info", ter)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("786 x 720", r.stdout)


if __name__ == "__main__":
    unittest.main(verbosity=2)
