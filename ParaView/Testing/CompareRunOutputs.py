"""Writes terrain.vti with each of `terroir run`'s encodings (run with --outputs vti) and checks
what ParaView read from them (ReadRunOutputs.py's JSON) against VTK 9.1's reader: the same
arrays, sizes and bytes, and the same across encodings.
    python3 CompareRunOutputs.py write TERROIR OUT_DIR      (before ParaView reads)
    python3 CompareRunOutputs.py check PARAVIEW.json VTI...
"""
import hashlib
import json
import os
import subprocess
import sys

ENCODINGS = ("lz4", "zlib", "none")

if sys.argv[1] == "write":
    terroir, out = sys.argv[2], sys.argv[3]
    for encoding in ENCODINGS:
        folder = os.path.join(out, "run-" + encoding)
        r = subprocess.run([terroir, "run", "--out", folder, "--no-png", "--outputs", "vti",
                            "--vti-compression", encoding, "--overwrite", "--backend", "cpu"],
                           capture_output=True, text=True)
        if r.returncode != 0:
            sys.exit("terroir run failed: " + r.stderr)
    sys.exit(0)

import vtk
from vtk.util.numpy_support import vtk_to_numpy

with open(sys.argv[2]) as f:
    paraview = json.load(f)
first = None
for path in sys.argv[3:]:
    reader = vtk.vtkXMLImageDataReader()
    reader.SetFileName(path)
    reader.Update()
    pd = reader.GetOutput().GetPointData()
    arrays = {}
    for k in range(pd.GetNumberOfArrays()):
        values = vtk_to_numpy(pd.GetArray(k))
        arrays[pd.GetArrayName(k)] = [values.size, hashlib.sha256(values.tobytes()).hexdigest()]
    if len(arrays) < 20:
        sys.exit("%s: %d arrays, a run's terrain.vti holds at least 20" % (path, len(arrays)))
    if paraview[path]["arrays"] != arrays:
        bad = sorted(n for n in set(arrays) | set(paraview[path]["arrays"])
                     if arrays.get(n) != paraview[path]["arrays"].get(n))
        sys.exit("%s: ParaView and VTK 9.1 read different arrays: %s" % (path, bad))
    if first is not None and arrays != first:
        sys.exit("%s: arrays differ from the first encoding's" % path)
    first = arrays
print("%d encodings, %d arrays each: ParaView and VTK 9.1 read the same bytes" %
      (len(sys.argv) - 3, len(first)))
