#!/usr/bin/python3
"""`terroir generate riverland` (Jensen 2011's RiverLand, vtkTerroirRiverLandSource): a good run
with its files, the same bits for a seed and on 1 or 2 threads, a bad --params key refused with
one line and no output, and the scenes of his figures (Examples/RiverLand/*.json) reproduced
from their parameter files.

Run by CTest with /usr/bin/python3 (env TERROIR_BIN_DIR, TERROIR_TEMP_DIR).
"""
import glob
import json
import os
import shutil
import subprocess
import tempfile
import unittest

import numpy as np

BIN = os.path.join(os.environ.get("TERROIR_BIN_DIR", "build/bin"), "terroir")
TEMP = os.environ.get("TERROIR_TEMP_DIR", tempfile.gettempdir())
SCENES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "Examples",
                      "RiverLand")


def terroir(*args):
    return subprocess.run([BIN, *args], capture_output=True, text=True, timeout=600)


def scene(name):
    """The parameters of Examples/RiverLand/NAME."""
    with open(os.path.join(SCENES, name)) as f:
        return json.load(f)


def read_vti(path):
    """Every point array of a .vti, as numpy arrays by name."""
    import vtk
    from vtk.util.numpy_support import vtk_to_numpy
    reader = vtk.vtkXMLImageDataReader()
    reader.SetFileName(path)
    reader.Update()
    pd = reader.GetOutput().GetPointData()
    return {pd.GetArrayName(k): vtk_to_numpy(pd.GetArray(k)) for k in range(pd.GetNumberOfArrays())}


