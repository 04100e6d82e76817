#!/usr/bin/python3
"""`terroir view` driven by --script: screenshots against Testing/Baselines/TerroirViewer_*.png
(Testing/Rendering/TerroirImageCompare.h's rule, as the C++ image tests: every pixel within 8
levels of a pixel within one pixel of it, both ways, at most 16 pixels otherwise; the viewer's
baselines are checked to fail darkened, tinted or with a block inverted), a lake clicked in a
bowl fills it to its spill level and, undone, gives the same picture as no click, navigation
events move the camera the right way, a brush stroke dragged over the terrain is one undo step,
a drag around the compass turns it by the angle swept, the on-screen buttons and the overlay
list answer clicks, the cluster table comes and goes with the clusters overlay, the clusters
follow the painted soil humidity, their keys and weights and export every month as CSV, and a
bad script is refused before any window work.

The scripts generate real interactor events (clicks, drags, wheel turns, keys), so the
interaction code of the window is what runs. Needs an X display (run the suite under
xvfb-run -a): skipped without DISPLAY unless TERROIR_REQUIRE_GPU=1, as the other image tests.
"""
import math
import os
import shutil
import subprocess
import tempfile
import unittest

import numpy as np
from TerroirImages import DIFFERING_PIXELS, LEVELS, compare_images, read_rgb
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOImage import vtkPNGReader

BIN = os.path.join(os.environ.get("TERROIR_BIN_DIR", "build/bin"), "terroir")
DATA = os.environ.get("TERROIR_DATA_DIR", "Data")
TEMP = os.environ.get("TERROIR_TEMP_DIR", tempfile.gettempdir())
DEM = os.path.join(DATA, "sagehen_creek_ca", "sagehen_dem_utm11n_10m.tif")
BASELINES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Baselines")
SIZE = (640, 480)
# The middle of the default relief view at 640 x 480 (pixels from the top left): a cell inside
# the bowl of BowlDEM.
BOWL = (250, 240)


def bowl_dem():
    """A 121 x 101 GeoTIFF of 10 m cells (UTM 11N): a plane rising 0.1 m per cell to the east
    with a Gaussian bowl 40 m deep (sigma 20 cells) in the middle, so that a lake clicked in the
    bowl spills over its western rim."""
    from osgeo import gdal, osr
    path = os.path.join(TEMP, "viewer_bowl.tif")
    z = bowl_heights()
    ny, nx = z.shape
    ds = gdal.GetDriverByName("GTiff").Create(path, nx, ny, 1, gdal.GDT_Float32)
    ds.SetGeoTransform((500000, 10, 0, 4380000, 0, -10))
    srs = osr.SpatialReference()
    srs.ImportFromEPSG(32611)
    ds.SetProjection(srs.ExportToWkt())
    ds.GetRasterBand(1).WriteArray(z)
    ds = None
    return path


def bowl_heights():
    """BowlDEM's heights (float32, as the GeoTIFF holds them), row j = 0 at the north edge."""
    nx, ny = 121, 101
    i = np.arange(nx)[None, :]
    j = np.arange(ny)[:, None]
    return (2000.0 + 0.1 * i - 40.0 * np.exp(-((i - 60.0) ** 2 + (j - 50.0) ** 2)
                                             / (2 * 20.0 ** 2))).astype(np.float32)


def sea_water(z, level):
    """Sum of level - z over the cells a breadth-first search from the edge cells at or below
    `level` reaches through such cells (8 neighbours): the sea's water, found independently."""
    ny, nx = z.shape
    wet = np.zeros(z.shape, dtype=bool)
    queue = [(a, b) for a in range(ny) for b in range(nx)
             if (a in (0, ny - 1) or b in (0, nx - 1)) and z[a, b] <= level]
    for a, b in queue:
        wet[a, b] = True
    while queue:
        a, b = queue.pop()
        for da in (-1, 0, 1):
            for db in (-1, 0, 1):
                p, q = a + da, b + db
                if 0 <= p < ny and 0 <= q < nx and not wet[p, q] and z[p, q] <= level:
                    wet[p, q] = True
                    queue.append((p, q))
    return float(np.sum((level - z.astype(np.float64))[wet]))


def need_display(test):
    if os.environ.get("DISPLAY"):
        return
    if os.environ.get("TERROIR_REQUIRE_GPU") == "1":
        test.fail("TERROIR_REQUIRE_GPU=1 but DISPLAY is unset")
    test.skipTest("no X display")


def run_view(name, lines, env=None, dem=DEM, extra=()):
    """Writes the script `lines` and runs `terroir view` on `dem` (the bundled DEM) with it
    (and the options `extra`)."""
    folder = os.path.join(TEMP, "viewer_" + name)
    shutil.rmtree(folder, ignore_errors=True)
    os.makedirs(folder)
    script = os.path.join(folder, "script.txt")
    with open(script, "w") as f:
        f.write("\n".join(lines) + "\n")
    proc = subprocess.run([BIN, "view", dem, "--size", "%dx%d" % SIZE, "--script", script]
                          + list(extra),
                          cwd=folder, capture_output=True, text=True, timeout=600, env=env)
    return proc, folder, script


def pixels(path):
    reader = vtkPNGReader()
    reader.SetFileName(path)
    reader.Update()
    image = reader.GetOutput()
    return image.GetDimensions(), vtk_to_numpy(image.GetPointData().GetScalars()).copy()


def states(stdout):
    """The `state` lines as dicts of their key/value pairs (numbers as floats)."""
    out = []
    for line in stdout.splitlines():
        if line.startswith("state "):
            words = line.split()[1:]
            d = {}
            for key, value in zip(words[0::2], words[1::2]):
                try:
                    d[key] = float(value)
                except ValueError:
                    d[key] = value
            out.append(d)
    return out


