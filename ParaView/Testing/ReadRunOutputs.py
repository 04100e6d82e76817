"""ParaView reads terrain.vti in each of `terroir run`'s encodings (--vti-compression lz4, zlib,
none; raw appended data with 64-bit headers): every point array's name, size and SHA-256 of
its bytes, as ParaView's reader delivers them, into a JSON file that
CompareRunOutputs.py checks against VTK 9.1's reader and across encodings.
    pvbatch RunInParaView.py ReadRunOutputs.py OUT.json VTI...
"""
import hashlib
import json
import sys

from paraview import servermanager
from paraview.simple import OpenDataFile
from vtkmodules.util.numpy_support import vtk_to_numpy

out, paths = sys.argv[1], sys.argv[2:]
result = {}
for path in paths:
    reader = OpenDataFile(path)
    if reader is None or reader.GetXMLName() != "XMLImageDataReader":
        sys.exit("%s: ParaView has no XML image data reader for it" % path)
    image = servermanager.Fetch(reader)
    pd = image.GetPointData()
    arrays = {}
    for k in range(pd.GetNumberOfArrays()):
        values = vtk_to_numpy(pd.GetArray(k))
        arrays[pd.GetArrayName(k)] = [values.size, hashlib.sha256(values.tobytes()).hexdigest()]
    result[path] = {"dimensions": list(image.GetDimensions()), "arrays": arrays}
with open(out, "w") as f:
    json.dump(result, f, indent=1)
