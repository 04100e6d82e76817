#!/usr/bin/python3
"""`terroir generate features`: Weiss (2015)'s feature curves from the command line.

Runs the shipped example (Examples/FeatureCurves/ridge_and_valley.geojson), checks the heights
the curves prescribe, the saved curves, a .vtp round trip, a base DEM kept outside the
envelopes, and that bad curves files are refused with one line naming the file, a non-zero exit
and no output. Run by CTest with /usr/bin/python3 (env TERROIR_BIN_DIR, TERROIR_DATA_DIR,
TERROIR_TEMP_DIR).
"""
import json
import os
import shutil
import subprocess
import tempfile
import unittest

import numpy as np

BIN = os.path.join(os.environ.get("TERROIR_BIN_DIR", "build/bin"), "terroir")
TEMP = os.environ.get("TERROIR_TEMP_DIR", tempfile.gettempdir())
HERE = os.path.dirname(os.path.abspath(__file__))
EXAMPLE = os.path.join(HERE, "..", "..", "Examples", "FeatureCurves", "ridge_and_valley.geojson")


def terroir(*args):
    return subprocess.run([BIN, *args], capture_output=True, text=True, timeout=600)


def read_vti(path):
    import vtk
    from vtk.util.numpy_support import vtk_to_numpy
    reader = vtk.vtkXMLImageDataReader()
    reader.SetFileName(path)
    reader.Update()
    image = reader.GetOutput()
    nx, ny, _ = image.GetDimensions()
    pd = image.GetPointData()
    return {pd.GetArrayName(k): vtk_to_numpy(pd.GetArray(k)).reshape(ny, nx)
            for k in range(pd.GetNumberOfArrays())}


def line(coordinates, **properties):
    return {"type": "Feature", "properties": properties,
            "geometry": {"type": "LineString", "coordinates": coordinates}}


def collection(*features):
    return {"type": "FeatureCollection", "features": list(features)}


