"""A Terroir chain in pieces under MPI (pvbatch --symmetric, run by mpirun -np N): every rank
builds the same pipeline, ParaView's parallel image writer writes one piece per rank (.pvti), and
each rank records what its reader read and what its last filter gave back.
    mpirun -np N pvbatch --symmetric RunInParaView.py DistributedChain.py \\
        PLUGIN DEM OUT_DIR terrain|zones
terrain: DEM -> slope -> temperature -> infiltration -> soil humidity (pointwise filters per
piece, slope and infiltration with one ghost layer each); zones: the same, then k-means;
zonesghost: zones, then slope again (k-means asked for a ghost layer).
OUT_DIR receives chain.pvti with its pieces (ParaView's parallel image writer: one .vti per
rank), for terrain slope.tif (TerroirGeoTIFFWriter: a serial format, for which ParaView updates
the whole grid on every rank and rank 0 writes), and
rank<R>.json per rank: the piece's extent, the reader's GDAL window (property ReadExtent) and
the number of points of the piece.
CompareDistributed.py checks both against the standalone build's serial run."""
import json
import os
import sys

from paraview import servermanager
from paraview.simple import LoadPlugin, XMLPImageDataWriter


def main():
    plugin, dem, out_dir, recipe = sys.argv[1:5]
    LoadPlugin(plugin, remote=False, ns=globals())
    reader = TerroirDEMReader(FileName=dem)  # noqa: F821 (the plugin defines them)
    slope = TerroirSlope(Input=reader)  # noqa: F821
    temperature = TerroirTemperature(Input=slope)  # noqa: F821
    infiltration = TerroirInfiltration(Input=temperature)  # noqa: F821
    last = TerroirSoilHumidity(Input=infiltration)  # noqa: F821
    if recipe in ('zones', 'zonesghost'):
        last = TerroirKMeans(Input=last)  # noqa: F821
    if recipe == 'zonesghost':
        # A stencil after k-means asks it for a ghost layer: k-means then receives its piece and
        # that layer, and must still count each point once.
        last = TerroirSlope(Input=last)  # noqa: F821
    elif recipe not in ('terrain', 'zones'):
        raise SystemExit('recipe must be terrain, zones or zonesghost, not ' + recipe)
    writer = XMLPImageDataWriter(Input=last, FileName=os.path.join(out_dir, 'chain.pvti'))
    writer.UpdatePipeline()

    pm = servermanager.vtkProcessModule.GetProcessModule()
    rank, ranks = pm.GetPartitionId(), pm.GetNumberOfLocalPartitions()
    # The local pipeline's objects: every rank runs this script (--symmetric).
    local = last.GetClientSideObject().GetOutputDataObject(0)
    reader.UpdatePropertyInformation()
    read_extent = list(reader.GetProperty('ReadExtent'))
    record = {
        'rank': rank,
        'ranks': ranks,
        'piece_extent': list(local.GetExtent()),
        'points': local.GetNumberOfPoints(),
        'read_extent': read_extent,
        'arrays': sorted(local.GetPointData().GetArrayName(i)
                         for i in range(local.GetPointData().GetNumberOfArrays())),
    }
    if recipe == 'terrain':
        # A serial-format writer (supports_parallel 0): ParaView updates the whole extent (the
        # one piece of one) on every rank and rank 0 writes the one GeoTIFF.
        tif = TerroirGeoTIFFWriter(Input=last, FileName=os.path.join(out_dir, 'slope.tif'),  # noqa: F821
                                   ArrayName='Slope')
        tif.UpdatePipeline()
        reader.UpdatePropertyInformation()
        record['read_extent_for_geotiff'] = list(reader.GetProperty('ReadExtent'))
    with open(os.path.join(out_dir, 'rank%d.json' % rank), 'w') as f:
        json.dump(record, f)
    print('rank %d of %d: piece %s, read %s' % (rank, ranks, record['piece_extent'],
                                                record['read_extent']))


if __name__ == '__main__':
    main()
