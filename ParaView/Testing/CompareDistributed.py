"""Checks a distributed run of DistributedChain.py (mpirun -np N pvbatch) against the same chain
run serially by the standalone build (Debian's VTK 9.1, /usr/bin/python3, package `terroir`):
    CompareDistributed.py terrain|zones|...|sun|sunhours|d8|d8ghost|mfd|dinf|full N DEM OUT_DIR
- the pieces of OUT_DIR/chain.pvti, reassembled by VTK 9.1's vtkXMLPImageDataReader, give the
  serial arrays bit for bit (besides the all-zero vtkGhostType ParaView's writer adds) (the same cores on the same cells in the same order: a piece's
  cells see the same neighbours through their ghost layer); `vtkValidPointMask`, which the
  serial run has only when some cell is no-data, must match it too;
- terrain: slope.tif (TerroirGeoTIFFWriter, a serial format: ParaView updates the whole grid
  on every rank for it and rank 0 writes) has the bytes of the standalone writer's GeoTIFF;
- the .pvti holds N pieces that tile the whole extent without overlap, one per rank;
- each rank's reader read only its piece grown by the ghost layers the chain asks for (slope 1,
  infiltration 1: 2 cells, clamped to the raster), so no rank read the whole DEM when N > 1
  (k-means, in zones, asks for its piece alone in a distributed run: all-reduced sums);
- flow (water flow, Pulse): every array bit for bit, the same iteration count and stop reason on
  every rank as serially, the volumes within FLOW_VOLUME_RTOL, and a river of the serial run
  crossing every column and row that the pieces share; flowghost: the same with a slope after
  the water flow (which then gives a ghost layer beyond its piece; the reader reads 4 cells);
- lakes (flood fill, FillDepressions in pieces, Barnes 2016): WaterBody and WaterDepth bit for
  bit, every rank's table of water bodies equal to the serial one (levels, cell counts, depths
  exact; areas and volumes within LAKE_RTOL), and on 4 ranks a lake of the serial run lying in
  more than one piece; lakesghost: the same with a slope after it (reader: 2 cells); seeds
  (flood fill from two seeds in pieces): the same checks;
- sun (solar illumination, Instant, each piece with a halo of 64 cells): `Illuminated` and
  `SunIncidence` bit for bit, and every rank measured no decision that terrain beyond its halo
  could change (SunHaloUncertainShare 0); sunhours (Daily, a halo of 16 cells, too small for
  the low sun): the hours and insolation above the serial run's somewhere and below it on at
  most 0.1 % of the cells (hours: by more than one step on at most 10; the horizon map's
  sampling), and a share
  of uncertain decisions above 0 on every rank (the measure sees what the halo lacks);
- d8 (flow accumulation, D8 in pieces): FilledElevation, FlowDirection, FlowAccumulation and
  River bit for bit, ContributingArea and ChannelInitiation within D8_RTOL, and a river of the
  serial run crossing every column and row that the pieces share; d8ghost: the same with a
  slope after it (reader: 3 cells); mfd, dinf (MFD and D-infinity in pieces): the same, with
  FlowAccumulation within D8_RTOL too (the dispersive sums are not integers) and FlowAngle
  (D-infinity) bit for bit; erosion (a whole-extent filter): every array bit for bit, and every
  rank read the whole raster;
- rivers (water flow, Rivers mode without the warm start, in pieces): as flow (every array bit
  for bit, DischargeRate, RiverStrength and LakeMask included; the same iterations and stop
  reason, Balanced; the volumes within FLOW_VOLUME_RTOL; a river across every shared line);
  riversghost: the same with a slope after it (reader: 4 cells); riverswarm (Rivers mode with
  its defaults: the warm start's coarse levels in pieces): the same, and the levels
  (WaterFlowWarmStartIterations: iterations and sizes) equal;
- full (every distributed stage in one chain, DistributedChain.full_chain): every array bit for
  bit (D8's sums within D8_RTOL), and the k-means, water-flow, water-body and sun checks above
  (reader: 72 cells, the sun's halo of 64 and the 8 ghost layers the stages after it ask for).
Fails (exit 1) with one line per problem."""
import filecmp
import json
import os
import sys
import xml.etree.ElementTree as ET

