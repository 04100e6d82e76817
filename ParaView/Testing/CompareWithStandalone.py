"""Runs an example's pipeline again with the standalone build (Debian's VTK 9.1, /usr/bin/python3,
package `terroir`) and checks that the ParaView plugin's output has the same arrays, bit for
bit: the same algorithm cores, compiled with the same flags, on the same input in the same
order of operations (ParaView's VTK 9.2 only carries the arrays).
    CompareWithStandalone.py chain|zones DEM PLUGIN_OUTPUT.vti"""
import math
import sys

import numpy as np
import terroir
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOXML import vtkXMLImageDataReader


def chain(dem):
    """ParaView/Examples/TerroirChain.py: every filter at its defaults, water flow in Rivers."""
    stages = [terroir.vtkTerroirSlope(), terroir.vtkTerroirSolarIllumination(),
              terroir.vtkTerroirTemperature(), terroir.vtkTerroirInfiltration(),
              terroir.vtkTerroirSoilHumidity(), terroir.vtkTerroirWaterFlow(),
              terroir.vtkTerroirKMeans()]
    stages[5].SetModeToRivers()
    return connect(dem, stages)


def zones(dem):
    """ParaView/Examples/TerroirZones.py."""
    slope = terroir.vtkTerroirSlope()
    slope.SetComputeNormals(False)
    sun = terroir.vtkTerroirSolarIllumination()
    sun.SetTimeStep(30)
    temperature = terroir.vtkTerroirTemperature()
    temperature.SetLapseRate(6.0)
    kmeans = terroir.vtkTerroirKMeans()
    kmeans.SetNumberOfClusters(4)
    kmeans.SetStandardize(True)
    for name, weight in [('Elevation', 1.0), ('Slope', 2.0), ('Temperature', 1.0),
                         ('IlluminationHours', 0.5)]:
        kmeans.AddFeature(name, weight)
    return connect(dem, [slope, sun, temperature, kmeans])


def connect(dem, stages):
    reader = terroir.vtkTerroirDEMReader()
    reader.SetFileName(dem)
    previous = reader
    for stage in stages:
        stage.SetInputConnection(previous.GetOutputPort())
        previous = stage
    previous.Update()
    return previous.GetOutput()


def arrays(data):
    pd = data.GetPointData()
    return {pd.GetArrayName(i): vtk_to_numpy(pd.GetArray(i)) for i in range(pd.GetNumberOfArrays())
            if pd.GetArray(i) is not None}


def main():
    recipe, dem, plugin_output = sys.argv[1:4]
    expected = {'chain': chain, 'zones': zones}[recipe](dem)
    reader = vtkXMLImageDataReader()
    reader.SetFileName(plugin_output)
    reader.Update()
    got = reader.GetOutput()
    status = 0
    if got.GetDimensions() != expected.GetDimensions():
        print('dimensions: plugin %s, standalone %s' % (got.GetDimensions(),
                                                        expected.GetDimensions()))
        return 1
    a, b = arrays(got), arrays(expected)
    if sorted(a) != sorted(b):
        print('arrays: plugin %s, standalone %s' % (sorted(a), sorted(b)))
        status = 1
    for name in sorted(set(a) & set(b)):
        x, y = a[name], b[name]
        same = x.dtype == y.dtype and x.shape == y.shape and np.array_equal(x, y, equal_nan=True)
        if not same:
            diff = np.nanmax(np.abs(x.astype(float) - y.astype(float))) if x.shape == y.shape \
                else math.inf
            print('%s: differs (max |difference| %g)' % (name, diff))
            status = 1
        else:
            print('%s: identical (%d values, %d NaN)' % (name, x.size,
                                                        int(np.isnan(x.astype(float)).sum())))
    return status


if __name__ == '__main__':
    sys.exit(main())
