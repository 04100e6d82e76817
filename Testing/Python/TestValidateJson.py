#!/usr/bin/python3
"""`terroir validate --json` on the bundled Sagehen Creek data.

The reference river cells are counted independently with GDAL (gdal.Rasterize of the NHD lines
and of the watershed polygon onto the DEM's grid); every score is re-derived from the counts in
the JSON (precision = simulated hits / simulated cells, recall = reference hits / reference
cells, F1 their harmonic mean); the length-matching rule gives as many simulated cells as
reference cells (up to ties of the measure); a user threshold is reported as such; the rows of
`--sweep` equal separate runs. The D8 score at 60 m is the one Documentation/validation.md
reports (0.78), kept as a regression guard.
"""
import json
import os
import shutil
import subprocess
import tempfile
import unittest

import numpy as np
from osgeo import gdal, ogr

gdal.UseExceptions()

DATA = os.environ.get("TERROIR_DATA_DIR", os.path.join(os.path.dirname(__file__), "..", "..", "Data"))
BIN = os.path.join(os.environ.get("TERROIR_BIN_DIR", "build/bin"), "terroir")
TEMP = os.environ.get("TERROIR_TEMP_DIR", tempfile.gettempdir())
SAGEHEN = os.path.join(DATA, "sagehen_creek_ca")
DEM = os.path.join(SAGEHEN, "sagehen_dem_utm11n_10m.tif")
LINES = os.path.join(SAGEHEN, "sagehen_nhd_flowlines_utm11n.geojson")
AREA = os.path.join(SAGEHEN, "sagehen_watershed_utm11n.geojson")


def burn(vector, like):
    """The vector file burnt onto the grid of `like` (1 inside/on, 0 elsewhere), GDAL defaults."""
    out = gdal.GetDriverByName("MEM").Create("", like.RasterXSize, like.RasterYSize, 1,
                                             gdal.GDT_Byte)
    out.SetGeoTransform(like.GetGeoTransform())
    out.SetProjection(like.GetProjection())
    src = ogr.Open(vector)
    gdal.RasterizeLayer(out, [1], src.GetLayer(0), burn_values=[1])
    return out.GetRasterBand(1).ReadAsArray().astype(bool)


def valid_cells(ds):
    """The cells of the DEM `ds` with data: finite and not the band's no-data value."""
    band = ds.GetRasterBand(1)
    z = band.ReadAsArray().astype(np.float64)
    valid = np.isfinite(z)
    if band.GetNoDataValue() is not None:
        valid &= z != band.GetNoDataValue()
    return valid


class TerroirValidateJson(unittest.TestCase):
    def setUp(self):
        os.makedirs(TEMP, exist_ok=True)
        self.work = tempfile.mkdtemp(prefix="validate-json-", dir=TEMP)

    def tearDown(self):
        shutil.rmtree(self.work, ignore_errors=True)

    def run_validate(self, *extra):
        path = os.path.join(self.work, "scores.json")
        if os.path.exists(path):
            os.remove(path)
        r = subprocess.run([BIN, "validate", "--json", path, "--backend", "cpu"] + list(extra),
                           capture_output=True, text=True, timeout=600)
        self.assertEqual(r.returncode, 0, r.stderr)
        with open(path) as f:
            return json.load(f), r.stdout

    def check_scores(self, method, reference_cells):
        for s in method["scores"]:
            self.assertEqual(s["reference_cells"], reference_cells)
            p = s["simulated_hits"] / s["simulated_cells"]
            r = s["reference_hits"] / s["reference_cells"]
            self.assertAlmostEqual(s["precision"], p, places=12)
            self.assertAlmostEqual(s["recall"], r, places=12)
            self.assertAlmostEqual(s["f1"], 2 * p * r / (p + r), places=12)
        at30, at60 = method["scores"]
        self.assertEqual((at30["tolerance_m"], at60["tolerance_m"]), (30.0, 60.0))
        # A wider tolerance can only find more matches.
        self.assertGreaterEqual(at60["simulated_hits"], at30["simulated_hits"])
        self.assertGreaterEqual(at60["reference_hits"], at30["reference_hits"])
        self.assertEqual(at30["simulated_cells"], at60["simulated_cells"])

    def test_scores_follow_from_the_counts_and_the_reference_is_gdals(self):
        scores, stdout = self.run_validate()
        ds = gdal.Open(DEM)
        valid = valid_cells(ds)
        reference = burn(LINES, ds) & burn(AREA, ds) & valid
        self.assertEqual(scores["reference_cells"], int(reference.sum()))
        self.assertEqual(scores["dem"], DEM)
        self.assertEqual(scores["mask"], AREA)
        names = [m["name"] for m in scores["methods"]]
        self.assertEqual(names[:2], ["terroir waterflow rivers", "D8"])
        for m in scores["methods"]:
            self.assertTrue(m["length_matched"])
            self.check_scores(m, scores["reference_cells"])
            # Length matching: as many river cells as reference cells, up to ties at the
            # threshold (cells with the same discharge or accumulation), which D8's integer
            # cell counts make common.
            cells = m["scores"][0]["simulated_cells"]
            self.assertLessEqual(abs(cells - scores["reference_cells"]),
                                 0.01 * scores["reference_cells"], m["name"])
        d8 = scores["methods"][1]["scores"][1]
        self.assertGreaterEqual(d8["f1"], 0.75)  # validation.md: 0.782
        self.assertIn("F1@60", stdout)

    def test_a_user_threshold_is_reported_as_such(self):
        scores, _ = self.run_validate("--mode", "pulse", "--river-threshold", "500",
                                      "--max-iterations", "40")
        flow = scores["methods"][0]
        self.assertEqual(flow["name"], "terroir waterflow pulse")
        self.assertFalse(flow["length_matched"])
        self.assertEqual(flow["threshold"], 500.0)
        self.assertGreater(flow["scores"][0]["simulated_cells"], 0)
        self.check_scores(flow, scores["reference_cells"])
        self.assertEqual(scores["water_flow"]["iterations"], 40)

    def test_sweep_rows_equal_separate_runs(self):
        # One row per value, the same scores and thresholds as a run with that value alone;
        # the baselines are scored once.
        sweep, stdout = self.run_validate("--sweep", "rain=0.3,3", "--max-iterations", "150")
        names = [m["name"] for m in sweep["methods"]]
        self.assertEqual(names[:3], ["rain=0.3", "rain=3", "D8"])
        self.assertEqual(names.count("D8"), 1)
        self.assertEqual(sweep["sweep"], {"option": "rain", "values": ["0.3", "3"]})
        self.assertEqual(len(sweep["water_flow_runs"]), 2)
        self.assertIn("rain=3", stdout)
        for row, rain in ((0, "0.3"), (1, "3")):
            alone, _ = self.run_validate("--rain", rain, "--max-iterations", "150")
            self.assertEqual(alone["methods"][0]["threshold"], sweep["methods"][row]["threshold"])
            self.assertEqual(alone["methods"][0]["scores"], sweep["methods"][row]["scores"])
        # A different rain changes the rivers (the rows are not copies of one run).
        self.assertNotEqual(sweep["methods"][0]["threshold"], sweep["methods"][1]["threshold"])


if __name__ == "__main__":
    unittest.main(verbosity=2)
