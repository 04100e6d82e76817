"""Ecological zones in ParaView (pvpython or pvbatch): slope, temperature and monthly sun hours
of a DEM clustered by k-means into four zones, on chosen features and weights, then the zones
(.vti) and the cluster table (.csv) written.

    pvpython TerroirZones.py PLUGIN DEM OUT.vti OUT.csv"""
import sys

from paraview.simple import CSVWriter, LoadPlugin, OutputPort, XMLImageDataWriter

# (array, weight): every component of a multi-component array is one feature.
FEATURES = [('Elevation', 1.0), ('Slope', 2.0), ('Temperature', 1.0), ('IlluminationHours', 0.5)]


def main():
    plugin, dem, out, table = sys.argv[1:5]
    LoadPlugin(plugin, remote=False, ns=globals())
    reader = TerroirDEMReader(FileName=dem)  # noqa: F821 (the plugin defines them)
    slope = TerroirSlope(Input=reader, ComputeNormals=0)  # noqa: F821
    sun = TerroirSolarIllumination(Input=slope, TimeStep=30)  # noqa: F821
    temperature = TerroirTemperature(Input=sun, LapseRate=6.0)  # noqa: F821
    zones = TerroirKMeans(Input=temperature, NumberOfClusters=4,  # noqa: F821
                          Standardize=1, Features=[v for f in FEATURES for v in (f[0], str(f[1]))])
    XMLImageDataWriter(Input=zones, FileName=out).UpdatePipeline()
    table_writer = CSVWriter(Input=OutputPort(zones, 1), FileName=table)
    table_writer.FieldAssociation = 'Row Data'
    table_writer.UpdatePipeline()
    ids = zones.PointData['ClusterId'].GetRange()
    print('zones', int(ids[0]), int(ids[1]))


if __name__ == '__main__':
    main()