class GenerateFeatures(unittest.TestCase):
    def setUp(self):
        self.work = tempfile.mkdtemp(prefix="features-", dir=TEMP)

    def tearDown(self):
        shutil.rmtree(self.work, ignore_errors=True)

    def path(self, name):
        return os.path.join(self.work, name)

    def write_json(self, name, value):
        with open(self.path(name), "w") as f:
            json.dump(value, f)
        return self.path(name)

    def test_example_runs_and_holds_its_curves(self):
        out, vtp = self.path("rv.vti"), self.path("rv.vtp")
        r = terroir("generate", "features", out, "--curves", EXAMPLE, "--width", "256",
                    "--height", "256", "--spacing", "20", "--base-elevation", "200",
                    "--save-curves", vtp)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("features 256 x 256: 3 curves", r.stdout)
        a = read_vti(out)
        e, kind = a["Elevation"], a["FeatureKind"]
        self.assertEqual(e.shape, (256, 256))
        # Control points on plateaus: (1800, 2100) m at 880 m; the mesa's 520 m; the valley's
        # first point (500, 4300) at 260 m (alpha = 0.9 lets a plateau sag a little).
        self.assertEqual(kind[105, 90], 1)
        self.assertAlmostEqual(float(e[105, 90]), 880.0, delta=3.0)
        self.assertAlmostEqual(float(e[37, 220]), 520.0, delta=3.0)
        self.assertAlmostEqual(float(e[215, 25]), 260.0, delta=3.0)
        # Far from every envelope the ground is the base elevation, exactly.
        self.assertEqual(float(e[0, 255]), 200.0)
        # The ridge falls away: 300 m beside its crest it is lower by about tan(30 deg) x 250 m.
        self.assertLess(float(e[120, 80]), float(e[105, 90]) - 100.0)
        # The saved curves give the same terrain (a .vtp round trip).
        out2 = self.path("rv2.vti")
        r = terroir("generate", "features", out2, "--curves", vtp, "--width", "256",
                    "--height", "256", "--spacing", "20", "--base-elevation", "200")
        self.assertEqual(r.returncode, 0, r.stderr)
        np.testing.assert_array_equal(read_vti(out2)["Elevation"], e)

    def test_straight_ridge_profile(self):
        # A ridge along x = 320 m across a 65 x 9 grid of 10 m: a hard plateau is not on the
        # command line, so alpha = 0.9: the plateau sits within centimetres of 100 m and the
        # slope falls 10 m per cell (45 degrees), ending about 200 m from the plateau.
        curves = self.write_json("ridge.geojson", collection(
            line([[320, -5000, 100], [320, 5000, 100]], plateau_width=100, slope=45,
                 slope_width=200)))
        out = self.path("ridge.vti")
        r = terroir("generate", "features", out, "--curves", curves, "--width", "65",
                    "--height", "9", "--spacing", "10", "--tolerance", "1e-5")
        self.assertEqual(r.returncode, 0, r.stderr)
        row = read_vti(out)["Elevation"][4].astype(float)
        self.assertTrue(np.all(np.abs(row[27:38] - 100.0) < 0.6), row[27:38])
        steps = row[37:48] - row[38:49]
        np.testing.assert_allclose(steps, 10.0, atol=0.05)
        np.testing.assert_allclose(row[::-1], row, atol=1e-3)

    def test_over_a_base_dem(self):
        """--base: the DEM's grid and world coordinates (UTM); far from the curve the DEM's
        heights are kept exactly, on the curve's plateau the curve's elevation holds."""
        dem = os.path.join(os.environ.get("TERROIR_DATA_DIR", os.path.join(HERE, "..", "..", "Data")),
                           "sagehen_creek_ca", "sagehen_dem_utm11n_10m.tif")
        # Origin 213985, 4366475 (UTM 11N), 786 x 720 cells of 10 m.
        outside = self.write_json("outside.geojson", collection(
            line([[0, 0, 10], [100, 0, 10]], envelope=10)))
        ridge = self.write_json("ridge.geojson", collection(
            line([[217000, 4369000, 2500], [219000, 4370000, 2500]], plateau_width=40,
                 slope=30, slope_width=150, envelope=200)))
        base, out = self.path("base.vti"), self.path("out.vti")
        for curves, path in ((outside, base), (ridge, out)):
            r = terroir("generate", "features", path, "--curves", curves, "--base", dem)
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertIn("features 786 x 720", r.stdout)
        b, e = read_vti(base)["Elevation"], read_vti(out)["Elevation"]
        # The segment runs from cell (i, j) = (301.5, 252.5) to (501.5, 352.5); its midpoint
        # (218000, 4369500) is cell (401.5, 302.5).
        self.assertAlmostEqual(float(e[302, 401]), 2500.0, delta=10.0)
        self.assertGreater(float(e[302, 401]) - float(b[302, 401]), 100.0)
        # Cells more than plateau + slope + envelope (370 m = 37 cells) from the segment keep
        # the DEM's heights: every row below 210 and every column left of 260.
        np.testing.assert_array_equal(e[:210, :], b[:210, :])
        np.testing.assert_array_equal(e[:, :260], b[:, :260])
        self.assertGreater(int(np.sum(e != b)), 5000)

    def test_bad_curves_files_are_refused(self):
        cases = {
            "notjson.geojson": ("{ not json", "not JSON"),
            "point.geojson": (json.dumps(collection(
                {"type": "Feature", "properties": {},
                 "geometry": {"type": "Point", "coordinates": [1, 2]}})),
                "feature 0: not a LineString feature"),
            "short.geojson": (json.dumps(collection(line([[0, 0, 5]]))),
                              "feature 0: a curve needs at least two points"),
            "count.geojson": (json.dumps(collection(
                line([[0, 0], [10, 0], [20, 0]], elevation=[1, 2]))),
                "feature 0: 'elevation' has 2 values for 3 points"),
            "noz.geojson": (json.dumps(collection(line([[0, 0], [10, 0]]))),
                            "feature 0: no 'elevation' property and no third coordinate"),
            "steep.geojson": (json.dumps(collection(line([[0, 0, 1], [10, 0, 1]], slope=90))),
                              "curve 0, point 0: slope angles must be within (-90, 90) degrees"),
            "empty.geojson": (json.dumps(collection()), "no LineString features"),
            "bad.vtp": ("<VTKFile>", "not a VTK polydata file with lines"),
        }
        for name, (text, message) in cases.items():
            with self.subTest(name=name):
                curves = self.path(name)
                with open(curves, "w") as f:
                    f.write(text)
                out = self.path("out.tif")
                r = terroir("generate", "features", out, "--curves", curves, "--width", "16",
                            "--height", "16")
                self.assertNotEqual(r.returncode, 0)
                lines = [l for l in r.stderr.splitlines() if l.strip()]
                self.assertEqual(len(lines), 1, r.stderr)
                self.assertIn(curves + ": " + message, lines[0])
                self.assertFalse(os.path.exists(out))
                self.assertEqual(sorted(os.listdir(self.work)), [name])
                os.remove(curves)
        r = terroir("generate", "features", self.path("out.tif"), "--curves",
                    self.path("missing.geojson"))
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("missing.geojson: cannot be read", r.stderr)
        r = terroir("generate", "features", self.path("out.tif"))
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("--curves", r.stderr)


    def test_view_draws_the_curves(self):
        """`terroir view --curves`: the curves are drawn over the terrain (red lines), and a
        bad curves file is refused before the window opens. Needs an X display (xvfb-run)."""
        if not os.environ.get("DISPLAY"):
            if os.environ.get("TERROIR_REQUIRE_GPU") == "1":
                self.fail("TERROIR_REQUIRE_GPU=1 but DISPLAY is unset")
            self.skipTest("no DISPLAY (run under xvfb-run -a)")
        import vtk
        from vtk.util.numpy_support import vtk_to_numpy
        dem = self.path("rv.tif")
        r = terroir("generate", "features", dem, "--curves", EXAMPLE, "--width", "128",
                    "--height", "128", "--spacing", "40", "--base-elevation", "200")
        self.assertEqual(r.returncode, 0, r.stderr)
        red = {}
        for name, extra in (("with", ["--curves", EXAMPLE]), ("without", [])):
            script = self.path(name + ".txt")
            with open(script, "w") as f:
                f.write("wait\nscreenshot %s\nquit\n" % self.path(name + ".png"))
            r = terroir("view", dem, "--script", script, "--size", "640x480", *extra)
            self.assertEqual(r.returncode, 0, r.stderr)
            reader = vtk.vtkPNGReader()
            reader.SetFileName(self.path(name + ".png"))
            reader.Update()
            image = reader.GetOutput()
            scalars = image.GetPointData().GetScalars()
            rgb = vtk_to_numpy(scalars).astype(int).reshape(-1, scalars.GetNumberOfComponents())
            red[name] = int(np.sum((rgb[:, 0] > 170) & (rgb[:, 1] < 80) & (rgb[:, 2] < 80)))
        # The compass arrow is red in both; the curves add hundreds of red pixels.
        self.assertGreater(red["with"] - red["without"], 300, red)
        bad = self.path("bad.geojson")
        with open(bad, "w") as f:
            f.write("{}")
        r = terroir("view", dem, "--curves", bad, "--script", self.path("with.txt"))
        self.assertNotEqual(r.returncode, 0)
        lines = [l for l in r.stderr.splitlines() if l.strip()]
        self.assertEqual(len(lines), 1, r.stderr)
        self.assertIn(bad + ": expected a GeoJSON FeatureCollection", lines[0])


if __name__ == "__main__":
    unittest.main()
