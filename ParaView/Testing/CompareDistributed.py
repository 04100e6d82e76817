"""Checks a distributed run of DistributedChain.py (mpirun -np N pvbatch) against the same chain
run serially by the standalone build (Debian's VTK 9.1, /usr/bin/python3, package `terroir`):
    CompareDistributed.py terrain|zones|zonesghost N DEM OUT_DIR
- the pieces of OUT_DIR/chain.pvti, reassembled by VTK 9.1's vtkXMLPImageDataReader, give the
  serial arrays bit for bit (besides the all-zero vtkGhostType ParaView's writer adds) (the same cores on the same cells in the same order: a piece's
  cells see the same neighbours through their ghost layer); `vtkValidPointMask`, which the
  serial run has only when some cell is no-data, must match it too;
- terrain: slope.tif (TerroirGeoTIFFWriter, a serial format: ParaView updates the whole grid
  on every rank for it and rank 0 writes) has the bytes of the standalone writer's GeoTIFF;
- the .pvti holds N pieces that tile the whole extent without overlap, one per rank;
- each rank's reader read only its piece grown by the ghost layers the chain asks for (slope 1,
  infiltration 1: 2 cells, clamped to the raster), so no rank read the whole DEM when N > 1
  (k-means, in zones, asks for its piece alone in a distributed run: all-reduced sums).
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
GHOST = {'terrain': 2, 'zones': 2, 'zonesghost': 3}


def serial(recipe, dem):
    reader = terroir.vtkTerroirDEMReader()
    reader.SetFileName(dem)
    stages = [terroir.vtkTerroirSlope(), terroir.vtkTerroirTemperature(),
              terroir.vtkTerroirInfiltration(), terroir.vtkTerroirSoilHumidity()]
    if recipe in ('zones', 'zonesghost'):
        stages.append(terroir.vtkTerroirKMeans())
    if recipe == 'zonesghost':
        stages.append(terroir.vtkTerroirSlope())
    previous = reader
    for stage in stages:
        stage.SetInputConnection(previous.GetOutputPort())
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

    reader = vtkXMLPImageDataReader()
    reader.SetFileName(os.path.join(out_dir, 'chain.pvti'))
    reader.Update()
    got = reader.GetOutput()
    if list(got.GetExtent()) != whole:
        problems.append('extent: pieces %s, serial %s' % (list(got.GetExtent()), whole))
    a, b = arrays(got), arrays(expected)
    # ParaView's parallel writer adds vtkGhostType to every piece; no point may be a ghost
    # there (each filter gave back exactly its piece, no ghost layer).
    ghost = a.pop('vtkGhostType', None)
    if ghost is not None and ghost.any():
        problems.append('%d points are marked ghost in the written pieces' % int((ghost != 0).sum()))
    if 'vtkValidPointMask' in a and 'vtkValidPointMask' not in b:
        problems.append('the pieces carry vtkValidPointMask, the serial run has no no-data cell')
    if sorted(a) != sorted(b):
        problems.append('arrays: pieces %s, serial %s' % (sorted(a), sorted(b)))
    compared = 0
    for name in sorted(set(a) & set(b)):
        x, y = a[name], b[name]
        if x.dtype != y.dtype or x.shape != y.shape or not np.array_equal(x, y, equal_nan=True):
            diff = (np.nanmax(np.abs(x.astype(float) - y.astype(float)))
                    if x.shape == y.shape else float('inf'))
            problems.append('%s: differs from the serial run (max |diff| %g)' % (name, diff))
        compared += 1
    if recipe in ('zones', 'zonesghost'):
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
        want = grow(piece, whole, GHOST[recipe]) if ranks > 1 else whole
        if read != want:
            problems.append('rank %d: read %s, expected %s (piece %s grown by %d)' % (
                r, read, want, piece, GHOST[recipe]))
        read_cells = (read[1] - read[0] + 1) * (read[3] - read[2] + 1)
        if ranks > 1 and read_cells >= whole_cells:
            problems.append('rank %d read the whole raster' % r)
        print('rank %d: piece %s (%d points), read %s (%d cells, %.1f%% of the raster)' % (
            r, piece, cells, read, read_cells, 100.0 * read_cells / whole_cells))

    for p in problems:
        print(p)
    print('%s, %d ranks: %d arrays compared, %s' % (recipe, ranks, compared,
                                                    'FAILED' if problems else 'bit-identical'))
    return 1 if problems else 0


if __name__ == '__main__':
    sys.exit(main())
