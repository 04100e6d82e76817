"""A Terroir chain in pieces under MPI (pvbatch --symmetric, run by mpirun -np N): every rank
builds the same pipeline, ParaView's parallel image writer writes one piece per rank (.pvti), and
each rank records what its reader read and what its last filter gave back.
    mpirun -np N pvbatch --symmetric RunInParaView.py DistributedChain.py \\
        PLUGIN DEM OUT_DIR terrain|zones|zonesghost|flow|flowghost|rivers|riversghost|riverswarm|lakes|
        lakesghost|seeds|sun|sunhours|d8|d8ghost|mfd|dinf|erosion|full
terrain: DEM -> slope -> temperature -> infiltration -> soil humidity (pointwise filters per
piece, slope and infiltration with one ghost layer each); zones: the same, then k-means;
zonesghost: zones, then slope again (k-means asked for a ghost layer); flow: DEM -> water
flow (Pulse, defaults: a halo exchanged every iteration, the stop rule's sums all-gathered);
flowghost: flow, then slope (the water flow asked for a ghost layer); rivers: DEM -> water flow
(Rivers mode, WarmStart off: the still water from the parallel fill, the rain's totals summed
over the pieces, the halo's rates, strengths and net discharge from their owners);
riversghost: rivers, then slope; riverswarm: DEM -> water flow (Rivers mode, its defaults: the
warm start's coarse levels in pieces too); full: every distributed stage in one chain (full_chain);
lakes: DEM -> flood fill
(FillDepressions: Barnes 2016's parallel Priority-Flood, the water bodies joined across the
pieces); lakesghost: lakes, then slope (the flood fill asked for a ghost layer); seeds: DEM ->
flood fill (Seeds: Independence Lake's cell and a cell in another piece, at the terrain height);
sun: DEM -> solar illumination (Instant, 21 June at 12:00 PST) with a halo of SUN_HALO cells;
sunhours: the same day's hours of sun (Daily, 30-minute steps) with a halo of 16 cells only;
d8: DEM -> flow accumulation (D8 in pieces: the parallel fill, the flats' distances relaxed
across the pieces, Barnes 2017's perimeter graph); d8ghost: d8, then slope; mfd, dinf: DEM ->
flow accumulation by MFD (Freeman) or D-infinity in pieces (the sums in rounds of inflow);
erosion: DEM -> erosion, 50 steps of rain (a whole-extent filter: every rank runs the whole grid).
OUT_DIR receives chain.pvti with its pieces (ParaView's parallel image writer: one .vti per
rank), for terrain slope.tif (TerroirGeoTIFFWriter: a serial format, for which ParaView updates
the whole grid on every rank and rank 0 writes), and
rank<R>.json per rank: the piece's extent, the reader's GDAL window (property ReadExtent) and
the number of points of the piece.
CompareDistributed.py checks both against the standalone build's serial run."""
import json
import os
import resource
import sys
import time

from paraview import servermanager
from paraview.simple import LoadPlugin, XMLPImageDataWriter


