#!/usr/bin/python3
"""The IO classes from Python: values equal what GDAL (python3-gdal) reads, rows south first,
no-data masked, feet converted, Terragen equal to the GeoTIFF within its 16-bit quantisation."""
import os
import sys
import unittest

import numpy as np
from osgeo import gdal
from vtkmodules.util.numpy_support import vtk_to_numpy

import terroir

gdal.UseExceptions()
DATA = os.environ.get("TERROIR_DATA_DIR", "Data")
TIF = os.path.join(DATA, "sagehen_creek_ca", "sagehen_dem_utm11n_10m.tif")
TER = os.path.join(DATA, "sagehen_creek_ca", "sagehen_dem_utm11n_10m.ter")
USGS = os.path.join(DATA, "san_francisco_usgs_dem", "sanfranciscos.dem")
TEMP = os.environ.get("TERROIR_TEMP_DIR", "/tmp")


def read(path):
    reader = terroir.vtkTerroirDEMReader()
    reader.SetFileName(path)
    reader.Update()
    return reader


def grid(image, name="Elevation"):
    nx, ny, _ = image.GetDimensions()
    return vtk_to_numpy(image.GetPointData().GetArray(name)).reshape(ny, nx)


class TerroirIOFromPython(unittest.TestCase):
    def test_geotiff_matches_gdal_with_rows_flipped(self):
        reader = read(TIF)
        self.assertEqual(reader.GetErrorMessage(), "")
        image = reader.GetOutput()
        ds = gdal.Open(TIF)  # keep the dataset alive while its band is used
        expected = ds.GetRasterBand(1).ReadAsArray()[::-1, :]
        np.testing.assert_array_equal(grid(image), expected)
        self.assertEqual(image.GetSpacing()[:2], (10.0, 10.0))
        # Origin is the south-west cell centre: 213980 + 5, 4373670 - 720*10 + 5.
        self.assertEqual(image.GetOrigin()[:2], (213985.0, 4366475.0))
        self.assertIn("UTM zone 11N", terroir.vtkTerroirGeoreference.GetCRS(image))

    def test_usgs_dem_in_feet_becomes_metres_and_nodata_is_masked(self):
        image = read(USGS).GetOutput()
        ds = gdal.Open(USGS)
        band = ds.GetRasterBand(1)
        raw = band.ReadAsArray().astype(np.float64)[::-1, :]
        nodata = raw == band.GetNoDataValue()
        z = grid(image)
        mask = grid(image, "vtkValidPointMask")
        np.testing.assert_array_equal(mask == 0, nodata)
        self.assertTrue(np.all(np.isnan(z[nodata])))
        np.testing.assert_allclose(z[~nodata], raw[~nodata] * 0.3048, rtol=1e-6)

    def test_terragen_equals_geotiff_within_quantisation(self):
        reader = terroir.vtkTerroirTerragenReader()
        reader.SetFileName(TER)
        reader.Update()
        ter = grid(reader.GetOutput()).astype(np.float64)
        tif = grid(read(TIF).GetOutput()).astype(np.float64)
        # Heights 1900..2680 m in 16 bits: one step is 10 * 81 / 65536 = 0.0124 m.
        self.assertLess(np.max(np.abs(ter - tif)), 10 * 81 / 65536 + 1e-3)

    def test_bad_file_gives_one_line_error(self):
        reader = terroir.vtkTerroirDEMReader()
        reader.SetFileName(os.path.join(DATA, "no_such_file.tif"))
        reader.GetExecutive().SetReleaseDataFlag(0, 0)
        # VTK prints the error through its output window; keep the test log readable.
        import vtkmodules.vtkCommonCore as cc
        cc.vtkObject.GlobalWarningDisplayOff()
        reader.Update()
        cc.vtkObject.GlobalWarningDisplayOn()
        message = reader.GetErrorMessage()
        self.assertIn("no_such_file.tif", message)
        self.assertNotIn("\n", message)
        self.assertEqual(reader.GetOutput().GetNumberOfPoints(), 0)

    def test_geotiff_writer_keeps_blocks_of_zeros(self):
        # A band whose rows are all 0 (flat ground's slope, rows in shadow) reads back as 0, not
        # as the band's no-data value; masked cells are the only no-data, in float and byte bands.
        from vtkmodules.vtkCommonDataModel import vtkImageData
        from vtkmodules.util.numpy_support import numpy_to_vtk
        nx, ny = 1024, 30  # GDAL strips of 2 rows: some hold nothing but zeros
        image = vtkImageData()
        image.SetDimensions(nx, ny, 1)
        image.SetSpacing(10, 10, 1)
        values = np.zeros((ny, nx), np.float32)
        values[20:, :] = 1.0  # the northern rows lit, the others 0
        mask = np.ones((ny, nx), np.uint8)
        for name, array in (("Illuminated", values), ("Class", values.astype(np.uint8))):
            a = numpy_to_vtk(array.ravel(), deep=1)
            a.SetName(name)
            image.GetPointData().AddArray(a)
        for masked in (False, True):
            if masked:
                mask[0, 0] = 0
                m = numpy_to_vtk(mask.ravel(), deep=1)
                m.SetName("vtkValidPointMask")
                image.GetPointData().AddArray(m)
            for name in ("Illuminated", "Class"):
                path = os.path.join(TEMP, f"python_zeros_{name}_{int(masked)}.tif")
                writer = terroir.vtkTerroirGeoTIFFWriter()
                writer.SetInputData(image)
                writer.SetArrayName(name)
                writer.SetFileName(path)
                writer.SetOverwrite(True)
                writer.Write()
                self.assertEqual(writer.GetErrorMessage(), "")
                ds = gdal.Open(path)
                band = ds.GetRasterBand(1)
                got = band.ReadAsArray().astype(np.float64)[::-1, :]
                nodata = band.GetNoDataValue()
                invalid = np.isnan(got) | (got == nodata if nodata is not None else False)
                np.testing.assert_array_equal(invalid, mask == 0, err_msg=name)
                np.testing.assert_array_equal(got[mask == 1], values[mask == 1], err_msg=name)
                ds = None
                os.remove(path)

    def test_fractal_source_is_deterministic(self):
        def make(seed):
            s = terroir.vtkTerroirFractalTerrainSource()
            s.SetDimensions(64, 48)
            s.SetSeed(seed)
            s.Update()
            return grid(s.GetOutput()).copy()

        a, b, c = make(3), make(3), make(4)
        self.assertEqual(a.shape, (48, 64))
        np.testing.assert_array_equal(a, b)
        self.assertGreater(np.max(np.abs(a - c)), 1.0)


if __name__ == "__main__":
    unittest.main(verbosity=2)
