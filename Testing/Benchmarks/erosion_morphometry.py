"""Erosion against real landscapes (issue 27, Documentation/Erosion.md, "Realism"): a fractal
and a polygon-map island, each before and after vtkTerroirErosion, and the bundled USGS DEMs,
through `terroir morphometry`; prints one table (closed depressions, slope distribution,
drainage density, Hack's exponent, hypsometric integral, bifurcation ratio) and, with --png,
writes hillshades of the synthetic terrains before and after.
    /usr/bin/python3 Testing/Benchmarks/erosion_morphometry.py BUILD_DIR OUT_DIR [SIZE] [--png DIR]
One set of erosion parameters for every terrain (EROSION below), chosen once: the model's time
step is raised from Weiss's 0.01 s to 0.5 s (stable: a wave of 1 m water travels
sqrt(g h) dt = 1.6 m a step on 10 m cells) so that water crosses the grid within the run; the
grid's edge is sea (water and what it carries leave there)."""
import json
import os
import subprocess
import sys

import terroir
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOImage import vtkPNGWriter
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.util.numpy_support import numpy_to_vtk
import numpy as np

EROSION = dict(Steps=500, TimeStep=0.5, InitialWater=0.5, RainRate=2000.0, Boundary=1,
               SeaLevel=-1e9)
STATS = [('closed_depressions.share', 'closed depressions (share)'),
         ('slope_deg.mean', 'slope mean (deg)'), ('slope_deg.p90', 'slope p90 (deg)'),
         ('drainage.drainage_density_km_per_km2', 'drainage density (km/km2)'),
         ('hack.exponent', 'Hack exponent'), ('hypsometric_integral', 'hypsometric integral'),
         ('horton.bifurcation_ratio', 'bifurcation ratio')]


def morphometry(build, dem, out_json):
    subprocess.run([os.path.join(build, 'bin', 'terroir'), 'morphometry', dem, '--json', out_json,
                    '--overwrite'], check=True, stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL)
    data = json.load(open(out_json))
    values = {}
    for key, _ in STATS:
        node = data
        for part in key.split('.'):
            node = node.get(part, {}) if isinstance(node, dict) else {}
        values[key] = node if isinstance(node, (int, float)) else float('nan')
    return values


def erode(dem, out_tif):
    reader = terroir.vtkTerroirDEMReader()
    reader.SetFileName(dem)
    erosion = terroir.vtkTerroirErosion()
    erosion.SetInputConnection(reader.GetOutputPort())
    for name, value in EROSION.items():
        getattr(erosion, 'Set' + name)(value)
    erosion.Update()
    writer = terroir.vtkTerroirGeoTIFFWriter()
    writer.SetInputData(erosion.GetOutput())
    writer.SetArrayName('ErodedElevation')
    writer.SetFileName(out_tif)
    writer.SetOverwrite(True)
    writer.Write()
    return reader.GetOutput(), erosion.GetOutput()


def hillshade(image, array, png):
    """A plain hillshade (sun from the north-west, 45 degrees up) as an 8-bit PNG."""
    nx, ny, _ = image.GetDimensions()
    dx, dy, _ = image.GetSpacing()
    z = vtk_to_numpy(image.GetPointData().GetArray(array)).reshape(ny, nx).astype(float)
    gy, gx = np.gradient(np.nan_to_num(z, nan=np.nanmin(z)), dy, dx)
    slope = np.arctan(np.hypot(gx, gy))
    aspect = np.arctan2(-gx, gy)
    sun_az, sun_el = np.radians(315.0), np.radians(45.0)
    shade = np.sin(sun_el) * np.cos(slope) + np.cos(sun_el) * np.sin(slope) * np.cos(sun_az - aspect)
    grey = np.clip(255.0 * shade, 0, 255).astype(np.uint8)
    out = vtkImageData()
    out.SetDimensions(nx, ny, 1)
    out.GetPointData().SetScalars(numpy_to_vtk(grey.ravel(), deep=True))
    writer = vtkPNGWriter()
    writer.SetInputData(out)
    writer.SetFileName(png)
    writer.Write()


def main():
    build, out = sys.argv[1], sys.argv[2]
    size = int(sys.argv[3]) if len(sys.argv) > 3 and not sys.argv[3].startswith('--') else 256
    png = sys.argv[sys.argv.index('--png') + 1] if '--png' in sys.argv else None
    os.makedirs(out, exist_ok=True)
    terroir_bin = os.path.join(build, 'bin', 'terroir')
    fractal = os.path.join(out, 'fractal.tif')
    island = os.path.join(out, 'island.tif')
    subprocess.run([terroir_bin, 'fractal', fractal, '--size', str(size), '--seed', '3',
                    '--overwrite'], check=True, stdout=subprocess.DEVNULL)
    subprocess.run([terroir_bin, 'generate', 'island', island, '--width', str(size), '--height',
                    str(size), '--spacing', '10', '--seed', '3', '--overwrite'], check=True,
                   stdout=subprocess.DEVNULL)
    rows = []
    for name, dem in (('fractal', fractal), ('island', island)):
        eroded = os.path.join(out, name + '_eroded.tif')
        before, after = erode(dem, eroded)
        rows.append((name, morphometry(build, dem, os.path.join(out, name + '.json'))))
        rows.append((name + ' eroded', morphometry(build, eroded,
                                                   os.path.join(out, name + '_eroded.json'))))
        if png:
            hillshade(before, 'Elevation', os.path.join(png, 'erosion_%s_before.png' % name))
            hillshade(after, 'ErodedElevation', os.path.join(png, 'erosion_%s_after.png' % name))
    data = os.environ.get('TERROIR_DATA_DIR', os.path.join(os.path.dirname(__file__), '..', '..',
                                                           'Data'))
    for name, rel in (('Sagehen Creek (USGS 10 m)', 'sagehen_creek_ca/sagehen_dem_utm11n_10m.tif'),
                      ('Wake County (USGS 30 m)', 'wake_county_nc/elev_ned_30m.tif'),
                      ('Shellmound (100 m)', 'shellmound_ms/meras_100m_dem.tif')):
        rows.append((name, morphometry(build, os.path.join(data, rel),
                                       os.path.join(out, name.split()[0] + '.json'))))
    print('| terrain | ' + ' | '.join(label for _, label in STATS) + ' |')
    print('|---|' + '---|' * len(STATS))
    for name, values in rows:
        print('| %s | %s |' % (name, ' | '.join('%.3g' % values[k] for k, _ in STATS)))


if __name__ == '__main__':
    main()
