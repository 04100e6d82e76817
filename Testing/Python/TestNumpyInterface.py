#!/usr/bin/python3
"""Terroir outputs through vtkmodules.numpy_interface.dataset_adapter (dsa), as users script them.

On a 160 x 120 window of the bundled DEM with a block of no-data cells written through numpy:
- shapes and types: one-component arrays are (cells,), Normals (cells, 3), monthly arrays
  (cells, 12), ClusterId integer; field data (SunPositions, KMeansClusterShare) and the cluster
  table's columns (dsa over a vtkTable) are arrays too;
- values: every dsa array equals the VTK array tuple for tuple (GetTuple, NaN included), and the
  grid reshape (ny, nx) puts cell (i, j) where vtkImageData::ComputePointId says (row 0 south);
- views, not copies: a value written through numpy is what the VTK array holds, and a filter
  downstream sees it (no-data written as NaN gives NaN slope and ClusterId -1 there);
- numpy back into VTK: dsa's append makes a point array with the right tuples and components,
  which vtkTerroirKMeans takes as a feature.
"""
import os
import unittest

import numpy as np
from vtkmodules.numpy_interface import dataset_adapter as dsa
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkImagingCore import vtkExtractVOI

import terroir

DATA = os.environ.get("TERROIR_DATA_DIR",
                      os.path.join(os.path.dirname(__file__), "..", "..", "Data"))
DEM = os.path.join(DATA, "sagehen_creek_ca", "sagehen_dem_utm11n_10m.tif")
NX, NY = 160, 120
HOLE = (slice(40, 50), slice(60, 75))  # rows j, columns i of the no-data block


def window_with_hole():
    """A deep copy of a DEM window, with NaN elevations in HOLE written through numpy."""
    reader = terroir.vtkTerroirDEMReader()
    reader.SetFileName(DEM)
    crop = vtkExtractVOI()
    crop.SetInputConnection(reader.GetOutputPort())
    crop.SetVOI(300, 300 + NX - 1, 300, 300 + NY - 1, 0, 0)
    crop.Update()
    terrain = vtkImageData()
    terrain.DeepCopy(crop.GetOutput())
    elevation = dsa.WrapDataObject(terrain).PointData["Elevation"]
    elevation.reshape(NY, NX)[HOLE] = np.nan  # a view: this writes into the VTK array
    terrain.GetPointData().GetArray("Elevation").Modified()
    return terrain


def equal_with_nan(a, b):
    return np.array_equal(np.asarray(a), np.asarray(b), equal_nan=True)


