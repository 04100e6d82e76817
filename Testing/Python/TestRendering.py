#!/usr/bin/python3
"""Rendering from Python: reader -> slope -> overlay PNG, as a pvpython-style script would.

Needs an X display (VTK 9.1 renders through X): skipped without DISPLAY unless
TERROIR_REQUIRE_GPU=1, as the C++ rendering tests do."""
import os
import tempfile
import unittest

import numpy as np
from vtkmodules.vtkIOImage import vtkPNGReader
from vtkmodules.util.numpy_support import vtk_to_numpy

import terroir

DATA = os.environ.get("TERROIR_DATA_DIR", "Data")
TEMP = os.environ.get("TERROIR_TEMP_DIR", tempfile.gettempdir())
DEM = os.path.join(DATA, "sagehen_creek_ca", "sagehen_dem_utm11n_10m.tif")


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
        view.SetWidth(200)
        view.SetHeight(160)
        path = os.path.join(TEMP, "python_slope_overlay.png")
        self.assertTrue(view.WritePNG(path), view.GetLastError())
        png = vtkPNGReader()
        png.SetFileName(path)
        png.Update()
        image = png.GetOutput()
        self.assertEqual(image.GetDimensions()[:2], (200, 160))
        pixels = vtk_to_numpy(image.GetPointData().GetScalars())
        # The slope preset is black (0 deg) to white (60 deg): the terrain shows many grey
        # levels, not a blank frame.
        self.assertGreater(len(np.unique(pixels[:, 0])), 50)

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