import numpy as np
import terroir
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOXML import vtkXMLPImageDataReader

# Ghost cells the reader reads around a piece: slope's layer and infiltration's, one each, and
# one more when a slope follows k-means.
# Water flow (flow) reads its piece grown by 3: 2 rings refreshed from the neighbours every
# iteration and 1 more for the heights of no-data cells beside them.
# The flood fill reads its piece and one ring (its perimeter's neighbours), one more for a slope.
GHOST = {'erosion': None, 'terrain': 2, 'zones': 2, 'zonesghost': 3, 'flow': 3, 'flowghost': 4, 'rivers': 3,
         'riversghost': 4, 'riverswarm': 3, 'lakes': 1, 'lakesghost': 2, 'seeds': 1, 'sun': 64, 'sunhours': 16,
         'd8': 2, 'd8ghost': 3, 'mfd': 2, 'dinf': 2, 'full': 72}
# Water flow: the run's volumes are sums over the cells that each process adds for its own
# cells before the processes' sums are added in rank order, another order than the serial
# rows (doubles, ~1e-16 relative per addition, over up to 1e4 iterations).
FLOW_VOLUME_RTOL = 1e-12
# Flood fill: a lake's area and volume are added piece by piece, then the pieces' sums in rank
# order, instead of breadth first over the lake (doubles: ~1e-16 relative per addition).
LAKE_RTOL = 1e-12
# D8 in pieces: a cell downstream of a piece edge adds the flow entering the piece before its own
# upstream cells (another order of the double additions than the serial sweep; cell counts are
# integers and exact).
D8_RTOL = 1e-12
# sunhours: the time step (30 min) in hours.
SUNHOURS_STEP_HOURS = 0.5
LAKE_FIELDS = ('WaterBodyLevel', 'WaterBodyArea', 'WaterBodyVolume', 'WaterBodyCells',
               'WaterBodyMaxDepth')


def piece_boundaries(pieces, whole):
    """The point columns and rows that two pieces share (image pieces share boundary points)."""
    columns = sorted({p[1] for p in pieces if p[1] < whole[1]})
    rows = sorted({p[3] for p in pieces if p[3] < whole[3]})
    return columns, rows


def river_crossings(river, line, axis):
    """Cells of `line` (a column when axis is 0, a row when 1) where a river cell has river
    cells on both sides of the line among its 8 neighbours: a river crosses there."""
    r = river if axis == 0 else river.T
    n = 0
    for j in range(1, r.shape[0] - 1):
        if r[j, line] and r[j - 1:j + 2, line - 1].any() and r[j - 1:j + 2, line + 1].any():
            n += 1
    return n