class NumpyInterface(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.terrain = window_with_hole()
        slope = terroir.vtkTerroirSlope()
        slope.SetBackendToCPU()
        slope.SetInputData(cls.terrain)
        temperature = terroir.vtkTerroirTemperature()
        temperature.SetBackendToCPU()
        temperature.SetInputConnection(slope.GetOutputPort())
        sun = terroir.vtkTerroirSolarIllumination()
        sun.SetBackendToCPU()
        sun.SetModeToMonthly()
        sun.SetTimeStep(60.0)
        sun.SetHorizonSectors(16)
        sun.SetInputConnection(temperature.GetOutputPort())
        cls.zones = terroir.vtkTerroirKMeans()
        cls.zones.SetBackendToCPU()
        cls.zones.SetNumberOfClusters(3)
        cls.zones.AddFeature("Slope", 1.0)
        cls.zones.AddFeature("Temperature", 1.0)
        cls.zones.SetInputConnection(sun.GetOutputPort())
        cls.zones.Update()
        cls.output = cls.zones.GetOutput()
        cls.wrapped = dsa.WrapDataObject(cls.output)

    def test_shapes_and_types(self):
        n = NX * NY
        points = self.wrapped.PointData
        for name, shape in (("Elevation", (n,)), ("Slope", (n,)), ("Aspect", (n,)),
                            ("Normals", (n, 3)), ("Temperature", (n, 12)),
                            ("IlluminationHours", (n, 12)), ("Insolation", (n, 12)),
                            ("ClusterId", (n,))):
            self.assertEqual(points[name].shape, shape, name)
        self.assertEqual(points["Slope"].dtype, np.float32)
        self.assertEqual(points["Temperature"].dtype, np.float32)
        self.assertTrue(np.issubdtype(points["ClusterId"].dtype, np.integer))
        positions = self.wrapped.FieldData["SunPositions"]
        self.assertEqual(positions.shape, (12 * 24, 6))  # 12 days of 24 one-hour steps
        self.assertTrue(np.array_equal(np.unique(positions[:, 0]), np.arange(1, 13)))

    def test_values_equal_the_vtk_arrays(self):
        point_data = self.output.GetPointData()
        for name in ("Elevation", "Slope", "Aspect", "Normals", "Temperature",
                     "IlluminationHours", "ClusterId"):
            array = point_data.GetArray(name)
            tuples = [array.GetTuple(t) for t in range(array.GetNumberOfTuples())]
            expected = np.array(tuples).reshape(self.wrapped.PointData[name].shape)
            self.assertTrue(equal_with_nan(self.wrapped.PointData[name], expected), name)

    def test_grid_reshape_follows_the_image(self):
        elevation = np.asarray(self.wrapped.PointData["Elevation"]).reshape(NY, NX)
        vtk_array = self.output.GetPointData().GetArray("Elevation")
        extent = self.output.GetExtent()
        for i, j in ((0, 0), (NX - 1, 0), (0, NY - 1), (17, 93), (NX - 1, NY - 1)):
            point = self.output.ComputePointId([extent[0] + i, extent[2] + j, 0])
            self.assertEqual(elevation[j, i], vtk_array.GetValue(point))
        # Row 0 is the south edge: its y is the smallest.
        self.assertLess(self.output.GetPoint(0)[1], self.output.GetPoint(NX * (NY - 1))[1])

    def test_numpy_writes_reach_vtk_and_the_filters(self):
        elevation = np.asarray(self.wrapped.PointData["Elevation"]).reshape(NY, NX)
        self.assertTrue(np.isnan(elevation[HOLE]).all())
        slope = np.asarray(self.wrapped.PointData["Slope"]).reshape(NY, NX)
        july = np.asarray(self.wrapped.PointData["Temperature"])[:, 6].reshape(NY, NX)
        zone = np.asarray(self.wrapped.PointData["ClusterId"]).reshape(NY, NX)
        self.assertTrue(np.isnan(slope[HOLE]).all() and np.isnan(july[HOLE]).all())
        self.assertTrue((zone[HOLE] == -1).all())
        outside = np.ones((NY, NX), bool)
        outside[HOLE] = False
        self.assertTrue(np.isfinite(july[outside]).all())
        self.assertTrue((zone[outside] >= 0).all())
        # A write through the dsa view is a write into the VTK array.
        copy = vtkImageData()
        copy.DeepCopy(self.output)
        view = dsa.WrapDataObject(copy).PointData["Slope"]
        view[5] = 123.5
        self.assertEqual(copy.GetPointData().GetArray("Slope").GetValue(5), 123.5)

    def test_the_cluster_table_through_dsa(self):
        table = dsa.WrapDataObject(self.zones.GetClusterTable())
        cells = np.asarray(table.RowData["Cells"])
        share = np.asarray(table.RowData["Share"])
        valid = NX * NY - 10 * 15
        self.assertEqual(cells.shape, (3,))
        self.assertEqual(cells.sum(), valid)
        self.assertAlmostEqual(share.sum(), 1.0, places=12)
        # Each zone's mean July temperature, recomputed with numpy from the labels.
        july = np.asarray(self.wrapped.PointData["Temperature"])[:, 6]
        zone = np.asarray(self.wrapped.PointData["ClusterId"])
        for k in range(3):
            self.assertAlmostEqual(float(july[zone == k].mean(dtype=np.float64)),
                                   float(table.RowData["Temperature_Jul"][k]), places=4)
        shares = np.asarray(self.wrapped.FieldData["KMeansClusterShare"]).ravel()
        self.assertTrue(np.allclose(shares, share))

    def test_numpy_arrays_go_back_into_vtk(self):
        copy = vtkImageData()
        copy.DeepCopy(self.output)
        wrapped = dsa.WrapDataObject(copy)
        hours = np.asarray(wrapped.PointData["IlluminationHours"])
        wrapped.PointData.append(hours.sum(axis=1), "AnnualSunHours")
        wrapped.PointData.append(hours * 60.0, "IlluminationMinutes")
        annual = copy.GetPointData().GetArray("AnnualSunHours")
        minutes = copy.GetPointData().GetArray("IlluminationMinutes")
        self.assertEqual((annual.GetNumberOfTuples(), annual.GetNumberOfComponents()),
                         (NX * NY, 1))
        self.assertEqual((minutes.GetNumberOfTuples(), minutes.GetNumberOfComponents()),
                         (NX * NY, 12))
        self.assertAlmostEqual(minutes.GetComponent(1000, 5), 60.0 * hours[1000, 5], places=3)
        # A filter takes the numpy-made array as a feature: one feature, so the zones are
        # intervals of annual sun hours.
        zones = terroir.vtkTerroirKMeans()
        zones.SetBackendToCPU()
        zones.SetNumberOfClusters(2)
        zones.AddFeature("AnnualSunHours", 1.0)
        zones.SetInputData(copy)
        zones.Update()
        labels = np.asarray(dsa.WrapDataObject(zones.GetOutput()).PointData["ClusterId"])
        annual_np = hours.sum(axis=1)
        valid = labels >= 0
        self.assertTrue(np.array_equal(valid, np.isfinite(annual_np)))
        low = annual_np[valid & (labels == 0)]
        high = annual_np[valid & (labels == 1)]
        self.assertTrue(low.max() < high.min() or high.max() < low.min())


if __name__ == "__main__":
    unittest.main(verbosity=2)