class GenerateRiverLand(unittest.TestCase):
    def setUp(self):
        self.work = tempfile.mkdtemp(prefix="riverland-", dir=TEMP)

    def tearDown(self):
        shutil.rmtree(self.work, ignore_errors=True)

    def path(self, name):
        return os.path.join(self.work, name)

    def run_scene(self, params, name):
        """Writes `params` to NAME.json and generates NAME.vti from it; its arrays."""
        with open(self.path(name + ".json"), "w") as f:
            json.dump(params, f)
        r = terroir("generate", "riverland", self.path(name + ".vti"), "--params",
                    self.path(name + ".json"))
        self.assertEqual(r.returncode, 0, r.stderr)
        return read_vti(self.path(name + ".vti"))

    def test_good_run_seeds_threads_and_files(self):
        """A run writes the elevation, the river map and the river lines; the river lines
        run through river cells; the same seed on 1 and 2 threads gives the same bytes, another
        seed another terrain; the sea is below 0 m and river mouths are at 0 m."""
        a, b, c = self.path("a.vti"), self.path("b.vti"), self.path("c.vti")
        rivers, lines = self.path("rivers.tif"), self.path("rivers.geojson")
        r = terroir("generate", "riverland", a, "--seed", "3", "--width", "160", "--height",
                    "128", "--spacing", "20", "--rivers", "6", "--river-map", rivers,
                    "--river-lines", lines)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertRegex(r.stdout, r"riverland 160 x 128, seed 3: land [0-9.]+ %, [0-9]+ rivers")
        self.assertTrue(os.path.exists(rivers))
        r = terroir("generate", "riverland", b, "--seed", "3", "--width", "160", "--height",
                    "128", "--spacing", "20", "--rivers", "6", "--threads", "2")
        self.assertEqual(r.returncode, 0, r.stderr)
        za, zb = read_vti(a), read_vti(b)
        for name in ("Elevation", "River", "RiverId", "MedialAxis", "DistanceToRiver",
                     "CellClass", "SlopeWeight"):
            self.assertIn(name, za)
            self.assertEqual(za[name].tobytes(), zb[name].tobytes(), name)
        r = terroir("generate", "riverland", c, "--seed", "4", "--width", "160", "--height",
                    "128", "--spacing", "20", "--rivers", "6")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertNotEqual(read_vti(c)["Elevation"].tobytes(), za["Elevation"].tobytes())
        z, cls, river = za["Elevation"], za["CellClass"], za["River"]
        self.assertTrue(np.all(z[cls == 0] < 0))
        self.assertTrue(np.all(z[cls == 1] >= 0))
        self.assertTrue(np.array_equal(river == 1, cls == 3))
        with open(lines) as f:
            collection = json.load(f)
        self.assertGreaterEqual(len(collection["features"]), 6)
        heights = z.reshape(128, 160)
        for feature in collection["features"]:
            coordinates = feature["geometry"]["coordinates"]
            cells = [(int(round(y / 20.0)), int(round(x / 20.0))) for x, y in coordinates]
            for j, i in cells:
                self.assertEqual(river[j * 160 + i], 1)
            along = [heights[j, i] for j, i in cells]
            if feature["properties"]["parent"] < 0:
                self.assertEqual(along[0], 0.0)  # the mouth
            self.assertTrue(all(q > p for p, q in zip(along, along[1:])), "rising inland")

    def test_bad_params_key_is_one_line_and_no_output(self):
        """An unknown key (or an island-only option) is a usage error naming the file and the
        key, and no file is written."""
        params, out = self.path("bad.json"), self.path("bad.tif")
        with open(params, "w") as f:
            json.dump({"seed": 2, "hill_slop": 0.5}, f)
        r = terroir("generate", "riverland", out, "--params", params)
        self.assertEqual(r.returncode, 2)
        self.assertEqual(r.stderr.strip(),
                         "terroir: error: %s: unknown parameter 'hill_slop'" % params)
        self.assertFalse(os.path.exists(out))
        with open(params, "w") as f:
            json.dump({"slopes": [{"profile": "custom", "curve": [[0, 0]]}]}, f)
        r = terroir("generate", "riverland", out, "--params", params)
        self.assertEqual(r.returncode, 2)
        self.assertEqual(len(r.stderr.strip().splitlines()), 1)
        self.assertIn("2 to 64 points", r.stderr)
        self.assertFalse(os.path.exists(out))
        r = terroir("generate", "riverland", out, "--regions", "50")
        self.assertEqual(r.returncode, 2)
        self.assertFalse(os.path.exists(out))

    def test_placed_in_a_crs(self):
        """With --crs the GeoTIFF is georeferenced (north up, the first cell's centre at
        --origin) and the river lines carry the CRS, every vertex on a river cell of the
        georeferenced river map."""
        from osgeo import gdal
        gdal.UseExceptions()
        out, lines, rivers = self.path("geo.tif"), self.path("geo.geojson"), self.path("r.tif")
        r = terroir("generate", "riverland", out, "--width", "96", "--height", "80", "--rivers",
                    "4", "--crs", "EPSG:32631", "--origin", "600000,4100000", "--river-lines",
                    lines, "--river-map", rivers)
        self.assertEqual(r.returncode, 0, r.stderr)
        ds = gdal.Open(out)
        gt = ds.GetGeoTransform()
        self.assertEqual(gt, (600000 - 15.0, 30.0, 0.0, 4100000 + 79.5 * 30.0, 0.0, -30.0))
        self.assertIn("32631", ds.GetSpatialRef().GetAuthorityCode(None))
        river_ds = gdal.Open(rivers)  # kept open while its band is read
        river = river_ds.GetRasterBand(1).ReadAsArray()  # row 0 north
        with open(lines) as f:
            collection = json.load(f)
        self.assertEqual(collection["crs"]["properties"]["name"], "EPSG:32631")
        self.assertGreater(len(collection["features"]), 0)
        for feature in collection["features"]:
            for x, y in feature["geometry"]["coordinates"]:
                row, col = int((gt[3] - y) // 30.0), int((x - gt[0]) // 30.0)
                self.assertEqual(river[row, col], 1)

    def test_params_file_and_command_line(self):
        """The parameter file gives what the same options give; an option wins over it."""
        params = {"seed": 6, "width": 96, "height": 80, "rivers": 4}
        with_file = self.run_scene(params, "file")
        r = terroir("generate", "riverland", self.path("opts.vti"), "--seed", "6", "--width",
                    "96", "--height", "80", "--rivers", "4")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(read_vti(self.path("opts.vti"))["Elevation"].tobytes(),
                         with_file["Elevation"].tobytes())
        r = terroir("generate", "riverland", self.path("wins.vti"), "--params",
                    self.path("file.json"), "--seed", "7")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("seed 7", r.stdout)
        self.assertNotEqual(read_vti(self.path("wins.vti"))["Elevation"].tobytes(),
                            with_file["Elevation"].tobytes())

    def test_every_scene_file_runs(self):
        """Every Examples/RiverLand scene runs and applies all its user slopes."""
        scenes = sorted(glob.glob(os.path.join(SCENES, "*.json")))
        self.assertGreaterEqual(len(scenes), 3)
        for path in scenes:
            slopes = len(scene(os.path.basename(path)).get("slopes", []))
            out = self.path(os.path.basename(path).replace(".json", ".tif"))
            r = terroir("generate", "riverland", out, "--params", path)
            self.assertEqual(r.returncode, 0, path + ": " + r.stderr)
            self.assertIn("user slopes %d" % slopes, r.stdout, path)

    def test_figure13_two_slopes_blend_where_they_overlap(self):
        """Figure 13: each slope alone changes only the cells it influences; together, their
        weights add up, cells under one slope only are as with that slope alone, and the cells
        under both (there are some) take a height blended from both (2.4.3)."""
        figure = scene("figure13_blended_slopes.json")
        both = self.run_scene(figure, "both")
        alone = []
        for k in range(2):
            p = dict(figure, slopes=[figure["slopes"][k]])
            alone.append(self.run_scene(p, "alone%d" % k))
        plain = self.run_scene(dict(figure, slopes=[]), "plain")
        w0, w1, w = (alone[0]["SlopeWeight"], alone[1]["SlopeWeight"], both["SlopeWeight"])
        for a in alone:
            untouched = a["SlopeWeight"] == 0
            np.testing.assert_array_equal(a["Elevation"][untouched], plain["Elevation"][untouched])
            self.assertGreater(int(np.count_nonzero(a["Elevation"] != plain["Elevation"])), 100)
        np.testing.assert_allclose(w, w0 + w1, rtol=1e-6)
        only0, only1, overlap = (w0 > 0) & (w1 == 0), (w1 > 0) & (w0 == 0), (w0 > 0) & (w1 > 0)
        self.assertGreater(int(np.count_nonzero(overlap)), 50)
        np.testing.assert_array_equal(both["Elevation"][only0], alone[0]["Elevation"][only0])
        np.testing.assert_array_equal(both["Elevation"][only1], alone[1]["Elevation"][only1])
        changed = overlap & (both["Elevation"] != alone[0]["Elevation"]) & (
            both["Elevation"] != alone[1]["Elevation"])
        self.assertGreater(int(np.count_nonzero(changed)), 50)

    def test_figure17_pruning_frees_the_slope(self):
        """Figure 17: pruning only removes medial-axis cells (those left are a subset of the
        unpruned ones, the removed ones marked 2), and the user slope's influence reaches more
        cells once the spurious ridges are gone."""
        pruned = self.run_scene(scene("figure17_pruning.json"), "pruned")
        unpruned = self.run_scene(scene("figure17_no_pruning.json"), "unpruned")
        kept, before = pruned["MedialAxis"] == 1, unpruned["MedialAxis"] == 1
        self.assertTrue(np.all(before[kept]))
        np.testing.assert_array_equal(pruned["MedialAxis"] == 2, before & ~kept)
        self.assertLess(int(np.count_nonzero(kept)), int(np.count_nonzero(before)))
        self.assertGreater(int(np.count_nonzero(pruned["SlopeWeight"] > 0)),
                           int(np.count_nonzero(unpruned["SlopeWeight"] > 0)))


if __name__ == "__main__":
    unittest.main()