def serial(recipe, dem):
    reader = terroir.vtkTerroirDEMReader()
    reader.SetFileName(dem)
    stages = [terroir.vtkTerroirSlope(), terroir.vtkTerroirTemperature(),
              terroir.vtkTerroirInfiltration(), terroir.vtkTerroirSoilHumidity()]
    if recipe in ('flow', 'flowghost'):
        stages = [terroir.vtkTerroirWaterFlow()]
    if recipe in ('rivers', 'riversghost', 'riverswarm'):
        stages = [terroir.vtkTerroirWaterFlow()]
        stages[0].SetModeToRivers()
        stages[0].SetWarmStart(recipe == 'riverswarm')
    if recipe in ('lakes', 'lakesghost'):
        stages = [terroir.vtkTerroirFloodFill()]
        stages[0].SetModeToFillDepressions()
    if recipe in ('sun', 'sunhours', 'full'):
        sun = terroir.vtkTerroirSolarIllumination()
        if recipe == 'sunhours':
            sun.SetModeToDaily()
            sun.SetTimeStep(30.0)
        else:
            sun.SetModeToInstant()
        sun.SetMonth(6)
        sun.SetDay(21)
        sun.SetTime(12.0)
        sun.SetUTCOffset(-8.0)
        sun.SetCacheHorizonMap(recipe != 'full')  # as DistributedChain's full chain
        stages = [sun]
    if recipe == 'full':
        # DistributedChain.full_chain's order.
        flood = terroir.vtkTerroirFloodFill()
        flood.SetModeToFillDepressions()
        flow = terroir.vtkTerroirWaterFlow()
        if os.environ.get('TERROIR_FLOW_ITERATIONS'):
            flow.SetMaximumIterations(int(os.environ['TERROIR_FLOW_ITERATIONS']))
            flow.SetAutoStopRatio(0.0)
        stages = [sun, terroir.vtkTerroirSlope(), terroir.vtkTerroirTemperature(),
                  terroir.vtkTerroirInfiltration(), terroir.vtkTerroirSoilHumidity(), flood,
                  terroir.vtkTerroirFlowAccumulation(), flow, terroir.vtkTerroirKMeans()]
    if recipe == 'erosion':
        stages = [terroir.vtkTerroirErosion()]
        stages[0].SetSteps(50)  # DistributedChain's erosion recipe
        stages[0].SetRainRate(20.0)
    if recipe == 'seeds':
        stages = [terroir.vtkTerroirFloodFill()]
        for x, y in ((215365.0, 4371215.0), (220005.0, 4368475.0)):  # DistributedChain.SEEDS
            stages[0].AddSeedPoint(x, y)
    if recipe in ('d8', 'd8ghost', 'mfd', 'dinf'):
        stages = [terroir.vtkTerroirFlowAccumulation()]
        if recipe == 'mfd':
            stages[0].SetMethodToMFD()
        if recipe == 'dinf':
            stages[0].SetMethodToDInfinity()
    if recipe in ('lakesghost', 'd8ghost'):
        stages.append(terroir.vtkTerroirSlope())
    if recipe in ('flowghost', 'riversghost'):
        stages.append(terroir.vtkTerroirSlope())
    if recipe in ('zones', 'zonesghost'):
        stages.append(terroir.vtkTerroirKMeans())
    if recipe == 'zonesghost':
        stages.append(terroir.vtkTerroirSlope())
    previous = reader
    for stage in stages:
        stage.SetInputConnection(previous.GetOutputPort())
        if recipe == 'full':
            previous.ReleaseDataFlagOn()  # as DistributedChain's full chain: less memory
        previous = stage
    previous.Update()
    return previous.GetOutput()


def arrays(data):
    pd = data.GetPointData()
    return {pd.GetArrayName(i): vtk_to_numpy(pd.GetArray(i)) for i in range(pd.GetNumberOfArrays())}


def grow(extent, whole, cells):
    return [max(extent[a] - cells, whole[a]) if a % 2 == 0 else min(extent[a] + cells, whole[a])
            for a in range(4)] + [0, 0]


