#!/usr/bin/env bash
# What writing adds to `terroir run` (issue 28), in one script on one machine:
#   1. compute only: --no-png --no-vti --outputs tables (the clusters' two small tables);
#   2. the default outputs (terrain.vti LZ4, 13 GeoTIFFs, 14 PNGs with a display, reports);
#   3. the same outputs with other encodings (zlib .vti, DEFLATE tiled GeoTIFFs with overviews).
# For each: wall seconds, the sum of the compute stages, what the run waited for its files after
# computing, the writing's busy seconds (both threads), and writing's share: wall / compute - 1.
# Then every array of 2 and 3 is compared, and with REFERENCE_DIR (an earlier build's
# `terroir run` output folder) every array of 2 against it: terrain.vti's arrays, every GeoTIFF
# band and every PNG's pixels must be identical.
#   Testing/Benchmarks/run_outputs.sh [BUILD_DIR] [DEM|SIZE] [REFERENCE_DIR]
# DEM: a file (default the bundled Sagehen DEM, with the NHD comparison); SIZE: a number, for a SIZE x SIZE
# `terroir fractal` DEM placed at 39.4 N 120.2 W. PNGs need an X display (xvfb-run -a).
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build=${1:-$here/build}
input=${2:-}
reference=${3:-}
terroir="$build/bin/terroir"
[ -x "$terroir" ] || { echo "$terroir not found: build first" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# The DEM and where it lies (none: the bundled DEM, whose rivers are also scored against NHD).
dem=()
if [[ "$input" =~ ^[0-9]+$ ]]; then
  "$terroir" fractal "$work/dem.tif" --size "$input" --seed 7 >/dev/null
  dem=("$work/dem.tif" --lat 39.4 --lon -120.2)
elif [ -n "$input" ]; then
  dem=("$input")
fi
png=()
[ -n "${DISPLAY:-}" ] || { png=(--no-png); echo "no X display: PNGs left out (run under xvfb-run -a)"; }

run() { # run NAME options...
  local name=$1; shift
  "$terroir" run "${dem[@]}" -o "$work/$name" "${png[@]}" "$@" >"$work/$name.log" 2>&1 ||
    { echo "terroir run ($name) failed:"; tail -3 "$work/$name.log"; exit 1; }
}
run compute --no-png --no-vti --outputs tables
run default
run encoded --vti-compression zlib --tiff-compression deflate --tiff-layout tiles \
  --tiff-threads 2 --tiff-overviews

/usr/bin/python3 - "$work" "$reference" <<'PY'
import json, os, sys
import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy
from osgeo import gdal

work, reference = sys.argv[1], sys.argv[2]
STAGES = ("read", "slope", "temperature", "illumination", "infiltration", "humidity", "lakes",
          "rivers", "clusters")

def report(name):
    with open(os.path.join(work, name, "report.json")) as f:
        return json.load(f)

first = report("compute")
cells = first["grid"]["nx"] * first["grid"]["ny"]
print("terroir run outputs: %d x %d = %.2f Mcells, %d cores" % (
    first["grid"]["nx"], first["grid"]["ny"], cells / 1e6, os.cpu_count()))
print("%-34s %8s %9s %10s %9s %9s %8s" % ("outputs", "wall s", "compute s", "after s",
                                         "busy s", "MB", "added"))
for name, label in (("compute", "compute only (tables)"), ("default", "default"),
                    ("encoded", "zlib vti, DEFLATE tiles + ovr")):
    r = report(name)
    st = r["stages"]
    compute = sum(st[s]["seconds"] for s in STAGES if "seconds" in st.get(s, {}))
    size = sum(os.path.getsize(os.path.join(work, name, f)) for f in os.listdir(os.path.join(work, name)))
    print("%-34s %8.2f %9.2f %10.2f %9.2f %9.1f %7.0f%%" % (
        label, r["wall_seconds"], compute, st["write"]["seconds"], st["write"]["busy_seconds"],
        size / 1e6, 100.0 * (r["wall_seconds"] / compute - 1.0)))
    if name != "compute":
        kinds = ", ".join("%s %.2f s" % kv for kv in sorted(st["write"]["seconds_by_kind"].items()))
        print("%-34s %s" % ("", "busy by kind: " + kinds))
base = report("compute")
wall_compute = base["wall_seconds"]
wall_default = report("default")["wall_seconds"]
print("writing adds %.0f%% to the compute-only run's wall time (default outputs: %.2f s vs %.2f s),"
      " %.1f ms per Mcell" % (100.0 * (wall_default / wall_compute - 1.0), wall_default,
                              wall_compute, 1e3 * (wall_default - wall_compute) / (cells / 1e6)))

def vti_arrays(path):
    reader = vtk.vtkXMLImageDataReader()
    reader.SetFileName(path)
    reader.Update()
    pd = reader.GetOutput().GetPointData()
    return {pd.GetArrayName(k): vtk_to_numpy(pd.GetArray(k)).tobytes()
            for k in range(pd.GetNumberOfArrays())}

def raster_bytes(path):
    if path.endswith(".png"):
        reader = vtk.vtkPNGReader()
        reader.SetFileName(path)
        reader.Update()
        return [vtk_to_numpy(reader.GetOutput().GetPointData().GetScalars()).tobytes()]
    ds = gdal.Open(path)
    return [ds.GetRasterBand(b + 1).ReadRaster() for b in range(ds.RasterCount)]

def compare(a, b, label):
    names = sorted(n for n in os.listdir(a) if n.endswith((".vti", ".tif", ".png")))
    other = sorted(n for n in os.listdir(b) if n.endswith((".vti", ".tif", ".png")))
    if names != other:
        sys.exit("%s: different files: %s vs %s" % (label, names, other))
    arrays = 0
    for n in names:
        pa, pb = os.path.join(a, n), os.path.join(b, n)
        if n.endswith(".vti"):
            va, vb = vti_arrays(pa), vti_arrays(pb)
            if va != vb:
                bad = [k for k in va if va.get(k) != vb.get(k)] or sorted(set(vb) - set(va))
                sys.exit("%s: terrain.vti arrays differ: %s" % (label, bad))
            arrays += len(va)
        else:
            if raster_bytes(pa) != raster_bytes(pb):
                sys.exit("%s: %s differs" % (label, n))
            arrays += 1
    print("%s: %d files, %d arrays/images, all identical" % (label, len(names), arrays))

compare(os.path.join(work, "default"), os.path.join(work, "encoded"), "default vs other encodings")
if reference:
    compare(os.path.join(work, "default"), reference, "default vs " + reference)
PY