def main():
    plugin, dem, out_dir, recipe = sys.argv[1:5]
    LoadPlugin(plugin, remote=False, ns=globals())
    reader = TerroirDEMReader(FileName=dem)  # noqa: F821 (the plugin defines them)
    if recipe == 'erosion':
        # A whole-extent filter (a global simulation): every rank computes the whole grid and
        # keeps its piece; 50 steps of rain on Sagehen.
        last = TerroirErosion(Input=reader, Steps=50, RainRate=20.0)  # noqa: F821
        return write(reader, last, out_dir, recipe)
    if recipe == 'riverswarm':
        # River-forming water flow with its defaults: the warm start's coarse levels in pieces
        # (each tiled by the halved pieces, its own parallel fill and halo), then the grid.
        last = TerroirWaterFlow(Input=reader, Mode='Rivers')  # noqa: F821
        return write(reader, last, out_dir, recipe)
    if recipe in ('rivers', 'riversghost'):
        # River-forming water flow without the warm start: the still water from the parallel
        # fill, rain every iteration until the outflow balances.
        last = TerroirWaterFlow(Input=reader, Mode='Rivers', WarmStart=0)  # noqa: F821
        if recipe == 'riversghost':
            last = TerroirSlope(Input=last)  # noqa: F821
        return write(reader, last, out_dir, recipe)
    if recipe in ('flow', 'flowghost'):
        # Water flow alone (Pulse, its defaults): each rank iterates on its piece and a halo
        # of 3 cells, exchanging 2 rings with its neighbours every iteration.
        last = TerroirWaterFlow(Input=reader)  # noqa: F821
        if os.environ.get('TERROIR_FLOW_ITERATIONS'):
            # Benchmarks (Testing/Benchmarks/scaling_mpi.sh): a fixed number of iterations.
            last.MaximumIterations = int(os.environ['TERROIR_FLOW_ITERATIONS'])
            last.AutoStopRatio = 0.0
        if recipe == 'flowghost':
            # A stencil after it asks the water flow for a ghost layer: its halo grows by one
            # and the cells it gives back beyond its piece must be right too.
            last = TerroirSlope(Input=last)  # noqa: F821
        return write(reader, last, out_dir, recipe)
    if recipe == 'sun':
        last = TerroirSolarIllumination(Input=reader, Mode='Instant', Month=6, Day=21,  # noqa: F821
                                        Time=12.0, UTCOffset=-8.0, DistributedHalo=SUN_HALO)
        return write(reader, last, out_dir, recipe)
    if recipe == 'sunhours':
        last = TerroirSolarIllumination(Input=reader, Mode='Daily', Month=6, Day=21,  # noqa: F821
                                        TimeStep=30.0, DistributedHalo=16)
        return write(reader, last, out_dir, recipe)
    if recipe == 'seeds':
        last = TerroirFloodFill(Input=reader, Mode='Seeds', SeedPoints=SEEDS)  # noqa: F821
        return write(reader, last, out_dir, recipe)
    if recipe in ('mfd', 'dinf'):
        # MFD (Freeman's) and D-infinity in pieces: the sums in rounds of inflow.
        method = 'MFD' if recipe == 'mfd' else 'DInfinity'
        last = TerroirFlowAccumulation(Input=reader, Method=method)  # noqa: F821
        return write(reader, last, out_dir, recipe)
    if recipe in ('d8', 'd8ghost'):
        # Each piece with 2 ghost layers; only the pieces' perimeters travel.
        last = TerroirFlowAccumulation(Input=reader, Method='D8')  # noqa: F821
        if recipe == 'd8ghost':
            last = TerroirSlope(Input=last)  # noqa: F821
        return write(reader, last, out_dir, recipe)
    if recipe in ('lakes', 'lakesghost'):
        # Depressions filled on each piece and a ring of one cell; rank 0 floods the graph of
        # the pieces' spill levels and joins the lakes that cross piece boundaries.
        last = TerroirFloodFill(Input=reader, Mode='FillDepressions')  # noqa: F821
        if recipe == 'lakesghost':
            last = TerroirSlope(Input=last)  # noqa: F821
        return write(reader, last, out_dir, recipe)
    if recipe == 'full':
        last = full_chain(reader)
        # Each stage's output is freed once the next has read it (a piece's output is a cropped
        # copy of its input's arrays: kept, every stage would hold its own copy of them all).
        # ParaView puts a vtkPVPostFilter after each proxy (it shallow-copies the output, so
        # that a filter reads the post filter's): both must release, or the arrays stay.
        algorithm = last.GetClientSideObject()
        while algorithm.GetNumberOfInputPorts() and algorithm.GetNumberOfInputConnections(0):
            algorithm = algorithm.GetInputAlgorithm()
            algorithm.ReleaseDataFlagOn()
        return write(reader, last, out_dir, recipe)
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
        raise SystemExit('recipe must be terrain, zones, zonesghost, flow, flowghost, rivers, '
                         'riversghost, riverswarm, erosion, lakes, lakesghost, seeds, sun, sunhours, d8, d8ghost, mfd, dinf or '
                         'full, not ' + recipe)
    return write(reader, last, out_dir, recipe)


def full_chain(reader):
    """Every distributed stage in one pipeline, the sun first (its halo then widens only the
    reader's window): sun (Instant, noon, SUN_HALO) -> slope -> temperature -> infiltration ->
    soil humidity -> flood fill (FillDepressions) -> flow accumulation (D8) -> water flow
    (Pulse; TERROIR_FLOW_ITERATIONS iterations when set) -> k-means. Each stage passes its
    ghost levels upstream: the water flow asks for 3, D8 for 5, the flood fill for 6, the
    stencils up to 8, the sun for 72 (its halo of 64 on top)."""
    # The horizon map (64 floats per cell) is freed once the sun is done (CacheHorizonMap).
    last = TerroirSolarIllumination(Input=reader, Mode='Instant', Month=6, Day=21,  # noqa: F821
                                    Time=12.0, UTCOffset=-8.0, DistributedHalo=SUN_HALO,
                                    CacheHorizonMap=0)
    for make in (TerroirSlope, TerroirTemperature, TerroirInfiltration,  # noqa: F821
                 TerroirSoilHumidity):  # noqa: F821
        last = make(Input=last)
    last = TerroirFloodFill(Input=last, Mode='FillDepressions')  # noqa: F821
    last = TerroirFlowAccumulation(Input=last, Method='D8')  # noqa: F821
    last = TerroirWaterFlow(Input=last)  # noqa: F821
    if os.environ.get('TERROIR_FLOW_ITERATIONS'):
        last.MaximumIterations = int(os.environ['TERROIR_FLOW_ITERATIONS'])
        last.AutoStopRatio = 0.0
    return TerroirKMeans(Input=last)  # noqa: F821