def main():
    recipe, ranks, dem, out_dir = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4]
    problems = []
    expected = serial(recipe, dem)
    whole = list(expected.GetExtent())

    # The pieces' arrays are read one at a time (the whole grid's arrays, besides the serial
    # run's, would double the memory this needs).
    reader = vtkXMLPImageDataReader()
    reader.SetFileName(os.path.join(out_dir, 'chain.pvti'))
    reader.UpdateInformation()
    names = [reader.GetPointArrayName(i) for i in range(reader.GetNumberOfPointArrays())]

    def piece_array(name):
        for other in names:
            reader.SetPointArrayStatus(other, int(other == name))
        reader.Update()
        return vtk_to_numpy(reader.GetOutput().GetPointData().GetArray(name))

    for name in names:
        reader.SetPointArrayStatus(name, 0)
    reader.Update()  # the extent and the field data
    got = reader.GetOutput()
    b = arrays(expected)
    # ParaView's parallel writer adds vtkGhostType to every piece; no point may be a ghost
    # there (each filter gave back exactly its piece, no ghost layer).
    if 'vtkGhostType' in names:
        ghost = piece_array('vtkGhostType')
        if ghost.any():
            problems.append('%d points are marked ghost in the written pieces' %
                            int((ghost != 0).sum()))
        del ghost
        names.remove('vtkGhostType')
    if list(got.GetExtent()) != whole:
        problems.append('extent: pieces %s, serial %s' % (list(got.GetExtent()), whole))
    if 'vtkValidPointMask' in names and 'vtkValidPointMask' not in b:
        problems.append('the pieces carry vtkValidPointMask, the serial run has no no-data cell')
    if sorted(names) != sorted(b):
        problems.append('arrays: pieces %s, serial %s' % (sorted(names), sorted(b)))
    compared = 0
    for name in sorted(set(names) & set(b)):
        x, y = piece_array(name), b[name]
        if recipe == 'sunhours' and name in ('IlluminationHours', 'Insolation'):
            # A halo too small for the low sun: terrain beyond it is missing, which can only
            # let more sun in, never less; the share measured says how much could change.
            # The horizon map's sweep lines start at the grid's edges, so a piece samples the
            # terrain between grid lines at other places than the whole grid: a decision near
            # its threshold can also go the other way (a few cells, by one step).
            more = int((x > y).sum())
            less = int((x < y).sum())
            below = float(np.nanmax(y - x)) if less else 0.0
            print('%s: %d cells above the serial run, %d below (by at most %g), max |diff| %g' % (
                name, more, less, below, float(np.nanmax(np.abs(x - y)))))
            # Hours: measured 296 of 298 such cells by one step, 2 by two to four.
            far = int((y - x > SUNHOURS_STEP_HOURS).sum()) if name == 'IlluminationHours' else 0
            if x.shape != y.shape or less > 0.001 * x.size or far > 10:
                problems.append('%s: %d cells get less sun in pieces than serially (by up to %g)'
                                % (name, less, below))
            if more == 0:
                problems.append('%s: equal to the serial run: the halo was not too small' % name)
            compared += 1
            continue
        if (recipe in ('d8', 'd8ghost', 'full') and name in ('ContributingArea',
                                                             'ChannelInitiation')) or \
                (recipe in ('mfd', 'dinf') and name in ('FlowAccumulation', 'ContributingArea',
                                                        'ChannelInitiation')):
            close = x.shape == y.shape and np.allclose(x, y, rtol=D8_RTOL, atol=0.0, equal_nan=True)
            print('%s: max relative difference %.3g' % (
                name, float(np.nanmax(np.abs(x - y) / np.maximum(np.abs(y), 1e-300)))))
            if not close:
                problems.append('%s: differs from the serial run by more than %g relative' % (
                    name, D8_RTOL))
            compared += 1
            continue
        if x.dtype != y.dtype or x.shape != y.shape or not np.array_equal(x, y, equal_nan=True):
            diff = (np.nanmax(np.abs(x.astype(float) - y.astype(float)))
                    if x.shape == y.shape else float('inf'))
            problems.append('%s: differs from the serial run (max |diff| %g)' % (name, diff))
        compared += 1
    if recipe in ('zones', 'zonesghost', 'full'):
        # k-means: the iteration count, stop reason and cluster shares (integer counts over the
        # same number of cells) are exact; the inertia is a sum whose terms each process adds
        # for its own cells before the processes' totals are added, another order than the
        # serial blocks of 4096 cells: equal within 1e-9 relative (doubles; measured below).
        fields = [got.GetFieldData(), expected.GetFieldData()]
        for name in ('KMeansIterations', 'KMeansRelocatedClusters', 'KMeansClusterShare'):
            fx, fy = (vtk_to_numpy(f.GetArray(name)) if f.GetArray(name) else None for f in fields)
            if fx is None or fy is None or not np.array_equal(fx, fy):
                problems.append('field %s: pieces %s, serial %s' % (name, fx, fy))
        reason = [f.GetAbstractArray('KMeansStopReason').GetValue(0) for f in fields]
        if reason[0] != reason[1]:
            problems.append('KMeansStopReason: pieces %s, serial %s' % tuple(reason))
        ix, iy = (f.GetArray('KMeansWithinClusterSumOfSquares').GetTuple1(0) for f in fields)
        print('inertia: pieces %.17g, serial %.17g, relative difference %.3g' % (
            ix, iy, abs(ix - iy) / abs(iy)))
        if not abs(ix - iy) <= 1e-9 * abs(iy):
            problems.append('inertia differs by more than 1e-9 relative')

    if recipe == 'terrain':
        # The GeoTIFF rank 0 wrote (a serial format: ParaView updated the whole grid on every
        # rank for it): the serial standalone writer's bytes.
        serial_tif = os.path.join(out_dir, 'serial-slope.tif')
        writer = terroir.vtkTerroirGeoTIFFWriter()
        writer.SetInputData(expected)
        writer.SetArrayName('Slope')
        writer.SetFileName(serial_tif)
        writer.SetOverwrite(True)
        writer.Write()
        tif = os.path.join(out_dir, 'slope.tif')
        if not os.path.exists(tif) or not filecmp.cmp(tif, serial_tif, shallow=False):
            problems.append('slope.tif is not the serial GeoTIFF, byte for byte')

    # The pieces in the .pvti: N of them, tiling the whole extent.
    pieces = [[int(v) for v in p.get('Extent').split()]
              for p in ET.parse(os.path.join(out_dir, 'chain.pvti')).getroot().iter('Piece')]
    if len(pieces) != ranks:
        problems.append('%d pieces in chain.pvti for %d ranks' % (len(pieces), ranks))
    # Image pieces share their boundary points (VTK splits the cells between the pieces): the
    # cells between the points, one fewer per axis, must be covered once.
    cover = np.zeros((max(whole[3], 1), max(whole[1], 1)), dtype=int)
    for p in pieces:
        cover[p[2]:max(p[3], p[2] + 1), p[0]:max(p[1], p[0] + 1)] += 1
    if not (cover == 1).all():
        problems.append('the pieces do not tile the extent (%d cells covered %s times)' % (
            int((cover != 1).sum()), sorted(set(cover.ravel().tolist()) - {1})))

    if recipe in ('flow', 'flowghost', 'rivers', 'riversghost', 'riverswarm', 'd8', 'd8ghost',
                  'mfd', 'dinf') and ranks > 1:
        # A river must cross every line the pieces share (else the halo is not really tested):
        # the serial run's River cells on both sides of each shared column and row.
        dims = expected.GetDimensions()
        river = b['River'].reshape(dims[1], dims[0]).astype(bool)
        columns, rows = piece_boundaries(pieces, whole)
        for axis, lines in ((0, columns), (1, rows)):
            for line in lines:
                n = river_crossings(river, line - whole[2 * axis], axis)
                print('%s %d: %d river cells cross it' % (('column', 'row')[axis], line, n))
                if n == 0:
                    problems.append('no river crosses the pieces\' %s %d' % (
                        ('column', 'row')[axis], line))
    if recipe in ('flow', 'flowghost', 'rivers', 'riversghost', 'riverswarm', 'full'):
        fy = expected.GetFieldData()
        want = {name: fy.GetArray(name).GetTuple1(0)
                for name in ('WaterFlowIterations', 'WaterFlowInitialVolume',
                             'WaterFlowStoredVolume', 'WaterFlowOutflowVolume',
                             'WaterFlowMovedVolume')}
        want['WaterFlowStopReason'] = fy.GetAbstractArray('WaterFlowStopReason').GetValue(0)
        if recipe == 'riverswarm':
            levels = fy.GetArray('WaterFlowWarmStartIterations')
            want['WaterFlowWarmStartIterations'] = [
                levels.GetComponent(t, c) for t in range(levels.GetNumberOfTuples())
                for c in range(levels.GetNumberOfComponents())]
        runs = []
        for r in range(ranks):
            path = os.path.join(out_dir, 'rank%d.json' % r)
            if os.path.exists(path):
                runs.append(json.load(open(path)).get('water_flow'))
        if any(run != runs[0] for run in runs):
            problems.append('the ranks ended different runs: %s' % runs)
        got_run = runs[0] if runs else None
        if not got_run:
            problems.append('no rank recorded its water-flow run')
        else:
            for name, value in want.items():
                have = got_run.get(name)
                if name in ('WaterFlowIterations', 'WaterFlowStopReason',
                            'WaterFlowWarmStartIterations'):
                    ok = have == value
                else:
                    ok = have is not None and abs(have - value) <= FLOW_VOLUME_RTOL * abs(value)
                print('%s: pieces %r, serial %r' % (name, have, value))
                if not ok:
                    problems.append('%s: pieces %r, serial %r' % (name, have, value))

    if recipe in ('lakes', 'lakesghost', 'seeds', 'full'):
        fy = expected.GetFieldData()
        want = {name: [fy.GetArray(name).GetTuple1(i)
                       for i in range(fy.GetArray(name).GetNumberOfTuples())]
                for name in LAKE_FIELDS}
        for r in range(ranks):
            path = os.path.join(out_dir, 'rank%d.json' % r)
            have = json.load(open(path)).get('water_bodies', {}) if os.path.exists(path) else {}
            for name in LAKE_FIELDS:
                x, y = np.array(have.get(name, [])), np.array(want[name])
                exact = name not in ('WaterBodyArea', 'WaterBodyVolume')
                ok = x.shape == y.shape and (np.array_equal(x, y) if exact else
                                             np.allclose(x, y, rtol=LAKE_RTOL, atol=0.0))
                if not ok:
                    problems.append('rank %d: %s differs from the serial table' % (r, name))
        print('%d water bodies, as serially on every rank' % len(want['WaterBodyLevel']))
        if ranks == 4:
            # A lake must lie in more than one piece (else the joining is not really tested):
            # Independence Lake on the bundled DEM crosses the row the pieces share (a connected
            # lake whose rows span a shared row lies on both sides of it).
            dims = expected.GetDimensions()
            body = b['WaterBody'].reshape(dims[1], dims[0])
            spanning = 0
            for lake in range(1, len(want['WaterBodyLevel']) + 1):
                js, is_ = np.nonzero(body == lake)
                rows = {p[3] for p in pieces if p[3] < whole[3]}
                cols = {p[1] for p in pieces if p[1] < whole[1]}
                crosses = any(js.min() + whole[2] < r_ < js.max() + whole[2] for r_ in rows) or \
                    any(is_.min() + whole[0] < c < is_.max() + whole[0] for c in cols)
                if crosses:
                    spanning += 1
                    print('lake %d (%d cells) crosses a piece boundary' % (lake, js.size))
            if spanning == 0:
                problems.append('no lake crosses a piece boundary')

    if recipe in ('sun', 'sunhours', 'full'):
        for r in range(ranks):
            path = os.path.join(out_dir, 'rank%d.json' % r)
            share = json.load(open(path)).get('sun_halo_uncertain_share') \
                if os.path.exists(path) else None
            print('rank %d: share of decisions terrain beyond the halo could change: %r' % (r, share))
            if ranks > 1 and recipe in ('sun', 'full') and share != 0.0:
                problems.append('rank %d: SunHaloUncertainShare %r, expected 0' % (r, share))
            if ranks > 1 and recipe == 'sunhours' and not (share and share > 0.0):
                problems.append('rank %d: SunHaloUncertainShare %r, expected > 0' % (r, share))

    # What each rank read.
    whole_cells = (whole[1] + 1) * (whole[3] + 1)
    for r in range(ranks):
        path = os.path.join(out_dir, 'rank%d.json' % r)
        if not os.path.exists(path):
            problems.append('rank %d wrote no record' % r)
            continue
        rec = json.load(open(path))
        piece, read = rec['piece_extent'], rec['read_extent']
        cells = (piece[1] - piece[0] + 1) * (piece[3] - piece[2] + 1)
        if rec['ranks'] != ranks or rec['points'] != cells:
            problems.append('rank %d: %s ranks, %s points for piece %s' % (
                r, rec['ranks'], rec['points'], piece))
        if piece not in pieces:
            problems.append('rank %d: piece %s is not one of the .pvti pieces' % (r, piece))
        # A whole-extent filter (GHOST None) reads the whole raster on every rank.
        want = grow(piece, whole, GHOST[recipe]) if ranks > 1 and GHOST[recipe] is not None \
            else whole
        if read != want:
            problems.append('rank %d: read %s, expected %s (piece %s grown by %d)' % (
                r, read, want, piece, GHOST[recipe]))
        read_cells = (read[1] - read[0] + 1) * (read[3] - read[2] + 1)
        if ranks > 1 and GHOST[recipe] is not None and read_cells >= whole_cells:
            problems.append('rank %d read the whole raster' % r)
        print('rank %d: piece %s (%d points), read %s (%d cells, %.1f%% of the raster)' % (
            r, piece, cells, read, read_cells, 100.0 * read_cells / whole_cells))

    for p in problems:
        print(p)
    verdict = 'within the stated bounds' if recipe == 'sunhours' else 'bit-identical'
    print('%s, %d ranks: %d arrays compared, %s' % (recipe, ranks, compared,
                                                    'FAILED' if problems else verdict))
    return 1 if problems else 0


if __name__ == '__main__':
    sys.exit(main())
