#!/usr/bin/python3
"""Rendering from Python: reader -> slope -> overlay PNG, as a pvpython-style script would.

Needs an X display (VTK 9.1 renders through X): skipped without DISPLAY unless
TERROIR_REQUIRE_GPU=1, as the C++ rendering tests do."""
import math
import os
import sys
import tempfile
import unittest

import numpy as np
from vtkmodules.vtkCommonCore import vtkLookupTable
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkIOImage import vtkPNGReader
from vtkmodules.util.numpy_support import numpy_to_vtk

import terroir

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from TerroirImages import DIFFERING_PIXELS, compare_images, read_rgb  # noqa: E402

DATA = os.environ.get("TERROIR_DATA_DIR", "Data")
TEMP = os.environ.get("TERROIR_TEMP_DIR", tempfile.gettempdir())
DEM = os.path.join(DATA, "sagehen_creek_ca", "sagehen_dem_utm11n_10m.tif")
BASELINES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Baselines")


def need_display(test):
    if os.environ.get("DISPLAY"):
        return
    if os.environ.get("TERROIR_REQUIRE_GPU") == "1":
        test.fail("TERROIR_REQUIRE_GPU=1 but DISPLAY is unset")
    test.skipTest("no X display")


class TerroirRenderingFromPython(unittest.TestCase):
    def test_slope_overlay_png(self):
        need_display(self)
        reader = terroir.vtkTerroirDEMReader()
        reader.SetFileName(DEM)
        slope = terroir.vtkTerroirSlope()
        slope.SetInputConnection(reader.GetOutputPort())
        slope.Update()
        view = terroir.vtkTerroirOverlayView()
        view.SetInputData(slope.GetOutput())
        view.SetArrayName("Slope")
        view.SetPreset("Slope")
        view.SetModeToMap()
        view.ShowLegendOff()
        view.SetWidth(400)
        view.SetHeight(400)
        path = os.path.join(TEMP, "python_slope_overlay.png")
        self.assertTrue(view.WritePNG(path), view.GetLastError())
        png = vtkPNGReader()
        png.SetFileName(path)
        png.Update()
        self.assertEqual(png.GetOutput().GetDimensions()[:2], (400, 400))
        # The same picture as the C++ test TerroirOverlayImages.SlopeMap (whose pixels are
        # probed against the colour table there), by the same comparison rule.
        baseline = os.path.join(BASELINES, "TerroirOverlayImages_SlopeMap.png")
        differing, worst = compare_images(read_rgb(path), read_rgb(baseline))
        self.assertLessEqual(differing, DIFFERING_PIXELS, (baseline, worst))

    def test_flat_ground_pixel_is_the_colour_table_colour_lit(self):
        # A flat 1 km square at a constant slope value of 30 deg: every pixel is the Slope
        # preset's colour at 30 (its mid grey, from vtkTerroirColorPresets) times the flat
        # shading 0.25 + 0.75 sin 45 plus the specular 0.15 cos(22.5)^20 (TestOverlayView).
        need_display(self)
        terrain = vtkImageData()
        terrain.SetDimensions(51, 51, 1)
        terrain.SetSpacing(20.0, 20.0, 1.0)
        z = numpy_to_vtk(np.full(51 * 51, 250.0), deep=1)
        z.SetName("Elevation")
        terrain.GetPointData().AddArray(z)
        paint = numpy_to_vtk(np.full(51 * 51, 30.0), deep=1)
        paint.SetName("Paint")
        terrain.GetPointData().AddArray(paint)
        view = terroir.vtkTerroirOverlayView()
        view.SetInputData(terrain)
        view.SetArrayName("Paint")
        view.SetPreset("Slope")
        view.SetModeToMap()
        view.ShowLegendOff()
        view.SetWidth(100)
        view.SetHeight(100)
        path = os.path.join(TEMP, "python_flat_overlay.png")
        self.assertTrue(view.WritePNG(path), view.GetLastError())
        lut = vtkLookupTable()
        self.assertTrue(terroir.vtkTerroirColorPresets.ConfigureLookupTable(lut, "Slope", 0, 60))
        colour = [0.0, 0.0, 0.0]
        lut.GetColor(30.0, colour)
        shade = 0.25 + 0.75 * math.sqrt(0.5)
        spec = 0.15 * math.cos(math.pi / 8) ** 20
        rgb = read_rgb(path)
        for y, x in ((50, 50), (20, 80), (80, 20)):
            for c in range(3):
                self.assertAlmostEqual(rgb[y, x, c], 255 * (colour[c] * shade + spec), delta=3,
                                       msg=(x, y, c))

    def test_missing_array_is_a_clear_error(self):
        need_display(self)
        source = terroir.vtkTerroirFractalTerrainSource()
        source.SetDimensions(32, 32)
        source.Update()
        view = terroir.vtkTerroirOverlayView()
        view.SetInputData(source.GetOutput())
        view.SetArrayName("NoSuchArray")
        path = os.path.join(TEMP, "python_missing_array.png")
        if os.path.exists(path):
            os.remove(path)
        self.assertFalse(view.WritePNG(path))
        self.assertIn("NoSuchArray", view.GetLastError())
        self.assertFalse(os.path.exists(path))


if __name__ == "__main__":
    unittest.main(verbosity=2)