def compass_centre():
    """The compass centre in script pixels (from the top left), as Viewer.md places it: 93 %
    across and 86 % up the terrain view, which spans 78 % of the width and the top 86 % of the
    height."""
    x = 0.93 * 0.78 * SIZE[0]
    y_up = (0.14 + 0.86 * 0.86) * SIZE[1]
    return x, SIZE[1] - 1 - y_up


def cameras(stdout):
    """(position, focal point) of each `camera` line, as numpy vectors."""
    out = []
    for line in stdout.splitlines():
        if line.startswith("camera position"):
            v = [float(x) for x in line.split()[2:5] + line.split()[6:9]]
            out.append((np.array(v[:3]), np.array(v[3:])))
    return out


class TerroirViewer(unittest.TestCase):
    def check_baseline(self, png, name):
        """`png` against Testing/Baselines/<name>.png by the rule of compare_images."""
        rendered = os.path.join(TEMP, name + ".png")
        shutil.copyfile(png, rendered)
        baseline = os.path.join(BASELINES, name + ".png")
        self.assertTrue(os.path.exists(baseline),
                        "no baseline %s; look at %s and copy it in with "
                        "Testing/Rendering/CompactBaseline.py" % (baseline, rendered))
        differing, worst = compare_images(read_rgb(rendered), read_rgb(baseline))
        self.assertLessEqual(differing, DIFFERING_PIXELS,
                             "%s differs from %s: %d pixels more than %d levels from every "
                             "pixel within one pixel (largest %d)"
                             % (rendered, baseline, differing, LEVELS, worst))

    def test_comparison_rejects_perturbed_baselines(self):
        """Every viewer baseline passes against itself and fails 30 % darker, +100 on red,
        green x 0.6, +90 on every channel and with a 10 x 10 block inverted (VTK's legacy metric
        at 0.15 passed the first four)."""
        names = sorted(f for f in os.listdir(BASELINES) if f.startswith("TerroirViewer_"))
        self.assertGreaterEqual(len(names), 4)
        for name in names:
            base = read_rgb(os.path.join(BASELINES, name)).astype(np.int32)
            self.assertEqual(compare_images(base, base)[0], 0, name)
            block = base.copy()
            h, w = block.shape[:2]
            block[h // 2 - 5:h // 2 + 5, w // 2 - 5:w // 2 + 5] = \
                255 - block[h // 2 - 5:h // 2 + 5, w // 2 - 5:w // 2 + 5]
            red = base.copy()
            red[..., 0] += 100
            green = base.copy()
            green[..., 1] = np.round(0.6 * green[..., 1])
            for label, changed in (("darker", np.round(0.7 * base)), ("red", red),
                                   ("green", green), ("brighter", base + 90), ("block", block)):
                differing, _ = compare_images(np.clip(changed, 0, 255), base)
                self.assertGreater(differing, DIFFERING_PIXELS, "%s, %s" % (name, label))

    def test_screenshots_match_the_baselines(self):
        need_display(self)
        proc, folder, _ = run_view("baselines", [
            "overlay slope", "wait", "screenshot slope.png",
            # Overlay key 2 (sun and shadow), a June evening through the hour slider value.
            "key 2", "month 6", "hour 18", "wait", "screenshot shadows.png",
            "quit"])
        self.assertEqual(proc.returncode, 0, proc.stderr)
        self.check_baseline(os.path.join(folder, "slope.png"), "TerroirViewer_SlopeRelief")
        self.check_baseline(os.path.join(folder, "shadows.png"),
                            "TerroirViewer_ShadowsJuneEvening")
        # A lake clicked in the bowl with a lake depth of 50 m, over the bare relief at 13:00:
        # the level stops at the bowl's spill level (its western rim, near 1999.5 m, about
        # 33.5 m above the bottom), and no water runs down the plane beyond it.
        proc, folder, _ = run_view("bowl", [
            "overlay none", "hour 13", "tool lake", "lake-depth 50",
            "click %d %d" % BOWL, "wait", "screenshot lake.png",
            "quit"], dem=bowl_dem())
        self.assertEqual(proc.returncode, 0, proc.stderr)
        self.check_baseline(os.path.join(folder, "lake.png"), "TerroirViewer_LakeOverRelief")
        # The clusters of the bowl with their table (K = 4).
        proc, folder, _ = run_view("bowl_clusters", [
            "clusters 4", "overlay clusters", "wait", "screenshot clusters.png",
            "quit"], dem=bowl_dem())
        self.assertEqual(proc.returncode, 0, proc.stderr)
        self.check_baseline(os.path.join(folder, "clusters.png"),
                            "TerroirViewer_ClusterTable")
        # The climate card over the temperature overlay of the bowl, July's intensity under
        # edit (orange).
        proc, folder, _ = run_view("bowl_climate_card", [
            "overlay temperature", "card climate", "key Down", "month 7", "wait",
            "screenshot climate.png", "quit"], dem=bowl_dem())
        self.assertEqual(proc.returncode, 0, proc.stderr)
        self.check_baseline(os.path.join(folder, "climate.png"), "TerroirViewer_ClimateCard")

    def test_a_brush_stroke_is_one_undo_step(self):
        need_display(self)
        proc, folder, _ = run_view("brush", [
            "overlay humidity", "wait", "state", "screenshot before.png",
            "tool brush", "brush-rate 0", "brush-size 3",
            "drag 150 200 350 260", "wait", "state", "screenshot painted.png",
            "key ctrl+z", "wait", "state", "screenshot undone.png",
            "quit"], dem=bowl_dem())
        self.assertEqual(proc.returncode, 0, proc.stderr)
        before, painted, undone = states(proc.stdout)
        # The default recipe: 15 mm/h on every cell of the gentle bowl (no slope over 30°).
        self.assertEqual(before["infiltration-sum"], 15.0 * 121 * 101)
        self.assertEqual(before["undo"], 0)
        # The stroke set 0 mm/h on a band: at least the cells within 3 of a 20-cell path.
        removed = (before["infiltration-sum"] - painted["infiltration-sum"]) / 15.0
        self.assertEqual(removed, int(removed))
        self.assertGreater(removed, 20 * 7)
        self.assertEqual(painted["undo"], 1)
        self.assertEqual(undone["infiltration-sum"], before["infiltration-sum"])
        self.assertEqual(undone["undo"], 0)
        _, a = pixels(os.path.join(folder, "before.png"))
        _, p = pixels(os.path.join(folder, "painted.png"))
        _, b = pixels(os.path.join(folder, "undone.png"))
        # The humidity overlay shows the stroke, and undoing it gives back the terrain's pixels
        # (the texts differ: compare the terrain view between them; PNG rows run bottom up).
        def terrain(image):
            rows = image.reshape(SIZE[1], SIZE[0], -1)[::-1]
            return rows[int(0.10 * SIZE[1]):int(0.80 * SIZE[1]), :int(0.78 * SIZE[0])]
        self.assertGreater(int(np.count_nonzero(np.any(terrain(p) != terrain(a), axis=2))), 500)
        self.assertTrue(np.array_equal(terrain(a), terrain(b)))

    def test_dragging_around_the_compass_turns_it_by_the_angle_swept(self):
        need_display(self)
        cx, cy = compass_centre()
        x0, y0 = int(round(cx)), int(round(cy - 20))   # above the centre
        x1, y1 = int(round(cx + 20)), int(round(cy))   # right of it: a quarter turn clockwise
        proc, _, _ = run_view("compass", [
            "view map", "state", "drag %d %d %d %d" % (x0, y0, x1, y1), "state",
            "quit"], dem=bowl_dem())
        self.assertEqual(proc.returncode, 0, proc.stderr)
        start, turned = states(proc.stdout)

        def angle(x, y):  # clockwise from screen up, y from the top
            return math.degrees(math.atan2(x - cx, cy - y))
        swept = angle(x1, y1) - angle(x0, y0)
        self.assertAlmostEqual(swept, 90.0, delta=3.0)
        # The arrow follows the pointer: grid north turns the other way from true north.
        expected = (start["orientation"] - swept) % 360.0
        self.assertAlmostEqual(turned["orientation"], expected, places=3)

    def test_buttons_and_the_overlay_list_answer_clicks(self):
        need_display(self)
        # The list's entry "1 Slope": its band is 0.84 - 2h .. 0.84 - h of the list pane
        # (h = 0.84 / 9), the pane spans the top 36 % of the right 22 %.
        u, v = 0.3, 0.84 - 1.5 * 0.84 / 9
        x = int((0.78 + u * 0.22) * SIZE[0])
        y = int(SIZE[1] - 1 - (0.64 + v * 0.36) * SIZE[1])
        proc, _, _ = run_view("buttons", [
            "click %d %d" % (x, y), "state",
            "brush-rate 7", "button fill", "state",
            "slope-threshold 2", "button slope-rule", "state",
            "button slope-rule", "state",
            "button undo", "state", "button undo", "state",
            "button lake", "state", "button table", "state",
            "overlay clusters", "wait", "state", "key t", "state", "button table", "state",
            "overlay slope", "state",
            "quit"], dem=bowl_dem())
        self.assertEqual(proc.returncode, 0, proc.stderr)
        s = states(proc.stdout)
        self.assertEqual(len(s), 12, proc.stdout)
        self.assertEqual(s[0]["overlay"], "slope")
        # Fill: 7 mm/h on each of the 12221 cells; one undo step.
        self.assertEqual(s[1]["infiltration-sum"], 7.0 * 121 * 101)
        self.assertEqual(s[1]["undo"], 1)
        # Slope rule at 2 degrees: the bowl's steep ring to 0, the rest keeps 7 mm/h.
        steep = (s[1]["infiltration-sum"] - s[2]["infiltration-sum"]) / 7.0
        self.assertEqual(steep, int(steep))
        self.assertGreater(steep, 1000)
        self.assertLess(steep, 121 * 101 - 1000)
        self.assertEqual(s[2]["undo"], 2)
        # A second time changes nothing and adds no step.
        self.assertEqual(s[3]["infiltration-sum"], s[2]["infiltration-sum"])
        self.assertEqual(s[3]["undo"], 2)
        # Undo, undo: the fill, then the default recipe.
        self.assertEqual(s[4]["infiltration-sum"], s[1]["infiltration-sum"])
        self.assertEqual(s[5]["infiltration-sum"], 15.0 * 121 * 101)
        self.assertEqual(s[5]["undo"], 0)
        self.assertEqual(s[6]["tool"], "lake")
        # The table comes with the clusters overlay only, and T / the button hide and show it.
        self.assertEqual(s[7]["table"], "hidden")
        self.assertEqual(s[8]["table"], "shown")
        self.assertEqual(s[9]["table"], "hidden")
        self.assertEqual(s[10]["table"], "shown")
        self.assertEqual(s[11]["table"], "hidden")

    def test_a_lake_clicked_then_undone_leaves_the_same_picture_as_no_click(self):
        need_display(self)
        common = ["overlay slope", "tool lake", "wait"]
        bowl = bowl_dem()
        proc, plain, _ = run_view("no_click", common + [
            "key ctrl+z",  # nothing to undo: the same status line as below
            "screenshot plain.png", "quit"], dem=bowl)
        self.assertEqual(proc.returncode, 0, proc.stderr)
        proc, undone, _ = run_view("click_undo", common + [
            "click %d %d" % BOWL, "screenshot lake.png",
            "key ctrl+z", "key ctrl+z", "screenshot undone.png", "quit"], dem=bowl)
        self.assertEqual(proc.returncode, 0, proc.stderr)
        size_a, a = pixels(os.path.join(plain, "plain.png"))
        size_l, lake = pixels(os.path.join(undone, "lake.png"))
        size_b, b = pixels(os.path.join(undone, "undone.png"))
        self.assertEqual(size_a, (SIZE[0], SIZE[1], 1))
        self.assertEqual(size_a, size_b)
        # The click made a lake (many pixels changed), and Ctrl+Z gave back every pixel.
        self.assertGreater(int(np.count_nonzero(np.any(lake != a, axis=1))), 5000)
        self.assertTrue(np.array_equal(a, b),
                        "%d pixels differ" % np.count_nonzero(np.any(a != b, axis=1)))

    def test_navigation_events_move_the_camera_the_expected_way(self):
        need_display(self)
        proc, _, _ = run_view("navigation", [
            "camera",
            "drag 250 200 350 200", "camera",         # pan: the terrain follows the pointer
            "wheel 3", "camera",                      # zoom in
            "drag 250 200 350 200 ctrl", "camera",    # rotate about the focal point
            "style first-person", "key w", "camera",  # one step forward
            "drag 250 200 300 200", "camera",         # look 20 degrees to the right
            "quit"])
        self.assertEqual(proc.returncode, 0, proc.stderr)
        c = cameras(proc.stdout)
        self.assertEqual(len(c), 6, proc.stdout)
        (p0, f0), (p1, f1), (p2, f2), (p3, f3), (p4, f4), (p5, f5) = c
        # Pan: camera and focal point move together, against the drag (screen right).
        forward = (f0 - p0) / np.linalg.norm(f0 - p0)
        right = np.cross(forward, [0.0, 0.0, 1.0])
        right /= np.linalg.norm(right)
        move = p1 - p0
        self.assertTrue(np.allclose(f1 - f0, move, atol=1e-6))
        self.assertLess(np.dot(move, right), -0.9 * np.linalg.norm(move))
        self.assertGreater(np.linalg.norm(move), 100.0)
        # Wheel forward 3 notches: 1.1^3 closer, same focal point.
        self.assertTrue(np.allclose(f2, f1))
        self.assertAlmostEqual(np.linalg.norm(p1 - f1) / np.linalg.norm(p2 - f2), 1.1 ** 3,
                               places=6)
        # Ctrl+drag 100 pixels right: 40 degrees about the vertical through the focal point,
        # same distance and height.
        self.assertTrue(np.allclose(f3, f2))
        self.assertAlmostEqual(np.linalg.norm(p3 - f3), np.linalg.norm(p2 - f2), places=3)
        self.assertAlmostEqual(p3[2], p2[2], places=3)
        a2 = math.degrees(math.atan2(p2[0] - f2[0], p2[1] - f2[1]))
        a3 = math.degrees(math.atan2(p3[0] - f3[0], p3[1] - f3[1]))
        self.assertAlmostEqual((a3 - a2 + 540.0) % 360.0 - 180.0, -40.0, places=4)
        # First person, W: one step (1 % of the DEM's diagonal) along the horizontal view.
        step = p4 - p3
        ahead = (f3 - p3)[:2] / np.linalg.norm((f3 - p3)[:2])
        self.assertAlmostEqual(step[2], 0.0, places=6)
        self.assertTrue(np.allclose(f4 - f3, step, atol=1e-6))
        self.assertAlmostEqual(float(np.dot(step[:2], ahead)), float(np.linalg.norm(step)),
                               places=3)
        diagonal = math.hypot(785 * 10.0, 719 * 10.0)
        self.assertAlmostEqual(float(np.linalg.norm(step)), 0.01 * diagonal, delta=0.5)
        # First person, drag 50 pixels right: the view turns 20 degrees clockwise seen from
        # above (0.4 degree per pixel), the camera stays, the pitch and the focal distance too.
        self.assertTrue(np.allclose(p5, p4))
        v4, v5 = f4 - p4, f5 - p5
        self.assertAlmostEqual(np.linalg.norm(v5), np.linalg.norm(v4), places=3)
        self.assertAlmostEqual(v5[2], v4[2], places=3)
        b4 = math.degrees(math.atan2(v4[0], v4[1]))
        b5 = math.degrees(math.atan2(v5[0], v5[1]))
        self.assertAlmostEqual((b5 - b4 + 540.0) % 360.0 - 180.0, 20.0, places=4)

    def test_clusters_follow_the_painted_soil_and_the_keys_and_export_every_month(self):
        """The clusters take the soil humidity of the infiltration map: on BowlDEM (slopes
        under 30 degrees, so the default 15 mm/h everywhere, more than any month's intensity)
        every cluster has the same weighted humidity, all the rain; after the fill paints
        0 mm/h everywhere it is 0 in every cluster. K and the weights follow the keys (K,
        Shift+K, J, X, Shift+X) and `cluster-weight`; `table-csv` writes every month."""
        need_display(self)
        proc, folder, _ = run_view("clusters", [
            "overlay clusters", "wait", "state", "table-csv before.csv",
            "key k", "key k", "key shift+k", "state",         # K 5 -> 7 -> 6
            "key j", "key x", "key j", "key x", "key shift+x", "state",  # slope x2, temp x2/2
            "cluster-weight humidity 1", "brush-rate 0", "button fill", "wait", "state",
            "table-csv after.csv", "quit"], dem=bowl_dem())
        self.assertEqual(proc.returncode, 0, proc.stderr)
        s = states(proc.stdout)
        self.assertEqual(len(s), 4, proc.stdout)
        self.assertEqual((s[0]["clusters"], s[0]["weight-slope"], s[0]["weight-temperature"],
                          s[0]["weight-sun"], s[0]["weight-humidity"]), (5, 1, 1, 1, 0.1))
        self.assertEqual(s[1]["clusters"], 6)
        self.assertEqual((s[2]["weight-slope"], s[2]["weight-temperature"]), (2, 1))
        self.assertEqual(s[3]["weight-humidity"], 1)
        self.assertEqual(s[3]["infiltration-sum"], 0.0)

        def read(name):
            with open(os.path.join(folder, name)) as f:
                lines = f.read().splitlines()
            header = [h.strip('"') for h in lines[0].split(",")]
            rows = [[float(v) if k != 1 else v for k, v in enumerate(line.split(","))]
                    for line in lines[1:]]
            return header, rows

        header, rows = read("before.csv")
        self.assertEqual(header[:4], ["Cluster", "Color", "Cells", "Share"])
        self.assertEqual(len(header), 4 + 1 + 3 * 12)  # slope, then 12 months of 3 resources
        self.assertEqual(len(rows), 5)
        self.assertAlmostEqual(sum(r[3] for r in rows), 1.0, places=6)
        self.assertEqual(sum(int(r[2]) for r in rows), 121 * 101)
        july = header.index("Humidity Jul (mm)")
        wet = [r[july] for r in rows]
        self.assertGreater(min(wet), 0.0)
        self.assertLess(max(wet) - min(wet), 1e-4)
        header, rows = read("after.csv")
        self.assertEqual(len(rows), 6)
        for month in ("Jan", "Jul", "Dec"):
            column = header.index("Humidity %s (mm)" % month)
            self.assertEqual([r[column] for r in rows], [0.0] * 6)

    def test_water_flow_controls_reach_the_run(self):
        """O, I/Shift+I, Y and the flow-* verbs set what `state` prints, and the run obeys
        them: the stop rule off and 7 iterations stop a pulse after exactly 7
        (MaximumIterations); the river-forming mode with 5 mm/h of rain stops at the balance."""
        need_display(self)
        proc, _, _ = run_view("flow_controls", [
            "state", "key o", "key i", "key i", "key shift+i", "key y", "key y", "state",
            "flow-mode pulse", "flow-water 50", "flow-stop 0", "flow-iterations 7", "flow",
            "wait", "state",
            "flow-mode rivers", "flow-rain-rate 5", "flow-iterations 100000", "flow", "wait",
            "state", "quit"], dem=bowl_dem())
        self.assertEqual(proc.returncode, 0, proc.stderr)
        s = states(proc.stdout)
        self.assertEqual(len(s), 4, proc.stdout)
        self.assertEqual((s[0]["flow-mode"], s[0]["flow-iterations"], s[0]["flow-stop"],
                          s[0]["flow-last-stop"]), ("pulse", 500, 0.001, "none"))
        self.assertTrue(math.isnan(s[0]["flow-water"]) and math.isnan(s[0]["flow-rain-rate"]))
        self.assertEqual((s[1]["flow-mode"], s[1]["flow-iterations"], s[1]["flow-rain-rate"]),
                         ("rivers", 1000, 2))
        self.assertEqual((s[2]["flow-last-iterations"], s[2]["flow-last-stop"], s[2]["undo"]),
                         (7, "MaximumIterations", 1))
        self.assertGreater(s[2]["water-sum"], 0.0)
        self.assertEqual((s[3]["flow-last-stop"], s[3]["undo"]), ("Balanced", 2))

    def test_live_erosion_runs_takes_dabs_and_keeps_its_bed(self):
        """F5 (and `erosion start`) runs the live erosion on its own thread with the Brush tool
        on; a click drops a dab of water (the run starts dry, so any water is the dab's);
        `wait-erosion 30` blocks until 30 steps are done; F5 stops it, F6 cycles the brush
        (water -> vegetation), F7 keeps the bed as the terrain and ends the run. Waiting for
        steps with no run stops the script with one line."""
        need_display(self)
        proc, _, _ = run_view("erosion", [
            "key F5", "erosion-brush water", "erosion-amount 1", "brush-size 6",
            "click %d %d" % BOWL, "wait-erosion 30", "state", "key F5", "state", "key F6",
            "state", "key F7", "state", "quit"], dem=bowl_dem())
        self.assertEqual(proc.returncode, 0, proc.stderr)
        s = states(proc.stdout)
        self.assertEqual(len(s), 4, proc.stdout)
        self.assertEqual((s[0]["erosion"], s[0]["tool"], s[0]["erosion-brush"]),
                         ("running", "brush", "water"))
        self.assertGreaterEqual(s[0]["erosion-steps"], 30)
        self.assertGreater(s[0]["erosion-water-sum"], 1.0)
        self.assertEqual(s[1]["erosion"], "stopped")
        self.assertGreaterEqual(s[1]["erosion-steps"], s[0]["erosion-steps"])
        self.assertEqual(s[2]["erosion-brush"], "vegetation")
        self.assertEqual((s[3]["erosion"], s[3]["erosion-steps"]), ("none", 0))
        proc, _, _ = run_view("erosion_none", ["wait-erosion 5", "quit"], dem=bowl_dem())
        self.assertNotEqual(proc.returncode, 0)
        self.assertIn("the erosion did not reach 5 steps", proc.stderr)

    def test_the_terrain_texture_comes_and_goes(self):
        """F8 (and `texture on|off`) puts Jensen's terrain texture on the relief instead of the
        overlay's colours and takes it off again: the textured picture differs from the plain
        one over much of the terrain, and after `texture off` the terrain view (above the status
        line, whose message differs) has exactly the plain picture's pixels."""
        need_display(self)
        proc, folder, _ = run_view("texture", [
            "wait", "screenshot plain.png", "key F8", "state", "screenshot textured.png",
            "texture off", "state", "screenshot off.png", "quit"], dem=bowl_dem())
        self.assertEqual(proc.returncode, 0, proc.stderr)
        s = states(proc.stdout)
        self.assertEqual((s[0]["texture"], s[1]["texture"]), ("on", "off"))
        shots = {}
        for name in ("plain", "textured", "off"):
            (w, h, _), values = pixels(os.path.join(folder, name + ".png"))
            image = values.reshape(h, w, -1)
            shots[name] = image[int(0.2 * h):, :int(0.78 * w)]  # rows from the bottom: skip it
        changed = np.any(shots["plain"] != shots["textured"], axis=2).sum()
        self.assertGreater(changed, 5000)
        self.assertTrue(np.array_equal(shots["plain"], shots["off"]))

    def test_the_sea_floods_from_the_edge_and_is_undone(self):
        """`sea 2003` on BowlDEM covers what a breadth-first search from the edge cells at or
        below 2003 m reaches through such cells (8 neighbours), each with 2003 - z m: the
        water sum matches. Key C picks the sea tool; a click in the bowl (about 1966 m, below
        every edge cell) makes no sea; Ctrl+Z takes the first sea back."""
        need_display(self)
        proc, _, _ = run_view("sea", [
            "sea 2003", "state", "key c", "click %d %d" % BOWL, "state", "key ctrl+z", "state",
            "quit"], dem=bowl_dem())
        self.assertEqual(proc.returncode, 0, proc.stderr)
        s = states(proc.stdout)
        self.assertEqual(len(s), 3, proc.stdout)
        expected = sea_water(bowl_heights(), 2003.0)
        self.assertGreater(expected, 1000.0)
        self.assertAlmostEqual(s[0]["water-sum"] / expected, 1.0, places=5)
        self.assertEqual((s[0]["undo"], s[1]["tool"], s[1]["undo"]), (1, "sea", 1))
        self.assertEqual(s[1]["water-sum"], s[0]["water-sum"])
        self.assertEqual((s[2]["undo"], s[2]["water-sum"]), (0, 0.0))

    def test_climate_verbs_set_save_and_load_the_climate(self):
        """precipitation, intensity, coldest, warmest and lapse-rate set what `state` prints
        and what climate-save writes (July 100 mm at 4 mm/h; temperatures from -5 in January
        to 25 in July: April -5 + 30 x 3/6 = 10); climate-load takes a file's 12 sea-level
        temperatures; a file without a known column stops the script with one line naming it."""
        need_display(self)
        folder = os.path.join(TEMP, "viewer_climate_in")
        os.makedirs(folder, exist_ok=True)
        given = os.path.join(folder, "given.csv")
        with open(given, "w") as f:
            f.write("month,temperature_c\n" + "".join("%d,%d\n" % (m, 10 + m) for m in
                                                       range(1, 13)))
        proc, out, _ = run_view("climate", [
            "precipitation 7 100", "intensity 7 4", "coldest -5", "warmest 25", "lapse-rate 5",
            "overlay temperature", "wait", "state", "climate-save saved.csv",
            "climate-load " + given, "state", "quit"], dem=bowl_dem())
        self.assertEqual(proc.returncode, 0, proc.stderr)
        # The default climate is announced as a placeholder, with its values.
        self.assertIn("terroir view: the climate is a placeholder (sea-level 2 \u00b0C in the "
                      "coldest month, 20 \u00b0C in the warmest, 6.4 \u00b0C/km", proc.stderr)
        s = states(proc.stdout)
        self.assertEqual(len(s), 2, proc.stdout)
        self.assertEqual((s[0]["coldest"], s[0]["warmest"], s[0]["lapse-rate"],
                          s[0]["temperatures"], s[0]["precipitation-jul"],
                          s[0]["intensity-jul"]), (-5, 25, 5, "extremes", 100, 4))
        self.assertEqual((s[1]["temperatures"], s[1]["precipitation-jul"]), ("monthly", 100))
        with open(os.path.join(out, "saved.csv")) as f:
            rows = [line.split(",") for line in f.read().splitlines()
                    if line and not line.startswith("#")]
        self.assertEqual(rows[0], ["month", "precipitation_mm", "intensity_mm_per_h",
                                   "temperature_c"])
        self.assertEqual(len(rows), 13)
        self.assertEqual([float(v) for v in rows[7][1:]], [100.0, 4.0, 25.0])
        self.assertEqual(float(rows[1][3]), -5.0)
        self.assertEqual(float(rows[4][3]), 10.0)
        bad = os.path.join(folder, "bad.csv")
        with open(bad, "w") as f:
            f.write("month,rain\nJan,3\n")
        proc, _, script = run_view("climate_bad", ["climate-load " + bad, "quit"], dem=bowl_dem())
        self.assertEqual(proc.returncode, 1)
        errors = [line for line in proc.stderr.splitlines() if "error" in line]
        self.assertEqual(len(errors), 1, proc.stderr)
        self.assertTrue(errors[0].startswith("terroir: error: %s:1: %s: " % (script, bad)),
                        errors[0])

    def test_the_climate_card_edits_the_climate_by_keys_and_mouse(self):
        """The climate card (F3, Viewer.md's layout: card 1-55 % across and 17-93 % up the
        window; precipitation chart 11-97 % across and 63-86 % up the card, 0 to the smallest
        multiple of 50 mm at least 1.25 x the wettest month, i.e. 100 mm for the default 65 mm;
        rows of [-] [+] at 20.5, 13.5 and 6.5 % up, [+] at 86-96 % across). Keys: Right x 6
        picks July, + adds 5 mm, Down then - takes 0.5 mm/h off July's intensity, Down + warms
        the coldest month by 1 degree. Mouse: a press half-way up January's bar sets 50 mm
        (+-1 mm: one pixel is 1.2 mm), a drag from there to March at a quarter sets March to
        25 mm and February on the way between; [+] of the lapse rate adds 0.5; Save CSV writes
        the same numbers; F3 closes the card."""
        need_display(self)
        w, h = SIZE

        def card_pixel(u, v):  # the card's normalised coordinates to script pixels
            x = (0.01 + u * 0.54) * w
            y_up = (0.17 + v * 0.76) * h
            return int(round(x)), int(round(h - 1 - y_up))

        def chart(month, fraction):  # month 0..11, fraction of the chart's height
            return card_pixel(0.11 + (month + 0.5) * 0.86 / 12, 0.63 + fraction * 0.23)

        def value_at(pixel_y):  # what the chart reads at a script row, mm
            v = ((h - 1 - pixel_y) / h - 0.17) / 0.76
            return (v - 0.63) / 0.23 * 100.0

        jan = chart(0, 0.5)
        mar = chart(2, 0.25)
        plus_lapse = card_pixel(0.91, 0.065)
        proc, out, _ = run_view("climate_card", [
            "state", "key F3", "state"] + ["key Right"] * 6 + [
            "key plus", "key Down", "key minus", "key Down", "key plus", "state",
            "click %d %d" % jan, "state", "drag %d %d %d %d" % (jan + mar), "state",
            "click %d %d" % plus_lapse, "state", "key F3", "state", "quit"], dem=bowl_dem())
        self.assertEqual(proc.returncode, 0, proc.stderr)
        s = states(proc.stdout)
        self.assertEqual(len(s), 7, proc.stdout)
        months = [[float(v) for v in d["precipitation-months"].split(",")] for d in s]
        rates = [[float(v) for v in d["intensity-months"].split(",")] for d in s]
        self.assertEqual((s[0]["card"], s[1]["card"], s[6]["card"]), ("none", "climate", "none"))
        self.assertEqual(max(months[0]), 65.0)  # the chart's top is then 100 mm
        self.assertEqual((s[2]["card-month"], s[2]["card-field"]), (7, 2))
        self.assertEqual(months[2][6], months[0][6] + 5.0)
        self.assertEqual(rates[2][6], rates[0][6] - 0.5)
        self.assertEqual(s[2]["coldest"], s[0]["coldest"] + 1.0)
        self.assertEqual(months[2][:6] + months[2][7:], months[0][:6] + months[0][7:])
        self.assertAlmostEqual(months[3][0], value_at(jan[1]), delta=0.51)
        self.assertAlmostEqual(months[3][0], 50.0, delta=1.5)
        self.assertEqual(s[3]["card-field"], 0)
        self.assertAlmostEqual(months[4][2], value_at(mar[1]), delta=0.51)
        self.assertAlmostEqual(months[4][2], 25.0, delta=1.5)
        self.assertTrue(25.0 - 1.5 <= months[4][1] <= 50.0 + 1.5, months[4])
        self.assertNotEqual(months[4][1], months[0][1])
        self.assertEqual(s[5]["lapse-rate"], s[0]["lapse-rate"] + 0.5)
        # Save CSV (top right of the card) writes what the state says.
        proc, out, _ = run_view("climate_card_save", [
            "card climate", "precipitation 2 42", "click %d %d" % card_pixel(0.885, 0.955),
            "quit"], dem=bowl_dem())
        self.assertEqual(proc.returncode, 0, proc.stderr)
        with open(os.path.join(out, "terroir-view-001.csv")) as f:
            rows = [line.split(",") for line in f.read().splitlines()
                    if line and not line.startswith("#")]
        self.assertEqual(float(rows[2][1]), 42.0)
        self.assertEqual([float(r[1]) for r in rows[1:]][6], months[0][6])

    def test_the_settings_card_sets_the_navigation(self):
        """The settings card (F4, the Settings button; card 60-93 % up the window, rows at 70,
        50 and 30 % up it, [+] at 86-96 % across): [+] of the mouse sensitivity multiplies it
        by 1.25; Down, - divides the move speed by 1.25; [+] of the control type switches to
        first-person; the script's sensitivity and move-speed set the same values; F4 closes
        the card."""
        need_display(self)
        w, h = SIZE

        def card_pixel(u, v):
            x = (0.01 + u * 0.54) * w
            y_up = (0.60 + v * 0.33) * h
            return int(round(x)), int(round(h - 1 - y_up))

        proc, _, _ = run_view("settings_card", [
            "key F4", "click %d %d" % card_pixel(0.91, 0.50), "state", "key Down", "key minus",
            "state", "click %d %d" % card_pixel(0.91, 0.70), "state", "sensitivity 3",
            "move-speed 0.5", "state", "key F4", "state", "button settings", "state", "quit"],
            dem=bowl_dem())
        self.assertEqual(proc.returncode, 0, proc.stderr)
        s = states(proc.stdout)
        self.assertEqual(len(s), 6, proc.stdout)
        self.assertEqual((s[0]["card"], s[0]["sensitivity"], s[0]["style"]),
                         ("settings", 1.25, "terrain"))
        self.assertEqual((s[1]["card-field"], s[1]["move-speed"]), (2, 0.8))
        self.assertEqual(s[2]["style"], "first-person")
        self.assertEqual((s[3]["sensitivity"], s[3]["move-speed"]), (3, 0.5))
        self.assertEqual((s[4]["card"], s[5]["card"]), ("none", "settings"))

    def test_the_slope_and_sea_sliders(self):
        """The fifth and sixth sliders under the terrain (Viewer.md: slider k spans
        (1.5 + 16.3 k) % to that + 14.5 % of the terrain's 78 % of the width, 4.5 % up; VTK's
        2-D slider: a click on an end cap jumps to that end, a press on the handle drags it;
        its handle, about 25 % long, travels with its centre from 24 % to 75 % of that span). The slope-rule threshold (0-90
        degrees): the left cap gives 0, the handle dragged from there past the right end 90,
        from the right end past the left 0. The sea level (the terrain's lowest to highest
        height) floods at the release: the right cap covers every cell (water = sum of max - z);
        the handle dragged back a little (below the highest edge cell) replaces that sea (the water is the breadth-first
        flood from the edge at the new level, not the higher sea kept), one undo step; Ctrl+Z
        leaves the terrain dry."""
        need_display(self)
        w, h = SIZE

        def slider(k, t):  # a point t of the way along slider k, script pixels
            x0 = (0.015 + 0.163 * k) * 0.78
            return int(round((x0 + t * 0.145 * 0.78) * w)), int(round(h - 1 - 0.045 * h))

        def click(k, t):
            return "click %d %d" % slider(k, t)

        def drag(k, a, b):
            return "drag %d %d %d %d" % (slider(k, a) + slider(k, b))

        proc, _, _ = run_view("sliders", [
            click(4, 0.02), "state", drag(4, 0.24, 1.2), "state", click(4, 0.99),
            drag(4, 0.75, -0.2), "state",
            click(5, 0.99), "state", drag(5, 0.75, 0.70), "state", "key ctrl+z", "state",
            "quit"], dem=bowl_dem())
        self.assertEqual(proc.returncode, 0, proc.stderr)
        s = states(proc.stdout)
        self.assertEqual(len(s), 6, proc.stdout)
        self.assertEqual([d["slope-threshold"] for d in s[:3]], [0, 90, 0])
        s = s[1:]
        z = bowl_heights()
        top = float(z.max())
        self.assertAlmostEqual(s[2]["sea-level"], top, places=3)
        full = float(np.sum(top - z.astype(np.float64)))
        self.assertAlmostEqual(s[2]["water-sum"] / full, 1.0, places=5)
        level = s[3]["sea-level"]
        self.assertTrue(2000.0 < level < top - 1.0, level)  # above the lowest edge cell
        expected = sea_water(z, level)
        self.assertGreater(expected, 0.0)
        self.assertAlmostEqual(s[3]["water-sum"] / expected, 1.0, places=4)
        self.assertEqual((s[2]["undo"], s[3]["undo"]), (1, 1))
        self.assertEqual((s[4]["undo"], s[4]["water-sum"]), (0, 0.0))

    def test_the_level_of_detail_draws_coarse_while_busy_and_full_when_still(self):
        """--lod-points 1000 on the 121 x 101 bowl (12,221 points) gives a coarse surface
        (every 4th point): renders after actions draw it (`state`: detail coarse), a screenshot
        draws the full one: its pixels equal those of the same session
        without a level of detail (--lod-points 0), whose state says full-only; the tools pick
        cells on the full surface (a lake clicked while the coarse one is shown fills the same
        water as without)."""
        need_display(self)
        lines = ["overlay slope", "tool lake", "click %d %d" % BOWL, "wait", "state",
                 "screenshot a.png", "state", "quit"]
        lod, folder_lod, _ = run_view("lod", lines, dem=bowl_dem(), extra=("--lod-points", "1000"))
        full, folder_full, _ = run_view("lod_off", lines, dem=bowl_dem(),
                                        extra=("--lod-points", "0"))
        for proc in (lod, full):
            self.assertEqual(proc.returncode, 0, proc.stderr)
        s, t = states(lod.stdout), states(full.stdout)
        self.assertEqual([d["detail"] for d in s], ["coarse", "coarse"])  # the runner redraws
        self.assertEqual([d["detail"] for d in t], ["full-only", "full-only"])
        self.assertGreater(s[0]["water-sum"], 0.0)
        self.assertEqual(s[0]["water-sum"], t[0]["water-sum"])
        (dims_a, a), (dims_b, b) = (pixels(os.path.join(folder_lod, "a.png")),
                                    pixels(os.path.join(folder_full, "a.png")))
        self.assertEqual(dims_a, dims_b)
        np.testing.assert_array_equal(a, b)

    def test_orientation_edit_mode_turns_the_compass_with_the_arrow_keys(self):
        """F2 (Long 2016's orientation edit mode, Fig. 3.5) turns the compass green; then
        Right, Right and Shift+Left turn grid north +1, +1 and -10 degrees; outside the mode
        Right changes nothing; F2 again ends the mode."""
        need_display(self)
        proc, folder, _ = run_view("orientation_edit", [
            "state", "key Right", "state", "key F2", "key Right", "key Right", "key shift+Left",
            "state", "screenshot edit.png", "key F2", "state", "screenshot plain.png", "quit"],
            dem=bowl_dem())
        self.assertEqual(proc.returncode, 0, proc.stderr)
        s = states(proc.stdout)
        self.assertEqual(len(s), 4, proc.stdout)
        o0 = s[0]["orientation"]
        self.assertEqual((s[1]["orientation"], s[1]["orientation-edit"]), (o0, "off"))
        # `state` prints 6 significant digits (0.001 degree here).
        self.assertAlmostEqual((s[2]["orientation"] - (o0 - 8.0) + 540.0) % 360.0 - 180.0, 0.0,
                               delta=0.002)
        self.assertEqual((s[2]["orientation-edit"], s[3]["orientation-edit"]), ("on", "off"))

        def green_near_compass(name):
            (w, h, _), rgb = pixels(os.path.join(folder, name))
            rgb = rgb.reshape(h, w, 3).astype(int)[::-1]  # rows from the top
            x, y = compass_centre()
            box = rgb[int(y) - 40:int(y) + 40, int(x) - 40:int(x) + 40]
            return int(np.count_nonzero((box[..., 1] > 120) & (box[..., 0] < 80)
                                        & (box[..., 2] < 100)))
        self.assertGreater(green_near_compass("edit.png"), 20)
        self.assertEqual(green_near_compass("plain.png"), 0)

    def test_a_bad_script_line_is_refused_before_any_window(self):
        # No DISPLAY: the script is checked first, so the display is never needed.
        env = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
        proc, folder, script = run_view("bad_script", ["overlay slope", "# fine", "month 13",
                                                       "quit"], env=env)
        self.assertEqual(proc.returncode, 1)
        self.assertEqual(proc.stderr,
                         "terroir: error: %s:3: 'month': value 13 is outside [1, 12]\n" % script)
        self.assertEqual(sorted(os.listdir(folder)), ["script.txt"])


if __name__ == "__main__":
    unittest.main()
