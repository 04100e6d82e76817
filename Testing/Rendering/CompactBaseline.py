#!/usr/bin/python3
"""Copy a rendered test image into Testing/Baselines/, compacted to stay under 100 KB.

Usage: /usr/bin/python3 Testing/Rendering/CompactBaseline.py RENDERED.png [BASELINE.png]

The PNG is written with zlib level 9. When it is still over 100 KB, each colour channel is
rounded to a multiple of a step (2, 4, then 8: every channel moves by at most step/2 grey
levels), using the smallest step that fits. The rounding stays inside the image comparison
the tests use (Testing/Rendering/TerroirImageCompare.h: a pixel matches when every channel is
within 8 levels of a pixel within one pixel of it): step 8 moves a channel by at most 4 levels,
half the tolerance, so a compacted baseline passes when the rendering is within 4 levels of the
exact one.
Use it only for baselines that are over 100 KB as plain PNGs; look at the image first.
"""
import os
import sys

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkIOImage import vtkPNGReader, vtkPNGWriter

LIMIT = 100 * 1000
STEPS = (1, 2, 4, 8)


def compact(src, dst):
    reader = vtkPNGReader()
    reader.SetFileName(src)
    reader.Update()
    image = reader.GetOutput()
    dims = image.GetDimensions()
    if dims[0] == 0:
        sys.exit(f"CompactBaseline: cannot read {src}")
    pixels = vtk_to_numpy(image.GetPointData().GetScalars()).astype(np.int32)
    tmp = dst + ".tmp.png"
    for step in STEPS:
        rounded = np.clip(((pixels + step // 2) // step) * step, 0, 255).astype(np.uint8)
        out = vtkImageData()
        out.SetDimensions(dims)
        array = numpy_to_vtk(rounded, deep=1)
        array.SetNumberOfComponents(pixels.shape[1] if pixels.ndim > 1 else 1)
        out.GetPointData().SetScalars(array)
        writer = vtkPNGWriter()
        writer.SetCompressionLevel(9)
        writer.SetFileName(tmp)
        writer.SetInputData(out)
        writer.Write()
        if writer.GetErrorCode() != 0:
            sys.exit(f"CompactBaseline: cannot write {tmp}")
        if os.path.getsize(tmp) <= LIMIT:
            break
    os.replace(tmp, dst)
    print(f"{dst}: {os.path.getsize(dst)} bytes (channels rounded to multiples of {step})")


if __name__ == "__main__":
    if len(sys.argv) not in (2, 3):
        sys.exit(__doc__)
    source = sys.argv[1]
    here = os.path.dirname(os.path.abspath(__file__))
    target = sys.argv[2] if len(sys.argv) == 3 else os.path.join(
        here, "..", "Baselines", os.path.basename(source))
    compact(source, os.path.normpath(target))