# Seeds recipe: Independence Lake (cell 138, 474 of the bundled DEM: the lake's flat, 23,531
# cells, crosses the row the 4 pieces share) and a cell of the south-east piece.
SEEDS = [215365.0, 4371215.0, 220005.0, 4368475.0]
# Sun recipe: each piece sees 64 cells (640 m) around it; at noon in June the sun (74 degrees)
# is above every tangent terrain beyond could make (at most 54 degrees on this DEM).
SUN_HALO = 64


def smp_threads():
    """The threads vtkSMPTools would use on this rank (VTK_SMP_MAX_THREADS caps them)."""
    from vtkmodules.vtkCommonCore import vtkSMPTools
    return vtkSMPTools.GetEstimatedNumberOfThreads()


def resident_mib():
    """This process's resident memory now (MiB), from /proc/self/statm."""
    with open('/proc/self/statm') as f:
        return int(f.read().split()[1]) * os.sysconf('SC_PAGE_SIZE') / 2.0**20


def stages(proxy):
    """The proxies from the reader to `proxy`, upstream first."""
    chain = [proxy]
    while hasattr(chain[0], 'Input') and chain[0].Input is not None:
        chain.insert(0, chain[0].Input)
    return chain


def write(reader, last, out_dir, recipe):
    # Seconds each stage's RequestData took on this rank (StartEvent to EndEvent), for the
    # scaling benchmark; a stage that runs twice adds up.
    # The resident memory (MiB) at each stage's start and end and the peak until its end, to
    # find which stage holds what.
    seconds, started, memory = {}, {}, {}
    for proxy in stages(last):
        algorithm = proxy.GetClientSideObject()
        name = algorithm.GetClassName()

        def start(obj, event, name=name):
            if os.environ.get('TERROIR_TRIM'):
                import ctypes
                ctypes.CDLL('libc.so.6').malloc_trim(0)
            memory.setdefault(name, {})['start_mib'] = resident_mib()
            started[name] = time.perf_counter()

        def end(obj, event, name=name):
            seconds[name] = seconds.get(name, 0.0) + time.perf_counter() - started[name]
            memory[name]['end_mib'] = resident_mib()
            memory[name]['peak_mib'] = \
                resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
        algorithm.AddObserver('StartEvent', start)
        algorithm.AddObserver('EndEvent', end)
    t0 = time.perf_counter()
    writer = XMLPImageDataWriter(Input=last, FileName=os.path.join(out_dir, 'chain.pvti'))
    writer.UpdatePipeline()
    wall = time.perf_counter() - t0

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
        'stage_seconds': seconds,
        'stage_memory': memory,
        'pipeline_seconds': wall,
        # The arrays this rank's output holds (KiB, VTK's count) and its peak resident memory.
        'output_kib': sum(local.GetPointData().GetArray(i).GetActualMemorySize()
                          for i in range(local.GetPointData().GetNumberOfArrays())),
        'max_rss_kib': resource.getrusage(resource.RUSAGE_SELF).ru_maxrss,
        'smp_threads': smp_threads(),
    }
    if recipe in ('flow', 'flowghost', 'rivers', 'riversghost', 'riverswarm', 'full'):
        # The water flow's run as this rank saw it: every rank must stop at the same iteration.
        fd = local.GetFieldData()
        record['water_flow'] = {
            name: fd.GetArray(name).GetTuple1(0)
            for name in ('WaterFlowIterations', 'WaterFlowInitialVolume', 'WaterFlowStoredVolume',
                         'WaterFlowOutflowVolume', 'WaterFlowMovedVolume')}
        record['water_flow']['WaterFlowStopReason'] = \
            fd.GetAbstractArray('WaterFlowStopReason').GetValue(0)
        levels = fd.GetArray('WaterFlowWarmStartIterations')
        if levels:
            # The warm start's levels (iterations, nx, ny each), coarsest first.
            record['water_flow']['WaterFlowWarmStartIterations'] = [
                levels.GetComponent(t, c) for t in range(levels.GetNumberOfTuples())
                for c in range(levels.GetNumberOfComponents())]
    if recipe in ('sun', 'sunhours', 'full'):
        # Only a distributed run (N > 1 pieces) measures it.
        share = local.GetFieldData().GetArray('SunHaloUncertainShare')
        record['sun_halo_uncertain_share'] = share.GetTuple1(0) if share else None
    if recipe in ('lakes', 'lakesghost', 'seeds', 'full'):
        # The water bodies' table (field data): every rank holds the whole grid's.
        fd = local.GetFieldData()
        record['water_bodies'] = {
            name: [fd.GetArray(name).GetTuple1(i)
                   for i in range(fd.GetArray(name).GetNumberOfTuples())]
            for name in ('WaterBodyLevel', 'WaterBodyArea', 'WaterBodyVolume', 'WaterBodyCells',
                         'WaterBodyMaxDepth') if fd.GetArray(name)}
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
